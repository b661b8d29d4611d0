/**
 * @file ptvBilateralGrid.h
 * @brief Per-cell / per-pixel kernels of the Neural Bilateral Grid denoiser (Meng et al. 2020):
 *        demodulate, outlier clamp, splat, slice, blend, re-modulate.
 *
 * This comment is THE definition of the semantics; vtkPTVDenoiser's grid (C++, through
 * ptvBilateralGridCpu) and Training/ptv_training/bilateral_grid.py (torch, differentiable) both
 * implement exactly this, in single precision, with the same float expressions, so they agree
 * to rounding of the splat sums.
 *
 * Inputs per frame (W x H pixels, W, H >= 1): radiance R (3 ch, HDR), albedo A (3 ch),
 * L = 1..3 levels, each with a guide image G_l (1 ch, range [0, 255]), and L - 1 blend weight
 * maps w_l (range [0, 1]).
 *
 * 1. Sanitise and demodulate (SanitizeRadiance, SanitizeAlbedo, Demodulate):
 *    R := 0 where NaN, +-Inf or negative; R := min(R, 1e30). A := 0 where NaN, +-Inf or
 *    negative; A := min(A, 1). D = R / (A + eps), eps = 0.01, per channel. Without albedo
 *    (A = nullptr: demodulation off) D = R and step 5 is the identity.
 *    (The caps on finite values keep every later sum finite; they never bind on real frames.)
 * 2. Outlier clamp (Luminance, OutlierLimit, ClampOutliers): m = mean of
 *    luminance(D) = 0.2126 r + 0.7152 g + 0.0722 b over the LIT pixels, those with
 *    luminance(D) > 0 (summed in double; m = 0 when none is lit), so that the empty background
 *    does not pull the limit down; if Clamp > 0, every channel of D is clamped to
 *    <= float(Clamp * max(m, 1e-6)). Clamp = 0 disables it.
 * 3. Per level with spatial cell size ss and range step sr (1..256; defaults (4,4), (8,8),
 *    (16,16)): grid GW = ceil(W / ss), GH = ceil(H / ss), GD = ceil(256 / sr).
 *    Pixel x maps to u = (x + 0.5) / ss - 0.5, evaluated as float(2x + 1 - ss) / float(2 ss)
 *    (PixelToGrid; likewise v for y). Guide g is sanitised to [0, 255] (NaN -> 0, +Inf -> 255)
 *    and maps to z = g / sr (GuideToGrid). Tent t(a) = max(0, 1 - |a|) (Tent).
 *    Splat (any summation order; SplatCell below is a gather, each cell written by one thread,
 *    used by CUDA; the CPU pushes each pixel into its cells, ptvBilateralGridRows.h):
 *      W_ijk = sum_p t(u_p - i) t(v_p - j) t(z_p - k),   V_ijk = sum_p (same weight) D_p / W_ijk,
 *    over the pixels p with |u_p - i| < 1, |v_p - j| < 1, |z_p - k| < 1; the weight of a pixel
 *    is evaluated as (t(u_p - i) * t(v_p - j)) * t(z_p - k). A cell with W_ijk = 0 is EMPTY:
 *    value 0, weight 0. There is no separate blur: the tent support is the blur.
 *    Slice (SliceLevel) at pixel p: the 8 cells (i0 + a, j0 + b, k0 + c), a, b, c in {0, 1},
 *    i0 = floor(u_p), j0 = floor(v_p), k0 = floor(z_p), with trilinear weights
 *    (t(u - i) * t(v - j)) * t(z - k); a cell outside the grid is dropped (not clamped) and an
 *    empty cell is dropped; the sum (order: b, then a, then c) is renormalized by the sum of the
 *    kept weights; 0 when that sum is 0.
 * 4. Blend (Blend): weights sanitised to [0, 1] (NaN -> 0). L = 3: s1 w1 + s2 w2 + s3 (1 - w1 -
 *    w2) (the third weight may be negative); L = 2: s1 w1 + s2 (1 - w1); L = 1: s1.
 * 5. Re-modulate (Remodulate): result = out * (A + eps) with the sanitised A (out without A). The result is
 *    finite everywhere (every slice is a convex combination of D values <= 1e32).
 *
 * Grid layout of SplatCell / SliceLevel (GridLevel; the CPU driver keeps its own interleaved,
 * padded layout, ptvBilateralGridRows.h): cell (i, j, k) is column (j * GW + i), Weights[column * GD + k],
 * Values[(column * GD + k) * 3 + channel]: a column of all range bins is contiguous.
 * Images (demodulated radiance, guides) are row-major, x fastest: pixel (x, y) is y * W + x.
 */
