// The CPU bilateral grid's slice rows (ptvBilateralGridRows.h), compiled per instruction set as
// ptvBilateralGridSplat.cxx is. On AVX2 / AVX-512 the slice keeps each level's (r, g, b, w) in one
// vector through the blend and re-modulation, with the blend's multiply-adds in the order GCC
// contracted Blend() into before: the same bits at 1 and 2 levels; at 3 levels (the fixed guide's
// default) 2 % of the pixels differ by 1-2 ulp.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "ptvBilateralGridSlice.cxx"
#include "hwy/foreach_target.h" // must come before highway.h

#include "hwy/highway.h"

#include "ptvBilateralGridLanes-inl.h"
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

/// One image row's two grid rows of a level (j0 and j0 + 1; j0's again where the pixel row's
/// tent weight on j0 + 1 is 0) and their tent weights.
struct SliceRowPair
{
  const float* Cells[2];
  const int* Start[2];
  const float* Alpha[2]; ///< the opacity's rows, or null
  float Ty[2];
};

/// Cell (column @a c, bin @a k) of row @a row of @a p: its first float.
HWY_INLINE const float* CellAt(const SliceRowPair& p, int row, int c, int k)
{
  return p.Cells[row] + 4 * static_cast<std::size_t>(p.Start[row][c] + k);
}

/// The opacity sum of the taps the colour's slice weighs at column @a x, bin @a k0 (tents
/// @a tz0, @a tz1) of @a p; the colour's kept weight divides it (an empty cell's opacity is 0).
HWY_INLINE float SliceAlphaSum(
  const PushGrid& g, const SliceRowPair& p, int x, int k0, float tz0, float tz1)
{
  const int c = g.I0[x] + 1;
  const float* a00 = p.Alpha[0] + p.Start[0][c] + k0;
  const float* a10 = p.Alpha[0] + p.Start[0][c + 1] + k0;
  const float* a01 = p.Alpha[1] + p.Start[1][c] + k0;
  const float* a11 = p.Alpha[1] + p.Start[1][c + 1] + k0;
  const float w00 = g.Tx0[x] * p.Ty[0];
  const float w10 = g.Tx1[x] * p.Ty[0];
  const float w01 = g.Tx0[x] * p.Ty[1];
  const float w11 = g.Tx1[x] * p.Ty[1];
  const float upper = (w00 * tz0) * a00[0] + (w00 * tz1) * a00[1] + (w10 * tz0) * a10[0] +
    (w10 * tz1) * a10[1];
  const float lower = (w01 * tz0) * a01[0] + (w01 * tz1) * a01[1] + (w11 * tz0) * a11[0] +
    (w11 * tz1) * a11[1];
  return upper + lower;
}

/// Image row @a y's two grid rows per level.
HWY_INLINE void SliceGridRows(const SliceInput& in, int y, SliceRowPair* pairs)
{
  for (int l = 0; l < in.NumberOfLevels; ++l)
  {
    const PushGrid& g = in.Levels[l];
    SliceRowPair& p = pairs[l];
    p.Ty[0] = g.Ty0[y];
    p.Ty[1] = g.Ty1[y];
    // The lower row's cells weigh 0 where its tent does: the upper row's (which this pixel
    // row touched, bin for bin) stand in for them, as the lower row may not hold those bins.
    const std::size_t r[2] = { static_cast<std::size_t>(g.J0[y] + 1),
      static_cast<std::size_t>(g.J0[y] + (p.Ty[1] > 0.f ? 2 : 1)) };
    for (int i = 0; i < 2; ++i)
    {
      p.Cells[i] = g.RowCells[r[i]].data();
      p.Start[i] = g.Start + r[i] * g.Columns;
      p.Alpha[i] = l == 0 && in.AlphaOut ? g.RowAlpha[r[i]].data() : nullptr;
    }
  }
}

