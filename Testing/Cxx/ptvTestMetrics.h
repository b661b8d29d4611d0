/**
 * @file ptvTestMetrics.h
 * @brief Shared by the C++ tests: the project's tone map x^(1/2.2) clipped to [0, 1]
 *        (docs/measuring.md) and mean squared differences after it.
 */
#ifndef ptvTestMetrics_h
#define ptvTestMetrics_h

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace
{
float Tone(float x)
{
  return std::min(1.0f, x > 0.0f ? std::pow(x, 1.0f / 2.2f) : 0.0f);
}

/// Mean squared difference of every value of @a a and @a b after the tone map.
double ToneMse(const std::vector<float>& a, const std::vector<float>& b)
{
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i)
  {
    const double d = Tone(a[i]) - Tone(b[i]);
    sum += d * d;
  }
  return sum / static_cast<double>(std::max<std::size_t>(a.size(), 1));
}

/// The same over the RGB pixels (3 values each) where @a mask is true (0 when none is).
double ToneMse(
  const std::vector<float>& a, const std::vector<float>& b, const std::vector<bool>& mask)
{
  double sum = 0.0;
  int count = 0;
  for (std::size_t p = 0; p < mask.size(); ++p)
  {
    if (!mask[p])
    {
      continue;
    }
    for (int c = 0; c < 3; ++c)
    {
      const double d = Tone(a[3 * p + c]) - Tone(b[3 * p + c]);
      sum += d * d;
    }
    ++count;
  }
  return count ? sum / (3.0 * count) : 0.0;
}
}

#endif
