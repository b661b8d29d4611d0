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
}

#endif
