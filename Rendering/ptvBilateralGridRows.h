/**
 * @file ptvBilateralGridRows.h
 * @brief Private: the CPU bilateral grid's row kernels (push splat, slice + blend + re-modulate),
 *        compiled for every x86-64 instruction set by Google Highway and chosen at run time.
 *
 * The semantics are those of Kernels/ptvBilateralGrid.h (tent weights, dropped cells, blend);
 * only the order of the splat sums differs (a push, not a gather; see PushGrid below).
 *
 * Storage of one level (PushGrid): cells are 4 floats, interleaved (r, g, b, w). Rows and
 * columns are padded by one on each side and columns by one range bin at the top, so that a
 * pixel's 2 x 2 x 2 neighbourhood is always addressable: row r = j + 1, column c = i + 1,
 * bin k (0..Depth, Depth is padding). After the splat a kept cell holds (mean r, g, b, 1), an
 * empty or padding cell (0, 0, 0, 0): the slice then needs no test per tap, its fourth lane sums
 * the kept weights. Only the cells a pixel touches are written in a frame; the slice only reads
 * those with a non-zero weight, so stale (finite) cells elsewhere never change a result.
 */
#ifndef ptvBilateralGridRows_h
#define ptvBilateralGridRows_h

#include "Kernels/ptvBilateralGrid.h"

#include <cstddef>

namespace ptv
{
/// One level of the CPU grid: geometry, interleaved padded cells and per-axis tent tables.
struct PushGrid
{
  GridLevel Geometry;  ///< Width, Height, Depth, steps (its Values/Weights are unused)
  int Columns = 0;     ///< Geometry.Width + 2
  int Bins = 0;        ///< Geometry.Depth + 1
  float* Cells = nullptr; ///< (Height + 2) * Columns * Bins * 4 floats
  // Per image column x: i0 = floor(u_x), Tent(u_x - i0), Tent(u_x - i0 - 1); likewise rows.
  const int* I0 = nullptr;
  const float* Tx0 = nullptr;
  const float* Tx1 = nullptr;
  const int* J0 = nullptr;
  const float* Ty0 = nullptr;
  const float* Ty1 = nullptr;
};

/// Scratch for splatting one grid row: Columns * Bins * 4 floats, zero between rows, and the
/// touched bin range of each column (KMin > KMax: none).
struct SplatScratch
{
  float* Cells;
  int* KMin;
  int* KMax;
};

/// What the splat reads: demodulated, clamped-on-the-fly pixels and one level's guides.
struct SplatInput
{
  const float* Demodulated4; ///< W * H pixels, (r, g, b, 1)
  const float* Guides;       ///< interleaved, GuideStride values per pixel
  int GuideStride;
  int GuideOffset;
  int Width;
  int Height;
  float Limit; ///< outlier clamp of r, g, b; +inf = off
};

/// What the slice reads and writes for image rows.
struct SliceInput
{
  const PushGrid* Levels; ///< NumberOfLevels grids
  int NumberOfLevels;
  const float* Guides;  ///< W * H * NumberOfLevels, interleaved
  const float* Weights; ///< W * H * (NumberOfLevels - 1), interleaved; may be null
  const float* Albedo;  ///< W * H * 3 raw albedo; null: no re-modulation
  float* Out;           ///< W * H * 3
  int Width;
};

/**
 * Splat grid rows [jBegin, jEnd) of @a grid: for each, push every pixel within its tent support
 * into @a scratch, then write the touched cells of its columns normalised into grid.Cells (and
 * leave @a scratch zero again). @a portable: the baseline build of the kernel instead of the best
 * instruction set of this CPU.
 */
void SplatGridRows(const SplatInput& in, PushGrid& grid, SplatScratch& scratch, int jBegin,
  int jEnd, bool portable);

/// Slice every level at image rows [yBegin, yEnd), blend, re-modulate, write RGB.
void SliceRows(const SliceInput& in, int yBegin, int yEnd, bool portable);

/// The instruction set the row kernels run with ("AVX3", "AVX2", "SSE4", "EMU128", ...).
const char* GridKernelTarget(bool portable);
}

#endif
