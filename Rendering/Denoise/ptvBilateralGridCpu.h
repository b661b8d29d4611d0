/**
 * @file ptvBilateralGridCpu.h
 * @brief Private: the CPU driver of the bilateral-grid denoiser: parallel loops (ptvThreads.h) over the row
 *        kernels of ptvBilateralGridRows.h (Highway, dispatched per instruction set), with the
 *        semantics of Kernels/ptvBilateralGrid.h.
 *
 * Three phases: demodulate (parallel over image rows: per-row sums of the demodulated
 * luminance for the outlier limit), splat (a push: parallel over fixed blocks of grid rows, each
 * block owning its rows and a scratch row, all levels in one pass; each pixel row demodulated
 * again as it is pushed, into (r, g, b, 1), and clamped as it is read), slice + blend +
 * re-modulate (parallel over image rows). Every cell and pixel is written by exactly one task in a fixed order and the mean luminance is summed per row and then
 * over rows in order, so the output is bit-identical for any number of threads.
 * Its cost follows the pixels: only cells that some pixel touches are cleared and normalised.
 *
 * The buffers live in the object and are reallocated only when the image size, the number of
 * levels, a level's steps or the thread count change, and a grid row's cells when its pixels
 * touch more range bins than it held (with an eighth to spare): repeated frames allocate nothing.
 */
#ifndef ptvBilateralGridCpu_h
#define ptvBilateralGridCpu_h

#include "Kernels/ptvBilateralGrid.h"
#include "ptvBilateralGridRows.h"
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
   * The settings must be valid (levels 1..3, steps 1..256, W, H >= 1); the caller validates.
   * @a out must not alias an input. With @a alphaIn (W * H opacities) the opacity goes through
   * the finest level beside the colour (sanitised as radiance is, not clamped, not
   * demodulated) into @a alphaOut (W * H, not clamped): what a second Apply with one level and
   * (alpha, alpha, alpha) as the radiance would give, up to the order of the sums.
   */
  void Apply(const BilateralGridSettings& settings, int width, int height,
    const float* radiance, const float* albedo, const float* guides, const float* weights,
    float* out, const float* alphaIn = nullptr, float* alphaOut = nullptr);

  /// Timings of the last Apply (ms).
  const BilateralGridTimings& GetLastTimings() const { return this->Timings; }

  /// How many times a buffer was (re)allocated since construction.
  std::size_t GetAllocationCount() const { return this->Allocations; }

  /// Bytes of the cells (colour and opacity, every level) the last Apply left in the grid.
  std::size_t GetCellBytes() const;

  /// The instruction set of the last Apply's kernels ("AVX3", "AVX2", ..., "EMU128").
  const char* GetLastKernelTarget() const { return this->KernelTarget; }

private:
  template <typename T>
  void Fit(std::vector<T>& buffer, std::size_t size);
  /// The storage of @a rows rows of one level (a padding row: its zero column alone).
  void FitRows(std::vector<std::vector<float>>& rows, std::size_t count, std::size_t bins,
    int floatsPerCell);
  /// Floats held (@a capacity: allocated; a change is an allocation) by every row of cells.
  std::size_t SumOverRows(bool capacity) const;
  void Prepare(const BilateralGridSettings& settings, int levels, int width, int height,
    int blocks, bool alpha);

  std::vector<float> RowPixels;     // per block: W * 4, a pixel row demodulated (r, g, b, 1)
  std::vector<double> RowLuminance; // H row sums of luminance(D)
  std::vector<std::size_t> RowLit;  // H row counts of pixels with luminance(D) > 0
  std::vector<std::vector<float>> RowCells[kMaxGridLevels]; // per level GH + 2 rows of cells
  std::vector<int> Start[kMaxGridLevels];       // per level (GH + 2) * (GW + 2) (rows header)
  std::vector<int> RowIndex[kMaxGridLevels];    // J0 per image row, I0 per image column
  std::vector<int> ColumnIndex[kMaxGridLevels];
  std::vector<float> RowTents[kMaxGridLevels];  // Ty0 then Ty1 (2 H)
  std::vector<float> ColumnTents[kMaxGridLevels]; // Tx0 then Tx1 (2 W)
  std::vector<float> Scratch;       // per block: 2 rows of the largest level's Columns * Bins * 4
  std::vector<int> ScratchRanges;   // per block and row: KMin, then KMax of each column
  std::vector<float> Alpha;         // with an opacity: W * H sanitised opacities
  std::vector<std::vector<float>> RowAlpha; // with an opacity: level 0's rows, as RowCells
  std::vector<float> AlphaScratch;  // with an opacity: per block 2 rows of ScratchFloats / 4
  PushGrid Levels[kMaxGridLevels];
  int Blocks = 0;
  std::size_t ScratchColumns = 0;
  std::size_t ScratchFloats = 0;
  std::size_t Allocations = 0;
  BilateralGridTimings Timings;
  const char* KernelTarget = "";
};
}

#endif
