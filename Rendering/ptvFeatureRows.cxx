// The colour feature's power law, vectorised: compiled once per instruction set by Google Highway
// (foreach_target.h re-includes this file per target) and dispatched at run time.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "ptvFeatureRows.cxx"
#include "hwy/foreach_target.h" // must come before highway.h

#include "hwy/contrib/math/math-inl.h"
#include "hwy/highway.h"

#include "ptvFeatureRows.h"

HWY_BEFORE_NAMESPACE();
namespace ptv
{
namespace HWY_NAMESPACE
{
namespace hn = hwy::HWY_NAMESPACE;

void GammaInPlaceKernel(float* HWY_RESTRICT values, std::size_t n)
{
  const hn::ScalableTag<float> d;
  const std::size_t lanes = hn::Lanes(d);
  const auto zero = hn::Zero(d);
  const auto one = hn::Set(d, 1.0f);
  const auto gamma = hn::Set(d, 1.0f / 2.2f);
  // x = clip(v, 0, 1) first: the power law is monotonic, so clipping before equals clipping
  // after; x = 0 (and NaN, which the comparisons turn into 0) gives 0, as powf(0, g) does.
  const auto transform = [&](hn::Vec<decltype(d)> v)
  {
    const auto x = hn::Min(hn::Max(v, zero), one);
    const auto positive = hn::Gt(x, zero);
    const auto safe = hn::IfThenElse(positive, x, one); // Log needs x > 0
    const auto y = hn::CallExp(d, hn::Mul(gamma, hn::CallLog(d, safe)));
    return hn::IfThenElseZero(positive, hn::Min(y, one));
  };
  std::size_t i = 0;
  for (; i + lanes <= n; i += lanes)
  {
    hn::StoreU(transform(hn::LoadU(d, values + i)), d, values + i);
  }
  for (; i < n; ++i) // the tail, one lane at a time (never reads past the buffer)
  {
    HWY_ALIGN float lane[hn::MaxLanes(d)] = {};
    lane[0] = values[i];
    values[i] = hn::GetLane(transform(hn::Load(d, lane)));
  }
}
} // namespace HWY_NAMESPACE
} // namespace ptv
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace ptv
{
HWY_EXPORT(GammaInPlaceKernel);

void GammaInPlace(float* values, std::size_t n, bool portable)
{
  if (portable)
  {
    HWY_STATIC_DISPATCH(GammaInPlaceKernel)(values, n);
  }
  else
  {
    HWY_DYNAMIC_DISPATCH(GammaInPlaceKernel)(values, n);
  }
}
}
#endif
