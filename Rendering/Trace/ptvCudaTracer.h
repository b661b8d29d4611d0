/**
 * @file ptvCudaTracer.h
 * @brief Private: the CUDA driver -- the same TracePixelMean (Kernels/ptvIntegrator.h) as the CPU
 *        driver, launched once per pixel, with the volume and tables in device memory.
 *
 * Explicit device allocations (no managed memory), reused across frames; the voxels are
 * uploaded again only when @a volumeVersion or the host pointer changes. Built from
 * Cuda/ptvCudaTracer.cu when PTV_ENABLE_CUDA is on; otherwise Trace() reports "built without
 * CUDA". No CUDA type appears here.
 */
#ifndef ptvCudaTracer_h
#define ptvCudaTracer_h

#include "Kernels/ptvIntegrator.h"

#include <memory>
#include <string>

namespace ptv
{
class PassBuffers;

/// Milliseconds of the phases of the last CudaTracer::Trace (host wall clock; the kernel by CUDA
/// events around its launch).
struct CudaTraceTimings
{
  double Upload = 0.0;   ///< volume (when it changed), tables, occupancy, depth limits
  double Kernel = 0.0;   ///< TraceKernel alone
  double Download = 0.0; ///< the passes back into the frame's pass buffers
};

class CudaTracer
{
public:
  CudaTracer();
  ~CudaTracer();
  CudaTracer(const CudaTracer&) = delete;
  CudaTracer& operator=(const CudaTracer&) = delete;

  /**
   * Trace one frame like TraceFrameCpu() into @a out. Returns false with the CUDA error in
   * @a error (ptvTracerRunner then traces on the CPU).
   */
  bool Trace(const TraceParams& params, unsigned long long volumeVersion, unsigned int firstSample,
    int samples, PassBuffers& out, std::string& error);

  /// Free the device memory.
  void Release();

  const CudaTraceTimings& GetLastTimings() const { return this->Timings; }

private:
  struct Internals;
  std::unique_ptr<Internals> Impl;
  CudaTraceTimings Timings;
};
}

#endif
