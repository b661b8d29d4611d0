// The CPU bilateral grid's row kernels (ptvBilateralGridRows.h), compiled once per instruction
// set by Google Highway (foreach_target.h re-includes this file per target) and dispatched at run
// time: one binary for every x86-64, AVX-512/AVX2 with FMA where the CPU has them. Cells are
// 4 floats (r, g, b, w), so one 128-bit multiply-add updates a cell (the baseline target, HWY_SCALAR
// with Debian's GCC 12, loops over the 4 lanes); the per-pixel index and tent arithmetic is the
// scalar code of Kernels/ptvBilateralGrid.h.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "ptvBilateralGridRows.cxx"
#include "hwy/foreach_target.h" // must come before highway.h

#include "hwy/highway.h"

#include "ptvBilateralGridRows.h"

#include <algorithm>
#include <climits>
#include <cstdint>
#include <limits>

HWY_BEFORE_NAMESPACE();
namespace ptv
{
namespace HWY_NAMESPACE
{
namespace hn = hwy::HWY_NAMESPACE;
using D4 = hn::CappedTag<float, 4>; // 4 lanes, 1 on HWY_SCALAR

/// fn(offset) for each vector of a 4-float cell (one call on 128-bit and wider targets).
template <class Fn>
HWY_INLINE void ForCell(const Fn& fn)
{
  const D4 d;
  for (std::size_t o = 0; o < 4; o += hn::Lanes(d))
  {
    fn(o);
  }
}

// AVX2 and AVX-512: two range bins (8 floats, contiguous) per operation. Elsewhere one cell.
// (This file is compiled once per target: the macro is redefined for each.)
#undef PTV_GRID_WIDE
#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX2
#define PTV_GRID_WIDE 1
using D8 = hn::FixedTag<float, 8>;
using DH = hn::Half<D8>;

/// (a, a, a, a, b, b, b, b): the tent weights of bins k0 and k0 + 1, one per half.
HWY_INLINE hn::Vec<D8> Pair(float a, float b)
{
  const D8 d8;
  const DH dh;
  return hn::Combine(d8, hn::Set(dh, b), hn::Set(dh, a));
}
#else
#define PTV_GRID_WIDE 0
#endif

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

void SplatGridRowsKernel(
  const SplatInput& in, PushGrid& g, SplatScratch& s, int jBegin, int jEnd)
{
  const D4 d;
  const GridLevel& geo = g.Geometry;
  const int bins = g.Bins;
  const std::size_t columnFloats = static_cast<std::size_t>(bins) * 4;
  const std::size_t rowFloats = static_cast<std::size_t>(g.Columns) * columnFloats;
  const float inf = std::numeric_limits<float>::infinity();
  HWY_ALIGN const float limit[4] = { in.Limit, in.Limit, in.Limit, inf }; // weight lane: never
  const std::size_t stride = static_cast<std::size_t>(in.GuideStride);
  for (int j = jBegin; j < jEnd; ++j)
  {
    int y0, y1;
    SplatSupport(j, geo.SpatialStep, in.Height, y0, y1);
    for (int y = y0; y <= y1; ++y)
    {
      // Tent(v_y - j): the row table holds it for j0 = J0[y] and j0 + 1.
      const float ty = g.J0[y] == j ? g.Ty0[y] : (g.J0[y] + 1 == j ? g.Ty1[y] : 0.f);
      if (!(ty > 0.f))
      {
        continue;
      }
      const std::size_t row = static_cast<std::size_t>(y) * in.Width;
      const float* demod = in.Demodulated4 + 4 * row;
      const float* guide = in.Guides + row * stride + in.GuideOffset;
#if PTV_GRID_WIDE
      // Consecutive pixels that push into the same two cell pairs (same i0 and k0: up to ss of
      // them along x where the guide is smooth) are summed in registers and added once, which
      // breaks the store-to-load chain through memory.
      const D8 d8;
      const DH dh;
      int runColumn = -1;
      int runBin = 0;
      auto acc0 = hn::Zero(d8);
      auto acc1 = hn::Zero(d8);
      const auto flush = [&]()
      {
        if (runColumn < 0)
        {
          return;
        }
        float* cell = s.Cells + static_cast<std::size_t>(runColumn) * columnFloats + 4 * runBin;
        hn::StoreU(hn::Add(hn::LoadU(d8, cell), acc0), d8, cell);
        cell += columnFloats;
        hn::StoreU(hn::Add(hn::LoadU(d8, cell), acc1), d8, cell);
        for (int c = runColumn; c <= runColumn + 1; ++c)
        {
          s.KMin[c] = runBin < s.KMin[c] ? runBin : s.KMin[c];
          s.KMax[c] = runBin + 1 > s.KMax[c] ? runBin + 1 : s.KMax[c];
        }
      };
      for (int x = 0; x < in.Width; ++x)
      {
        const float z = GuideToGrid(guide[x * stride], geo.RangeStep);
        const int k0 = FloorToInt(z);
        const int c0 = g.I0[x] + 1;
        if (c0 != runColumn || k0 != runBin)
        {
          flush();
          runColumn = c0;
          runBin = k0;
          acc0 = hn::Zero(d8);
          acc1 = hn::Zero(d8);
        }
        const auto tz = Pair(Tent(z - static_cast<float>(k0)), Tent(z - static_cast<float>(k0 + 1)));
        const auto v4 = hn::Min(hn::LoadU(dh, demod + 4 * x), hn::Load(dh, limit));
        const auto value = hn::Combine(d8, v4, v4);
        // (tx * ty) * tz, as the definition
        acc0 = hn::MulAdd(hn::Mul(hn::Set(d8, g.Tx0[x] * ty), tz), value, acc0);
        acc1 = hn::MulAdd(hn::Mul(hn::Set(d8, g.Tx1[x] * ty), tz), value, acc1);
      }
      flush();
#else
      for (int x = 0; x < in.Width; ++x)
      {
        const float z = GuideToGrid(guide[x * stride], geo.RangeStep);
        const int k0 = FloorToInt(z);
        const float tz0 = Tent(z - static_cast<float>(k0));
        const float tz1 = Tent(z - static_cast<float>(k0 + 1));
        const int c0 = g.I0[x] + 1;
        const float w0 = g.Tx0[x] * ty; // (tx * ty) * tz, as the definition
        const float w1 = g.Tx1[x] * ty;
        float* cell = s.Cells + static_cast<std::size_t>(c0) * columnFloats + 4 * k0;
        HWY_ALIGN float value[4];
        ForCell([&](std::size_t o)
          { hn::Store(hn::Min(hn::LoadU(d, demod + 4 * x + o), hn::Load(d, limit + o)), d,
              value + o); });
        Push(cell, w0 * tz0, value);
        Push(cell + 4, w0 * tz1, value);
        Push(cell + columnFloats, w1 * tz0, value);
        Push(cell + columnFloats + 4, w1 * tz1, value);
        for (int c = c0; c <= c0 + 1; ++c)
        {
          s.KMin[c] = k0 < s.KMin[c] ? k0 : s.KMin[c];
          s.KMax[c] = k0 + 1 > s.KMax[c] ? k0 + 1 : s.KMax[c];
        }
      }
#endif
    }
    // Normalise the touched cells of the grid's own columns into the level (the padding columns
    // and bin stay zero there) and zero the scratch again.
    float* target = g.Cells + static_cast<std::size_t>(j + 1) * rowFloats;
    for (int c = 0; c < g.Columns; ++c)
    {
      const int kLo = s.KMin[c];
      const int kHi = s.KMax[c];
      if (kLo > kHi)
      {
        continue;
      }
      float* scratch = s.Cells + static_cast<std::size_t>(c) * columnFloats;
      const bool inside = c >= 1 && c <= geo.Width;
      const int kLast = kHi < geo.Depth - 1 ? kHi : geo.Depth - 1;
      for (int k = kLo; inside && k <= kLast; ++k)
      {
        const float w = scratch[4 * k + 3];
        float* cell = target + static_cast<std::size_t>(c) * columnFloats + 4 * k;
        // A kept cell becomes (r, g, b, w) / w = (mean, 1); an empty one (0, 0, 0, 0).
        ForCell([&](std::size_t o)
          { hn::StoreU(w > 0.f ? hn::Div(hn::LoadU(d, scratch + 4 * k + o), hn::Set(d, w))
                                : hn::Zero(d), d, cell + o); });
      }
      std::fill(scratch + 4 * kLo, scratch + 4 * (kHi + 1), 0.f);
      s.KMin[c] = INT_MAX;
      s.KMax[c] = -1;
    }
  }
}

void SliceRowsKernel(const SliceInput& in, int yBegin, int yEnd)
{
  const D4 d;
  const int levels = in.NumberOfLevels;
  for (int y = yBegin; y < yEnd; ++y)
  {
    const float* rows[kMaxGridLevels][2] = {};
    float ty0[kMaxGridLevels] = {};
    float ty1[kMaxGridLevels] = {};
    for (int l = 0; l < levels; ++l)
    {
      const PushGrid& g = in.Levels[l];
      const std::size_t rowFloats = static_cast<std::size_t>(g.Columns) * g.Bins * 4;
      rows[l][0] = g.Cells + static_cast<std::size_t>(g.J0[y] + 1) * rowFloats;
      rows[l][1] = rows[l][0] + rowFloats;
      ty0[l] = g.Ty0[y];
      ty1[l] = g.Ty1[y];
    }
    const std::size_t row = static_cast<std::size_t>(y) * in.Width;
    for (int x = 0; x < in.Width; ++x)
    {
      const std::size_t p = row + x;
      Vec3 s[kMaxGridLevels] = { MakeVec3(0.f, 0.f, 0.f), MakeVec3(0.f, 0.f, 0.f),
        MakeVec3(0.f, 0.f, 0.f) };
      for (int l = 0; l < levels; ++l)
      {
        const PushGrid& g = in.Levels[l];
        const std::size_t columnFloats = static_cast<std::size_t>(g.Bins) * 4;
        const float z = GuideToGrid(in.Guides[p * levels + l], g.Geometry.RangeStep);
        const int k0 = FloorToInt(z);
        const float tz0 = Tent(z - static_cast<float>(k0));
        const float tz1 = Tent(z - static_cast<float>(k0 + 1));
        const std::size_t offset =
          static_cast<std::size_t>(g.I0[x] + 1) * columnFloats + 4 * static_cast<std::size_t>(k0);
        const float* c00 = rows[l][0] + offset; // (j0, i0)
        const float* c01 = rows[l][1] + offset; // (j0 + 1, i0)
        const float w00 = g.Tx0[x] * ty0[l];
        const float w10 = g.Tx1[x] * ty0[l];
        const float w01 = g.Tx0[x] * ty1[l];
        const float w11 = g.Tx1[x] * ty1[l];
        const float* c10 = c00 + columnFloats;  // (j0, i0 + 1)
        const float* c11 = c01 + columnFloats;  // (j0 + 1, i0 + 1)
        HWY_ALIGN float sum[4];
#if PTV_GRID_WIDE
        const D8 d8;
        const DH dh;
        const auto tz = Pair(tz0, tz1);
        // Two independent sums (grid rows j0 and j0 + 1) halve the dependency chain.
        auto upper = hn::Mul(hn::Mul(hn::Set(d8, w00), tz), hn::LoadU(d8, c00));
        auto lower = hn::Mul(hn::Mul(hn::Set(d8, w01), tz), hn::LoadU(d8, c01));
        upper = hn::MulAdd(hn::Mul(hn::Set(d8, w10), tz), hn::LoadU(d8, c10), upper);
        lower = hn::MulAdd(hn::Mul(hn::Set(d8, w11), tz), hn::LoadU(d8, c11), lower);
        const auto acc = hn::Add(upper, lower);
        const auto total = hn::Add(hn::LowerHalf(dh, acc), hn::UpperHalf(dh, acc));
        hn::Store(hn::Div(total, hn::Broadcast<3>(total)), dh, sum); // (mean r, g, b, 1)
        if (hn::GetLane(hn::Broadcast<3>(total)) > 0.f) // the kept weights; 0: all dropped
        {
          s[l] = MakeVec3(sum[0], sum[1], sum[2]);
        }
#else
        ForCell(
          [&](std::size_t o)
          {
            auto acc = hn::Mul(hn::Set(d, w00 * tz0), hn::LoadU(d, c00 + o));
            acc = hn::MulAdd(hn::Set(d, w00 * tz1), hn::LoadU(d, c00 + 4 + o), acc);
            acc = hn::MulAdd(hn::Set(d, w10 * tz0), hn::LoadU(d, c10 + o), acc);
            acc = hn::MulAdd(hn::Set(d, w10 * tz1), hn::LoadU(d, c10 + 4 + o), acc);
            acc = hn::MulAdd(hn::Set(d, w01 * tz0), hn::LoadU(d, c01 + o), acc);
            acc = hn::MulAdd(hn::Set(d, w01 * tz1), hn::LoadU(d, c01 + 4 + o), acc);
            acc = hn::MulAdd(hn::Set(d, w11 * tz0), hn::LoadU(d, c11 + o), acc);
            acc = hn::MulAdd(hn::Set(d, w11 * tz1), hn::LoadU(d, c11 + 4 + o), acc);
            hn::Store(acc, d, sum + o);
          });
        if (sum[3] > 0.f) // the kept weights; 0 when every tap was dropped
        {
          s[l] = MakeVec3(sum[0] / sum[3], sum[1] / sum[3], sum[2] / sum[3]);
        }
#endif
      }
      const float* w = in.Weights ? in.Weights + p * (levels - 1) : nullptr;
      const float w1 = levels >= 2 && w ? w[0] : 0.f;
      const float w2 = levels >= 3 && w ? w[1] : 0.f;
      const Vec3 r =
        Remodulate(Blend(s[0], s[1], s[2], levels, w1, w2), in.Albedo ? in.Albedo + 3 * p : nullptr);
      in.Out[3 * p + 0] = r.x;
      in.Out[3 * p + 1] = r.y;
      in.Out[3 * p + 2] = r.z;
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
HWY_EXPORT(SliceRowsKernel);

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

void SliceRows(const SliceInput& in, int yBegin, int yEnd, bool portable)
{
  if (portable)
  {
    HWY_STATIC_DISPATCH(SliceRowsKernel)(in, yBegin, yEnd);
  }
  else
  {
    HWY_DYNAMIC_DISPATCH(SliceRowsKernel)(in, yBegin, yEnd);
  }
}

const char* GridKernelTarget(bool portable)
{
  const int64_t target =
    portable ? HWY_STATIC_DISPATCH(KernelTarget)() : HWY_DYNAMIC_DISPATCH(KernelTarget)();
  return hwy::TargetName(target);
}
}
#endif
