/**
 * @file ptvOccupancy.h
 * @brief Empty-space skipping: per-brick signed distances (to the nearest brick that may be
 *        visible, or to the nearest empty one), and the ray/region exit query.
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
 * Distance[bx + Bricks[0] * (by + Bricks[1] * bz)] is a signed chessboard (Chebyshev) distance
 * in bricks, so that one lookup settles a whole cube of bricks around the brick:
 *  - d >= 1 (empty brick): every brick within distance d - 1 is empty. A ray in empty brick b
 *    skips the whole cube [b - (d-1), b + (d-1)] in one step (RegionExitT), instead of one
 *    brick at a time. d is the distance to the nearest occupied brick, capped at 127.
 *  - d <= 0 (occupied brick): every brick within distance -d is occupied (-d is the distance to
 *    the nearest empty brick minus one, capped at 127). A ray in occupied brick b visits every
 *    sample up to the exit of the cube [b + d, b - d] without another lookup: inside dense
 *    material it looks up once per cube, not once per brick. Visiting samples is always exact
 *    (only skipping relies on the grid), so this part needs no conservative rounding.
 * Cubes are clipped to the grid; edge bricks still extend to infinity, and bricks outside the
 * grid limit neither distance. Both come from the exact two-pass chamfer transform with the
 * 26-neighbourhood and unit weights (which computes the chessboard metric exactly), one from
 * the occupied bricks and one from the empty ones.
 */
#ifndef ptvOccupancy_h
#define ptvOccupancy_h

#include "ptvIsosurface.h"
#include "ptvKernelCommon.h"
#include "ptvTransferTable.h"
#include "ptvVolumeGrid.h"

#include <vector>

namespace ptv
{
struct OccupancyGrid
{
  /// Bricks[0]*Bricks[1]*Bricks[2] signed distances (>= 1 empty, <= 0 occupied; see the file
  /// comment), or nullptr (no skipping)
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

/// Signed distance of brick b (>= 1: empty, <= 0: occupied).
PTV_HD PTV_INLINE int DistanceAt(const OccupancyGrid& occ, const int b[3])
{
  return occ.Distance[b[0] + occ.Bricks[0] * (b[1] + occ.Bricks[1] * b[2])];
}

/// Half-width, in bricks, of the cube around a brick of signed distance d that a ray crosses
/// in one step: d - 1 for an empty brick, -d for an occupied one.
PTV_HD PTV_INLINE int CubeRadius(int d)
{
  return d > 0 ? d - 1 : -d;
}

/// Exit parameter on one axis of the slab of bricks [b - r, b + r] for a ray with origin o and
/// direction component d (invD = 1 / d); kTMax if it has none in that direction (the ray is
/// parallel, or the slab reaches the grid's edge brick).
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
 * leaves the cube of bricks [b - r, b + r] (r = 0: brick b itself); always > t (the next float
 * above t when rounding puts the computed exit at or before t), kTMax when the ray never leaves
 * it. Rounding of the exit only moves it by ulps, far inside the one-voxel border that keeps
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
 * HOST ONLY. For the bricks with z coordinate in [bzBegin, bzEnd): the range of values their
 * trilinear samples can take (see the file comment: footprint plus a one-voxel border, widened
 * by a few ulps), ranges[2 b] = lo and ranges[2 b + 1] = hi. A footprint holding a NaN voxel gets
 * lo = -kTMax, which makes the test include table entry 0 (NaN samples are transparent, so
 * this is only conservative). This depends on the voxels alone: a transfer-function change
 * reuses it (BuildOccupancy). Slabs of bz can be filled in parallel.
 */
inline void BuildBrickRanges(
  const VolumeGrid& g, int brickSize, int bzBegin, int bzEnd, float* ranges)
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
        for (int k = lo[2]; k <= hi[2]; ++k)
        {
          for (int j = lo[1]; j <= hi[1]; ++j)
          {
            for (int i = lo[0]; i <= hi[0]; ++i)
            {
              const float v = VoxelValue(g, i, j, k);
              hasNaN = hasNaN || v != v;
              vmin = fminf(vmin, v);
              vmax = fmaxf(vmax, v);
            }
          }
        }
        const float eps = 1e-6f * (fabsf(vmin) + fabsf(vmax)) + 1e-30f;
        const int64_t index = bx + static_cast<int64_t>(bricks[0]) * (by + bricks[1] * bz);
        ranges[2 * index] = hasNaN ? -kTMax : vmin - eps;
        ranges[2 * index + 1] = vmax + eps;
      }
    }
  }
}

