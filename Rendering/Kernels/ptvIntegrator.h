/**
 * @file ptvIntegrator.h
 * @brief The per-pixel Monte Carlo estimator: one sample of one pixel per call (TracePixel).
 *
 * The pieces, bottom up: ptvTraceParams.h (the structs), ptvMarch.h (the one march of every
 * ray, with empty-space skipping), ptvShading.h (classification, normals, transmittance and
 * the radiance of an event); ptvIntegratorModes.h (isosurfaces and
 * intensity projections); this file runs the camera ray.
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
 *     min(tExit, MaxDistance[pixel])] (camera inside the volume works; opaque geometry clips),
 *     and with CameraBoxed further clipped to CameraBox (a distributed piece without its ghost
 *     layers; OverSample in ptvTraceParams.h composites the pieces' samples), its xi moved so
 *     that it samples where the ray through the whole volume (WholeBox) would (ClipToPiece).
 *     With PieceStream k > 0, every draw after ux, uy, xi comes from MakeRng(pixel, frame, Seed
 *     ^ PcgHash(k)): pieces share the camera ray and its samples (a pixel's coverage at a
 *     silhouette, the discrete transmittance), and their events are independent, as one ray's
 *     free flight is in consecutive segments: the composite is the whole ray's sample.
 *  2. Samples at t_k = tStart + (k + xi) StepWorld, k = 0, 1, ... while t_k < tEnd (one jitter
 *     per ray, so for an integer number of steps the sample count is fixed and stratified).
 *     Per sample: s = trilinear (with Nearest: nearest-voxel) scalar, (c, alpha) = table(s),
 *     alpha *= gradient-opacity factor
 *     of the world-space gradient magnitude (if that table exists), a = CorrectOpacity(alpha,
 *     StepWorld / UnitDistance). Without gradient opacity the frame carries the table with its
 *     entries already corrected (TransferTable::StepRGBA, ShadowAlpha) and a is interpolated
 *     from those: equal at the 4096 entries, and between them off by the correction's
 *     curvature over one entry (second order; VTK's GPU ray caster does the same). It saves
 *     the two transcendental calls per sample (5-6 % of the frame on the head and concrete).
 *  3. First event: the first sample with a > 0 gives Depth1 = t, Position1 (world), Normal1 and
 *     Albedo = c there.
 *  4. Event (free-flight sampling): T <- T (1 - a) at every sample with a > 0, and with
 *     Scattering = 1 the event is the first such sample where 1 - T >= u'. It lands on sample k
 *     with probability T_k a_k (T_k = prod_{j<k} (1 - a_j)), so E[Alpha] and E[Radiance] are
 *     exactly the front-to-back composite sum_k T_k a_k L_k. With Scattering = 0 the event is the
 *     first event (an isosurface-like first hit). The march stops at the event.
 *  4b. ExpectedCoverage (the mapper's property; with Scattering, no CameraBoxed): the march goes on
 *     past the event to tEnd, or until T < kCoverageCutoff; the ray's opacity
 *     c = sum_k T_k a_k = 1 - T is stored as Alpha and the event is drawn among the samples
 *     with probability T_k a_k / c (a weighted reservoir: sample k replaces the candidate when
 *     u_k c_k < T_k a_k, c_k the running sum, one draw per absorbing sample), and Radiance =
 *     c L(event). Same expectations as step 4 without the coin flip between event and no
 *     event. Measured (research/results/expected_coverage.md): not worth its cost on
 *     the datasets' presets, so off by default; large gains in translucent transfer functions
 *     (research/results/coverage_frames.md).
 *  4c. CoverageMarch (with Scattering): after step 4's march stops at its event, a second
 *     march carries T on over the samples after it (the same grid) until T <
 *     kCoverageMarchCutoff or tEnd, and the ray's opacity 1 - T is stored as Coverage (a
 *     noise-free feature for the denoiser: below 1 in a fog or a thin translucent layer, 1 on
 *     an opaque surface; without an event step 4's march has reached tEnd, and its T is the
 *     whole ray's). The second march draws no random numbers and comes after the shading, so
 *     every other field is bit-identical to step 4's. Without it Coverage = Alpha.
 *  4d. FootprintRays: Footprint = 1 where the camera ray met a sample with opacity > 0 (it
 *     has a first hit). Where it met none but came near (its march visited a sample of an
 *     occupied brick), Footprint is whether the ray through the pixel's corner (x, y) may meet
 *     opacity (CornerMeetsVolume); where it crossed empty bricks only, 0. The denoiser takes a
 *     pixel whose four corners -- its own entry and those of pixels (x + 1, y), (x, y + 1),
 *     (x + 1, y + 1) -- are 0 for empty space and keeps it black: at one sample such a pixel
 *     cannot otherwise be told from a fringe its one ray missed. (Taking a met ray's corner as
 *     covered and an empty-brick ray's corner as empty saves the corner rays where they rarely
 *     matter: docs/denoiser-empty-space.md.) No random numbers: every other field is
 *     unchanged. Without FootprintRays, Footprint is 1.
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
 *       With EnvironmentReach > 0, T_e is the transmittance of the first EnvironmentReach of
 *       the ray only (local occlusion, like VTK's GlobalIlluminationReach).
 *       Drawn (u1, u2 then the march) only when c Environment != 0.
 *  6. Transmittance estimate (shadow and environment rays): from x along the unit direction,
 *     samples at (j + xi_s) StepWorld ShadowStepScale (own jitter xi_s), j >= 0, up to the box
 *     exit (or the light), T *= 1 - a_j with a_j corrected for the longer step. Russian
 *     roulette after each absorbing sample while T < RouletteThreshold (default 0.05, chosen
 *     by research/benchmarks/roulette.py): survive with probability 1/2 and double T, else
 *     return 0 -- unbiased (E = T) and terminating.
 *  Empty-space skipping (every march, see March()): when the current sample's brick is empty
 *  (ptvOccupancy.h), k jumps to the first sample index whose t is past the empty cube of bricks
 *  ahead of it (for the ray's direction octant); the skipped samples all have a = 0 and draw no
 *  random numbers, so results are
 *  bit-identical with and without skipping.
 *  Clipping and cropping (ptvClipping.h): points that are cut away classify as transparent, and
 *  every march first clips its [tStart, tEnd] to the convex kept part (fewer samples only).
 *  Isosurfaces and intensity projections replace steps 2-6 for their camera rays:
 *  ptvIntegratorModes.h.
 *  Misses and no-event fields: Normal 0, Position 0, Depth = Camera.FarDistance, Albedo 0.
 *
 * Parameter guards: StepWorld <= 0 (or NaN) renders nothing; UnitDistance <= 0 means alpha is
 * already per step (no correction); ShadowStepScale <= 0 means 2. x, y must lie in the image.
 */
