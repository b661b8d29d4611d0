/**
 * @file ptvShading.h
 * @brief What happens at samples and events: classification (transfer function, gradient
 *        opacity, clipping, colour data), normals, the transmittance estimate of shadow and
 *        environment rays (composite medium and isosurfaces), and the radiance of an event
 *        (ptvIntegrator.h, steps 2 and 5-6).
 */
#ifndef ptvShading_h
#define ptvShading_h

#include "ptvMarch.h"
#include "ptvRandom.h"
#include "ptvSampling.h"
#include "ptvTraceParams.h"

namespace ptv
{
constexpr float kRouletteThreshold = 0.05f;
/// Shadow and environment steps in camera steps (chosen by research/benchmarks/shadow_step.py).
constexpr float kShadowStepScale = 2.f;

/// Colour from dependent colour data at an index-space point (see VolumeGrid::Colors), or
/// @a fallback (the transfer function's colour) without such data.
PTV_HD PTV_INLINE Vec3 SampleColor(const TraceParams& p, Vec3 pIdx, Vec3 fallback)
{
  const VolumeGrid& g = p.Volume;
  if (g.ColorScalars)
  {
    const float c = p.Nearest ? SampleNearestArray(g, g.ColorScalars, 1, pIdx)
                              : SampleTrilinearArray(g, g.ColorScalars, 1, pIdx);
    return LookupTransfer(p.ColorTable, c).Color;
  }
  if (g.Colors)
  {
    float rgb[3];
    for (int c = 0; c < 3; ++c)
    {
      rgb[c] = p.Nearest ? SampleNearestArray(g, g.Colors + c, 3, pIdx)
                         : SampleTrilinearArray(g, g.Colors + c, 3, pIdx);
    }
    return MakeVec3(rgb[0], rgb[1], rgb[2]);
  }
  return fallback;
}

/// The scalar at an index-space point (trilinear, or the nearest voxel's).
PTV_HD PTV_INLINE float SampleScalar(const TraceParams& p, Vec3 pIdx)
{
  return p.Nearest ? SampleNearest(p.Volume, pIdx) : SampleTrilinear(p.Volume, pIdx);
}

/// Colour and opacity at an index-space point from @a rgba (p.Transfer.RGBA or a copy laid out
/// as it), with clipping, the gradient-opacity factor and dependent colour data.
PTV_HD PTV_INLINE TransferSample ClassifyFrom(const TraceParams& p, const float* rgba, Vec3 pIdx)
{
  TransferSample ts = LookupRGBA(p.Transfer, rgba, SampleScalar(p, pIdx));
  if (!(ts.Opacity > 0.f))
  {
    return ts; // transparent whether or not the point is cut away
  }
  if (HasClipping(p.Clip) && !KeptPoint(p.Clip, pIdx))
  {
    return TransferSample{ MakeVec3(0.f, 0.f, 0.f), 0.f }; // cut away: transparent
  }
  if (HasGradientOpacity(p.Transfer))
  {
    const Vec3 gWorld = MultiplyMatrix3(p.Volume.NormalToWorld, GradientIndex(p.Volume, pIdx));
    ts.Opacity *= LookupGradientOpacity(p.Transfer, Length(gWorld));
  }
  if (ts.Opacity > 0.f)
  {
    ts.Color = SampleColor(p, pIdx, ts.Color);
  }
  return ts;
}

/// Colour and (uncorrected) opacity per unit distance at an index-space point, including the
/// gradient-opacity factor.
PTV_HD PTV_INLINE TransferSample ClassifyPoint(const TraceParams& p, Vec3 pIdx)
{
  return ClassifyFrom(p, p.Transfer.RGBA, pIdx);
}

/// Colour and opacity of one camera-ray step at pIdx: ClassifyPoint with the opacity corrected
/// for the step (CorrectOpacity(alpha, stepOverUnit)), read from the step-corrected table when
/// the frame has one (TransferTable::StepRGBA).
PTV_HD PTV_INLINE TransferSample ClassifyStep(const TraceParams& p, Vec3 pIdx, float stepOverUnit)
{
  if (!p.Transfer.StepRGBA)
  {
    TransferSample ts = ClassifyPoint(p, pIdx);
    ts.Opacity = CorrectOpacity(ts.Opacity, stepOverUnit);
    return ts;
  }
  return ClassifyFrom(p, p.Transfer.StepRGBA, pIdx); // (set only without gradient opacity)
}

/// Opacity of one shadow/environment step at pIdx (ClassifyStep's opacity for that step; from
/// TransferTable::ShadowAlpha when the frame has it, without computing a colour).
PTV_HD PTV_INLINE float ShadowStepOpacity(const TraceParams& p, Vec3 pIdx, float stepOverUnit)
{
  if (!p.Transfer.ShadowAlpha)
  {
    return CorrectOpacity(ClassifyPoint(p, pIdx).Opacity, stepOverUnit);
  }
  const float a = LookupValue(p.Transfer, p.Transfer.ShadowAlpha, SampleScalar(p, pIdx));
  return a > 0.f && !(HasClipping(p.Clip) && !KeptPoint(p.Clip, pIdx)) ? a : 0.f;
}

/// Isosurface marches: the scalar at a sample, NaN where the point is cut away (no crossing).
PTV_HD PTV_INLINE float IsoScalar(const TraceParams& p, Vec3 pIdx)
{
  if (HasClipping(p.Clip) && !KeptPoint(p.Clip, pIdx))
  {
    return nanf("");
  }
  return SampleScalar(p, pIdx);
}

/**
 * The crossings of one isosurface march step: the previous visited sample (index, t, scalar)
 * and the current one; crossings count only between consecutive samples (a skipped sample lies
 * in an empty brick, whose neighbouring step crosses nothing; ptvIsosurface.h).
 */
struct IsoStep
{
  int K = -2;
  float T = 0.f;
  float S = 0.f;
  /// For sample (k, t, s): visit(tHit, value) per crossing since the previous sample, in order.
  template <class Visit>
  PTV_HD PTV_INLINE bool Advance(const IsoSurfaces& iso, int k, float t, float s, Visit&& visit)
  {
    const bool consecutive = k == this->K + 1;
    const float t0 = this->T, s0 = this->S;
    this->K = k;
    this->T = t;
    this->S = s;
    return consecutive &&
      ForEachCrossing(iso, s0, s,
        [&](float f, float v) { return visit(t0 + f * (t - t0), v); });
  }
};

/// World-space unit normal at pIdx facing against viewDir, or 0 where the gradient is ~0.
PTV_HD PTV_INLINE Vec3 ShadingNormal(const TraceParams& p, Vec3 pIdx, Vec3 viewDir)
{
  const Vec3 g = GradientIndex(p.Volume, pIdx);
  const float range = fabsf(p.Transfer.ScalarMax - p.Transfer.ScalarMin);
  if (!(Length(g) > 1e-6f * (range > 0.f ? range : 1.f)))
  {
    return MakeVec3(0.f, 0.f, 0.f);
  }
  Vec3 n = Normalize(MultiplyMatrix3(p.Volume.NormalToWorld, -g));
  if (Dot(n, viewDir) > 0.f)
  {
    n = -n;
  }
  return n;
}

PTV_HD PTV_INLINE float StepOverUnit(const TraceParams& p, float step)
{
  return p.UnitDistance > 0.f ? step / p.UnitDistance : 1.f;
}

/// World step of shadow and environment rays (StepWorld * ShadowStepScale; kShadowStepScale
/// when that is not positive).
PTV_HD PTV_INLINE float ShadowStep(const TraceParams& p)
{
  return p.StepWorld * (p.ShadowStepScale > 0.f ? p.ShadowStepScale : kShadowStepScale);
}

/// The step of shadow and environment rays and the quotients each of them needs: computed once
/// per event (ShadeEvent), not per ray, to keep divisions out of the rays' setup.
struct TransmittanceSteps
{
  float Step;         ///< ShadowStep(p)
  float InvStep;      ///< 1 / Step
  float StepOverUnit; ///< StepOverUnit(p, Step)
};

PTV_HD PTV_INLINE TransmittanceSteps MakeTransmittanceSteps(const TraceParams& p)
{
  TransmittanceSteps s;
  s.Step = ShadowStep(p);
  s.InvStep = 1.f / s.Step;
  s.StepOverUnit = StepOverUnit(p, s.Step);
  return s;
}

/// Russian roulette while T < the threshold (TraceParams::RouletteThreshold): survive with
/// probability 1/2 and double T (unbiased); returns false (and T = 0) when the ray ends.
PTV_HD PTV_INLINE bool Roulette(const TraceParams& p, float& T, Rng& rng)
{
  const float threshold = p.RouletteThreshold > 0.f ? p.RouletteThreshold : kRouletteThreshold;
  while (T < threshold)
  {
    if (NextFloat(rng) >= 0.5f)
    {
      T = 0.f;
      return false;
    }
    T *= 2.f;
  }
  return true;
}

/// EstimateTransmittance() through isosurfaces: 1 - alpha per crossing, one-voxel steps
/// (ptvIsosurface.h); [tStart, tEnd] already clipped, xi the march jitter.
PTV_HD PTV_INLINE PTV_NOINLINE float EstimateTransmittanceIso(const TraceParams& p,
  Vec3 oIdx, Vec3 dIdx, float tStart, float tEnd, float xi, Rng& rng)
{
  float T = 1.f;
  IsoStep iso;
  March(p.Occupancy, oIdx, dIdx, tStart, tEnd, xi, p.StepWorld,
    [&](int k, float t, Vec3 pIdx)
    {
      return iso.Advance(p.Iso, k, t, IsoScalar(p, pIdx),
        [&](float, float v)
        {
          T *= 1.f - LookupTransfer(p.Transfer, v).Opacity;
          if (!(T > 0.f))
          {
            T = 0.f;
            return true;
          }
          return !Roulette(p, T, rng);
        });
    });
  return T;
}

/**
 * Unbiased transmittance estimate from world point x along unit direction w up to distance
 * tMax (or the box exit): jittered march with step StepWorld * ShadowStepScale (@a steps =
 * MakeTransmittanceSteps(p)), empty-space skipping and Russian roulette (see the file comment,
 * step 6).
 */
PTV_HD PTV_INLINE float EstimateTransmittance(const TraceParams& p,
  const TransmittanceSteps& steps, Vec3 x, Vec3 w, float tMax, Rng& rng)
{
  const float xi = NextFloat(rng);
  const Vec3 oIdx = TransformPoint(p.Volume.WorldToIndex, x);
  const Vec3 dIdx = TransformVector(p.Volume.WorldToIndex, w);
  const Vec3 invD = Reciprocal(dIdx);
  float tEnter, tExit;
  if (!IntersectBox(p.Volume, oIdx, dIdx, invD, tEnter, tExit))
  {
    return 1.f;
  }
  float tStart = Max(tEnter, 0.f);
  float tEnd = Min(tExit, tMax);
  if (HasClipping(p.Clip) && !ClipInterval(p.Clip, oIdx, dIdx, tStart, tEnd))
  {
    return 1.f; // the ray meets no kept point
  }
  float T = 1.f;
  if (p.Iso.Count > 0)
  {
    return EstimateTransmittanceIso(p, oIdx, dIdx, tStart, tEnd, xi, rng);
  }
  March(p.Occupancy, oIdx, dIdx, invD, tStart, tEnd, xi, steps.Step, steps.InvStep,
    [&](int, float, Vec3 pIdx)
    {
      const float a = ShadowStepOpacity(p, pIdx, steps.StepOverUnit);
      if (a > 0.f)
      {
        T *= 1.f - a;
        if (!(T > 0.f))
        {
          T = 0.f;
          return true;
        }
        return !Roulette(p, T, rng);
      }
      return false;
    });
  return T;
}

/// The values of a pixel without any volume contribution.
PTV_HD PTV_INLINE PixelSample MissSample(float farDistance)
{
  const Vec3 zero = MakeVec3(0.f, 0.f, 0.f);
  PixelSample s;
  s.Radiance = zero;
  s.Alpha = 0.f;
  s.Albedo = zero;
  s.Depth1 = farDistance;
  s.Position1 = zero;
  s.Normal1 = zero;
  s.Depth2 = farDistance;
  s.Position2 = zero;
  s.Normal2 = zero;
  s.Coverage = 0.f;
  s.Footprint = 1.f;
  return s;
}

/// Radiance leaving event point x (world) with colour c and normal n towards -dir (step 5).
PTV_HD PTV_INLINE Vec3 ShadeEvent(
  const TraceParams& p, Vec3 x, Vec3 dir, Vec3 c, Vec3 n, Rng& rng)
{
  const Light& light = p.KeyLight;
  const bool shaded = p.Shade && !IsZero(n);
  // Surface-like events (shaded, with a gradient) start their shadow and environment rays one
  // step outside along the normal: otherwise a dense band shadows itself (the ray re-crosses the
  // layer it was sampled in) and the estimate turns into near-binary noise.
  const Vec3 xs = shaded ? x + n * p.StepWorld : x;

  // Direct light with a stochastic shadow ray.
  Vec3 l;
  float lightDistance = kTMax;
  if (light.Positional)
  {
    const Vec3 toLight = light.Position - xs;
    lightDistance = Length(toLight);
    l = Normalize(toLight);
  }
  else
  {
    l = Normalize(-light.Direction);
  }
  Vec3 f;
  if (shaded)
  {
    const float ndl = Max(0.f, Dot(n, l));
    const float ndh = Max(0.f, Dot(n, Normalize(l - dir)));
    const float spec = ndh > 0.f ? p.Specular * powf(ndh, p.SpecularPower) : 0.f;
    f = c * (p.Diffuse * ndl) + MakeVec3(spec, spec, spec);
  }
  else
  {
    f = c * p.Diffuse;
  }
  Vec3 radiance = MakeVec3(0.f, 0.f, 0.f);
  const TransmittanceSteps steps = MakeTransmittanceSteps(p);
  const Vec3 directCoefficient = light.Radiance * f;
  if (!IsZero(directCoefficient) && !IsZero(l))
  {
    radiance +=
      directCoefficient * EstimateTransmittance(p, steps, xs, l, lightDistance, rng);
  }

  // VTK's flat ambient term.
  radiance += c * p.Ambient * light.Radiance;

  // Environment: (c/pi) int E T cos / (cos/pi) = c E T, or isotropic (c/4pi) int E T / (1/4pi).
  const Vec3 envCoefficient = c * p.Environment;
  if (!p.AmbientOcclusion)
  {
    radiance += envCoefficient;
  }
  else if (!IsZero(envCoefficient))
  {
    const float u1 = NextFloat(rng);
    const float u2 = NextFloat(rng);
    const Vec3 w = shaded ? SampleCosineHemisphere(n, u1, u2) : SampleUniformSphere(u1, u2);
    const float reach = p.EnvironmentReach > 0.f ? p.EnvironmentReach : kTMax;
    radiance += envCoefficient * EstimateTransmittance(p, steps, xs, w, reach, rng);
  }
  return radiance;
}
}

#endif