/**
 * HOST ONLY. In place: turn flags (0 or not) over bricks[3] into each brick's chessboard
 * distance to the nearest flagged brick (0 for flagged ones, 255 when none is flagged or the
 * distance is larger) by a forward and a backward chamfer pass; bricks outside the grid are
 * not flagged.
 */
inline void ChessboardDistance(const int bricks[3], uint8_t* d)
{
  const int nx = bricks[0], ny = bricks[1], nz = bricks[2];
  auto at = [&](int x, int y, int z) -> uint8_t& { return d[x + nx * (y + ny * z)]; };
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x)
        at(x, y, z) = at(x, y, z) ? 0 : 255;
  for (int pass = 0; pass < 2; ++pass)
  {
    const int s = pass == 0 ? 1 : -1; // forward: neighbours already visited lie at -1 offsets
    for (int zi = 0; zi < nz; ++zi)
    {
      const int z = pass == 0 ? zi : nz - 1 - zi;
      for (int yi = 0; yi < ny; ++yi)
      {
        const int y = pass == 0 ? yi : ny - 1 - yi;
        for (int xi = 0; xi < nx; ++xi)
        {
          const int x = pass == 0 ? xi : nx - 1 - xi;
          int best = at(x, y, z);
          // The 13 neighbours that precede (x, y, z) in this pass's scan order.
          for (int dz = -1; dz <= 0; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
              for (int dx = -1; dx <= 1; ++dx)
              {
                if (dz == 0 && (dy > 0 || (dy == 0 && dx >= 0)))
                {
                  continue;
                }
                const int qx = x + s * dx, qy = y + s * dy, qz = z + s * dz;
                if (qx >= 0 && qx < nx && qy >= 0 && qy < ny && qz >= 0 && qz < nz)
                {
                  best = best < at(qx, qy, qz) + 1 ? best : at(qx, qy, qz) + 1;
                }
              }
          at(x, y, z) = static_cast<uint8_t>(best < 255 ? best : 255);
        }
      }
    }
  }
}

/**
 * HOST ONLY. The signed distances of the file comment from occupancy flags (0 empty, else
 * occupied) over bricks[3]: @a out[b] >= 1 for empty bricks, <= 0 for occupied ones.
 */
inline void SignedChessboardDistance(const int bricks[3], const uint8_t* occupied, int8_t* out)
{
  const std::size_t n = static_cast<std::size_t>(bricks[0]) * bricks[1] * bricks[2];
  std::vector<uint8_t> toOccupied(occupied, occupied + n);
  std::vector<uint8_t> toEmpty(n);
  for (std::size_t b = 0; b < n; ++b)
  {
    toEmpty[b] = occupied[b] ? 0 : 1;
  }
  ChessboardDistance(bricks, toOccupied.data());
  ChessboardDistance(bricks, toEmpty.data());
  for (std::size_t b = 0; b < n; ++b)
  {
    const int d = occupied[b] ? -(toEmpty[b] - 1) : toOccupied[b];
    out[b] = static_cast<int8_t>(ClampInt(d, -127, 127));
  }
}

/**
 * HOST ONLY. Fill out[Bricks[0]*Bricks[1]*Bricks[2]] with each brick's signed distance from the
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
    positive[0] = 0;
    for (int i = 0; i < tf.Size; ++i)
    {
      positive[i + 1] = positive[i] + (tf.RGBA[4 * i + 3] > 0.f ? 1 : 0);
    }
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
  SignedChessboardDistance(bricks, occupied.data(), out);
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
