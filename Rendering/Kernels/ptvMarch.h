/**
 * @file ptvMarch.h
 * @brief The one march every ray uses (camera, shadow and environment rays): jittered samples
 *        at a fixed step, with exact empty-space skipping (ptvOccupancy.h).
 */
#ifndef ptvMarch_h
#define ptvMarch_h

#include "ptvKernelCommon.h"
#include "ptvOccupancy.h"

namespace ptv
{
/// Ray parameter of march sample k; the single expression every march uses.
PTV_HD PTV_INLINE float MarchSampleT(float tStart, float xi, float step, int k)
{
  return tStart + (static_cast<float>(k) + xi) * step;
}

/// An upper bound on the number of samples in [tStart, tEnd) (clamped to 2^30); invStep =
/// 1 / step (its rounding is far inside the bound's margin of two samples).
PTV_HD PTV_INLINE int MarchSampleLimit(float tStart, float tEnd, float xi, float invStep)
{
  const float n = ceilf((tEnd - tStart) * invStep - xi) + 2.f;
  return static_cast<int>(Clamp(n, 0.f, 1073741824.f));
}

/// About the first sample at or after tTarget, clamped to [kMin, kLimit] (kLimit when tTarget
/// is infinite or NaN): the rounded quotient, which may be one sample off either way.
PTV_HD PTV_INLINE int SampleNear(
  float tStart, float xi, float invStep, float tTarget, int kMin, int kLimit)
{
  const float estimate = ceilf((tTarget - tStart) * invStep - xi);
  if (!(estimate < static_cast<float>(kLimit)))
  {
    return kLimit;
  }
  return estimate > static_cast<float>(kMin) ? static_cast<int>(estimate) : kMin;
}

/// Smallest k in [kMin, kLimit] with MarchSampleT(k) >= tTarget (kLimit if none); invStep =
/// 1 / step only seeds the search (SampleNear), the result is exact.
PTV_HD PTV_INLINE int FirstSampleAtOrAfter(
  float tStart, float xi, float step, float invStep, float tTarget, int kMin, int kLimit)
{
  int k = SampleNear(tStart, xi, invStep, tTarget, kMin, kLimit);
  if (k == kLimit)
  {
    return kLimit;
  }
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
 * march jumps to the first sample at or after the exit of the empty cube ahead of it
 * (RegionExitT; exact, FirstSampleAtOrAfter); at a sample in an occupied brick it visits every
 * sample up to about the exit of the occupied cube ahead of it without further lookups (there a
 * sample more or less before the next lookup costs nothing, so SampleNear's estimate will do).
 * Skipped samples all have zero opacity and the visits are the same samples, so the visits
 * that matter are the same with and without skipping. invD = Reciprocal(dIdx) and invStep =
 * 1 / step come from the caller, which computes them once (per ray, per event). @a kFirst > 0
 * starts at sample kFirst of the same grid (a march carried on after the sample it stopped at).
 */
template <class Visit>
PTV_HD PTV_INLINE void March(const OccupancyGrid& occ, Vec3 oIdx, Vec3 dIdx, Vec3 invD,
  float tStart, float tEnd, float xi, float step, float invStep, Visit&& visit, int kFirst = 0)
{
  const int kLimit = MarchSampleLimit(tStart, tEnd, xi, invStep);
  const float invBrick = occ.Distance ? 1.f / static_cast<float>(occ.BrickSize) : 0.f;
  const int octant = DirectionOctant(dIdx);
  int k = kFirst;
  while (k < kLimit)
  {
    float t = MarchSampleT(tStart, xi, step, k);
    if (!(t < tEnd))
    {
      return;
    }
    Vec3 pIdx = oIdx + dIdx * t;
    int kEnd = kLimit;
    if (occ.Distance)
    {
      int b[3];
      BrickOf(occ, pIdx, invBrick, b);
      const int distance = DistanceAt(occ, b, octant);
      const float tExit = RegionExitT(occ, oIdx, dIdx, invD, t, b, CubeRadius(distance));
      if (distance > 0)
      {
        k = FirstSampleAtOrAfter(tStart, xi, step, invStep, tExit, k + 1, kLimit);
        continue;
      }
      kEnd = SampleNear(tStart, xi, invStep, tExit, k + 1, kLimit);
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

/// March() computing the reciprocals itself (the isosurface marches).
template <class Visit>
PTV_HD PTV_INLINE void March(const OccupancyGrid& occ, Vec3 oIdx, Vec3 dIdx, float tStart,
  float tEnd, float xi, float step, Visit&& visit)
{
  March(occ, oIdx, dIdx, Reciprocal(dIdx), tStart, tEnd, xi, step, 1.f / step,
    static_cast<Visit&&>(visit));
}
}

#endif
