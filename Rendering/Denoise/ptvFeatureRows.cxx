// The feature builder's row kernels (every channel's transform from its interleaved pass, the
// colour's power law included, and the stride-2 pooling's pair sums), vectorised: compiled once per instruction
// set by Google Highway (foreach_target.h re-includes this file per target) and dispatched at run
// time. Each lane computes what the scalar definition does, in the same order.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "ptvFeatureRows.cxx"
#include "hwy/foreach_target.h" // must come before highway.h

#include "hwy/contrib/math/math-inl.h"
#include "hwy/highway.h"

#include "ptvFeatureRows.h"

#include <algorithm>

HWY_BEFORE_NAMESPACE();
namespace ptv
{
namespace HWY_NAMESPACE
{
namespace hn = hwy::HWY_NAMESPACE;

using DF = hn::ScalableTag<float>;
using VF = hn::Vec<DF>;

/// clip(max(v, 0)^(1 / 2.2), 0, 1): x = clip(v, 0, 1) first (the power law is monotonic, so
/// clipping before equals clipping after); x = 0 (and NaN, which the comparisons turn into 0)
/// gives 0, as powf(0, g) does.
HWY_INLINE VF Gamma(DF d, VF v)
{
  const auto zero = hn::Zero(d);
  const auto one = hn::Set(d, 1.0f);
  const auto x = hn::Min(hn::Max(v, zero), one);
  const auto positive = hn::Gt(x, zero);
  const auto safe = hn::IfThenElse(positive, x, one); // Log needs x > 0
  const auto y = hn::Exp(d, hn::Mul(hn::Set(d, 1.0f / 2.2f), hn::Log(d, safe)));
  return hn::IfThenElseZero(positive, hn::Min(y, one));
}

/// clip(v, 0, 1) with NaN -> 0 (x86's max returns its second operand for NaN, as std::max(0, v)).
HWY_INLINE VF Clip01(DF d, VF v)
{
  return hn::Min(hn::Max(v, hn::Zero(d)), hn::Set(d, 1.0f));
}

/// The feature values of pixels whose pass values are @a v and hit-test depths @a mask.
HWY_INLINE VF Transform(DF d, const FeatureRowInput& in, VF v, VF mask)
{
  switch (in.Transform)
  {
    case FeatureTransform::Gamma:
      return Gamma(d, v);
    case FeatureTransform::Clip:
      return Clip01(d, v);
    case FeatureTransform::Normal:
      return Clip01(d, hn::Mul(hn::Add(v, hn::Set(d, 1.0f)), hn::Set(d, 0.5f)));
    case FeatureTransform::Inverse: // v >= 1 ? 1 / v : 1 (NaN fails the test: 1)
    {
      const auto one = hn::Set(d, 1.0f);
      return hn::Div(one, hn::IfThenElse(hn::Ge(v, one), v, one));
    }
    case FeatureTransform::Range:
    default:
    {
      const auto value = in.Range > 0.0f
        ? Clip01(d, hn::Div(hn::Sub(v, hn::Set(d, in.Low)), hn::Set(d, in.Range)))
        : hn::Zero(d);
      return hn::IfThenElse(hn::Lt(mask, hn::Set(d, in.HitLimit)), value, hn::Set(d, in.Miss));
    }
  }
}

void FeatureRowKernel(const FeatureRowInput& in, float* HWY_RESTRICT dst)
{
  const DF d;
  const std::size_t lanes = hn::Lanes(d);
  const std::size_t width = static_cast<std::size_t>(in.Width);
  const std::size_t comps = static_cast<std::size_t>(in.Components);
  const std::size_t component = static_cast<std::size_t>(in.Component);
  const auto mask = [&](std::size_t x)
  { return in.Mask ? hn::LoadU(d, in.Mask + x) : hn::Zero(d); };
  std::size_t x = 0;
  if (comps == 1 || comps == 3)
  {
    for (; x + lanes <= width; x += lanes)
    {
      VF v = hn::Zero(d);
      if (comps == 1)
      {
        v = hn::LoadU(d, in.Row + x);
      }
      else
      {
        VF v0, v1, v2;
        hn::LoadInterleaved3(d, in.Row + 3 * x, v0, v1, v2);
        v = component == 0 ? v0 : (component == 1 ? v1 : v2);
      }
      hn::StoreU(Transform(d, in, v, mask(x)), d, dst + x);
    }
  }
  for (; x < width; x += lanes) // the rest through an aligned copy (never reads past a row)
  {
    HWY_ALIGN float values[hn::MaxLanes(d)] = {};
    HWY_ALIGN float depths[hn::MaxLanes(d)] = {};
    HWY_ALIGN float result[hn::MaxLanes(d)];
    const std::size_t count = std::min(lanes, width - x);
    for (std::size_t i = 0; i < count; ++i)
    {
      values[i] = in.Row[(x + i) * comps + component];
      depths[i] = in.Mask ? in.Mask[x + i] : 0.f;
    }
    hn::Store(Transform(d, in, hn::Load(d, values), hn::Load(d, depths)), d, result);
    std::copy(result, result + count, dst + x);
  }
}

void AccumulatePairsKernel(
  const float* HWY_RESTRICT line, std::size_t pairs, bool first, float* HWY_RESTRICT out)
{
  const DF d;
  const std::size_t lanes = hn::Lanes(d);
  std::size_t j = 0;
  for (; j + lanes <= pairs; j += lanes)
  {
    VF even, odd;
    hn::LoadInterleaved2(d, line + 2 * j, even, odd);
    const VF start = first ? hn::Zero(d) : hn::LoadU(d, out + j);
    hn::StoreU(hn::Add(hn::Add(start, even), odd), d, out + j);
  }
  for (; j < pairs; ++j)
  {
    out[j] = ((first ? 0.f : out[j]) + line[2 * j]) + line[2 * j + 1];
  }
}
} // namespace HWY_NAMESPACE
} // namespace ptv
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace ptv
{
HWY_EXPORT(FeatureRowKernel);
HWY_EXPORT(AccumulatePairsKernel);

void FeatureRow(const FeatureRowInput& in, float* dst, bool portable)
{
  if (portable)
  {
    HWY_STATIC_DISPATCH(FeatureRowKernel)(in, dst);
  }
  else
  {
    HWY_DYNAMIC_DISPATCH(FeatureRowKernel)(in, dst);
  }
}

void AccumulatePairs(const float* line, std::size_t pairs, bool first, float* out, bool portable)
{
  if (portable)
  {
    HWY_STATIC_DISPATCH(AccumulatePairsKernel)(line, pairs, first, out);
  }
  else
  {
    HWY_DYNAMIC_DISPATCH(AccumulatePairsKernel)(line, pairs, first, out);
  }
}
}
#endif
