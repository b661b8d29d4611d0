/**
 * @file ptvCamera.h
 * @brief Primary rays from a pixel position by unprojecting OpenGL NDC points.
 *
 * WorldFromNdc is the row-major inverse of (projection * view) acting on column vectors, e.g.
 * the inverse of vtkCamera::GetCompositeProjectionTransformMatrix(aspect, -1, 1). Pixel
 * coordinates run over [0, Width] x [0, Height] with y up (OpenGL window convention); the centre
 * of pixel (x, y) is (x + 0.5, y + 0.5). NDC x = 2 px / Width - 1, y = 2 py / Height - 1; the
 * points at NDC z = -1 (near plane) and z = +1 (far plane) give the ray direction. A perspective
 * ray starts at Eye, a parallel one on the near plane; the ray parameter is world distance from
 * that origin (Depth outputs and MaxDistance use it). FarDistance is the depth reported for
 * pixels without a hit.
 */
#ifndef ptvCamera_h
#define ptvCamera_h

#include "ptvKernelCommon.h"

namespace ptv
{
struct CameraRays
{
  float WorldFromNdc[16]; ///< row-major inverse of projection * view
  Vec3 Eye;               ///< camera position (origin of perspective rays)
  int Parallel;           ///< 1: parallel projection
  int Width;              ///< image width in pixels
  int Height;             ///< image height in pixels
  float FarDistance;      ///< depth written for misses
};

/// Projective transform of (x, y, z, 1) by a row-major 4x4 matrix, divided by w.
PTV_HD PTV_INLINE Vec3 TransformProjective(const float m[16], float x, float y, float z)
{
  const float X = m[0] * x + m[1] * y + m[2] * z + m[3];
  const float Y = m[4] * x + m[5] * y + m[6] * z + m[7];
  const float Z = m[8] * x + m[9] * y + m[10] * z + m[11];
  const float W = m[12] * x + m[13] * y + m[14] * z + m[15];
  const float invW = 1.f / W;
  return MakeVec3(X * invW, Y * invW, Z * invW);
}

/// World-space ray through pixel position (px, py); dir is unit length.
PTV_HD PTV_INLINE void GenerateRay(
  const CameraRays& cam, float px, float py, Vec3& origin, Vec3& dir)
{
  const float nx = 2.f * px / static_cast<float>(cam.Width) - 1.f;
  const float ny = 2.f * py / static_cast<float>(cam.Height) - 1.f;
  const Vec3 pNear = TransformProjective(cam.WorldFromNdc, nx, ny, -1.f);
  const Vec3 pFar = TransformProjective(cam.WorldFromNdc, nx, ny, 1.f);
  dir = Normalize(pFar - pNear);
  origin = cam.Parallel ? pNear : cam.Eye;
}
}

#endif
