/**
 * @file ptvOccupancy.h
 * @brief Empty-space skipping: per-brick, per-direction-octant signed distances (to the nearest
 *        brick ahead that may be visible, or to the nearest empty one), and the exit query.
 *
 * The grid is cut into bricks of BrickSize^3 voxels in index space; brick b covers positions
 * [b B, (b+1) B) on each axis, with the outermost bricks extended to infinity (positions outside
 * the box sample the edge voxels, which belong to them). Bricks[a] = (Dims[a] - 1) / B + 1.
 * A brick is *empty* only if every trilinear sample at a position of the brick has zero
 * opacity, so skipping empty space never changes a result.
 *
 * To guarantee that, BuildOccupancy() takes the min/max of the voxel values over the brick's
 * trilinear footprint [b B, (b+1) B] widened by a one-voxel border on every side, i.e. voxels
 * [b B - 1, (b+1) B + 1] (clamped to the grid): the border keeps the flag valid for positions up
 * to a voxel outside the brick, far more than the rounding of sample positions and exit
 * parameters. The range is widened by a few ulps (trilinear interpolation in float may overshoot
 * its inputs by rounding), and the brick is occupied iff the largest table opacity over that
 * scalar range (every entry inside it plus the interpolated end points; the table is piecewise
 * linear, so that is the maximum) is > 0; a NaN voxel adds entry 0 (conservative: NaN samples
 * are transparent). Infinite voxel values make the widened range infinite, which only makes the
 * test more conservative. Gradient opacity only scales opacity down and is ignored here.
 *
 * Distance[8 (bx + Bricks[0] * (by + Bricks[1] * bz)) + octant] is a one-sided, signed
 * chessboard (Chebyshev) distance in bricks for rays whose direction lies in that octant
 * (DirectionOctant: bit a set when component a is negative). A ray only moves forward along
 * each axis, so what matters is the cube of bricks that starts at its brick and extends in the
 * octant's direction, [b, b + r s] (s the octant's signs); one lookup settles that cube:
 *  - d >= 1 (empty brick): every brick of the forward cube of d - 1 is empty (d is the
 *    distance to the nearest occupied brick in the forward orthant, capped at 127). A ray in
 *    empty brick b skips to the cube's exit (RegionExitT: its exit faces are the far faces,
 *    b + (d-1) s, which is all a forward ray can reach) in one step, instead of one brick at a
 *    time. Near a surface the ray is heading away from or along, the forward cube is far
 *    larger than a symmetric one around the brick would be.
 *  - d <= 0 (occupied brick): every brick of the forward cube of -d is occupied (-d is the
 *    distance to the nearest empty brick in the forward orthant minus one, capped at 127). A
 *    ray in occupied brick b visits every sample up to that cube's exit without another
 *    lookup. Visiting samples is always exact (only skipping relies on the grid), so this part
 *    needs no conservative rounding.
 * Cubes are clipped to the grid; edge bricks still extend to infinity, and bricks outside the
 * grid limit neither distance. OctantDistances() computes them exactly, one pass per octant.
 */
#ifndef ptvOccupancy_h
#define ptvOccupancy_h

#include "ptvIsosurface.h"
#include "ptvKernelCommon.h"
#include "ptvTransferTable.h"
#include "ptvVolumeGrid.h"

#include <limits>
#include <type_traits>
#include <vector>

