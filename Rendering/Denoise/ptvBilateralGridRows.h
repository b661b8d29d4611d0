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
 * the kept weights. A column keeps only the bins its pixels touched (a pixel's guides span a
 * few of the Depth bins): row r's storage is a zero column (Bins cells) followed by each
 * column's touched bins, and Start[r][c] + k is the index of cell (r, c, k) there (Start 0:
 * the zero column, for padding and untouched columns). A pixel slices exactly the cells its
 * own splat touched, except the lower grid row when its tent weight there is 0: the slice then
 * reads the upper row's cells for it, with weight 0.
 *
 * The opacity (the denoiser's DenoiseAlpha) can ride along at level 0: one more float per cell
 * in rows of their own (PushGrid::RowAlpha), pushed with the colour's tent weights and normalised
 * by the colour's weight sum, sliced with the colour's taps -- what a second grid pass over
 * (alpha, alpha, alpha) would give, for a fraction of its cost.
 */
#ifndef ptvBilateralGridRows_h
#define ptvBilateralGridRows_h

#include "Kernels/ptvBilateralGrid.h"

#include <cstddef>
#include <vector>

namespace ptv
{
/// One level of the CPU grid: geometry, the touched cells of each padded row and per-axis
/// tent tables.
struct PushGrid
{
  GridLevel Geometry;  ///< Width, Height, Depth, steps (its Values/Weights are unused)
  int Columns = 0;     ///< Geometry.Width + 2
  int Bins = 0;        ///< Geometry.Depth + 1
  /// Height + 2 rows of cells (4 floats each): a zero column, then each column's touched bins.
  std::vector<float>* RowCells = nullptr;
  /// (Height + 2) * Columns: cell (r, c, k) is cell Start[r * Columns + c] + k of row r.
  int* Start = nullptr;
  // Per image column x: i0 = floor(u_x), Tent(u_x - i0), Tent(u_x - i0 - 1); likewise rows.
  const int* I0 = nullptr;
  const float* Tx0 = nullptr;
  const float* Tx1 = nullptr;
  const int* J0 = nullptr;
  const float* Ty0 = nullptr;
  const float* Ty1 = nullptr;
  /// With an opacity (level 0 only; else null): Height + 2 rows of one float per cell of
  /// RowCells (the same indices), each cell's mean opacity over the same tent weights as its
  /// colour (0 for an empty cell).
  std::vector<float>* RowAlpha = nullptr;
};

/// Scratch for splatting two consecutive grid rows (a pixel row pushes into both): row j's is
/// Cells[j & 1], Columns * Bins * 4 floats, zero between rows, and the touched bin range of each
/// of its columns, KMin[j & 1][c] .. KMax[j & 1][c] (KMin > KMax: none).
struct SplatScratch
{
  float* Cells[2];
  int* KMin[2];
  int* KMax[2];
  float* Alpha[2]; ///< with an opacity: Columns * Bins floats per row, zero between rows
  float* Row;      ///< W pixels (r, g, b, 1): the pixel row being pushed, demodulated
};

/// What the splat reads: the pixels (demodulated a row at a time as they are pushed, clamped
/// on the fly) and one level's guides.
struct SplatInput
{
  const float* Radiance; ///< W * H RGB pixels
  const float* Albedo;   ///< W * H RGB pixels, or null: no demodulation
  bool Portable;         ///< the demodulation's baseline build (the same bits on every target)
  const float* Guides;   ///< interleaved, GuideStride values per pixel
  int GuideStride;
  int GuideOffset;
  int Width;
  int Height;
  float Limit; ///< outlier clamp of r, g, b; +inf = off
  /// W * H sanitised opacities splatted beside the colour (not clamped) into grid.RowAlpha,
  /// or null (then grid.RowAlpha is not touched).
  const float* Alpha = nullptr;
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
  /// W * H: level 0's slice of the opacity (its Alpha cells, the same taps as the colour), or
  /// null.
  float* AlphaOut = nullptr;
};

/**
 * Splat grid rows [jBegin, jEnd) of @a grid: every pixel row y with j0 = J0[y] in
 * [jBegin - 1, jEnd - 1] is read once and pushed into grid rows j0 and j0 + 1 (those of the
 * range); once the rows of j0 are done, grid row j0 is complete and its touched cells are written
 * normalised into its row of grid.RowCells, sized to them (and its scratch left zero again).
 * Each cell receives its pixels in increasing y, then x, as a loop over one grid row's support
 * would. @a portable: the baseline build of the kernel instead of the best instruction set of
 * this CPU.
 */
void SplatGridRows(const SplatInput& in, PushGrid& grid, SplatScratch& scratch, int jBegin,
  int jEnd, bool portable);

/// Slice every level at image rows [yBegin, yEnd), blend, re-modulate, write RGB.
void SliceRows(const SliceInput& in, int yBegin, int yEnd, bool portable);

/// The instruction set the row kernels run with ("AVX3", "AVX2", "SSE4", "EMU128", ...).
const char* GridKernelTarget(bool portable);
}

#endif
