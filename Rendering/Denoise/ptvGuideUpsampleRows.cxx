// The guide upsampler's row kernels (ptvGuideUpsampleRows.h), compiled once per instruction set by
// Google Highway (foreach_target.h re-includes this file per target) and dispatched at run time.
// CMakeLists.txt compiles this file with -ffp-contract=off: no target fuses a multiply and an add,
// so the values equal the scalar definition's bit for bit.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "ptvGuideUpsampleRows.cxx"
#include "hwy/foreach_target.h" // must come before highway.h

#include "hwy/highway.h"

#include "ptvGuideUpsampleRows.h"

#include <algorithm>

HWY_BEFORE_NAMESPACE();
namespace ptv
{
namespace HWY_NAMESPACE
{
namespace hn = hwy::HWY_NAMESPACE;

/// The definition for one pixel (scalar; this file never fuses a multiply and an add).
HWY_INLINE float Bilinear(const UpsampleRowInput& in, std::size_t x)
{
  const int a = in.X0[x];
  const int b = in.X1[x];
  const float lx = in.LX[x];
  const float top = (1.f - lx) * in.R0[a] + lx * in.R0[b];
  const float bottom = (1.f - lx) * in.R1[a] + lx * in.R1[b];
  return ((1.f - in.LY) * top + in.LY * bottom) * in.Factor;
}

void UpsampleRowKernel(const UpsampleRowInput& in, float* HWY_RESTRICT out)
{
  const hn::ScalableTag<float> d;
  const std::size_t lanes = hn::Lanes(d);
  const std::size_t width = static_cast<std::size_t>(in.Width);
  std::size_t x = 0;
  if (in.Stride == 2 && in.NetWidth >= 3)
  {
    const std::size_t last = static_cast<std::size_t>(in.NetWidth) - 2; // last interior k
    const auto one = hn::Set(d, 1.f);
    const auto ly = hn::Set(d, in.LY);
    const auto wy = hn::Sub(one, ly);
    const auto factor = hn::Set(d, in.Factor);
    const auto even = hn::Set(d, 0.75f); // lx of pixel 2k: sources k - 1, k
    const auto odd = hn::Set(d, 0.25f);  // lx of pixel 2k + 1: sources k, k + 1
    const auto mix = [&](auto lx, auto a0, auto b0, auto a1, auto b1)
    {
      const auto wx = hn::Sub(one, lx);
      const auto top = hn::Add(hn::Mul(wx, a0), hn::Mul(lx, b0));
      const auto bottom = hn::Add(hn::Mul(wx, a1), hn::Mul(lx, b1));
      return hn::Mul(hn::Add(hn::Mul(wy, top), hn::Mul(ly, bottom)), factor);
    };
    out[0] = Bilinear(in, 0);
    out[1] = Bilinear(in, 1);
    std::size_t k = 1;
    for (; k + lanes - 1 <= last; k += lanes)
    {
      const auto p0 = hn::LoadU(d, in.R0 + k - 1);
      const auto q0 = hn::LoadU(d, in.R0 + k);
      const auto n0 = hn::LoadU(d, in.R0 + k + 1);
      const auto p1 = hn::LoadU(d, in.R1 + k - 1);
      const auto q1 = hn::LoadU(d, in.R1 + k);
      const auto n1 = hn::LoadU(d, in.R1 + k + 1);
      hn::StoreInterleaved2(
        mix(even, p0, q0, p1, q1), mix(odd, q0, n0, q1, n1), d, out + 2 * k);
    }
    x = 2 * k;
  }
  for (; x < width; ++x)
  {
    out[x] = Bilinear(in, x);
  }
}

void InterleaveRowsKernel(
  const float* const* HWY_RESTRICT rows, int count, int width, float* HWY_RESTRICT out)
{
  const hn::ScalableTag<float> d;
  const std::size_t lanes = hn::Lanes(d);
  const std::size_t n = static_cast<std::size_t>(width);
  const std::size_t c = static_cast<std::size_t>(count);
  std::size_t x = 0;
  if (count == 1)
  {
    std::copy(rows[0], rows[0] + n, out);
    return;
  }
  for (; x + lanes <= n; x += lanes)
  {
    if (count == 2)
    {
      hn::StoreInterleaved2(hn::LoadU(d, rows[0] + x), hn::LoadU(d, rows[1] + x), d, out + 2 * x);
    }
    else
    {
      hn::StoreInterleaved3(hn::LoadU(d, rows[0] + x), hn::LoadU(d, rows[1] + x),
        hn::LoadU(d, rows[2] + x), d, out + 3 * x);
    }
  }
  for (; x < n; ++x)
  {
    for (std::size_t k = 0; k < c; ++k)
    {
      out[c * x + k] = rows[k][x];
    }
  }
}
} // namespace HWY_NAMESPACE
} // namespace ptv
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace ptv
{
HWY_EXPORT(UpsampleRowKernel);
HWY_EXPORT(InterleaveRowsKernel);

void UpsampleRow(const UpsampleRowInput& in, float* out, bool portable)
{
  if (portable)
  {
    HWY_STATIC_DISPATCH(UpsampleRowKernel)(in, out);
  }
  else
  {
    HWY_DYNAMIC_DISPATCH(UpsampleRowKernel)(in, out);
  }
}

void InterleaveRows(const float* const* rows, int count, int width, float* out, bool portable)
{
  if (portable)
  {
    HWY_STATIC_DISPATCH(InterleaveRowsKernel)(rows, count, width, out);
  }
  else
  {
    HWY_DYNAMIC_DISPATCH(InterleaveRowsKernel)(rows, count, width, out);
  }
}
}
#endif