namespace ptv
{
struct OccupancyGrid
{
  /// 8 signed distances per brick, one per direction octant (>= 1 empty, <= 0 occupied; see
  /// the file comment), or nullptr (no skipping)
  const int8_t* Distance;
  int BrickSize; ///< voxels per brick edge (>= 1)
  int Bricks[3]; ///< brick counts
};

/// Brick counts covering index positions [0, Dims-1]: (Dims - 1) / brickSize + 1 per axis.
PTV_HD PTV_INLINE void ComputeBrickCounts(const int dims[3], int brickSize, int bricks[3])
{
  for (int a = 0; a < 3; ++a)
  {
    bricks[a] = (dims[a] > 1 ? dims[a] - 1 : 0) / brickSize + 1;
  }
}

/// Brick coordinate of an index-space coordinate, given 1 / BrickSize (clamped; NaN -> 0).
PTV_HD PTV_INLINE int BrickCoordinate(float x, float invBrickSize, int bricks)
{
  return static_cast<int>(Clamp(floorf(x * invBrickSize), 0.f, static_cast<float>(bricks - 1)));
}

/// Brick coordinates of an index-space point (clamped to the grid), given 1 / BrickSize.
PTV_HD PTV_INLINE void BrickOf(const OccupancyGrid& occ, Vec3 p, float invBrickSize, int b[3])
{
  b[0] = BrickCoordinate(p.x, invBrickSize, occ.Bricks[0]);
  b[1] = BrickCoordinate(p.y, invBrickSize, occ.Bricks[1]);
  b[2] = BrickCoordinate(p.z, invBrickSize, occ.Bricks[2]);
}

/// Octant (0-7) of a direction: bit a set when component a is negative.
PTV_HD PTV_INLINE int DirectionOctant(Vec3 d)
{
  return (d.x < 0.f ? 1 : 0) | (d.y < 0.f ? 2 : 0) | (d.z < 0.f ? 4 : 0);
}

/// Signed distance of brick b for rays in direction octant @a octant (>= 1: empty, <= 0:
/// occupied).
PTV_HD PTV_INLINE int DistanceAt(const OccupancyGrid& occ, const int b[3], int octant)
{
  const int64_t brick = b[0] + static_cast<int64_t>(occ.Bricks[0]) * (b[1] + occ.Bricks[1] * b[2]);
  return occ.Distance[8 * brick + octant];
}

/// Extent, in bricks beyond the ray's own, of the forward cube a ray crosses in one step from a
/// brick of signed distance d: d - 1 for an empty brick, -d for an occupied one.
PTV_HD PTV_INLINE int CubeRadius(int d)
{
  return d > 0 ? d - 1 : -d;
}

/// Exit parameter on one axis of the bricks b to b + r in the ray's direction of travel (the far
/// face, which a forward cube [b, b + r s] and a symmetric one [b - r, b + r] share) for a ray
/// with origin o and direction component d (invD = 1 / d); kTMax if it has none in that
/// direction (the ray is parallel, or the bricks reach the grid's edge brick).
PTV_HD PTV_INLINE float RegionAxisExit(
  int b, int r, float o, float d, float invD, int brickSize, int bricks)
{
  if (d > 0.f && b + r < bricks - 1)
  {
    return (static_cast<float>((b + r + 1) * brickSize) - o) * invD;
  }
  if (d < 0.f && b - r > 0)
  {
    return (static_cast<float>((b - r) * brickSize) - o) * invD;
  }
  return kTMax;
}

/**
 * Ray parameter where the index-space ray o + t d (invD: the component-wise reciprocals of d)
 * leaves the cube of bricks from b to r bricks ahead on every axis (r = 0: brick b itself);
 * always > t (the next float above t when rounding puts the computed exit at or before t),
 * kTMax when the ray never leaves it. Rounding of the exit only moves it by ulps, far inside the one-voxel border that keeps
 * the occupancy conservative.
 */
PTV_HD PTV_INLINE float RegionExitT(
  const OccupancyGrid& occ, Vec3 o, Vec3 d, Vec3 invD, float t, const int b[3], int r)
{
  const float ex = RegionAxisExit(b[0], r, o.x, d.x, invD.x, occ.BrickSize, occ.Bricks[0]);
  const float ey = RegionAxisExit(b[1], r, o.y, d.y, invD.y, occ.BrickSize, occ.Bricks[1]);
  const float ez = RegionAxisExit(b[2], r, o.z, d.z, invD.z, occ.BrickSize, occ.Bricks[2]);
  const float te = Min(ex, Min(ey, ez));
  return te > t ? te : nextafterf(t, kTMax);
}

/**
 * HOST ONLY. The smallest and largest voxel value of the index box [lo, hi] (inclusive) into
 * @a vmin / @a vmax (which come in as kTMax / -kTMax), and whether it holds a NaN: rows of
 * integers are reduced in their own type (vectorizable, no NaN), floats with comparisons that
 * skip NaN as fminf / fmaxf do.
 */
template <typename T>
inline void FootprintRange(const VolumeGrid& g, const T* data, const int lo[3], const int hi[3],
  float& vmin, float& vmax, bool& hasNaN)
{
  const int64_t row = g.Dims[0];
  const int64_t slice = row * g.Dims[1];
  const int count = hi[0] - lo[0] + 1;
  if constexpr (std::is_integral<T>::value)
  {
    T tmin = std::numeric_limits<T>::max();
    T tmax = std::numeric_limits<T>::lowest();
    for (int k = lo[2]; k <= hi[2]; ++k)
    {
      for (int j = lo[1]; j <= hi[1]; ++j)
      {
        const T* v = data + lo[0] + row * j + slice * k;
        for (int i = 0; i < count; ++i)
        {
          tmin = v[i] < tmin ? v[i] : tmin;
          tmax = v[i] > tmax ? v[i] : tmax;
        }
      }
    }
    vmin = static_cast<float>(tmin);
    vmax = static_cast<float>(tmax);
  }
  else
  {
    for (int k = lo[2]; k <= hi[2]; ++k)
    {
      for (int j = lo[1]; j <= hi[1]; ++j)
      {
        const T* v = data + lo[0] + row * j + slice * k;
        for (int i = 0; i < count; ++i)
        {
          const float x = static_cast<float>(v[i]);
          hasNaN = hasNaN || x != x;
          vmin = x < vmin ? x : vmin;
          vmax = x > vmax ? x : vmax;
        }
      }
    }
  }
}

/**
 * HOST ONLY. For the bricks with z coordinate in [bzBegin, bzEnd): the range of values their
 * trilinear samples can take (see the file comment: footprint plus a one-voxel border, widened
 * by a few ulps), ranges[2 b] = lo and ranges[2 b + 1] = hi. A footprint holding a NaN voxel gets
 * lo = -kTMax, which makes the test include table entry 0 (NaN samples are transparent, so
 * this is only conservative). This depends on the voxels alone: a transfer-function change
 * reuses it (BuildOccupancy). Slabs of bz can be filled in parallel.
 */
template <typename T>
inline void BuildBrickRangesOf(
  const VolumeGrid& g, const T* data, int brickSize, int bzBegin, int bzEnd, float* ranges)
{
  int bricks[3];
  ComputeBrickCounts(g.Dims, brickSize, bricks);
  for (int bz = bzBegin; bz < bzEnd; ++bz)
  {
    for (int by = 0; by < bricks[1]; ++by)
    {
      for (int bx = 0; bx < bricks[0]; ++bx)
      {
        const int b[3] = { bx, by, bz };
        int lo[3], hi[3];
        for (int a = 0; a < 3; ++a)
        {
          lo[a] = ClampInt(b[a] * brickSize - 1, 0, g.Dims[a] - 1);
          hi[a] = ClampInt((b[a] + 1) * brickSize + 1, 0, g.Dims[a] - 1);
        }
        float vmin = kTMax;
        float vmax = -kTMax;
        bool hasNaN = false;
        FootprintRange(g, data, lo, hi, vmin, vmax, hasNaN);
        const float eps = 1e-6f * (fabsf(vmin) + fabsf(vmax)) + 1e-30f;
        const int64_t index = bx + static_cast<int64_t>(bricks[0]) * (by + bricks[1] * bz);
        ranges[2 * index] = hasNaN ? -kTMax : vmin - eps;
        ranges[2 * index + 1] = vmax + eps;
      }
    }
  }
}

/// BuildBrickRangesOf for the voxels' own type (VolumeGrid::Type).
inline void BuildBrickRanges(
  const VolumeGrid& g, int brickSize, int bzBegin, int bzEnd, float* ranges)
{
  // Not WithScalars: that one is __host__ __device__, and nvcc refuses it a host-only body.
  switch (g.Type)
  {
    case kScalarUInt8:
      BuildBrickRangesOf(g, static_cast<const uint8_t*>(g.Scalars), brickSize, bzBegin, bzEnd,
        ranges);
      break;
    case kScalarInt8:
      BuildBrickRangesOf(g, static_cast<const int8_t*>(g.Scalars), brickSize, bzBegin, bzEnd,
        ranges);
      break;
    case kScalarUInt16:
      BuildBrickRangesOf(g, static_cast<const uint16_t*>(g.Scalars), brickSize, bzBegin, bzEnd,
        ranges);
      break;
    case kScalarInt16:
      BuildBrickRangesOf(g, static_cast<const int16_t*>(g.Scalars), brickSize, bzBegin, bzEnd,
        ranges);
      break;
    default:
      BuildBrickRangesOf(g, static_cast<const float*>(g.Scalars), brickSize, bzBegin, bzEnd,
        ranges);
      break;
  }
}

/**
 * HOST ONLY. The one-sided signed distances of the file comment from occupancy flags (0 empty,
 * else occupied) over bricks[3]: out[8 b + octant]. For each octant one pass visits the bricks
 * so that the 7 forward neighbours (one brick further along one, two or three axes of the
 * octant) come first: an empty brick's distance is 1 + the smallest of theirs (0 for an
 * occupied one), an occupied brick's radius 1 + the smallest of theirs (-1 for an empty one);
 * neighbours outside the grid limit neither (capped at 127).
 */
inline void OctantDistances(const int bricks[3], const uint8_t* occupied, int8_t* out)
{
  const int n[3] = { bricks[0], bricks[1], bricks[2] };
  std::vector<int> value(static_cast<std::size_t>(n[0]) * n[1] * n[2]);
  for (int octant = 0; octant < 8; ++octant)
  {
    const int s[3] = { octant & 1 ? -1 : 1, octant & 2 ? -1 : 1, octant & 4 ? -1 : 1 };
    for (int zi = 0; zi < n[2]; ++zi)
    {
      const int z = s[2] > 0 ? n[2] - 1 - zi : zi;
      for (int yi = 0; yi < n[1]; ++yi)
      {
        const int y = s[1] > 0 ? n[1] - 1 - yi : yi;
        for (int xi = 0; xi < n[0]; ++xi)
        {
          const int x = s[0] > 0 ? n[0] - 1 - xi : xi;
          const std::size_t b = static_cast<std::size_t>(x) + static_cast<std::size_t>(n[0]) *
              (static_cast<std::size_t>(y) + static_cast<std::size_t>(n[1]) * z);
          const bool full = occupied[b] != 0;
          int best = 127; // no forward neighbour inside the grid: nothing limits it
          for (int k = 1; k < 8; ++k)
          {
            const int qx = x + ((k & 1) ? s[0] : 0);
            const int qy = y + ((k & 2) ? s[1] : 0);
            const int qz = z + ((k & 4) ? s[2] : 0);
            if (qx < 0 || qx >= n[0] || qy < 0 || qy >= n[1] || qz < 0 || qz >= n[2])
            {
              continue;
            }
            const std::size_t q = static_cast<std::size_t>(qx) + static_cast<std::size_t>(n[0]) *
                (static_cast<std::size_t>(qy) + static_cast<std::size_t>(n[1]) * qz);
            const bool qFull = occupied[q] != 0;
            // Empty b: distance to the nearest forward occupied brick; occupied b: radius of the
            // forward cube that stays occupied.
            const int via = full ? (qFull ? value[q] + 1 : 0) : (qFull ? 1 : value[q] + 1);
            best = via < best ? via : best;
          }
          best = best < 127 ? best : 127;
          value[b] = best;
          out[8 * b + static_cast<std::size_t>(octant)] =
            static_cast<int8_t>(full ? -best : best);
        }
      }
    }
  }
}

/**
 * HOST ONLY. Fill out[8 Bricks[0]*Bricks[1]*Bricks[2]] with each brick's signed distances from the
 * brick ranges of BuildBrickRanges(): a brick is occupied when it may hold visible samples (the
 * table's largest opacity over the brick's range is > 0; the table is piecewise linear, so that
 * largest value is at an entry inside the range or at an interpolated end point), provably
 * empty otherwise; see the file comment. With isosurfaces (@a iso with Count > 0) a brick is
 * occupied when a visible iso value lies in its range instead (ptvIsosurface.h).
 */
inline void BuildOccupancy(const TransferTable& tf, const int bricks[3], const float* ranges,
  int8_t* out, const IsoSurfaces* iso = nullptr)
{
  const int64_t n = static_cast<int64_t>(bricks[0]) * bricks[1] * bricks[2];
  std::vector<uint8_t> occupied(static_cast<std::size_t>(n), 0);
  if (tf.RGBA && tf.Size > 0) // no table: every sample is transparent, every brick empty
  {
    // positive[i] = number of entries < i with opacity > 0: any opacity in [i0, i1] in O(1).
    std::vector<int> positive(static_cast<std::size_t>(tf.Size) + 1);
    BuildOpaqueCounts(tf.RGBA, tf.Size, positive.data());
    for (int64_t b = 0; b < n; ++b)
    {
      const float lo = ranges[2 * b];
      const float hi = ranges[2 * b + 1];
      bool visible = false;
      if (iso && iso->Count > 0)
      {
        visible = IsoInRange(*iso, tf, lo, hi); // a visible iso value inside the range
      }
      else if (lo <= hi)
      {
        visible = LookupTransfer(tf, lo).Opacity > 0.f || LookupTransfer(tf, hi).Opacity > 0.f;
        const int i0 =
          static_cast<int>(ceilf(TableCoordinate(lo, tf.ScalarMin, tf.ScalarMax, tf.Size)));
        const int i1 =
          static_cast<int>(floorf(TableCoordinate(hi, tf.ScalarMin, tf.ScalarMax, tf.Size)));
        visible = visible || (i0 <= i1 && positive[i1 + 1] - positive[i0] > 0);
      }
      occupied[b] = visible ? 1 : 0;
    }
  }
  OctantDistances(bricks, occupied.data(), out);
}

/// Occupancy view over a distance array built by BuildOccupancy() for g and brickSize.
PTV_HD PTV_INLINE OccupancyGrid MakeOccupancyGrid(
  const VolumeGrid& g, int brickSize, const int8_t* distance)
{
  OccupancyGrid occ;
  occ.Distance = distance;
  occ.BrickSize = brickSize;
  ComputeBrickCounts(g.Dims, brickSize, occ.Bricks);
  return occ;
}
}

#endif
