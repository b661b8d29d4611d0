/**
 * @file ptvSampling.h
 * @brief Direction sampling (pbrt-v4 style small functions): uniform sphere, cosine hemisphere.
 *
 * Each Sample* function maps uniform numbers in [0,1)^2 to a direction; the matching *Pdf gives
 * its density with respect to solid angle. The orthonormal basis around a normal is the
 * branchless construction of Duff et al., "Building an Orthonormal Basis, Revisited" (JCGT 2017),
 * robust for every unit normal including n = (0, 0, -1).
 */
#ifndef ptvSampling_h
#define ptvSampling_h

#include "ptvKernelCommon.h"

namespace ptv
{
/// Unit tangents b1, b2 such that (b1, b2, n) is a right-handed orthonormal frame (n unit).
PTV_HD PTV_INLINE void OrthonormalBasis(Vec3 n, Vec3& b1, Vec3& b2)
{
  const float sign = copysignf(1.f, n.z);
  const float a = -1.f / (sign + n.z);
  const float b = n.x * n.y * a;
  b1 = MakeVec3(1.f + sign * n.x * n.x * a, sign * b, -sign * n.x);
  b2 = MakeVec3(b, sign + n.y * n.y * a, -n.y);
}

/// Shirley-Chiu concentric map of [0,1)^2 onto the unit disk (area-uniform).
PTV_HD PTV_INLINE void SampleUniformDiskConcentric(float u1, float u2, float& dx, float& dy)
{
  const float ox = 2.f * u1 - 1.f;
  const float oy = 2.f * u2 - 1.f;
  if (ox == 0.f && oy == 0.f)
  {
    dx = 0.f;
    dy = 0.f;
    return;
  }
  float r, theta;
  if (fabsf(ox) > fabsf(oy))
  {
    r = ox;
    theta = 0.25f * kPi * (oy / ox);
  }
  else
  {
    r = oy;
    theta = 0.5f * kPi - 0.25f * kPi * (ox / oy);
  }
  dx = r * cosf(theta);
  dy = r * sinf(theta);
}

/// Cosine-weighted direction about +z (Malley's method), pdf = cos(theta) / pi.
PTV_HD PTV_INLINE Vec3 SampleCosineHemisphereLocal(float u1, float u2)
{
  float dx, dy;
  SampleUniformDiskConcentric(u1, u2, dx, dy);
  const float dz = sqrtf(Max(0.f, 1.f - dx * dx - dy * dy));
  return MakeVec3(dx, dy, dz);
}

PTV_HD PTV_INLINE float CosineHemispherePdf(float cosTheta)
{
  return cosTheta > 0.f ? cosTheta * kInvPi : 0.f;
}

/// Cosine-weighted direction about the unit normal n, pdf = max(0, dot(w, n)) / pi.
PTV_HD PTV_INLINE Vec3 SampleCosineHemisphere(Vec3 n, float u1, float u2)
{
  Vec3 b1, b2;
  OrthonormalBasis(n, b1, b2);
  const Vec3 l = SampleCosineHemisphereLocal(u1, u2);
  return b1 * l.x + b2 * l.y + n * l.z;
}

/// Uniform direction on the unit sphere (z = 1 - 2 u1, phi = 2 pi u2), pdf = 1 / (4 pi).
PTV_HD PTV_INLINE Vec3 SampleUniformSphere(float u1, float u2)
{
  const float z = 1.f - 2.f * u1;
  const float r = sqrtf(Max(0.f, 1.f - z * z));
  const float phi = 2.f * kPi * u2;
  return MakeVec3(r * cosf(phi), r * sinf(phi), z);
}

PTV_HD PTV_INLINE float UniformSpherePdf()
{
  return kInv4Pi;
}
}

#endif
