/**
 * @file ptvTransferTable.h
 * @brief Sampled transfer function: RGBA table over a scalar range, optional gradient-opacity
 *        table, and the step-length opacity correction.
 *
 * RGBA holds Size entries (r, g, b, a) with entry i at scalar ScalarMin + i (ScalarMax -
 * ScalarMin) / (Size - 1); lookups interpolate linearly between entries and clamp outside the
 * range. The alpha is the opacity accumulated over one ScalarOpacityUnitDistance (VTK's
 * semantics), i.e. before step correction: a segment of length s has opacity
 * CorrectOpacity(alpha, s / UnitDistance) = 1 - (1 - alpha)^(s / UnitDistance), which equals an
 * extinction coefficient sigma = -ln(1 - alpha) / UnitDistance.
 *
 * GradientOpacity (optional, nullptr means factor 1) holds GradientSize factors over gradient
 * magnitudes [0, GradientMax] (world units, scalar per world distance), same interpolation.
 */
#ifndef ptvTransferTable_h
#define ptvTransferTable_h

#include "ptvKernelCommon.h"

namespace ptv
{
struct TransferTable
{
  const float* RGBA;            ///< 4 * Size floats
  int Size;                     ///< number of entries (>= 1)
  float ScalarMin;              ///< scalar of entry 0
  float ScalarMax;              ///< scalar of entry Size-1
  const float* GradientOpacity; ///< GradientSize factors, or nullptr
  int GradientSize;             ///< number of gradient-opacity entries
  float GradientMax;            ///< gradient magnitude of the last entry
  /// Optional copies with the opacity already corrected for one march step (nullptr: corrected
  /// per sample): StepRGBA is RGBA with alpha = CorrectOpacity(alpha, camera step / unit
  /// distance), ShadowAlpha the opacities of one shadow/environment step (Size floats). Only
  /// without gradient opacity, whose factor multiplies alpha before the correction.
  const float* StepRGBA;
  const float* ShadowAlpha;
  /// Optional (nullptr: none): Size + 1 prefix counts, OpaqueBefore[i] = the number of entries
  /// j < i whose opacity is > 0, for MayBeOpaque's interval queries.
  const int* OpaqueBefore;
};

/// Colour and opacity per unit distance (uncorrected) of one classified sample.
struct TransferSample
{
  Vec3 Color;
  float Opacity;
};

/// Continuous table coordinate in [0, size-1] of value v mapped from [lo, hi] (NaN -> 0).
PTV_HD PTV_INLINE float TableCoordinate(float v, float lo, float hi, int size)
{
  const float last = static_cast<float>(size - 1);
  if (!(hi > lo))
  {
    return v >= hi ? last : 0.f;
  }
  return Clamp((v - lo) * (last / (hi - lo)), 0.f, last);
}

/// Lower entry index and weight of table coordinate x (0 <= x <= size-1).
PTV_HD PTV_INLINE void TableCell(float x, int size, int& i0, float& f)
{
  i0 = static_cast<int>(x);
  if (i0 > size - 2)
  {
    i0 = size >= 2 ? size - 2 : 0;
  }
  f = size >= 2 ? x - static_cast<float>(i0) : 0.f;
}

/// Colour and opacity at scalar s from @a rgba, a table laid out as tf.RGBA over tf's scalar
/// range (linear between entries, clamped outside; NaN is transparent).
PTV_HD PTV_INLINE TransferSample LookupRGBA(const TransferTable& tf, const float* rgba, float s)
{
  TransferSample out = { MakeVec3(0.f, 0.f, 0.f), 0.f };
  if (!rgba || tf.Size <= 0 || !(s == s))
  {
    return out; // no table, or a NaN sample ("no data": the mapper maps non-finite voxels to NaN)
  }
  int i0;
  float f;
  TableCell(TableCoordinate(s, tf.ScalarMin, tf.ScalarMax, tf.Size), tf.Size, i0, f);
  const int i1 = tf.Size >= 2 ? i0 + 1 : i0;
  const float* a = rgba + 4 * i0;
  const float* b = rgba + 4 * i1;
  out.Color = MakeVec3(Lerp(a[0], b[0], f), Lerp(a[1], b[1], f), Lerp(a[2], b[2], f));
  out.Opacity = Lerp(a[3], b[3], f);
  return out;
}

/// Whether the table's opacity is > 0 at some scalar between @a a and @a b (either order; a NaN
/// end counts as the other, two NaN ends as transparent), from OpaqueBefore (which must be
/// set): the table is linear between entries, so the entries from the one at or below the
/// interval's low end to the one at or above its high end decide -- exact but for the two end
/// cells, where it errs towards opacity. Gradient opacity, which only scales it down, is not
/// read.
PTV_HD PTV_INLINE bool MayBeOpaque(const TransferTable& tf, float a, float b)
{
  if (!(a == a))
  {
    a = b;
  }
  if (!(b == b))
  {
    b = a;
  }
  if (!(a == a) || tf.Size <= 0)
  {
    return false;
  }
  const float lo = TableCoordinate(Min(a, b), tf.ScalarMin, tf.ScalarMax, tf.Size);
  const float hi = TableCoordinate(Max(a, b), tf.ScalarMin, tf.ScalarMax, tf.Size);
  const int i0 = static_cast<int>(floorf(lo));
  const int i1 = Min(static_cast<int>(ceilf(hi)), tf.Size - 1);
  return tf.OpaqueBefore[i1 + 1] > tf.OpaqueBefore[i0];
}

/// OpaqueBefore of @a size entries of @a rgba (size + 1 counts into @a counts); the occupancy
/// grid (BuildOccupancy) tests its bricks' scalar ranges with the same counts.
inline void BuildOpaqueCounts(const float* rgba, int size, int* counts)
{
  counts[0] = 0;
  for (int i = 0; i < size; ++i)
  {
    counts[i + 1] = counts[i] + (rgba[4 * i + 3] > 0.f ? 1 : 0);
  }
}

/// Colour and opacity per unit distance at scalar s (linear between entries, clamped outside;
/// NaN is transparent).
PTV_HD PTV_INLINE TransferSample LookupTransfer(const TransferTable& tf, float s)
{
  return LookupRGBA(tf, tf.RGBA, s);
}

/// One value per entry (Size floats over tf's scalar range) at scalar s, as LookupRGBA; NaN or
/// no table gives 0.
PTV_HD PTV_INLINE float LookupValue(const TransferTable& tf, const float* values, float s)
{
  if (!values || tf.Size <= 0 || !(s == s))
  {
    return 0.f;
  }
  int i0;
  float f;
  TableCell(TableCoordinate(s, tf.ScalarMin, tf.ScalarMax, tf.Size), tf.Size, i0, f);
  const int i1 = tf.Size >= 2 ? i0 + 1 : i0;
  return Lerp(values[i0], values[i1], f);
}

/// True when a gradient-opacity table is present.
PTV_HD PTV_INLINE bool HasGradientOpacity(const TransferTable& tf)
{
  return tf.GradientOpacity && tf.GradientSize > 0;
}

/// Gradient-opacity factor at world-space gradient magnitude m (1 without a table).
PTV_HD PTV_INLINE float LookupGradientOpacity(const TransferTable& tf, float m)
{
  if (!HasGradientOpacity(tf))
  {
    return 1.f;
  }
  int i0;
  float f;
  TableCell(TableCoordinate(m, 0.f, tf.GradientMax, tf.GradientSize), tf.GradientSize, i0, f);
  const int i1 = tf.GradientSize >= 2 ? i0 + 1 : i0;
  return Lerp(tf.GradientOpacity[i0], tf.GradientOpacity[i1], f);
}

/**
 * Opacity of a segment of length stepOverUnit * UnitDistance for per-unit-distance opacity
 * alpha: 1 - (1 - alpha)^stepOverUnit, evaluated as -expm1(stepOverUnit * log1p(-alpha)) for
 * accuracy at small alpha. alpha <= 0 (or NaN) gives 0, alpha >= 1 gives 1.
 */
PTV_HD PTV_INLINE float CorrectOpacity(float alpha, float stepOverUnit)
{
  if (!(alpha > 0.f))
  {
    return 0.f;
  }
  if (alpha >= 1.f)
  {
    return 1.f;
  }
  return -expm1f(stepOverUnit * log1pf(-alpha));
}

/**
 * Fill the step-corrected copies of tf.RGBA (see TransferTable::StepRGBA, ShadowAlpha): 4 *
 * Size and Size floats. Interpolating corrected entries instead of correcting the interpolated
 * alpha differs only between entries, by the curvature of the correction (second order in the
 * entry spacing; VTK's GPU ray caster corrects its table the same way), and saves the two
 * transcendental calls per sample.
 */
inline void BuildStepTables(const TransferTable& tf, float stepOverUnit, float shadowStepOverUnit,
  float* stepRGBA, float* shadowAlpha)
{
  for (int i = 0; i < tf.Size; ++i)
  {
    const float* e = tf.RGBA + 4 * i;
    stepRGBA[4 * i + 0] = e[0];
    stepRGBA[4 * i + 1] = e[1];
    stepRGBA[4 * i + 2] = e[2];
    stepRGBA[4 * i + 3] = CorrectOpacity(e[3], stepOverUnit);
    shadowAlpha[i] = CorrectOpacity(e[3], shadowStepOverUnit);
  }
}
}

#endif
