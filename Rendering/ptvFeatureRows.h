/**
 * @file ptvFeatureRows.h
 * @brief Private: the feature builder's vectorised row kernel, compiled for every x86-64
 *        instruction set by Google Highway and chosen at run time (like ptvBilateralGridRows.h).
 */
#ifndef ptvFeatureRows_h
#define ptvFeatureRows_h

#include <cstddef>

namespace ptv
{
/**
 * values[i] = clip(max(values[i], 0)^(1 / 2.2), 0, 1), the colour feature of features.py, for
 * @a n values in place (exp(log(x) / 2.2) with Highway's vector math: within a few ulp of powf).
 * @a portable: the baseline build instead of this CPU's best instruction set.
 */
void GammaInPlace(float* values, std::size_t n, bool portable);
}

#endif