#ifndef ptvBilateralGrid_h
#define ptvBilateralGrid_h

#include "ptvKernelCommon.h"

namespace ptv
{
/// eps of the albedo demodulation D = R / (A + eps).
constexpr float kDemodulationEpsilon = 0.01f;
/// Radiance above this (finite) value is treated as this value.
constexpr float kMaxGridRadiance = 1e30f;
/// Largest finite float: radiance or albedo above it is +Inf.
constexpr float kMaxFiniteFloat = 3.402823466e38f;
/// Guides cover [0, kGuideMax]; the range axis spans kGuideRange values.
constexpr float kGuideMax = 255.f;
constexpr int kGuideRange = 256;
/// Spatial and range steps are in [1, kMaxGridStep].
constexpr int kMaxGridStep = 256;
/// At most this many levels.
constexpr int kMaxGridLevels = 3;
/// Floor of the mean luminance in the outlier limit.
constexpr double kMinOutlierMean = 1e-6;

/// One level of the bilateral grid: sizes, steps and the caller-owned cell buffers.
struct GridLevel
{
  int Width;       ///< GW = ceil(W / SpatialStep)
  int Height;      ///< GH = ceil(H / SpatialStep)
  int Depth;       ///< GD = ceil(256 / RangeStep)
  int SpatialStep; ///< ss, pixels per cell along x and y
  int RangeStep;   ///< sr, guide values per range bin
  float* Values;   ///< GW * GH * GD * 3 normalized means (0 in empty cells)
  float* Weights;  ///< GW * GH * GD tent-weight sums (0 = empty)
};

/// ceil(n / step) for n >= 0, step >= 1.
PTV_HD PTV_INLINE int GridCells(int n, int step)
{
  return (n + step - 1) / step;
}

/// GD = ceil(256 / rangeStep).
PTV_HD PTV_INLINE int GridDepth(int rangeStep)
{
  return (kGuideRange + rangeStep - 1) / rangeStep;
}

// Min/max below are written as comparisons, not fminf/fmaxf: without -ffast-math those are libm
// calls on x86-64 (NaN rules), which made the inner loops several times slower. The results
// are the same, NaN handling included (a comparison with NaN is false).

/// Tent t(a) = max(0, 1 - |a|) (0 for NaN).
PTV_HD PTV_INLINE float Tent(float a)
{
  const float t = 1.f - fabsf(a);
  return t > 0.f ? t : 0.f;
}

/// v clamped to [lo, hi], NaN -> lo.
PTV_HD PTV_INLINE float ClampNanLow(float v, float lo, float hi)
{
  return v > lo ? (v < hi ? v : hi) : lo;
}

/// Grid coordinate of pixel index x: (x + 0.5) / step - 0.5 with a single rounding.
PTV_HD PTV_INLINE float PixelToGrid(int x, int step)
{
  return static_cast<float>(2 * x + 1 - step) / static_cast<float>(2 * step);
}

/// Range coordinate of a guide value: clamp(g, 0, 255) / rangeStep (NaN -> 0, +Inf -> 255).
PTV_HD PTV_INLINE float GuideToGrid(float g, int rangeStep)
{
  return ClampNanLow(g, 0.f, kGuideMax) / static_cast<float>(rangeStep);
}

/// NaN, +-Inf and negatives -> 0; finite values above 1e30 -> 1e30.
PTV_HD PTV_INLINE float SanitizeRadiance(float r)
{
  if (!(r >= 0.f) || r > kMaxFiniteFloat)
  {
    return 0.f;
  }
  return r < kMaxGridRadiance ? r : kMaxGridRadiance;
}

/// NaN, +-Inf and negatives -> 0; values above 1 -> 1.
PTV_HD PTV_INLINE float SanitizeAlbedo(float a)
{
  if (!(a >= 0.f) || a > kMaxFiniteFloat)
  {
    return 0.f;
  }
  return a < 1.f ? a : 1.f;
}

/// Blend weight sanitised to [0, 1] (NaN -> 0).
PTV_HD PTV_INLINE float SanitizeBlendWeight(float w)
{
  return ClampNanLow(w, 0.f, 1.f);
}

/// Demodulated radiance D = R / (A + eps) of raw (unsanitised) radiance and albedo.
PTV_HD PTV_INLINE Vec3 Demodulate(const float* radiance, const float* albedo)
{
  if (!albedo)
  {
    return MakeVec3(
      SanitizeRadiance(radiance[0]), SanitizeRadiance(radiance[1]), SanitizeRadiance(radiance[2]));
  }
  return MakeVec3(
    SanitizeRadiance(radiance[0]) / (SanitizeAlbedo(albedo[0]) + kDemodulationEpsilon),
    SanitizeRadiance(radiance[1]) / (SanitizeAlbedo(albedo[1]) + kDemodulationEpsilon),
    SanitizeRadiance(radiance[2]) / (SanitizeAlbedo(albedo[2]) + kDemodulationEpsilon));
}

/// result = out * (A + eps) of raw (unsanitised) albedo; out when @a albedo is nullptr.
PTV_HD PTV_INLINE Vec3 Remodulate(Vec3 out, const float* albedo)
{
  if (!albedo)
  {
    return out;
  }
  return MakeVec3(out.x * (SanitizeAlbedo(albedo[0]) + kDemodulationEpsilon),
    out.y * (SanitizeAlbedo(albedo[1]) + kDemodulationEpsilon),
    out.z * (SanitizeAlbedo(albedo[2]) + kDemodulationEpsilon));
}

/// Rec. 709 luminance, evaluated as (0.2126 r + 0.7152 g) + 0.0722 b.
PTV_HD PTV_INLINE float Luminance(Vec3 c)
{
  return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z;
}

/// Per-channel upper limit of D: float(clamp * max(meanLuminance, 1e-6)); 0 (no limit) when
/// clamp <= 0.
PTV_HD PTV_INLINE float OutlierLimit(double meanLuminance, double clamp)
{
  if (!(clamp > 0.0))
  {
    return 0.f;
  }
  const double m = meanLuminance > kMinOutlierMean ? meanLuminance : kMinOutlierMean;
  return static_cast<float>(clamp * m);
}

/// min(d, limit) per channel; unchanged when limit <= 0 (clamp off).
PTV_HD PTV_INLINE Vec3 ClampOutliers(Vec3 d, float limit)
{
  if (!(limit > 0.f))
  {
    return d;
  }
  return MakeVec3(d.x < limit ? d.x : limit, d.y < limit ? d.y : limit, d.z < limit ? d.z : limit);
}

/// floor(x) as an int for |x| < 2^31 (exactly floorf(x); no libm call without SSE4.1).
PTV_HD PTV_INLINE int FloorToInt(float x)
{
  const int i = static_cast<int>(x); // truncates towards zero
  return static_cast<float>(i) > x ? i - 1 : i;
}

/// floor(a / b) for b > 0.
PTV_HD PTV_INLINE int FloorDiv(int a, int b)
{
  const int q = a / b;
  return (a % b != 0 && a < 0) ? q - 1 : q;
}

/**
 * Pixels [first, last] (clamped to [0, n - 1]) whose coordinate is within the tent support of
 * cell i: |u_x - i| < 1 <=> (2i - 1) ss < 2x + 1 < (2i + 3) ss. Empty when first > last.
 */
PTV_HD PTV_INLINE void SplatSupport(int i, int ss, int n, int& first, int& last)
{
  first = FloorDiv((2 * i - 1) * ss - 1, 2) + 1;
  last = -FloorDiv(1 - (2 * i + 3) * ss, 2) - 1; // ceil(((2i + 3) ss - 1) / 2) - 1
  first = first > 0 ? first : 0;
  last = last < n - 1 ? last : n - 1;
}

/**
 * Splat column (i, j) of level @a g: all GD range bins of the cells (i, j, k), gathered from the
 * pixels within the tent support (|u_p - i| < 1, |v_p - j| < 1). @a demod holds W * H clamped
 * demodulated pixels (3 floats each), @a guide the W * H raw guide values of this level.
 * Only column (i, j) of g.Values / g.Weights is written.
 */
PTV_HD PTV_INLINE void SplatCell(
  const float* demod, const float* guide, int W, int H, GridLevel& g, int i, int j)
{
  const int depth = g.Depth;
  const int ss = g.SpatialStep;
  const int64_t column = static_cast<int64_t>(j) * g.Width + i;
  float* weights = g.Weights + column * depth;
  float* values = g.Values + column * depth * 3;
  for (int k = 0; k < depth; ++k)
  {
    weights[k] = 0.f;
    values[3 * k + 0] = 0.f;
    values[3 * k + 1] = 0.f;
    values[3 * k + 2] = 0.f;
  }
  int x0, x1, y0, y1;
  SplatSupport(i, ss, W, x0, x1);
  SplatSupport(j, ss, H, y0, y1);
  const float fi = static_cast<float>(i);
  const float fj = static_cast<float>(j);
  for (int y = y0; y <= y1; ++y)
  {
    const float ty = Tent(PixelToGrid(y, ss) - fj);
    if (!(ty > 0.f))
    {
      continue;
    }
    for (int x = x0; x <= x1; ++x)
    {
      const float tx = Tent(PixelToGrid(x, ss) - fi);
      if (!(tx > 0.f))
      {
        continue;
      }
      const float wxy = tx * ty;
      const int64_t p = static_cast<int64_t>(y) * W + x;
      const float z = GuideToGrid(guide[p], g.RangeStep);
      const int k0 = FloorToInt(z);
      const float* d = demod + 3 * p;
      for (int c = 0; c < 2; ++c)
      {
        const int k = k0 + c;
        if (k < 0 || k >= depth)
        {
          continue;
        }
        const float w = wxy * Tent(z - static_cast<float>(k));
        weights[k] += w;
        values[3 * k + 0] += w * d[0];
        values[3 * k + 1] += w * d[1];
        values[3 * k + 2] += w * d[2];
      }
    }
  }
  for (int k = 0; k < depth; ++k)
  {
    const float w = weights[k];
    if (w > 0.f)
    {
      values[3 * k + 0] = values[3 * k + 0] / w;
      values[3 * k + 1] = values[3 * k + 1] / w;
      values[3 * k + 2] = values[3 * k + 2] / w;
    }
    else
    {
      weights[k] = 0.f;
      values[3 * k + 0] = 0.f;
      values[3 * k + 1] = 0.f;
      values[3 * k + 2] = 0.f;
    }
  }
}

/**
 * Trilinear slice of level @a g at grid coordinates (u, v, z): the 8 neighbouring cells, dropping
 * those outside the grid and the empty ones, renormalized by the kept weights; 0 if none.
 */
PTV_HD PTV_INLINE Vec3 SliceLevel(const GridLevel& g, float u, float v, float z)
{
  const int i0 = FloorToInt(u);
  const int j0 = FloorToInt(v);
  const int k0 = FloorToInt(z);
  Vec3 acc = MakeVec3(0.f, 0.f, 0.f);
  float weightSum = 0.f;
  for (int b = 0; b < 2; ++b)
  {
    const int j = j0 + b;
    if (j < 0 || j >= g.Height)
    {
      continue;
    }
    const float ty = Tent(v - static_cast<float>(j));
    for (int a = 0; a < 2; ++a)
    {
      const int i = i0 + a;
      if (i < 0 || i >= g.Width)
      {
        continue;
      }
      const float wxy = Tent(u - static_cast<float>(i)) * ty;
      const int64_t column = static_cast<int64_t>(j) * g.Width + i;
      for (int c = 0; c < 2; ++c)
      {
        const int k = k0 + c;
        if (k < 0 || k >= g.Depth)
        {
          continue;
        }
        const int64_t cell = column * g.Depth + k;
        // Branch-free drop of an empty cell: its stored value is 0, so only the weight sum
        // needs the mask (same result as skipping it).
        const float w = g.Weights[cell] > 0.f ? wxy * Tent(z - static_cast<float>(k)) : 0.f;
        const float* value = g.Values + 3 * cell;
        acc.x += w * value[0];
        acc.y += w * value[1];
        acc.z += w * value[2];
        weightSum += w;
      }
    }
  }
  if (!(weightSum > 0.f))
  {
    return MakeVec3(0.f, 0.f, 0.f);
  }
  return MakeVec3(acc.x / weightSum, acc.y / weightSum, acc.z / weightSum);
}

/**
 * Combine the per-level slices with raw (unsanitised) blend weights w1, w2:
 * levels 3: s1 w1 + s2 w2 + s3 (1 - w1 - w2); 2: s1 w1 + s2 (1 - w1); 1: s1.
 */
PTV_HD PTV_INLINE Vec3 Blend(Vec3 s1, Vec3 s2, Vec3 s3, int levels, float w1, float w2)
{
  if (levels <= 1)
  {
    return s1;
  }
  const float a = SanitizeBlendWeight(w1);
  if (levels == 2)
  {
    const float b = 1.f - a;
    return MakeVec3(s1.x * a + s2.x * b, s1.y * a + s2.y * b, s1.z * a + s2.z * b);
  }
  const float b = SanitizeBlendWeight(w2);
  const float c = (1.f - a) - b;
  return MakeVec3(s1.x * a + s2.x * b + s3.x * c, s1.y * a + s2.y * b + s3.y * c,
    s1.z * a + s2.z * b + s3.z * c);
}
}

#endif
