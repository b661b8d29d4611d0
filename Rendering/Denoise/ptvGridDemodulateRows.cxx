// The bilateral grid's sanitise + demodulate row kernel (ptvGridDemodulateRows.h), compiled
// once per instruction set by Google Highway (foreach_target.h re-includes this file per target)
// and dispatched at run time. Each lane evaluates Kernels/ptvBilateralGrid.h's scalar
// definitions in their order (no fused multiply-add: -ffp-contract=off in CMakeLists.txt).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "ptvGridDemodulateRows.cxx"
#include "hwy/foreach_target.h" // must come before highway.h

#include "hwy/highway.h"

#include "Kernels/ptvBilateralGrid.h"
#include "ptvGridDemodulateRows.h"

#include <algorithm>

HWY_BEFORE_NAMESPACE();
namespace ptv
{
namespace HWY_NAMESPACE
{
namespace hn = hwy::HWY_NAMESPACE;

using DF = hn::ScalableTag<float>;
using VF = hn::Vec<DF>;

/// SanitizeRadiance: 0 where NaN, negative or above the largest float; min(r, 1e30).
HWY_INLINE VF SanitizedRadiance(DF d, VF r)
{
  const auto ok = hn::And(hn::Ge(r, hn::Zero(d)), hn::Le(r, hn::Set(d, kMaxFiniteFloat)));
  return hn::IfThenElseZero(ok, hn::Min(r, hn::Set(d, kMaxGridRadiance)));
}

/// SanitizeAlbedo + kDemodulationEpsilon: the divisor of Demodulate.
HWY_INLINE VF AlbedoDivisor(DF d, VF a)
{
  const auto ok = hn::And(hn::Ge(a, hn::Zero(d)), hn::Le(a, hn::Set(d, kMaxFiniteFloat)));
  const VF sane = hn::IfThenElseZero(ok, hn::Min(a, hn::Set(d, 1.0f)));
  return hn::Add(sane, hn::Set(d, kDemodulationEpsilon));
}

/// Demodulated (r, g, b) of @a count pixels (a whole vector) and their luminance.
HWY_INLINE void Pixels(DF d, const float* HWY_RESTRICT radiance,
  const float* HWY_RESTRICT albedo, float* HWY_RESTRICT demod4, VF& lum)
{
  VF r, g, b;
  hn::LoadInterleaved3(d, radiance, r, g, b);
  r = SanitizedRadiance(d, r);
  g = SanitizedRadiance(d, g);
  b = SanitizedRadiance(d, b);
  if (albedo)
  {
    VF ar, ag, ab;
    hn::LoadInterleaved3(d, albedo, ar, ag, ab);
    r = hn::Div(r, AlbedoDivisor(d, ar));
    g = hn::Div(g, AlbedoDivisor(d, ag));
    b = hn::Div(b, AlbedoDivisor(d, ab));
  }
  hn::StoreInterleaved4(r, g, b, hn::Set(d, 1.0f), d, demod4);
  // Luminance(): (0.2126 r + 0.7152 g) + 0.0722 b, each product rounded.
  lum = hn::Add(hn::Add(hn::Mul(hn::Set(d, 0.2126f), r), hn::Mul(hn::Set(d, 0.7152f), g)),
    hn::Mul(hn::Set(d, 0.0722f), b));
}

DemodulatedRow DemodulateRowKernel(const float* HWY_RESTRICT radiance,
  const float* HWY_RESTRICT albedo, std::size_t width, float* HWY_RESTRICT demod4)
{
  const DF d;
  const std::size_t lanes = hn::Lanes(d);
  DemodulatedRow row;
  VF lum;
  std::size_t x = 0;
  for (; x + lanes <= width; x += lanes)
  {
    Pixels(d, radiance + 3 * x, albedo ? albedo + 3 * x : nullptr, demod4 + 4 * x, lum);
    row.Luminance += static_cast<double>(hn::GetLane(hn::SumOfLanes(d, lum)));
    row.Lit += hn::CountTrue(d, hn::Gt(lum, hn::Zero(d)));
  }
  if (x < width) // the rest through aligned copies (never reads or writes past the row)
  {
    const std::size_t count = width - x;
    HWY_ALIGN float rgb[3 * hn::MaxLanes(d)] = {};
    HWY_ALIGN float alb[3 * hn::MaxLanes(d)] = {};
    HWY_ALIGN float cells[4 * hn::MaxLanes(d)];
    std::copy(radiance + 3 * x, radiance + 3 * width, rgb);
    if (albedo)
    {
      std::copy(albedo + 3 * x, albedo + 3 * width, alb);
    }
    Pixels(d, rgb, albedo ? alb : nullptr, cells, lum);
    std::copy(cells, cells + 4 * count, demod4 + 4 * x);
    // Padding lanes have radiance 0: luminance 0, not lit, nothing added.
    row.Luminance += static_cast<double>(hn::GetLane(hn::SumOfLanes(d, lum)));
    row.Lit += hn::CountTrue(d, hn::Gt(lum, hn::Zero(d)));
  }
  return row;
}
} // namespace HWY_NAMESPACE
} // namespace ptv
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace ptv
{
HWY_EXPORT(DemodulateRowKernel);

DemodulatedRow DemodulateRow(const float* radiance, const float* albedo, std::size_t width,
  float* demod4, bool portable)
{
  return portable
    ? HWY_STATIC_DISPATCH(DemodulateRowKernel)(radiance, albedo, width, demod4)
    : HWY_DYNAMIC_DISPATCH(DemodulateRowKernel)(radiance, albedo, width, demod4);
}
}
#endif
