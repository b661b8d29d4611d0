#include "ptvCoverage.h"

#include "Kernels/ptvCamera.h"
#include "Kernels/ptvOccupancy.h"
#include "Kernels/ptvVolumeGrid.h"
#include "ptvThreads.h"

#include <algorithm>
#include <atomic>
#include <cmath>

namespace ptv
{
namespace
{
/// Safety factor on the footprint offsets measured at five pixels (they vary across the image).
constexpr float kOffsetMargin = 1.25f;

float InfNorm(Vec3 v)
{
  return std::max(std::fabs(v.x), std::max(std::fabs(v.y), std::fabs(v.z)));
}

/// World position of index position @a q for the row-major 3x4 affine @a m (index = M w + t).
bool IndexToWorld(const float m[12], const double q[3], double w[3])
{
  const double a = m[0], b = m[1], c = m[2], d = m[4], e = m[5], f = m[6], g = m[8], h = m[9],
               i = m[10];
  const double det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
  if (!(std::fabs(det) > 0.0) || !std::isfinite(det))
  {
    return false;
  }
  const double r[3] = { q[0] - m[3], q[1] - m[7], q[2] - m[11] };
  w[0] = ((e * i - f * h) * r[0] - (b * i - c * h) * r[1] + (b * f - c * e) * r[2]) / det;
  w[1] = (-(d * i - f * g) * r[0] + (a * i - c * g) * r[1] - (a * f - c * d) * r[2]) / det;
  w[2] = ((d * h - e * g) * r[0] - (a * h - b * g) * r[1] + (a * e - b * d) * r[2]) / det;
  return std::isfinite(w[0]) && std::isfinite(w[1]) && std::isfinite(w[2]);
}

/**
 * Whether every ray through the footprint of every pixel stays within @a brick voxels (index
 * space, each axis) of its pixel's centre ray inside the box widened by @a brick (file comment,
 * step 3): a0 + a1 tFar < brick, tFar the farthest ray parameter a widened-box corner can have.
 */
bool FootprintFits(const TraceParams& p, float brick)
{
  const CameraRays& cam = p.Camera;
  const float* m = p.Volume.WorldToIndex;
  float a0 = 0.f, a1 = 0.f;
  const float probes[5][2] = { { 0.5f * cam.Width, 0.5f * cam.Height }, { 0.5f, 0.5f },
    { cam.Width - 1.5f, 0.5f }, { 0.5f, cam.Height - 1.5f },
    { cam.Width - 1.5f, cam.Height - 1.5f } };
  Vec3 o0{}, d0{};
  for (const auto& q : probes)
  {
    Vec3 ox, dx, oy, dy;
    GenerateRay(cam, q[0], q[1], o0, d0);
    GenerateRay(cam, q[0] + 1.f, q[1], ox, dx);
    GenerateRay(cam, q[0], q[1] + 1.f, oy, dy);
    a0 = std::max(a0, 0.5f * (InfNorm(TransformVector(m, ox - o0)) +
                          InfNorm(TransformVector(m, oy - o0))));
    a1 = std::max(a1, 0.5f * (InfNorm(TransformVector(m, dx - d0)) +
                          InfNorm(TransformVector(m, dy - d0))));
  }
  double tFar = 0.0;
  for (int corner = 0; corner < 8; ++corner)
  {
    double q[3], w[3];
    for (int a = 0; a < 3; ++a)
    {
      q[a] = (corner >> a) & 1 ? p.Volume.Dims[a] - 1 + brick : -brick;
    }
    if (!IndexToWorld(m, q, w))
    {
      return false;
    }
    // Perspective: the distance from the eye; parallel: along the common direction from the
    // near plane (the origins all lie on it, so any of them will do).
    const double v[3] = { w[0] - o0.x, w[1] - o0.y, w[2] - o0.z };
    tFar = std::max(tFar,
      cam.Parallel ? v[0] * d0.x + v[1] * d0.y + v[2] * d0.z
                   : std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
  }
  const double reach = kOffsetMargin * (a0 + a1 * tFar);
  return std::isfinite(reach) && reach < brick;
}

/**
 * Signed distance of brick @a b in the occupancy grid dilated by one brick, for rays in
 * direction octant @a octant (>= 1 empty, <= 0 occupied), from the undilated grid: the dilated
 * forward cube of radius r from b is the undilated forward cube of radius r + 2 from the brick
 * one step back on every axis (b - s, clamped to the grid: positions outside it belong to the
 * edge bricks), which is empty when that brick's distance d has d - 1 >= r + 2. So the dilated
 * distance is d - 2: one lookup, no second grid (a cap of 127 only makes it shorter).
 */
int DilatedDistance(const OccupancyGrid& occ, const int b[3], int octant)
{
  int back[3];
  for (int a = 0; a < 3; ++a)
  {
    const int s = (octant >> a) & 1 ? -1 : 1;
    back[a] = std::min(std::max(b[a] - s, 0), occ.Bricks[a] - 1);
  }
  return DistanceAt(occ, back, octant) - 2;
}

/// Whether the ray o + t d (index space, t >= 0) meets a brick of the dilated grid that may be
/// occupied, inside the box widened by occ.BrickSize voxels.
bool MeetsOccupied(const OccupancyGrid& occ, const int dims[3], Vec3 o, Vec3 d)
{
  const float brick = static_cast<float>(occ.BrickSize);
  const Vec3 invD = Reciprocal(d);
  float t0 = -kTMax, t1 = kTMax;
  if (!ClipSlabInv(o.x, d.x, invD.x, -brick, dims[0] - 1 + brick, t0, t1) ||
    !ClipSlabInv(o.y, d.y, invD.y, -brick, dims[1] - 1 + brick, t0, t1) ||
    !ClipSlabInv(o.z, d.z, invD.z, -brick, dims[2] - 1 + brick, t0, t1) || !(t1 >= 0.f))
  {
    return false;
  }
  const float invBrick = 1.f / brick;
  const int octant = DirectionOctant(d);
  // Each step leaves a cube of at least one brick; more steps than this mean a degenerate ray.
  const int maxSteps = 4 * (occ.Bricks[0] + occ.Bricks[1] + occ.Bricks[2]) + 16;
  float t = std::max(t0, 0.f);
  for (int step = 0; t <= t1; ++step)
  {
    if (step >= maxSteps)
    {
      return true; // cannot tell: covered
    }
    int b[3];
    BrickOf(occ, o + d * t, invBrick, b);
    const int distance = DilatedDistance(occ, b, octant);
    if (distance <= 0)
    {
      return true;
    }
    t = RegionExitT(occ, o, d, invD, t, b, CubeRadius(distance));
  }
  return false;
}
}

//------------------------------------------------------------------------------
std::int64_t ComputeCoverage(const TraceParams& p, float* out, int threads)
{
  const int width = p.Camera.Width;
  const int height = p.Camera.Height;
  const std::size_t pixels = static_cast<std::size_t>(std::max(width, 0)) *
    static_cast<std::size_t>(std::max(height, 0));
  std::fill(out, out + pixels, 1.0f);
  const OccupancyGrid& occ = p.Occupancy;
  if (pixels == 0 || !occ.Distance || p.CameraBoxed || occ.BrickSize < 1 ||
    !FootprintFits(p, static_cast<float>(occ.BrickSize)))
  {
    return 0;
  }
  std::atomic<std::int64_t> empty{ 0 };
  ParallelFor(threads, 0, height, 8,
    [&](int yBegin, int yEnd)
    {
      std::int64_t count = 0;
      for (int y = yBegin; y < yEnd; ++y)
      {
        for (int x = 0; x < width; ++x)
        {
          Vec3 origin, dir;
          GenerateRay(p.Camera, x + 0.5f, y + 0.5f, origin, dir);
          const Vec3 o = TransformPoint(p.Volume.WorldToIndex, origin);
          const Vec3 d = TransformVector(p.Volume.WorldToIndex, dir);
          if (!MeetsOccupied(occ, p.Volume.Dims, o, d))
          {
            out[static_cast<std::size_t>(y) * width + x] = 0.0f;
            ++count;
          }
        }
      }
      empty += count;
    });
  return empty.load();
}
}
