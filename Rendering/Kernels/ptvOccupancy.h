/**
 * @file ptvOccupancy.h
 * @brief Empty-space skipping: a per-brick "may be visible" flag and the ray/brick exit query.
 *
 * The grid is cut into bricks of BrickSize^3 voxels in index space; brick b covers positions
 * [b B, (b+1) B) on each axis, with the outermost bricks extended to infinity (positions outside
 * the box sample the edge voxels, which belong to them). Bricks[a] = (Dims[a] - 1) / B + 1.
 * Occupied[bx + Bricks[0] * (by + Bricks[1] * bz)] is 0 only if every trilinear sample at a
 * position of the brick has zero opacity, so skipping empty bricks never changes a result.
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
 */
#ifndef ptvOccupancy_h
#define ptvOccupancy_h

#include "ptvKernelCommon.h"
#include "ptvTransferTable.h"
#include "ptvVolumeGrid.h"

namespace ptv
{
struct OccupancyGrid
{
  const uint8_t* Occupied; ///< Bricks[0]*Bricks[1]*Bricks[2] flags, or nullptr (no skipping)
  int BrickSize;           ///< voxels per brick edge (>= 1)
  int Bricks[3];           ///< brick counts
};

/// Brick counts covering index positions [0, Dims-1]: (Dims - 1) / brickSize + 1 per axis.
PTV_HD PTV_INLINE void ComputeBrickCounts(const int dims[3], int brickSize, int bricks[3])
{
  for (int a = 0; a < 3; ++a)
  {
    bricks[a] = (dims[a] > 1 ? dims[a] - 1 : 0) / brickSize + 1;
  }
}

/// Brick coordinate of an index-space coordinate (clamped; NaN -> 0).
PTV_HD PTV_INLINE int BrickCoordinate(float x, int brickSize, int bricks)
{
  return static_cast<int>(
    Clamp(floorf(x / static_cast<float>(brickSize)), 0.f, static_cast<float>(bricks - 1)));
}

/// True when the brick containing the index-space point is marked empty.
PTV_HD PTV_INLINE bool BrickEmpty(const OccupancyGrid& occ, Vec3 p)
{
  const int bx = BrickCoordinate(p.x, occ.BrickSize, occ.Bricks[0]);
  const int by = BrickCoordinate(p.y, occ.BrickSize, occ.Bricks[1]);
  const int bz = BrickCoordinate(p.z, occ.BrickSize, occ.Bricks[2]);
  return occ.Occupied[bx + occ.Bricks[0] * (by + occ.Bricks[1] * bz)] == 0;
}

/// Exit parameter on one axis of the brick slab containing coordinate x (kTMax if none).
PTV_HD PTV_INLINE float BrickAxisExit(float x, float o, float d, int brickSize, int bricks)
{
  const int b = BrickCoordinate(x, brickSize, bricks);
  if (d > 0.f && b < bricks - 1)
  {
    return (static_cast<float>((b + 1) * brickSize) - o) / d;
  }
  if (d < 0.f && b > 0)
  {
    return (static_cast<float>(b * brickSize) - o) / d;
  }
  return kTMax;
}

/**
 * Ray parameter where the index-space ray o + t d leaves the brick containing o + t d;
 * always > t (the next float above t when rounding puts the computed exit at or before t),
 * kTMax when the ray never leaves it.
 */
PTV_HD PTV_INLINE float BrickExitT(const OccupancyGrid& occ, Vec3 o, Vec3 d, float t)
{
  const Vec3 p = o + d * t;
  const float te = fminf(BrickAxisExit(p.x, o.x, d.x, occ.BrickSize, occ.Bricks[0]),
    fminf(BrickAxisExit(p.y, o.y, d.y, occ.BrickSize, occ.Bricks[1]),
      BrickAxisExit(p.z, o.z, d.z, occ.BrickSize, occ.Bricks[2])));
  return te > t ? te : nextafterf(t, kTMax);
}

/// Largest table opacity over scalars [lo, hi] (entries inside plus interpolated end points).
PTV_HD PTV_INLINE float MaxOpacityInRange(const TransferTable& tf, float lo, float hi)
{
  if (!tf.RGBA || tf.Size <= 0)
  {
    return 0.f;
  }
  float m = fmaxf(LookupTransfer(tf, lo).Opacity, LookupTransfer(tf, hi).Opacity);
  const float x0 = TableCoordinate(lo, tf.ScalarMin, tf.ScalarMax, tf.Size);
  const float x1 = TableCoordinate(hi, tf.ScalarMin, tf.ScalarMax, tf.Size);
  for (int i = static_cast<int>(ceilf(x0)); i <= static_cast<int>(floorf(x1)); ++i)
  {
    m = fmaxf(m, tf.RGBA[4 * i + 3]);
  }
  return m;
}

/**
 * HOST ONLY. Fill out[Bricks[0]*Bricks[1]*Bricks[2]] (see ComputeBrickCounts) with 1 for bricks
 * that may hold visible samples and 0 for provably empty ones; see the file comment.
 */
inline void BuildOccupancy(
  const VolumeGrid& g, const TransferTable& tf, int brickSize, uint8_t* out)
{
  int bricks[3];
  ComputeBrickCounts(g.Dims, brickSize, bricks);
  for (int bz = 0; bz < bricks[2]; ++bz)
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
        float maxOpacity = vmin <= vmax ? MaxOpacityInRange(tf, vmin - eps, vmax + eps) : 0.f;
        if (hasNaN && tf.RGBA && tf.Size > 0)
        {
          maxOpacity = fmaxf(maxOpacity, tf.RGBA[3]); // conservative (NaN samples are transparent)
        }
        out[bx + bricks[0] * (by + bricks[1] * bz)] = maxOpacity > 0.f ? 1 : 0;
      }
    }
  }
}

/// Occupancy view over a flag array built by BuildOccupancy() for g and brickSize.
PTV_HD PTV_INLINE OccupancyGrid MakeOccupancyGrid(
  const VolumeGrid& g, int brickSize, const uint8_t* occupied)
{
  OccupancyGrid occ;
  occ.Occupied = occupied;
  occ.BrickSize = brickSize;
  ComputeBrickCounts(g.Dims, brickSize, occ.Bricks);
  return occ;
}
}

#endif
