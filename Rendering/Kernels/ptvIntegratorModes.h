/**
 * @file ptvIntegratorModes.h
 * @brief The camera rays of TracePixel() that are not a scattering medium: isosurfaces and
 * intensity projections (the steps refer to ptvIntegrator.h's file comment).
 *
 * Isosurfaces (Iso.Count > 0, ptvIsosurface.h): the medium is replaced by the surfaces where
 * the scalar crosses an iso value. Camera and transmittance rays march one-voxel steps and meet
 * the surfaces between samples; the events and transmittances follow steps 3-6 with the
 * surface's opacity alpha (at its value) in place of a, at the crossing instead of a sample.
 *
 * Projections (Projection > 0, VTK's intensity blend modes; no light transport, no draws after
 * step 1): the camera ray visits every sample of step 2 (no skipping: a projection reads
 * scalars, not opacities), cut-away and no-data samples excluded. MaximumIntensity /
 * MinimumIntensity: the largest / smallest scalar m; Alpha = alpha(m) uncorrected and
 * Radiance = c(m) alpha(m), the first event at m's sample (as VTK's ray casters). Average /
 * Additive (as vtkGPUVolumeRayCastMapper): the mean (over samples with AverageLo <= s <=
 * AverageHi) / the sum of a s_n, a the step-corrected opacity and s_n the scalar normalized
 * to the table's range, clamped to [0, 1], as a grey of Alpha 1 wherever the ray met a sample
 * (first event at its entry). The pixel jitter and the march offset still vary per sample, so
 * frames average into an antialiased image.
 */
#ifndef ptvIntegratorModes_h
#define ptvIntegratorModes_h

#include "ptvShading.h"

namespace ptv
{
/// The camera ray of TracePixel() through isosurfaces (ptvIsosurface.h), filling @a out.
PTV_HD PTV_INLINE PTV_NOINLINE void TraceIsoSurfaces(const TraceParams& p, Vec3 origin,
  Vec3 dir, Vec3 oIdx, Vec3 dIdx, float tStart, float tEnd, float xi, float threshold, Rng& rng,
  PixelSample& out)
{
  const float step = p.StepWorld;
  float T = 1.f;
  bool haveFirst = false;
  // Isosurfaces: the first crossing is the first event; a surface of opacity alpha scatters
  // when 1 - T >= threshold after T *= 1 - alpha (ptvIsosurface.h).
  IsoStep iso;
  March(p.Occupancy, oIdx, dIdx, tStart, tEnd, xi, step,
    [&](int k, float t, Vec3 pIdx)
    {
      return iso.Advance(p.Iso, k, t, IsoScalar(p, pIdx),
        [&](float tHit, float v)
        {
          const TransferSample ts = LookupTransfer(p.Transfer, v);
          if (!(ts.Opacity > 0.f))
          {
            return false;
          }
          const Vec3 hit = origin + dir * tHit;
          const Vec3 hitIdx = oIdx + dIdx * tHit;
          const Vec3 n = ShadingNormal(p, hitIdx, dir);
          const Vec3 color = SampleColor(p, hitIdx, ts.Color);
          if (!haveFirst)
          {
            haveFirst = true;
            out.Depth1 = tHit;
            out.Position1 = hit;
            out.Normal1 = n;
            out.Albedo = color;
          }
          T *= 1.f - ts.Opacity;
          if (p.Scattering && 1.f - T < threshold)
          {
            return false;
          }
          out.Alpha = 1.f;
          out.Depth2 = tHit;
          out.Position2 = hit;
          out.Normal2 = n;
          out.Radiance = ShadeEvent(p, hit, dir, color, n, rng);
          return true;
        });
    });
}

/// Step 3: the first-event fields of @a out, for the sample at ray distance @a t (index
/// position @a pIdx, colour @a color).
PTV_HD PTV_INLINE void SetFirstEvent(const TraceParams& p, Vec3 origin, Vec3 dir, float t,
  Vec3 pIdx, Vec3 color, PixelSample& out)
{
  out.Depth1 = t;
  out.Position1 = origin + dir * t;
  out.Normal1 = ShadingNormal(p, pIdx, dir);
  out.Albedo = color;
}

/// The camera ray of TracePixel() for an intensity projection (TraceParams::Projection; see the
/// file comment), filling @a out.
PTV_HD PTV_INLINE PTV_NOINLINE void TraceProjection(const TraceParams& p, Vec3 origin, Vec3 dir,
  Vec3 oIdx, Vec3 dIdx, float tStart, float tEnd, float xi, PixelSample& out)
{
  const float step = p.StepWorld;
  const TransferTable& tf = p.Transfer;
  const float span = tf.ScalarMax - tf.ScalarMin;
  const float invSpan = span > 0.f ? 1.f / span : 0.f;
  const float stepOverUnit = StepOverUnit(p, step);
  const bool extreme = p.Projection == kProjectionMaximum || p.Projection == kProjectionMinimum;
  float best = 0.f, bestT = 0.f, sum = 0.f, firstT = 0.f;
  int count = 0;
  for (int k = 0;; ++k)
  {
    const float t = tStart + (static_cast<float>(k) + xi) * step;
    if (!(t < tEnd))
    {
      break;
    }
    const float s = IsoScalar(p, oIdx + dIdx * t); // NaN where cut away or without data
    if (!(s == s) ||
      (p.Projection == kProjectionAverage && !(s >= p.AverageLo && s <= p.AverageHi)))
    {
      continue;
    }
    if (count++ == 0)
    {
      firstT = t;
    }
    if (extreme)
    {
      if (count == 1 || (p.Projection == kProjectionMaximum ? s > best : s < best))
      {
        best = s;
        bestT = t;
      }
      continue;
    }
    const float a = CorrectOpacity(LookupTransfer(tf, s).Opacity, stepOverUnit);
    sum += a * Clamp((s - tf.ScalarMin) * invSpan, 0.f, 1.f);
  }
  if (count == 0)
  {
    return;
  }
  if (extreme)
  {
    const TransferSample ts = LookupTransfer(tf, best);
    out.Alpha = ts.Opacity;
    out.Radiance = ts.Color * ts.Opacity;
    if (ts.Opacity > 0.f)
    {
      SetFirstEvent(p, origin, dir, bestT, oIdx + dIdx * bestT, ts.Color, out);
    }
  }
  else
  {
    const float g =
      Clamp(p.Projection == kProjectionAverage ? sum / static_cast<float>(count) : sum, 0.f, 1.f);
    out.Alpha = 1.f;
    out.Radiance = MakeVec3(g, g, g);
    SetFirstEvent(p, origin, dir, firstT, oIdx + dIdx * firstT, out.Radiance, out);
  }
  out.Depth2 = out.Depth1;
  out.Position2 = out.Position1;
  out.Normal2 = out.Normal1;
}

} // namespace ptv

#endif // ptvIntegratorModes_h
