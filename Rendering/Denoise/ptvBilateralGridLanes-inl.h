// Highway per-target helpers shared by the CPU bilateral grid's row kernels (ptvBilateralGridSplat.cxx,
// ptvBilateralGridSlice.cxx): included once per target after hwy/highway.h, hence the toggled guard.
#if defined(PTV_BILATERAL_GRID_LANES_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef PTV_BILATERAL_GRID_LANES_INL_H_
#undef PTV_BILATERAL_GRID_LANES_INL_H_
#else
#define PTV_BILATERAL_GRID_LANES_INL_H_
#endif

#include "hwy/highway.h"

#include <cstddef>

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

} // namespace HWY_NAMESPACE
} // namespace ptv
HWY_AFTER_NAMESPACE();

#endif // PTV_BILATERAL_GRID_LANES_INL_H_
