// The CPU bilateral grid's splat rows (ptvBilateralGridRows.h), compiled once per instruction set
// by Google Highway (foreach_target.h re-includes this file per target) and dispatched at run time:
// one binary for every x86-64, AVX-512/AVX2 with FMA where the CPU has them. Cells are 4 floats
// (r, g, b, w), so one 128-bit multiply-add updates a cell (the baseline target, HWY_SCALAR with
// Debian's GCC 12, loops over the 4 lanes); on AVX2 / AVX-512 two range bins per operation. The
// per-pixel index and tent arithmetic is the scalar code of Kernels/ptvBilateralGrid.h.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "ptvBilateralGridSplat.cxx"
#include "hwy/foreach_target.h" // must come before highway.h

#include "hwy/highway.h"

#include "ptvBilateralGridLanes-inl.h"
#include "ptvBilateralGridRows.h"
#include "ptvGridDemodulateRows.h"

#include <algorithm>
#include <climits>
#include <cstdint>
#include <limits>
#include <vector>

HWY_BEFORE_NAMESPACE();
namespace ptv
{
namespace HWY_NAMESPACE
{

/// cell[0..3] += w * value[0..3]
HWY_INLINE void Push(float* HWY_RESTRICT cell, float w, const float* HWY_RESTRICT value)
{
  const D4 d;
  ForCell([&](std::size_t o)
    { hn::StoreU(hn::MulAdd(hn::Set(d, w), hn::Load(d, value + o), hn::LoadU(d, cell + o)), d,
        cell + o); });
}

int64_t KernelTarget()
{
  return HWY_TARGET;
}

/// One grid row's scratch as a pixel row pushes into it.
struct RowTarget
{
  float* Cells;
  int* KMin;
  int* KMax;
  float Ty;     ///< the pixel row's tent weight for this grid row
  float* Alpha; ///< the row's opacity scratch (Columns * Bins), or null
};

/// Adds (c0 k0, c0 k0+1, c0+1 k0, c0+1 k0+1) @a add to grid row @a t's opacity scratch.
HWY_INLINE void AddAlpha(const RowTarget& t, int bins, int c0, int k0, const float* add)
{
  float* a = t.Alpha + static_cast<std::size_t>(c0) * bins + k0;
  a[0] += add[0];
  a[1] += add[1];
  a[bins] += add[2];
  a[bins + 1] += add[3];
}

/// Marks bins k0, k0 + 1 of columns c0, c0 + 1 touched.
HWY_INLINE void Touch(const RowTarget& t, int c0, int k0)
{
  for (int c = c0; c <= c0 + 1; ++c)
  {
    t.KMin[c] = k0 < t.KMin[c] ? k0 : t.KMin[c];
    t.KMax[c] = k0 + 1 > t.KMax[c] ? k0 + 1 : t.KMax[c];
  }
}

/**
 * Pushes pixel row @a y into grid row j0 (@a upper, weight Ty0) and / or j0 + 1 (@a lower, Ty1),
 * reading each pixel once. Every push is w * value with w = (tx * ty) * tz, as the definition.
 */
template <bool kUpper, bool kLower>
HWY_INLINE void PushPixelRow(const SplatInput& in, const PushGrid& g, std::size_t columnFloats,
  const float* HWY_RESTRICT limit, int y, const float* HWY_RESTRICT demod, const RowTarget& upper,
  const RowTarget& lower)
{
  const std::size_t row = static_cast<std::size_t>(y) * in.Width;
  const std::size_t stride = static_cast<std::size_t>(in.GuideStride);
  const float* guide = in.Guides + row * stride + in.GuideOffset;
  const int rangeStep = g.Geometry.RangeStep;
#if PTV_GRID_WIDE
  // Consecutive pixels that push into the same cell pairs (same i0 and k0: up to ss of them
  // along x where the guide is smooth) are summed in registers and added once, which breaks the
  // store-to-load chain through memory.
  const D8 d8;
  const DH dh;
  int runColumn = -1;
  int runBin = 0;
  auto up0 = hn::Zero(d8);
  auto up1 = hn::Zero(d8);
  auto lo0 = hn::Zero(d8);
  auto lo1 = hn::Zero(d8);
  // The opacity's sums of the run: (c0 k0, c0 k0+1, c0+1 k0, c0+1 k0+1) per grid row.
  const float* alpha = in.Alpha ? in.Alpha + row : nullptr;
  const int bins = g.Bins;
  float upA[4] = { 0.f, 0.f, 0.f, 0.f };
  float loA[4] = { 0.f, 0.f, 0.f, 0.f };
  const auto add = [&](const RowTarget& t, hn::Vec<D8> acc0, hn::Vec<D8> acc1, const float* accA)
  {
    float* cell = t.Cells + static_cast<std::size_t>(runColumn) * columnFloats + 4 * runBin;
    hn::StoreU(hn::Add(hn::LoadU(d8, cell), acc0), d8, cell);
    cell += columnFloats;
    hn::StoreU(hn::Add(hn::LoadU(d8, cell), acc1), d8, cell);
    Touch(t, runColumn, runBin);
    if (alpha)
    {
      AddAlpha(t, bins, runColumn, runBin, accA);
    }
  };
  const auto flush = [&]()
  {
    if (runColumn < 0)
    {
      return;
    }
    if (kUpper)
    {
      add(upper, up0, up1, upA);
    }
    if (kLower)
    {
      add(lower, lo0, lo1, loA);
    }
  };
  for (int x = 0; x < in.Width; ++x)
  {
    const float z = GuideToGrid(guide[x * stride], rangeStep);
    const int k0 = FloorToInt(z);
    const int c0 = g.I0[x] + 1;
    if (c0 != runColumn || k0 != runBin)
    {
      flush();
      runColumn = c0;
      runBin = k0;
      up0 = hn::Zero(d8);
      up1 = hn::Zero(d8);
      lo0 = hn::Zero(d8);
      lo1 = hn::Zero(d8);
      std::fill(upA, upA + 4, 0.f);
      std::fill(loA, loA + 4, 0.f);
    }
    const float tz0 = Tent(z - static_cast<float>(k0));
    const float tz1 = Tent(z - static_cast<float>(k0 + 1));
    const auto tz = Pair(tz0, tz1);
    const auto v4 = hn::Min(hn::LoadU(dh, demod + 4 * x), hn::Load(dh, limit));
    const auto value = hn::Combine(d8, v4, v4);
    // The opacity's four taps, each tap's weight computed as the colour's lanes are (scalar
    // sums: a vector built from four stores would stall on store forwarding).
    const auto pushAlpha = [&](float ty, float* acc)
    {
      const float a = alpha[x];
      const float w0 = g.Tx0[x] * ty;
      const float w1 = g.Tx1[x] * ty;
      acc[0] += (w0 * tz0) * a;
      acc[1] += (w0 * tz1) * a;
      acc[2] += (w1 * tz0) * a;
      acc[3] += (w1 * tz1) * a;
    };
    if (kUpper)
    {
      up0 = hn::MulAdd(hn::Mul(hn::Set(d8, g.Tx0[x] * upper.Ty), tz), value, up0);
      up1 = hn::MulAdd(hn::Mul(hn::Set(d8, g.Tx1[x] * upper.Ty), tz), value, up1);
      if (alpha)
      {
        pushAlpha(upper.Ty, upA);
      }
    }
    if (kLower)
    {
      lo0 = hn::MulAdd(hn::Mul(hn::Set(d8, g.Tx0[x] * lower.Ty), tz), value, lo0);
      lo1 = hn::MulAdd(hn::Mul(hn::Set(d8, g.Tx1[x] * lower.Ty), tz), value, lo1);
      if (alpha)
      {
        pushAlpha(lower.Ty, loA);
      }
    }
  }
  flush();
#else
  const D4 d;
  const float* alpha = in.Alpha ? in.Alpha + row : nullptr;
  const auto push = [&](const RowTarget& t, int c0, int k0, float tx0, float tx1, float tz0,
                      float tz1, const float* value, int x)
  {
    float* cell = t.Cells + static_cast<std::size_t>(c0) * columnFloats + 4 * k0;
    const float w0 = tx0 * t.Ty;
    const float w1 = tx1 * t.Ty;
    Push(cell, w0 * tz0, value);
    Push(cell + 4, w0 * tz1, value);
    Push(cell + columnFloats, w1 * tz0, value);
    Push(cell + columnFloats + 4, w1 * tz1, value);
    Touch(t, c0, k0);
    if (alpha)
    {
      const float a = alpha[x];
      const float add[4] = { w0 * tz0 * a, w0 * tz1 * a, w1 * tz0 * a, w1 * tz1 * a };
      AddAlpha(t, g.Bins, c0, k0, add);
    }
  };
  for (int x = 0; x < in.Width; ++x)
  {
    const float z = GuideToGrid(guide[x * stride], rangeStep);
    const int k0 = FloorToInt(z);
    const float tz0 = Tent(z - static_cast<float>(k0));
    const float tz1 = Tent(z - static_cast<float>(k0 + 1));
    const int c0 = g.I0[x] + 1;
    HWY_ALIGN float value[4];
    ForCell([&](std::size_t o)
      { hn::Store(hn::Min(hn::LoadU(d, demod + 4 * x + o), hn::Load(d, limit + o)), d,
          value + o); });
    if (kUpper)
    {
      push(upper, c0, k0, g.Tx0[x], g.Tx1[x], tz0, tz1, value, x);
    }
    if (kLower)
    {
      push(lower, c0, k0, g.Tx0[x], g.Tx1[x], tz0, tz1, value, x);
    }
  }
#endif
}

void SplatGridRowsKernel(
  const SplatInput& in, PushGrid& g, SplatScratch& s, int jBegin, int jEnd)
{
  const D4 d;
  const GridLevel& geo = g.Geometry;
  const std::size_t columnFloats = static_cast<std::size_t>(g.Bins) * 4;
  const float inf = std::numeric_limits<float>::infinity();
  HWY_ALIGN const float limit[4] = { in.Limit, in.Limit, in.Limit, inf }; // weight lane: never
  const bool withAlpha = in.Alpha && g.RowAlpha;
  const auto target = [&](int j, float ty)
  {
    return RowTarget{ s.Cells[j & 1], s.KMin[j & 1], s.KMax[j & 1], ty,
      withAlpha ? s.Alpha[j & 1] : nullptr };
  };
  SplatInput input = in;
  input.Alpha = withAlpha ? in.Alpha : nullptr;
  // The pixel rows with J0 = j0 push into grid rows j0 and j0 + 1 (J0 never decreases with y).
  int y = static_cast<int>(std::lower_bound(g.J0, g.J0 + in.Height, jBegin - 1) - g.J0);
  for (int j0 = jBegin - 1; j0 < jEnd; ++j0)
  {
    const bool ownUpper = j0 >= jBegin;
    const bool ownLower = j0 + 1 < jEnd;
    for (; y < in.Height && g.J0[y] == j0; ++y)
    {
      const RowTarget upper = target(j0, g.Ty0[y]);
      const RowTarget lower = target(j0 + 1, g.Ty1[y]);
      const bool u = ownUpper && upper.Ty > 0.f;
      const bool l = ownLower && lower.Ty > 0.f;
      if (u || l)
      {
        const std::size_t p = static_cast<std::size_t>(y) * in.Width;
        DemodulateRow(in.Radiance + 3 * p, in.Albedo ? in.Albedo + 3 * p : nullptr,
          static_cast<std::size_t>(in.Width), s.Row, in.Portable);
      }
      if (u && l)
      {
        PushPixelRow<true, true>(input, g, columnFloats, limit, y, s.Row, upper, lower);
      }
      else if (u)
      {
        PushPixelRow<true, false>(input, g, columnFloats, limit, y, s.Row, upper, lower);
      }
      else if (l)
      {
        PushPixelRow<false, true>(input, g, columnFloats, limit, y, s.Row, upper, lower);
      }
    }
    if (!ownUpper)
    {
      continue;
    }
    // Grid row j0 has all its pixels: its touched cells, normalised, become its row of the
    // level (a zero column first, for the padding and untouched columns; the padding bin of a
    // touched column stays zero), and its scratch is zeroed again.
    const RowTarget done = target(j0, 0.f);
    const std::size_t r = static_cast<std::size_t>(j0 + 1);
    int* start = g.Start + r * g.Columns;
    int kept = g.Bins; // cells of the row: the zero column, then the touched bins
    for (int c = 0; c < g.Columns; ++c)
    {
      const bool inside = c >= 1 && c <= geo.Width && done.KMin[c] <= done.KMax[c];
      start[c] = inside ? kept - done.KMin[c] : 0;
      kept += inside ? done.KMax[c] - done.KMin[c] + 1 : 0;
    }
    std::vector<float>& cells = g.RowCells[r];
    std::vector<float>* alphaRow = withAlpha ? &g.RowAlpha[r] : nullptr;
    const std::size_t size = static_cast<std::size_t>(kept);
    if (4 * size > cells.capacity()) // a little room, so that the next frames seldom grow it
    {
      std::vector<float>().swap(cells);
      cells.reserve(4 * (size + size / 8));
    }
    cells.resize(4 * size);
    std::fill(cells.begin(), cells.begin() + 4 * g.Bins, 0.f);
    if (alphaRow)
    {
      if (size > alphaRow->capacity())
      {
        std::vector<float>().swap(*alphaRow);
        alphaRow->reserve(size + size / 8);
      }
      alphaRow->resize(size);
      std::fill(alphaRow->begin(), alphaRow->begin() + g.Bins, 0.f);
    }
    for (int c = 0; c < g.Columns; ++c)
    {
      const int kLo = done.KMin[c];
      const int kHi = done.KMax[c];
      if (kLo > kHi)
      {
        continue;
      }
      float* scratch = done.Cells + static_cast<std::size_t>(c) * columnFloats;
      const bool inside = c >= 1 && c <= geo.Width;
      for (int k = kLo; inside && k <= kHi; ++k)
      {
        const float w = k < geo.Depth ? scratch[4 * k + 3] : 0.f; // bin Depth: padding
        const std::size_t index = static_cast<std::size_t>(start[c] + k);
        float* cell = cells.data() + 4 * index;
        // A kept cell becomes (r, g, b, w) / w = (mean, 1); an empty one (0, 0, 0, 0).
        ForCell([&](std::size_t o)
          { hn::StoreU(w > 0.f ? hn::Div(hn::LoadU(d, scratch + 4 * k + o), hn::Set(d, w))
                                : hn::Zero(d), d, cell + o); });
        if (alphaRow)
        {
          (*alphaRow)[index] =
            w > 0.f ? done.Alpha[static_cast<std::size_t>(c) * g.Bins + k] / w : 0.f;
        }
      }
      std::fill(scratch + 4 * kLo, scratch + 4 * (kHi + 1), 0.f);
      if (withAlpha)
      {
        float* a = done.Alpha + static_cast<std::size_t>(c) * g.Bins;
        std::fill(a + kLo, a + kHi + 1, 0.f);
      }
      done.KMin[c] = INT_MAX;
      done.KMax[c] = -1;
    }
  }
}
} // namespace HWY_NAMESPACE
} // namespace ptv
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace ptv
{
HWY_EXPORT(KernelTarget);
HWY_EXPORT(SplatGridRowsKernel);

void SplatGridRows(const SplatInput& in, PushGrid& grid, SplatScratch& scratch, int jBegin,
  int jEnd, bool portable)
{
  if (portable)
  {
    HWY_STATIC_DISPATCH(SplatGridRowsKernel)(in, grid, scratch, jBegin, jEnd);
  }
  else
  {
    HWY_DYNAMIC_DISPATCH(SplatGridRowsKernel)(in, grid, scratch, jBegin, jEnd);
  }
}

const char* GridKernelTarget(bool portable)
{
  const int64_t target =
    portable ? HWY_STATIC_DISPATCH(KernelTarget)() : HWY_DYNAMIC_DISPATCH(KernelTarget)();
  return hwy::TargetName(target);
}
} // namespace ptv
#endif
