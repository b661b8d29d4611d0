/**
 * @file ptvIntegrator.h
 * @brief The per-pixel Monte Carlo estimator: one sample of one pixel per call (TracePixel).
 *
 * The volume is an absorbing/scattering medium whose extinction is given by the transfer
 * function: a ray segment of length s has opacity CorrectOpacity(alpha, s / UnitDistance).
 * Each call returns an independent, unbiased-in-expectation sample; averaging frames converges
 * (RMSE ~ N^-1/2) to the front-to-back composite of the ray-marched volume under the shading
 * model below. All randomness comes from MakeRng(y * Width + x, Frame, Seed), drawn in a fixed
 * order, so results do not depend on threads, tiles or devices (up to FMA contraction).
 *
 * Algorithm for pixel (x, y):
 *  1. rng draws, in order: jitter ux, uy; march offset xi; scattering threshold u' = 1 - u in
 *     (0, 1] (always drawn). The camera ray through (x + ux, y + uy) (see ptvCamera.h) is moved
 *     to index space (origin by WorldToIndex, unit direction as a vector), so index position =
 *     oIdx + t dIdx with t in WORLD distance. [tStart, tEnd] = [max(tEnter, 0),
 *     min(tExit, MaxDistance[pixel])] (camera inside the volume works; opaque geometry clips).
 *  2. Samples at t_k = tStart + (k + xi) StepWorld, k = 0, 1, ... while t_k < tEnd (one jitter
 *     per ray, so for an integer number of steps the sample count is fixed and stratified).
 *     Per sample: s = trilinear (with Nearest: nearest-voxel) scalar, (c, alpha) = table(s),
 *     alpha *= gradient-opacity factor
 *     of the world-space gradient magnitude (if that table exists), a = CorrectOpacity(alpha,
 *     StepWorld / UnitDistance).
 *  3. First event: the first sample with a > 0 gives Depth1 = t, Position1 (world), Normal1 and
 *     Albedo = c there.
 *  4. Event (free-flight sampling): T <- T (1 - a) at every sample with a > 0, and with
 *     Scattering = 1 the event is the first such sample where 1 - T >= u'. It lands on sample k
 *     with probability T_k a_k (T_k = prod_{j<k} (1 - a_j)), so E[Alpha] and E[Radiance] are
 *     exactly the front-to-back composite sum_k T_k a_k L_k. With Scattering = 0 the event is the
 *     first event (an isosurface-like first hit). The march stops at the event.
 *  5. No event before tEnd: Radiance 0, Alpha 0 (premultiplied; the background is composited
 *     outside). Otherwise Alpha = 1, Depth2/Position2/Normal2 describe the event point x and
 *     Radiance = direct + ambient + env with c = colour at x:
 *     - normal n = normalize(NormalToWorld * -GradientIndex(x)), flipped so dot(n, -dir) >= 0;
 *       zero (unshaded) when |GradientIndex| <= 1e-6 of the table's scalar range per voxel.
 *     - direct: l = normalize(Light.Position - x) (shadow ray ends at the light) or -Direction.
 *       With Shade and n != 0: f = c Diffuse max(0, n.l) + Specular max(0, n.h)^SpecularPower,
 *       h = normalize(l - dir) (specular is not tinted by c); otherwise f = c Diffuse.
 *       direct = T_s Light.Radiance f, where T_s is the transmittance estimate along l (below).
 *       Shaded events (Shade and n != 0) start shadow and environment rays at x + StepWorld n,
 *       one step outside the layer they were sampled in (no self-shadowing of dense bands).
 *       The shadow ray is only traced (and its random numbers only drawn) when
 *       Light.Radiance f != 0.
 *     - ambient: c Ambient Light.Radiance (VTK's flat ambient term, unoccluded).
 *     - env: with AmbientOcclusion, one direction w and env = c Environment T_e(w), T_e the
 *       transmittance estimate along w; without it env = c Environment (unoccluded).
 *       Shade and n != 0: Lambertian, L = (c/pi) int_H E T(w) (n.w) dw; w ~ pdf (n.w)/pi, so
 *       the estimator (c/pi) E T (n.w) / ((n.w)/pi) = c E T. Otherwise an isotropic phase
 *       function, L = c int_S2 E T(w) / (4 pi) dw; w ~ uniform, pdf 1/(4 pi), estimator c E T.
 *       Drawn (u1, u2 then the march) only when c Environment != 0.
 *  6. Transmittance estimate (shadow and environment rays): from x along the unit direction,
 *     samples at (j + xi_s) StepWorld ShadowStepScale (own jitter xi_s), j >= 0, up to the box
 *     exit (or the light), T *= 1 - a_j with a_j corrected for the longer step. Russian
 *     roulette after each absorbing sample while T < 0.05: survive with probability 1/2 and
 *     double T, else return 0 -- unbiased (E = T) and terminating.
 *  Empty-space skipping (every march, see March()): when the current sample's brick is empty
 *  (ptvOccupancy.h), k jumps to the first sample index whose t is past the empty cube of bricks
 *  around it; the skipped samples all have a = 0 and draw no random numbers, so results are
 *  bit-identical with and without skipping.
 *  Clipping and cropping (ptvClipping.h): points that are cut away classify as transparent, and
 *  every march first clips its [tStart, tEnd] to the convex kept part (fewer samples only).
 *  Isosurfaces (Iso.Count > 0, ptvIsosurface.h): the medium is replaced by the surfaces where
 *  the scalar crosses an iso value. Camera and transmittance rays march one-voxel steps and meet
 *  the surfaces between samples; the events and transmittances follow steps 3-6 with the
 *  surface's opacity alpha (at its value) in place of a, at the crossing instead of a sample.
 *  Misses and no-event fields: Normal 0, Position 0, Depth = Camera.FarDistance, Albedo 0.
 *
 * Parameter guards: StepWorld <= 0 (or NaN) renders nothing; UnitDistance <= 0 means alpha is
 * already per step (no correction); ShadowStepScale <= 0 means 2. x, y must lie in the image.
 */
