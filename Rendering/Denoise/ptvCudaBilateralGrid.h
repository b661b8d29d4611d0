/**
 * @file ptvCudaBilateralGrid.h
 * @brief Private: the CUDA driver of the bilateral-grid denoiser -- the same kernel body as the
 *        CPU driver (Kernels/ptvBilateralGrid.h: Demodulate, SplatCell, SliceLevel, Blend,
 *        Remodulate), one thread per pixel or per grid column.
 *
 * Phases as on the CPU: demodulate (per pixel), luminance row sums in double (one thread per
 * row, x ascending) summed over rows on the host in order -- so the outlier limit is the CPU's
 * to the bit -- then clamp, splat (one thread per column (i, j) of each level: a gather, no
 * atomics, deterministic) and slice + blend + re-modulate (per pixel). Explicit device
 * allocations reused across frames. Built from Cuda/ptvCudaBilateralGrid.cu when PTV_ENABLE_CUDA
 * is on; otherwise Apply() reports "built without CUDA". No CUDA type appears here.
 */
#ifndef ptvCudaBilateralGrid_h
#define ptvCudaBilateralGrid_h

#include "ptvBilateralGridSettings.h"

#include <memory>
#include <string>

namespace ptv
{
class CudaBilateralGrid
{
public:
  CudaBilateralGrid();
  ~CudaBilateralGrid();
  CudaBilateralGrid(const CudaBilateralGrid&) = delete;
  CudaBilateralGrid& operator=(const CudaBilateralGrid&) = delete;

  /**
   * Same inputs and result as BilateralGridCpu::Apply (host buffers; @a albedo may be nullptr:
   * no demodulation). Returns false with the CUDA error in @a error (the caller falls back to
   * the CPU grid).
   */
  bool Apply(const BilateralGridSettings& settings, int width, int height, const float* radiance,
    const float* albedo, const float* guides, const float* weights, float* out,
    std::string& error);

  const BilateralGridTimings& GetLastTimings() const { return this->Timings; }

  /// Free the device memory.
  void Release();

private:
  struct Internals;
  std::unique_ptr<Internals> Impl;
  BilateralGridTimings Timings;
};
}

#endif
