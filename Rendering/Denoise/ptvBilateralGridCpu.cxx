#include "ptvBilateralGridCpu.h"
#include "ptvGridDemodulateRows.h"

#include "ptvKernelDispatch.h"
#include "ptvThreads.h"

#include "vtkType.h"

#include <algorithm>
#include <chrono>
#include <climits>
#include <limits>

namespace ptv
{
namespace
{
double MillisecondsSince(std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
    .count();
}

/// i0 = floor(u), Tent(u - i0), Tent(u - i0 - 1) of every pixel index along one axis.
void AxisTables(int n, int step, int* index, float* tent0, float* tent1)
{
  for (int x = 0; x < n; ++x)
  {
    const float u = PixelToGrid(x, step);
    const int i0 = FloorToInt(u);
    index[x] = i0;
    tent0[x] = Tent(u - static_cast<float>(i0));
    tent1[x] = Tent(u - static_cast<float>(i0 + 1));
  }
}
}

//------------------------------------------------------------------------------
template <typename T>
void BilateralGridCpu::Fit(std::vector<T>& buffer, std::size_t size)
{
  if (buffer.size() != size)
  {
    std::vector<T>(size).swap(buffer); // exact size, zero-filled; also releases a larger one
    if (size > 0)
    {
      ++this->Allocations;
    }
  }
}

//------------------------------------------------------------------------------
void BilateralGridCpu::FitRows(std::vector<std::vector<float>>& rows, std::size_t count,
  std::size_t bins, int floatsPerCell)
{
  if (rows.size() != count)
  {
    std::vector<std::vector<float>>(count).swap(rows);
    ++this->Allocations;
  }
  if (count == 0)
  {
    return;
  }
  // The padding rows are never splatted: their zero column alone (the splat writes the others),
  // set when the rows or the bins change.
  for (const std::size_t r : { std::size_t(0), count - 1 })
  {
    if (rows[r].size() != bins * floatsPerCell)
    {
      rows[r].assign(bins * floatsPerCell, 0.f);
    }
  }
}

//------------------------------------------------------------------------------
std::size_t BilateralGridCpu::SumOverRows(bool capacity) const
{
  std::size_t sum = 0;
  auto add = [&](const std::vector<std::vector<float>>& rows)
  {
    for (const auto& row : rows)
    {
      sum += capacity ? row.capacity() : row.size();
    }
  };
  for (const auto& level : this->RowCells)
  {
    add(level);
  }
  add(this->RowAlpha);
  return sum;
}

//------------------------------------------------------------------------------
std::size_t BilateralGridCpu::GetCellBytes() const
{
  return this->SumOverRows(false) * sizeof(float);
}

//------------------------------------------------------------------------------
void BilateralGridCpu::Prepare(
  const BilateralGridSettings& settings, int levels, int width, int height, int blocks, bool alpha)
{
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  this->Fit(this->RowPixels, 4 * static_cast<std::size_t>(width) * blocks);
  this->Fit(this->RowLuminance, static_cast<std::size_t>(height));
  this->Fit(this->RowLit, static_cast<std::size_t>(height));
  std::size_t scratchColumns = 0;
  std::size_t scratchFloats = 0;
  for (int l = 0; l < kMaxGridLevels; ++l)
  {
    PushGrid& g = this->Levels[l];
    if (l >= levels)
    {
      std::vector<std::vector<float>>().swap(this->RowCells[l]);
      this->Fit(this->Start[l], 0);
      g = PushGrid{};
      continue;
    }
    const GridLevel geometry = LevelGeometry(settings, l, width, height);
    const bool same = g.RowCells && g.Geometry.Width == geometry.Width &&
      g.Geometry.Height == geometry.Height && g.Geometry.Depth == geometry.Depth &&
      g.Geometry.SpatialStep == geometry.SpatialStep &&
      this->ColumnIndex[l].size() == static_cast<std::size_t>(width) &&
      this->RowIndex[l].size() == static_cast<std::size_t>(height);
    g.Geometry = geometry;
    g.Columns = geometry.Width + 2;
    g.Bins = geometry.Depth + 1;
    const std::size_t rows = static_cast<std::size_t>(geometry.Height + 2);
    const std::size_t bins = static_cast<std::size_t>(g.Bins);
    this->FitRows(this->RowCells[l], rows, bins, 4);
    g.RowCells = this->RowCells[l].data();
    // The padding rows' columns read their zero column; the splat writes the other rows'.
    this->Fit(this->Start[l], rows * g.Columns);
    g.Start = this->Start[l].data();
    g.RowAlpha = nullptr;
    if (l == 0 && alpha)
    {
      this->FitRows(this->RowAlpha, rows, bins, 1);
      g.RowAlpha = this->RowAlpha.data();
    }
    this->Fit(this->ColumnIndex[l], static_cast<std::size_t>(width));
    this->Fit(this->ColumnTents[l], 2 * static_cast<std::size_t>(width));
    this->Fit(this->RowIndex[l], static_cast<std::size_t>(height));
    this->Fit(this->RowTents[l], 2 * static_cast<std::size_t>(height));
    if (!same)
    {
      AxisTables(width, geometry.SpatialStep, this->ColumnIndex[l].data(),
        this->ColumnTents[l].data(), this->ColumnTents[l].data() + width);
      AxisTables(height, geometry.SpatialStep, this->RowIndex[l].data(),
        this->RowTents[l].data(), this->RowTents[l].data() + height);
    }
    g.I0 = this->ColumnIndex[l].data();
    g.Tx0 = this->ColumnTents[l].data();
    g.Tx1 = g.Tx0 + width;
    g.J0 = this->RowIndex[l].data();
    g.Ty0 = this->RowTents[l].data();
    g.Ty1 = g.Ty0 + height;
    scratchColumns = std::max(scratchColumns, static_cast<std::size_t>(g.Columns));
    scratchFloats = std::max(scratchFloats, static_cast<std::size_t>(g.Columns) * g.Bins * 4);
  }
  if (alpha)
  {
    this->Fit(this->Alpha, pixels);
  }
  else
  {
    std::vector<std::vector<float>>().swap(this->RowAlpha);
  }
  if (blocks != this->Blocks || scratchColumns != this->ScratchColumns ||
    scratchFloats != this->ScratchFloats)
  {
    this->AlphaScratch.clear(); // allocated on the first frame with an opacity
    this->Blocks = blocks;
    this->ScratchColumns = scratchColumns;
    this->ScratchFloats = scratchFloats;
    this->Scratch.clear();
    this->Fit(this->Scratch, 2 * scratchFloats * blocks);
    this->ScratchRanges.clear();
    this->Fit(this->ScratchRanges, 4 * scratchColumns * blocks);
    // KMin: nothing touched; then KMax. Per block: row 0's KMin, KMax, row 1's KMin, KMax.
    for (std::size_t r = 0; r < 2 * static_cast<std::size_t>(blocks); ++r)
    {
      int* ranges = this->ScratchRanges.data() + 2 * scratchColumns * r;
      std::fill(ranges, ranges + scratchColumns, INT_MAX);
      std::fill(ranges + scratchColumns, ranges + 2 * scratchColumns, -1);
    }
  }
  if (alpha)
  {
    this->Fit(this->AlphaScratch, 2 * (scratchFloats / 4) * blocks); // zero, kept zero by the splat
  }
}

//------------------------------------------------------------------------------
void BilateralGridCpu::Apply(const BilateralGridSettings& settings, int width, int height,
  const float* radiance, const float* albedo, const float* guides, const float* weights,
  float* out, const float* alphaIn, float* alphaOut)
{
  const bool alpha = alphaIn && alphaOut;
  const int levels = ClampedLevels(settings);
  const bool portable = UsePortableKernels(settings.Portable);
  this->KernelTarget = GridKernelTarget(portable);

  // The splat's blocks of grid rows: one per thread, each with its own scratch row.
  this->Prepare(settings, levels, width, height, ResolvedThreads(settings.Threads), alpha);
  float* sanitisedAlpha = alpha ? this->Alpha.data() : nullptr;

  double* rowLuminance = this->RowLuminance.data();
  std::size_t* rowLit = this->RowLit.data();
  PushGrid* grid = this->Levels;
  const int blocks = this->Blocks;

  // Phase 1: row sums of the sanitised, demodulated luminance (the splat demodulates each
  // pixel row again as it pushes it: no image of demodulated pixels is kept).
  auto start = std::chrono::steady_clock::now();
  ParallelFor(settings.Threads, 0, blocks, 1,
    [&](vtkIdType blockBegin, vtkIdType blockEnd)
    {
      const vtkIdType b = blockBegin; // a task's blocks, one after another, share a row
      float* pixels = this->RowPixels.data() + 4 * static_cast<std::size_t>(width) * b;
      const vtkIdType rowBegin = static_cast<vtkIdType>(height) * b / blocks;
      const vtkIdType rowEnd = static_cast<vtkIdType>(height) * blockEnd / blocks;
      for (vtkIdType y = rowBegin; y < rowEnd; ++y)
      {
        const std::size_t p = static_cast<std::size_t>(y) * width;
        const DemodulatedRow row = DemodulateRow(radiance + 3 * p,
          albedo ? albedo + 3 * p : nullptr, static_cast<std::size_t>(width), pixels, portable);
        rowLuminance[y] = row.Luminance;
        rowLit[y] = row.Lit;
        for (std::size_t x = 0; alpha && x < static_cast<std::size_t>(width); ++x)
        {
          sanitisedAlpha[p + x] = SanitizeRadiance(alphaIn[p + x]);
        }
      }
    });
  double total = 0.0;
  std::size_t litPixels = 0;
  for (int y = 0; y < height; ++y)
  {
    total += rowLuminance[y];
    litPixels += rowLit[y];
  }
  const double mean = litPixels > 0 ? total / static_cast<double>(litPixels) : 0.0;
  const float limit = OutlierLimit(mean, settings.Clamp);
  this->Timings.Demodulate = MillisecondsSince(start);

  // Phase 2: push splat, every level; block b owns a fixed range of each level's grid rows.
  start = std::chrono::steady_clock::now();
  const std::size_t capacity = this->SumOverRows(true);
  ParallelFor(settings.Threads, 0, blocks, 1,
    [&](vtkIdType blockBegin, vtkIdType blockEnd)
    {
      for (vtkIdType b = blockBegin; b < blockEnd; ++b)
      {
        SplatScratch scratch;
        for (int r = 0; r < 2; ++r)
        {
          scratch.Cells[r] = this->Scratch.data() + this->ScratchFloats * (2 * b + r);
          scratch.KMin[r] = this->ScratchRanges.data() + 2 * this->ScratchColumns * (2 * b + r);
          scratch.KMax[r] = scratch.KMin[r] + this->ScratchColumns;
          scratch.Alpha[r] = alpha
            ? this->AlphaScratch.data() + this->ScratchFloats / 4 * (2 * b + r)
            : nullptr;
        }
        scratch.Row = this->RowPixels.data() + 4 * static_cast<std::size_t>(width) * b;
        for (int l = 0; l < levels; ++l)
        {
          const int rows = grid[l].Geometry.Height;
          SplatInput in;
          in.Radiance = radiance;
          in.Albedo = albedo;
          in.Portable = portable;
          in.Guides = guides;
          in.GuideStride = levels;
          in.GuideOffset = l;
          in.Width = width;
          in.Height = height;
          in.Limit = limit > 0.f ? limit : std::numeric_limits<float>::infinity();
          in.Alpha = l == 0 ? sanitisedAlpha : nullptr;
          const int jBegin = static_cast<int>(rows * b / blocks);
          const int jEnd = static_cast<int>(rows * (b + 1) / blocks);
          SplatGridRows(in, grid[l], scratch, jBegin, jEnd, portable);
        }
      }
    });
  if (this->SumOverRows(true) != capacity) // some rows needed more cells than they had
  {
    ++this->Allocations;
  }
  this->Timings.Splat = MillisecondsSince(start);

  // Phase 3: slice every level, blend, re-modulate; parallel over image rows.
  start = std::chrono::steady_clock::now();
  SliceInput in;
  in.Levels = grid;
  in.NumberOfLevels = levels;
  in.Guides = guides;
  in.Weights = levels > 1 ? weights : nullptr;
  in.Albedo = albedo;
  in.Out = out;
  in.Width = width;
  in.AlphaOut = alpha ? alphaOut : nullptr;
  ParallelFor(settings.Threads, 0, height, 8,
    [&](vtkIdType rowBegin, vtkIdType rowEnd)
    { SliceRows(in, static_cast<int>(rowBegin), static_cast<int>(rowEnd), portable); });
  this->Timings.Slice = MillisecondsSince(start);
}
}