#ifndef ptvIntegrator_h
#define ptvIntegrator_h

#include "ptvCamera.h"
#include "ptvClipping.h"
#include "ptvIsosurface.h"
#include "ptvKernelCommon.h"
#include "ptvOccupancy.h"
#include "ptvRandom.h"
#include "ptvSampling.h"
#include "ptvTransferTable.h"
#include "ptvVolumeGrid.h"

namespace ptv
{
struct Light
{
  Vec3 Position;  ///< world position (positional lights)
  Vec3 Direction; ///< direction the light travels (directional lights)
  int Positional; ///< 1: point light at Position, 0: directional
  Vec3 Radiance;  ///< colour * intensity
};

struct TraceParams
{
  VolumeGrid Volume;
  TransferTable Transfer;
  OccupancyGrid Occupancy; ///< Occupancy.SkipDistance == nullptr: no skipping
  ClipRegion Clip;         ///< clipping planes and cropping (ptvClipping.h); default: none
  IsoSurfaces Iso;         ///< Iso.Count > 0: isosurfaces instead of the composite medium
  TransferTable ColorTable; ///< colours of Volume.ColorScalars (2-component data); else unused
  CameraRays Camera;
  Light KeyLight;
  Vec3 Environment;      ///< uniform environment radiance
  float StepWorld;       ///< camera-ray step in world units (typically one voxel)
  float ShadowStepScale; ///< shadow/environment step = StepWorld * ShadowStepScale (default 2)
  float UnitDistance;    ///< ScalarOpacityUnitDistance (world units)
  int Shade;
  float Ambient, Diffuse, Specular, SpecularPower;
  int Scattering;       ///< 1: event at a random opacity threshold, 0: first non-transparent sample
  int AmbientOcclusion; ///< 1: environment visibility traced, 0: unoccluded environment
  int Nearest;          ///< 1: nearest-voxel classification (VTK_NEAREST_INTERPOLATION)
  const float* MaxDistance; ///< per-pixel ray-length limit (world distance), nullptr = none
  uint32_t Seed;
  uint32_t Frame;
};

struct PixelSample
{
  Vec3 Radiance; ///< premultiplied radiance (0 without an event)
  float Alpha;   ///< 1 with an event, else 0
  Vec3 Albedo;   ///< colour at the first event
  float Depth1;  ///< first event: ray distance
  Vec3 Position1;
  Vec3 Normal1;
  float Depth2; ///< sampled (scattering) event: ray distance
  Vec3 Position2;
  Vec3 Normal2;
};

/// acc += s, field by field (averaging several samples of a pixel: CPU and CUDA drivers).
PTV_HD PTV_INLINE void AddSample(PixelSample& acc, const PixelSample& s)
{
  acc.Radiance = acc.Radiance + s.Radiance;
  acc.Alpha += s.Alpha;
  acc.Albedo = acc.Albedo + s.Albedo;
  acc.Depth1 += s.Depth1;
  acc.Position1 = acc.Position1 + s.Position1;
  acc.Normal1 = acc.Normal1 + s.Normal1;
  acc.Depth2 += s.Depth2;
  acc.Position2 = acc.Position2 + s.Position2;
  acc.Normal2 = acc.Normal2 + s.Normal2;
}

/// acc *= w, field by field.
PTV_HD PTV_INLINE void ScaleSample(PixelSample& acc, float w)
{
  acc.Radiance = acc.Radiance * w;
  acc.Alpha *= w;
  acc.Albedo = acc.Albedo * w;
  acc.Depth1 *= w;
  acc.Position1 = acc.Position1 * w;
  acc.Normal1 = acc.Normal1 * w;
  acc.Depth2 *= w;
  acc.Position2 = acc.Position2 * w;
  acc.Normal2 = acc.Normal2 * w;
}

constexpr float kRouletteThreshold = 0.05f;

/// Ray parameter of march sample k; the single expression every march uses.
PTV_HD PTV_INLINE float MarchSampleT(float tStart, float xi, float step, int k)
{
  return tStart + (static_cast<float>(k) + xi) * step;
}

/// An upper bound on the number of samples in [tStart, tEnd) (clamped to 2^30).
PTV_HD PTV_INLINE int MarchSampleLimit(float tStart, float tEnd, float xi, float step)
{
  const float n = ceilf((tEnd - tStart) / step - xi) + 2.f;
  return static_cast<int>(Clamp(n, 0.f, 1073741824.f));
}

/// Smallest k in [kMin, kLimit] with MarchSampleT(k) >= tTarget (kLimit if none); invStep =
/// 1 / step only seeds the search, the result is exact.
PTV_HD PTV_INLINE int FirstSampleAtOrAfter(
  float tStart, float xi, float step, float invStep, float tTarget, int kMin, int kLimit)
{
  const float estimate = ceilf((tTarget - tStart) * invStep - xi);
  if (!(estimate < static_cast<float>(kLimit)))
  {
    return kLimit;
  }
  int k = estimate > static_cast<float>(kMin) ? static_cast<int>(estimate) : kMin;
  while (k > kMin && MarchSampleT(tStart, xi, step, k - 1) >= tTarget)
  {
    --k;
  }
  while (k < kLimit && MarchSampleT(tStart, xi, step, k) < tTarget)
  {
    ++k;
  }
  return k;
}

/**
 * The one march every ray uses (camera, shadow and environment rays): the samples t_k =
 * MarchSampleT(tStart, xi, step, k), k = 0, 1, ... with t_k < tEnd, in order, calling
 * visit(k, t, pIdx) (pIdx = oIdx + dIdx t) for each until it returns true (stop). With an occupancy
 * grid, samples in empty regions are skipped without a call: at a sample in an empty brick the
 * march jumps to the first sample at or after the exit of the empty cube around it
 * (RegionExitT); at a sample in an occupied brick it visits every sample before that brick's
 * exit without further lookups. Skipped samples all have zero opacity and visiting one more
 * (rounding at a brick face) only classifies a transparent sample, so the visits that matter are
 * the same with and without skipping.
 */
template <class Visit>
PTV_HD PTV_INLINE void March(const OccupancyGrid& occ, Vec3 oIdx, Vec3 dIdx, float tStart,
  float tEnd, float xi, float step, Visit&& visit)
{
  const int kLimit = MarchSampleLimit(tStart, tEnd, xi, step);
  // Reciprocals for the skipping arithmetic (per ray, not per brick).
  const float invStep = 1.f / step;
  const float invBrick = occ.SkipDistance ? 1.f / static_cast<float>(occ.BrickSize) : 0.f;
  const Vec3 invD = MakeVec3(1.f / dIdx.x, 1.f / dIdx.y, 1.f / dIdx.z);
  int k = 0;
  while (k < kLimit)
  {
    float t = MarchSampleT(tStart, xi, step, k);
    if (!(t < tEnd))
    {
      return;
    }
    Vec3 pIdx = oIdx + dIdx * t;
    int kEnd = kLimit;
    if (occ.SkipDistance)
    {
      int b[3];
      BrickOf(occ, pIdx, invBrick, b);
      const int distance = SkipDistanceAt(occ, b);
      const float tExit =
        RegionExitT(occ, oIdx, dIdx, invD, t, b, distance > 0 ? distance - 1 : 0);
      const int kExit = FirstSampleAtOrAfter(tStart, xi, step, invStep, tExit, k + 1, kLimit);
      if (distance > 0)
      {
        k = kExit;
        continue;
      }
      kEnd = kExit;
    }
    for (;;)
    {
      if (visit(k, t, pIdx))
      {
        return;
      }
      if (++k >= kEnd)
      {
        break;
      }
      t = MarchSampleT(tStart, xi, step, k);
      if (!(t < tEnd))
      {
        return;
      }
      pIdx = oIdx + dIdx * t;
    }
  }
}

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

/// Colour and (uncorrected) opacity per unit distance at an index-space point, including the
/// gradient-opacity factor.
PTV_HD PTV_INLINE TransferSample ClassifyPoint(const TraceParams& p, Vec3 pIdx)
{
  const float s =
    p.Nearest ? SampleNearest(p.Volume, pIdx) : SampleTrilinear(p.Volume, pIdx);
  TransferSample ts = LookupTransfer(p.Transfer, s);
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

/// Isosurface marches: the scalar at a sample, NaN where the point is cut away (no crossing).
PTV_HD PTV_INLINE float IsoScalar(const TraceParams& p, Vec3 pIdx)
{
  if (HasClipping(p.Clip) && !KeptPoint(p.Clip, pIdx))
  {
    return nanf("");
  }
  return p.Nearest ? SampleNearest(p.Volume, pIdx) : SampleTrilinear(p.Volume, pIdx);
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

/// Russian roulette while T < kRouletteThreshold: survive with probability 1/2 and double T
/// (unbiased); returns false (and T = 0) when the ray ends.
PTV_HD PTV_INLINE bool Roulette(float& T, Rng& rng)
{
  while (T < kRouletteThreshold)
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
PTV_HD PTV_INLINE PTV_NOINLINE float EstimateTransmittanceIso(const TraceParams& p, Vec3 oIdx, Vec3 dIdx,
  float tStart, float tEnd, float xi, Rng& rng)
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
          return !Roulette(T, rng);
        });
    });
  return T;
}

