/**
 * @file ptvClipping.h
 * @brief What part of the volume is kept: VTK's clipping planes and cropping regions, in index
 *        space.
 *
 * Clipping planes (vtkAbstractMapper::AddClippingPlane, world space, at most 6): a point is kept
 * when it lies on the side the plane normal points to, N.p + D >= 0 (VTK's convention). Cropping
 * (vtkVolumeMapper::SetCropping): six axis-aligned planes x0 <= x1, y0 <= y1, z0 <= z1 cut the
 * index box into 27 regions, numbered x fastest (region r = rx + 3 ry + 9 rz with ra = 0 below
 * the lower plane, 1 between, 2 above the upper one); bit r of Flags keeps region r
 * (VTK_CROP_SUBVOLUME = bit 13 keeps the centre only).
 *
 * Every march treats a point that is not kept as transparent (ClassifyPoint), so camera, shadow
 * and environment rays all see the same cut volume, and empty-space skipping stays exact. Rays
 * are also clipped to the convex part (the planes' half-spaces, and the centre box when only
 * the centre region is kept) before marching (ClipInterval), which only saves samples.
 */
#ifndef ptvClipping_h
#define ptvClipping_h

#include "ptvKernelCommon.h"
#include "ptvVolumeGrid.h"

namespace ptv
{
struct ClipRegion
{
  int PlaneCount = 0;   ///< 0..6
  float Planes[6][4];   ///< index space (N.x, N.y, N.z, D): kept where N.p + D >= 0
  int Cropping = 0;     ///< 0: no cropping
  float CropPlanes[6];  ///< index space: x0, x1, y0, y1, z0, z1
  int CropFlags = 0;    ///< bit r keeps region r
};

/// Whether anything is cut away at all.
PTV_HD PTV_INLINE bool HasClipping(const ClipRegion& c)
{
  return c.PlaneCount > 0 || c.Cropping;
}

/// Cropping region (0..26) of an index-space point.
PTV_HD PTV_INLINE int CropRegion(const ClipRegion& c, Vec3 p)
{
  const float v[3] = { p.x, p.y, p.z };
  int region = 0;
  int scale = 1;
  for (int a = 0; a < 3; ++a)
  {
    const int r = v[a] < c.CropPlanes[2 * a] ? 0 : (v[a] > c.CropPlanes[2 * a + 1] ? 2 : 1);
    region += r * scale;
    scale *= 3;
  }
  return region;
}

/// Whether the index-space point is kept (see the file comment).
PTV_HD PTV_INLINE bool KeptPoint(const ClipRegion& c, Vec3 p)
{
  for (int i = 0; i < c.PlaneCount; ++i)
  {
    const float* q = c.Planes[i];
    if (!(q[0] * p.x + q[1] * p.y + q[2] * p.z + q[3] >= 0.f))
    {
      return false;
    }
  }
  return !c.Cropping || ((c.CropFlags >> CropRegion(c, p)) & 1) != 0;
}

/**
 * Clip [t0, t1] of the index-space ray o + t d to the convex kept part: every plane's
 * half-space, and the centre box when the crop flags keep the centre region only. Returns
 * false when nothing is left. Points outside the result are never kept, so marching the clipped
 * interval only skips transparent samples of the unclipped one.
 */
PTV_HD PTV_INLINE bool ClipInterval(const ClipRegion& c, Vec3 o, Vec3 d, float& t0, float& t1)
{
  for (int i = 0; i < c.PlaneCount; ++i)
  {
    const float* q = c.Planes[i];
    const float s = q[0] * o.x + q[1] * o.y + q[2] * o.z + q[3]; // value at t = 0
    const float rate = q[0] * d.x + q[1] * d.y + q[2] * d.z;      // change per unit t
    if (rate == 0.f)
    {
      if (!(s >= 0.f))
      {
        return false;
      }
      continue;
    }
    const float tPlane = -s / rate;
    if (rate > 0.f)
    {
      t0 = Max(t0, tPlane);
    }
    else
    {
      t1 = Min(t1, tPlane);
    }
  }
  if (c.Cropping && c.CropFlags == (1 << 13))
  {
    if (!ClipSlab(o.x, d.x, c.CropPlanes[0], c.CropPlanes[1], t0, t1) ||
      !ClipSlab(o.y, d.y, c.CropPlanes[2], c.CropPlanes[3], t0, t1) ||
      !ClipSlab(o.z, d.z, c.CropPlanes[4], c.CropPlanes[5], t0, t1))
    {
      return false;
    }
  }
  return t0 < t1;
}
}

#endif
