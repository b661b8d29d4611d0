/**
 * @file ptvBilateralGridCpu.h
 * @brief Private: the CPU driver of the bilateral-grid denoiser, vtkSMPTools loops over
 *        Kernels/ptvBilateralGrid.h (which defines the semantics).
 *
 * Three phases: demodulate + outlier clamp (parallel over image rows), splat (per level,
 * parallel over grid rows j, one SplatCell per column), slice + blend + re-modulate (parallel
 * over image rows). Every cell and pixel is written by exactly one task and the mean luminance
 * is summed per row and then over rows in order, so the output is bit-identical for any number
 * of threads and any SMP backend.
 *
 * The buffers live in the object and are reallocated only when the image size, the number of
 * levels or a level's steps change: repeated frames of one size allocate nothing.
 */
#ifndef ptvBilateralGridCpu_h
#define ptvBilateralGridCpu_h

#include "Kernels/ptvBilateralGrid.h"
#include "ptvBilateralGridSettings.h"
#include "vtkPTVRenderingModule.h" // for export macro

#include <cstddef>
#include <vector>

namespace ptv
{
class VTKPTVRENDERING_EXPORT BilateralGridCpu
{
public:
  /**
   * Denoise one W x H frame. @a radiance, @a albedo and @a out hold W * H RGB pixels (x
   * fastest), @a guides W * H * Levels interleaved values, @a weights W * H * (Levels - 1)
   * interleaved values (may be nullptr when Levels == 1). @a albedo nullptr: no demodulation.
   * The settings must be valid (levels
   * 1..3, steps 1..256, W, H >= 1); the caller validates. @a out must not alias an input.
   */
  void Apply(const BilateralGridSettings& settings, int width, int height,
    const float* radiance, const float* albedo, const float* guides, const float* weights,
    float* out);

  /// Timings of the last Apply (ms).
  const BilateralGridTimings& GetLastTimings() const { return this->Timings; }

  /// How many times a buffer was (re)allocated since construction.
  std::size_t GetAllocationCount() const { return this->Allocations; }

private:
  template <typename T>
  void Fit(std::vector<T>& buffer, std::size_t size);

  std::vector<float> Demodulated;            // W * H * 3, clamped
  std::vector<float> Guides;                 // Levels * W * H, one plane per level
  std::vector<double> RowLuminance;          // H row sums of luminance(D)
  std::vector<std::size_t> RowLit;           // H row counts of pixels with luminance(D) > 0
  std::vector<float> Values[kMaxGridLevels]; // per level GW * GH * GD * 3
  std::vector<float> Weights[kMaxGridLevels];
  GridLevel Levels[kMaxGridLevels] = {};
  std::size_t Allocations = 0;
  BilateralGridTimings Timings;
};
}

#endif