#ifndef ptvIntegrator_h
#define ptvIntegrator_h

#include "ptvIntegratorModes.h"
#include "ptvShading.h"

namespace ptv
{
/// The camera ray of TracePixel() with ExpectedCoverage (step 4b), filling @a out.
PTV_HD PTV_INLINE PTV_NOINLINE void TraceCoverage(const TraceParams& p, Vec3 origin, Vec3 dir,
  Vec3 oIdx, Vec3 dIdx, Vec3 invD, float tStart, float tEnd, float xi, float stepOverUnit,
  Rng& rng, PixelSample& out)
{
  const float step = p.StepWorld;
  float T = 1.f;
  float coverage = 0.f;
  bool haveFirst = false;
  bool chosenFirst = false;
  float tEvent = 0.f;
  Vec3 eventIdx = oIdx;
  Vec3 eventColor = Vec3{ 0.f, 0.f, 0.f };
  March(p.Occupancy, oIdx, dIdx, invD, tStart, tEnd, xi, step, 1.f / step,
    [&](int, float t, Vec3 pIdx)
    {
      const TransferSample ts = ClassifyStep(p, pIdx, stepOverUnit);
      const float a = ts.Opacity;
      if (!(a > 0.f))
      {
        return false;
      }
      const bool first = !haveFirst;
      if (first)
      {
        haveFirst = true;
        SetFirstEvent(p, origin, dir, t, pIdx, ts.Color, out);
      }
      const float w = T * a; // this sample's share of the ray's opacity
      coverage += w;
      if (NextFloat(rng) * coverage < w) // keeps sample k with probability w_k / sum_k w
      {
        chosenFirst = first;
        tEvent = t;
        eventIdx = pIdx;
        eventColor = ts.Color;
      }
      T *= 1.f - a;
      return T < kCoverageCutoff;
    });
  if (!(coverage > 0.f))
  {
    return;
  }
  const Vec3 event = origin + dir * tEvent;
  const Vec3 n = chosenFirst ? out.Normal1 : ShadingNormal(p, eventIdx, dir);
  out.Alpha = coverage;
  out.Coverage = coverage;
  out.Depth2 = tEvent;
  out.Position2 = event;
  out.Normal2 = n;
  out.Radiance = ShadeEvent(p, event, dir, eventColor, n, rng) * coverage;
}

/// Step 4c: the transmittance @a T of a camera ray whose march stopped at its event, sample
/// @a k, carried on over the samples after it (the same grid) until below kCoverageMarchCutoff.
PTV_HD PTV_INLINE PTV_NOINLINE float CarriedTransmittance(const TraceParams& p, Vec3 oIdx,
  Vec3 dIdx, Vec3 invD, float tStart, float tEnd, float xi, float stepOverUnit, int k, float T)
{
  const float step = p.StepWorld;
  March(p.Occupancy, oIdx, dIdx, invD, tStart, tEnd, xi, step, 1.f / step,
    [&](int, float, Vec3 pIdx)
    {
      const float a = ClassifyStep(p, pIdx, stepOverUnit).Opacity;
      if (a > 0.f)
      {
        T *= 1.f - a;
      }
      return T < kCoverageMarchCutoff;
    },
    k + 1);
  return T;
}

/**
 * A distributed piece's part of the camera ray: [t0, t1] clipped to CameraBox, and @a xi moved
 * so that the piece samples exactly where the ray through the whole volume (WholeBox, clipped
 * like any ray) would: at tWhole + (k + xi) StepWorld. Pieces that share xi then take the whole
 * ray's samples between them, each sample once. False when the ray misses the piece.
 */
PTV_HD PTV_INLINE bool ClipToPiece(
  const TraceParams& p, Vec3 oIdx, Vec3 dIdx, float& t0, float& t1, float& xi)
{
  float w0 = -kTMax, w1 = kTMax;
  if (!(ClipSlab(oIdx.x, dIdx.x, p.WholeBox[0], p.WholeBox[1], w0, w1) &&
        ClipSlab(oIdx.y, dIdx.y, p.WholeBox[2], p.WholeBox[3], w0, w1) &&
        ClipSlab(oIdx.z, dIdx.z, p.WholeBox[4], p.WholeBox[5], w0, w1)))
  {
    return false;
  }
  float wStart = Max(w0, 0.f);
  if (HasClipping(p.Clip) && !ClipInterval(p.Clip, oIdx, dIdx, wStart, w1))
  {
    return false;
  }
  if (!(ClipSlab(oIdx.x, dIdx.x, p.CameraBox[0], p.CameraBox[1], t0, t1) &&
        ClipSlab(oIdx.y, dIdx.y, p.CameraBox[2], p.CameraBox[3], t0, t1) &&
        ClipSlab(oIdx.z, dIdx.z, p.CameraBox[4], p.CameraBox[5], t0, t1)))
  {
    return false;
  }
  t0 = Max(t0, wStart);
  const float shifted = xi + (wStart - t0) / p.StepWorld; // t0 + (k + xi') step on the grid
  xi = shifted - floorf(shifted);
  return true;
}

/// The part of a camera ray that is marched (step 1).
struct CameraSegment
{
  Vec3 Origin, Dir;     ///< world space
  Vec3 OIdx, DIdx, InvD; ///< index space; InvD = Reciprocal(DIdx)
  float TStart, TEnd;   ///< world distances
  float Xi;             ///< the march offset (moved onto the whole ray's grid in a piece)
};

/**
 * Step 1 for the camera ray through image point (fx, fy) of pixel @a pixel with march offset
 * @a xi: [TStart, TEnd] inside the volume's box, before the pixel's MaxDistance, the clipping
 * and (CameraBoxed) the piece. False when nothing of the ray is left to march.
 */
PTV_HD PTV_INLINE bool SetUpCameraRay(
  const TraceParams& p, float fx, float fy, uint32_t pixel, float xi, CameraSegment& ray)
{
  GenerateRay(p.Camera, fx, fy, ray.Origin, ray.Dir);
  ray.OIdx = TransformPoint(p.Volume.WorldToIndex, ray.Origin);
  ray.DIdx = TransformVector(p.Volume.WorldToIndex, ray.Dir);
  ray.InvD = Reciprocal(ray.DIdx);
  float tEnter, tExit;
  if (!IntersectBox(p.Volume, ray.OIdx, ray.DIdx, ray.InvD, tEnter, tExit))
  {
    return false;
  }
  ray.TStart = Max(tEnter, 0.f);
  ray.TEnd = p.MaxDistance ? Min(tExit, p.MaxDistance[pixel]) : tExit;
  ray.Xi = xi;
  if (HasClipping(p.Clip) && !ClipInterval(p.Clip, ray.OIdx, ray.DIdx, ray.TStart, ray.TEnd))
  {
    return false;
  }
  if (p.CameraBoxed && !ClipToPiece(p, ray.OIdx, ray.DIdx, ray.TStart, ray.TEnd, ray.Xi))
  {
    return false; // a distributed piece: this ray misses this process's own part
  }
  return ray.TStart < ray.TEnd;
}

/**
 * Step 4d (FootprintRays): whether the ray through the corner (x, y) of pixel (x, y) -- the
 * image point where the pixel meets its neighbours (x - 1, y), (x, y - 1) and (x - 1, y - 1) --
 * may meet opacity anywhere along it (1) or nowhere (0). The march (offset 0, the camera step)
 * tests the scalar interval between each visited sample and the samples before and after it
 * (MayBeOpaque), so that a layer thinner than a step between two samples counts as met, as it
 * does for some of the jittered camera rays; what the occupancy grid skips is transparent at
 * every point. Without TransferTable::OpaqueBefore: the samples' own opacity. No random
 * numbers. Isosurfaces: 1 (not traced).
 */
PTV_HD PTV_INLINE PTV_NOINLINE float CornerMeetsVolume(
  const TraceParams& p, int x, int y, uint32_t pixel)
{
  const float step = p.StepWorld;
  CameraSegment ray;
  if (p.Iso.Count > 0)
  {
    return 1.f;
  }
  if (!(step > 0.f) ||
    !SetUpCameraRay(p, static_cast<float>(x), static_cast<float>(y), pixel, 0.f, ray))
  {
    return 0.f;
  }
  const float stepOverUnit = StepOverUnit(p, step);
  const bool intervals = p.Transfer.OpaqueBefore != nullptr;
  bool met = false;
  int previous = -2;  // the last visited sample
  float ahead = 0.f;  // the scalar one step after it
  March(p.Occupancy, ray.OIdx, ray.DIdx, ray.InvD, ray.TStart, ray.TEnd, ray.Xi, step,
    1.f / step,
    [&](int k, float t, Vec3 pIdx)
    {
      if (!intervals)
      {
        met = ClassifyStep(p, pIdx, stepOverUnit).Opacity > 0.f;
        return met;
      }
      const bool follows = previous == k - 1; // (previous, k) was tested from previous
      const float s = follows ? ahead : SampleScalar(p, pIdx);
      if (!follows)
      {
        const float tBefore = Max(t - step, ray.TStart);
        met = MayBeOpaque(p.Transfer, SampleScalar(p, ray.OIdx + ray.DIdx * tBefore), s);
      }
      const float tAfter = Min(t + step, ray.TEnd);
      ahead = SampleScalar(p, ray.OIdx + ray.DIdx * tAfter);
      previous = k;
      met = met || MayBeOpaque(p.Transfer, s, ahead);
      return met;
    });
  return met ? 1.f : 0.f;
}

/// TracePixel() without step 4d; @a near: the camera ray came near opacity (its march visited
/// a sample of an occupied brick; always with isosurfaces and ExpectedCoverage). @a jitter,
/// when given, replaces the two jitter draws (which are still drawn: every later number is
/// unchanged) with its (x, y) in [0, 1) (ptvEdgeSamples: a shifted lattice).
PTV_HD PTV_INLINE PixelSample TraceCameraRay(const TraceParams& p, int x, int y, uint32_t pixel,
  uint32_t frame, bool& near, const float* jitter = nullptr)
{
  PixelSample out = MissSample(p.Camera.FarDistance);
  near = false;
  Rng rng = MakeRng(pixel, frame, p.Seed);
  const float drawnX = NextFloat(rng);
  const float drawnY = NextFloat(rng);
  const float jx = jitter ? jitter[0] : drawnX;
  const float jy = jitter ? jitter[1] : drawnY;
  float xi = NextFloat(rng);
  if (p.PieceStream != 0u)
  {
    rng = MakeRng(pixel, frame, p.Seed ^ PcgHash(p.PieceStream)); // the piece's own stream
  }
  const float threshold = 1.f - NextFloat(rng); // in (0, 1]

  const float step = p.StepWorld;
  CameraSegment ray;
  if (!(step > 0.f) ||
    !SetUpCameraRay(p, static_cast<float>(x) + jx, static_cast<float>(y) + jy, pixel, xi, ray))
  {
    return out;
  }
  const Vec3 origin = ray.Origin, dir = ray.Dir, oIdx = ray.OIdx, dIdx = ray.DIdx,
             invD = ray.InvD;
  const float tStart = ray.TStart, tEnd = ray.TEnd;
  xi = ray.Xi;

  if (p.Projection > 0)
  {
    near = true;
    TraceProjection(p, origin, dir, oIdx, dIdx, tStart, tEnd, xi, out);
    out.Coverage = out.Alpha;
    return out;
  }
  float T = 1.f;
  bool haveFirst = false;
  if (p.Iso.Count > 0)
  {
    near = true;
    TraceIsoSurfaces(p, origin, dir, oIdx, dIdx, tStart, tEnd, xi, threshold, rng, out);
    out.Coverage = out.Alpha;
    return out;
  }
  const float stepOverUnit = StepOverUnit(p, step);
  if (p.ExpectedCoverage && p.Scattering && !p.CameraBoxed)
  {
    near = true;
    TraceCoverage(p, origin, dir, oIdx, dIdx, invD, tStart, tEnd, xi, stepOverUnit, rng, out);
    return out;
  }
  int eventStep = -1; // the event's sample (CoverageMarch carries the march on after it)
  March(p.Occupancy, oIdx, dIdx, invD, tStart, tEnd, xi, step, 1.f / step,
    [&](int k, float t, Vec3 pIdx)
    {
      near = true;
      const TransferSample ts = ClassifyStep(p, pIdx, stepOverUnit);
      const float a = ts.Opacity;
      if (!(a > 0.f))
      {
        return false;
      }
      const bool first = !haveFirst;
      if (first)
      {
        haveFirst = true;
        SetFirstEvent(p, origin, dir, t, pIdx, ts.Color, out);
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
      eventStep = k;
      return true;
    });
  out.Coverage = out.Alpha;
  if (p.CoverageMarch && p.Scattering) // step 4c; without an event T is the whole ray's already
  {
    const bool carry = eventStep >= 0 && !(T < kCoverageMarchCutoff);
    out.Coverage = 1.f - (carry ? CarriedTransmittance(p, oIdx, dIdx, invD, tStart, tEnd, xi,
                                    stepOverUnit, eventStep, T)
                                : T);
  }
  return out;
}

/// One Monte Carlo sample of pixel (x, y) for sample (frame) index @a frame (see the file
/// comment; p.Frame is not read). @a jitter as TraceCameraRay's. @a corner, when given, holds
/// step 4d's corner ray answer for the pixel across its samples (it has no jitter): < 0 until
/// a sample traces it, then reused (ptvEdgeSamples).
PTV_HD PTV_INLINE PixelSample TracePixel(const TraceParams& p, int x, int y, uint32_t frame,
  const float* jitter = nullptr, float* corner = nullptr)
{
  const uint32_t pixel =
    static_cast<uint32_t>(y) * static_cast<uint32_t>(p.Camera.Width) + static_cast<uint32_t>(x);
  bool near;
  PixelSample out = TraceCameraRay(p, x, y, pixel, frame, near, jitter);
  if (p.FootprintRays) // step 4d; a first event means the ray met opacity
  {
    const bool met = out.Depth1 < kHitFraction * p.Camera.FarDistance;
    float answer = 0.f;
    if (!met && near)
    {
      answer = corner && *corner >= 0.f ? *corner : CornerMeetsVolume(p, x, y, pixel);
      if (corner)
      {
        *corner = answer;
      }
    }
    out.Footprint = met ? 1.f : answer;
  }
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
