/**
 * @file ptvFeatureRows.h
 * @brief Private: the feature builder's vectorised row kernels, compiled for every x86-64
 *        instruction set by Google Highway and chosen at run time (like ptvBilateralGridRows.h).
 */
#ifndef ptvFeatureRows_h
#define ptvFeatureRows_h

#include <cstddef>

namespace ptv
{
/// How a feature channel's values follow from its pass (features.py).
enum class FeatureTransform
{
  Gamma,  ///< clip(max(v, 0)^(1 / 2.2), 0, 1) (exp(log(x) / 2.2) with Highway's vector math:
          ///< within a few ulp of powf)
  Clip,   ///< clip(v, 0, 1) (NaN -> 0)
  Normal, ///< clip((v + 1) * 0.5, 0, 1)
  Range,  ///< hit (mask < HitLimit): Range > 0 ? clip((v - Low) / Range, 0, 1) : 0; else Miss
  Inverse ///< 1 / max(v, 1), in (0, 1] (NaN -> 1, +inf -> 0): a frame count's newest share
};

/// One full-resolution row of one feature channel.
struct FeatureRowInput
{
  const float* Row;    ///< the pass's row: Width pixels of Components floats
  int Components;      ///< floats per pixel of the pass
  int Component;       ///< which of them
  int Width;
  FeatureTransform Transform;
  const float* Mask = nullptr; ///< Range: the hit test's depth row (Width floats)
  float HitLimit = 0.f;
  float Low = 0.f;
  float Range = 0.f;
  float Miss = 0.f;
};

/// dst[x] = the feature value of pixel x of the row, x < Width.
void FeatureRow(const FeatureRowInput& in, float* dst, bool portable);

/// out[j] = ((first ? 0 : out[j]) + line[2 j]) + line[2 j + 1] for j < @a pairs (the stride-2
/// pooling's row sums, in that order).
void AccumulatePairs(const float* line, std::size_t pairs, bool first, float* out, bool portable);
}

#endif