#if PTV_GRID_WIDE
/// One level's slice at a pixel with guide @a guide in column @a x, grid rows @a p: (mean r, g,
/// b, 1) where the taps kept weight, else zero. With @a alpha (and the opacity's rows in @a p)
/// the opacity of the same taps into @a alpha.
HWY_INLINE hn::Vec<DH> SliceLevelWide(
  const PushGrid& g, const SliceRowPair& p, int x, float guide, float* alpha = nullptr)
{
  const D8 d8;
  const DH dh;
  const float z = GuideToGrid(guide, g.Geometry.RangeStep);
  const int k0 = FloorToInt(z);
  const float tz0 = Tent(z - static_cast<float>(k0));
  const float tz1 = Tent(z - static_cast<float>(k0 + 1));
  const auto tz = Pair(tz0, tz1);
  const int c = g.I0[x] + 1;
  const float ty0 = p.Ty[0];
  const float ty1 = p.Ty[1];
  // Two independent sums (grid rows j0 and j0 + 1) halve the dependency chain.
  auto upper = hn::Mul(hn::Mul(hn::Set(d8, g.Tx0[x] * ty0), tz), hn::LoadU(d8, CellAt(p, 0, c, k0)));
  auto lower = hn::Mul(hn::Mul(hn::Set(d8, g.Tx0[x] * ty1), tz), hn::LoadU(d8, CellAt(p, 1, c, k0)));
  upper = hn::MulAdd(
    hn::Mul(hn::Set(d8, g.Tx1[x] * ty0), tz), hn::LoadU(d8, CellAt(p, 0, c + 1, k0)), upper);
  lower = hn::MulAdd(
    hn::Mul(hn::Set(d8, g.Tx1[x] * ty1), tz), hn::LoadU(d8, CellAt(p, 1, c + 1, k0)), lower);
  const auto acc = hn::Add(upper, lower);
  const auto total = hn::Add(hn::LowerHalf(dh, acc), hn::UpperHalf(dh, acc));
  const auto weight = hn::Broadcast<3>(total); // the kept weights; 0: every tap dropped
  if (alpha)
  {
    const float kept = hn::GetLane(weight);
    *alpha = kept > 0.f ? SliceAlphaSum(g, p, x, k0, tz0, tz1) / kept : 0.f;
  }
  return hn::IfThenElseZero(hn::Gt(weight, hn::Zero(dh)), hn::Div(total, weight));
}

/// SliceRowsKernel on AVX2 / AVX-512: each level's (r, g, b) and the blend stay in one vector.
void SliceRowsWide(const SliceInput& in, int yBegin, int yEnd)
{
  const DH dh;
  const int levels = in.NumberOfLevels;
  const auto epsilon = hn::Set(dh, kDemodulationEpsilon);
  const auto maxFinite = hn::Set(dh, kMaxFiniteFloat);
  const auto one = hn::Set(dh, 1.f);
  for (int y = yBegin; y < yEnd; ++y)
  {
    SliceRowPair pairs[kMaxGridLevels];
    SliceGridRows(in, y, pairs);
    const std::size_t row = static_cast<std::size_t>(y) * in.Width;
    for (int x = 0; x < in.Width; ++x)
    {
      const std::size_t p = row + x;
      const float* guides = in.Guides + p * levels;
      auto r = SliceLevelWide(
        in.Levels[0], pairs[0], x, guides[0], in.AlphaOut ? in.AlphaOut + p : nullptr);
      if (levels >= 2)
      {
        // Blend: s1 w1 + s2 (1 - w1), or s1 w1 + s2 w2 + s3 (1 - w1 - w2) (ptvBilateralGrid.h)
        const float* w = in.Weights ? in.Weights + p * (levels - 1) : nullptr;
        const float a = SanitizeBlendWeight(w ? w[0] : 0.f);
        const auto s2 = SliceLevelWide(in.Levels[1], pairs[1], x, guides[1]);
        if (levels == 2)
        {
          r = hn::MulAdd(s2, hn::Set(dh, 1.f - a), hn::Mul(r, hn::Set(dh, a)));
        }
        else
        {
          const float b = SanitizeBlendWeight(w ? w[1] : 0.f);
          const float c = (1.f - a) - b;
          const auto s3 = SliceLevelWide(in.Levels[2], pairs[2], x, guides[2]);
          r = hn::MulAdd(
            s3, hn::Set(dh, c), hn::Add(hn::Mul(r, hn::Set(dh, a)), hn::Mul(s2, hn::Set(dh, b))));
        }
      }
      if (in.Albedo) // Remodulate: times SanitizeAlbedo(A) + eps
      {
        HWY_ALIGN float albedo[4] = { in.Albedo[3 * p], in.Albedo[3 * p + 1],
          in.Albedo[3 * p + 2], 0.f };
        const auto al = hn::Load(dh, albedo);
        const auto kept = hn::And(hn::Ge(al, hn::Zero(dh)), hn::Le(al, maxFinite));
        r = hn::Mul(r, hn::Add(hn::IfThenElseZero(kept, hn::Min(al, one)), epsilon));
      }
      float* out = in.Out + 3 * p;
      if (x + 1 < in.Width) // the fourth lane lands on the next pixel, written after this one
      {
        hn::StoreU(r, dh, out);
      }
      else
      {
        HWY_ALIGN float last[4];
        hn::Store(r, dh, last);
        out[0] = last[0];
        out[1] = last[1];
        out[2] = last[2];
      }
    }
  }
}
#endif

