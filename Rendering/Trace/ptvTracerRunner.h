/**
 * @file ptvTracerRunner.h
 * @brief Private: trace a frame on the CUDA device when asked and able, else on the CPU -- the
 *        one place that chooses between ptvCudaTracer and ptvCpuTracer (as
 *        ptvBilateralGridRunner does for the denoiser's grid).
 *
 * Backends are ptvBackend.h's kBackendAuto / kBackendCpu / kBackendCuda (the public class's
 * BACKEND_* numbers). Both run the same kernel (Kernels/ptvIntegrator.h), so a fallback changes where
 * the frame is traced, not what it shows.
 */
#ifndef ptvTracerRunner_h
#define ptvTracerRunner_h

#include "ptvCudaTracer.h"

#include <string>

namespace ptv
{
class PassBuffers;

/**
 * The backend that runs for a @a requested one: CUDA when CUDA (or Auto) is requested and a
 * device is available, else the CPU. A CUDA request that cannot be honoured sets @a message
 * (the caller reports it as an error and renders on the CPU); otherwise @a message is cleared.
 */
int ResolveBackend(
  int requested, bool cudaAvailable, const std::string& cudaStatus, std::string& message);

class TracerRunner
{
public:
  /**
   * Trace @a samples samples per pixel (sample indices from @a firstSample) into @a out on the
   * backend @a requested resolves to; CUDA errors fall back to the CPU for this frame.
   * @a problem receives a backend problem to report (empty when there is none). @a threads and
   * @a portable are the CPU driver's (see TraceFrameCpu).
   */
  void Trace(const TraceParams& params, unsigned long long volumeVersion,
    unsigned int firstSample, int samples, int threads, bool portable, int requested,
    PassBuffers& out, std::string& problem);

  /// "CPU" or "CUDA": where the last frame was traced ("none" before the first).
  const std::string& GetLastBackend() const { return this->LastBackend; }

  /// Free the device memory.
  void Release() { this->Cuda.Release(); }

private:
  CudaTracer Cuda;
  std::string LastBackend = "none";
};
}

#endif