/**
 * Unbiased transmittance estimate from world point x along unit direction w up to distance
 * tMax (or the box exit): jittered march with step StepWorld * ShadowStepScale, empty-space
 * skipping and Russian roulette (see the file comment, step 6).
 */
PTV_HD PTV_INLINE float EstimateTransmittance(
  const TraceParams& p, Vec3 x, Vec3 w, float tMax, Rng& rng)
{
  const float xi = NextFloat(rng);
  const float step = p.StepWorld * (p.ShadowStepScale > 0.f ? p.ShadowStepScale : 2.f);
  const float stepOverUnit = StepOverUnit(p, step);
  const Vec3 oIdx = TransformPoint(p.Volume.WorldToIndex, x);
  const Vec3 dIdx = TransformVector(p.Volume.WorldToIndex, w);
  float tEnter, tExit;
  if (!IntersectBox(p.Volume, oIdx, dIdx, tEnter, tExit))
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
  March(p.Occupancy, oIdx, dIdx, tStart, tEnd, xi, step,
    [&](int, float, Vec3 pIdx)
    {
      const float a = CorrectOpacity(ClassifyPoint(p, pIdx).Opacity, stepOverUnit);
      if (a > 0.f)
      {
        T *= 1.f - a;
        if (!(T > 0.f))
        {
          T = 0.f;
          return true;
        }
        return !Roulette(T, rng);
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
  const Vec3 directCoefficient = light.Radiance * f;
  if (!IsZero(directCoefficient) && !IsZero(l))
  {
    radiance += directCoefficient * EstimateTransmittance(p, xs, l, lightDistance, rng);
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
    radiance += envCoefficient * EstimateTransmittance(p, xs, w, kTMax, rng);
  }
  return radiance;
}

/// The camera ray of TracePixel() through isosurfaces (ptvIsosurface.h), filling @a out.
PTV_HD PTV_INLINE PTV_NOINLINE void TraceIsoSurfaces(const TraceParams& p, Vec3 origin, Vec3 dir, Vec3 oIdx,
  Vec3 dIdx, float tStart, float tEnd, float xi, float threshold, Rng& rng, PixelSample& out)
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

/// One Monte Carlo sample of pixel (x, y) for sample (frame) index @a frame (see the file
/// comment; p.Frame is not read).
PTV_HD PTV_INLINE PixelSample TracePixel(const TraceParams& p, int x, int y, uint32_t frame)
{
  PixelSample out = MissSample(p.Camera.FarDistance);
  const uint32_t pixel =
    static_cast<uint32_t>(y) * static_cast<uint32_t>(p.Camera.Width) + static_cast<uint32_t>(x);
  Rng rng = MakeRng(pixel, frame, p.Seed);
  const float jx = NextFloat(rng);
  const float jy = NextFloat(rng);
  const float xi = NextFloat(rng);
  const float threshold = 1.f - NextFloat(rng); // in (0, 1]

  const float step = p.StepWorld;
  if (!(step > 0.f))
  {
    return out;
  }
  Vec3 origin, dir;
  GenerateRay(p.Camera, static_cast<float>(x) + jx, static_cast<float>(y) + jy, origin, dir);
  const Vec3 oIdx = TransformPoint(p.Volume.WorldToIndex, origin);
  const Vec3 dIdx = TransformVector(p.Volume.WorldToIndex, dir);
  float tEnter, tExit;
  if (!IntersectBox(p.Volume, oIdx, dIdx, tEnter, tExit))
  {
    return out;
  }
  float tStart = Max(tEnter, 0.f);
  float tEnd = p.MaxDistance ? Min(tExit, p.MaxDistance[pixel]) : tExit;
  if (HasClipping(p.Clip) && !ClipInterval(p.Clip, oIdx, dIdx, tStart, tEnd))
  {
    return out;
  }
  if (!(tStart < tEnd))
  {
    return out;
  }

  float T = 1.f;
  bool haveFirst = false;
  if (p.Iso.Count > 0)
  {
    TraceIsoSurfaces(p, origin, dir, oIdx, dIdx, tStart, tEnd, xi, threshold, rng, out);
    return out;
  }
  const float stepOverUnit = StepOverUnit(p, step);
  March(p.Occupancy, oIdx, dIdx, tStart, tEnd, xi, step,
    [&](int, float t, Vec3 pIdx)
    {
      const TransferSample ts = ClassifyPoint(p, pIdx);
      const float a = CorrectOpacity(ts.Opacity, stepOverUnit);
      if (!(a > 0.f))
      {
        return false;
      }
      const bool first = !haveFirst;
      if (first)
      {
        haveFirst = true;
        out.Depth1 = t;
        out.Position1 = origin + dir * t;
        out.Normal1 = ShadingNormal(p, pIdx, dir);
        out.Albedo = ts.Color;
      }
      T *= 1.f - a;
      if (p.Scattering && 1.f - T < threshold)
      {
        return false;
      }
      const Vec3 event = origin + dir * t;
      const Vec3 n = first ? out.Normal1 : ShadingNormal(p, pIdx, dir);
      out.Alpha = 1.f;
      out.Depth2 = t;
      out.Position2 = event;
      out.Normal2 = n;
      out.Radiance = ShadeEvent(p, event, dir, ts.Color, n, rng);
      return true;
    });
  return out;
}

/// One Monte Carlo sample of pixel (x, y) for frame p.Frame.
PTV_HD PTV_INLINE PixelSample TracePixel(const TraceParams& p, int x, int y)
{
  return TracePixel(p, x, y, p.Frame);
}

/**
 * Mean of @a samples samples of pixel (x, y) with sample (frame) indices firstSample,
 * firstSample + 1, ...: what one frame of SamplesPerFrame stores. Both drivers (CPU, CUDA) call
 * this, so a frame is the same on either.
 */
PTV_HD PTV_INLINE PixelSample TracePixelMean(
  const TraceParams& p, uint32_t firstSample, int samples, int x, int y)
{
  PixelSample acc = TracePixel(p, x, y, firstSample);
  for (int s = 1; s < samples; ++s)
  {
    AddSample(acc, TracePixel(p, x, y, firstSample + static_cast<uint32_t>(s)));
  }
  if (samples > 1)
  {
    ScaleSample(acc, 1.f / static_cast<float>(samples));
  }
  return acc;
}
}

#endif