void SliceRowsKernel(const SliceInput& in, int yBegin, int yEnd)
{
#if PTV_GRID_WIDE
  SliceRowsWide(in, yBegin, yEnd);
#else
  const D4 d;
  const int levels = in.NumberOfLevels;
  for (int y = yBegin; y < yEnd; ++y)
  {
    SliceRowPair pairs[kMaxGridLevels];
    SliceGridRows(in, y, pairs);
    const std::size_t row = static_cast<std::size_t>(y) * in.Width;
    for (int x = 0; x < in.Width; ++x)
    {
      const std::size_t p = row + x;
      Vec3 s[kMaxGridLevels] = { MakeVec3(0.f, 0.f, 0.f), MakeVec3(0.f, 0.f, 0.f),
        MakeVec3(0.f, 0.f, 0.f) };
      for (int l = 0; l < levels; ++l)
      {
        const PushGrid& g = in.Levels[l];
        const SliceRowPair& pair = pairs[l];
        const float z = GuideToGrid(in.Guides[p * levels + l], g.Geometry.RangeStep);
        const int k0 = FloorToInt(z);
        const float tz0 = Tent(z - static_cast<float>(k0));
        const float tz1 = Tent(z - static_cast<float>(k0 + 1));
        const int c = g.I0[x] + 1;
        const float* c00 = CellAt(pair, 0, c, k0);     // (j0, i0)
        const float* c01 = CellAt(pair, 1, c, k0);     // (j0 + 1, i0)
        const float* c10 = CellAt(pair, 0, c + 1, k0); // (j0, i0 + 1)
        const float* c11 = CellAt(pair, 1, c + 1, k0); // (j0 + 1, i0 + 1)
        const float w00 = g.Tx0[x] * pair.Ty[0];
        const float w10 = g.Tx1[x] * pair.Ty[0];
        const float w01 = g.Tx0[x] * pair.Ty[1];
        const float w11 = g.Tx1[x] * pair.Ty[1];
        HWY_ALIGN float sum[4];
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
        if (l == 0 && in.AlphaOut)
        {
          in.AlphaOut[p] = sum[3] > 0.f
            ? SliceAlphaSum(g, pair, x, k0, tz0, tz1) / sum[3]
            : 0.f;
        }
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
#endif
}
} // namespace HWY_NAMESPACE
} // namespace ptv
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace ptv
{
HWY_EXPORT(SliceRowsKernel);

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
} // namespace ptv
#endif
