/**
 * @file ptvKernelCommon.h
 * @brief Shared basics of the per-pixel kernels: the PTV_HD/PTV_INLINE qualifiers and a float Vec3.
 *
 * Everything under Rendering/Kernels is plain C++17 that compiles unchanged for the CPU and,
 * through nvcc, for CUDA devices: no virtual calls, no exceptions, no STL containers, no
 * allocation, only plain structs of pointers and PODs. Every function is `PTV_HD PTV_INLINE`.
 * Math is single precision throughout (float literals, the `f`-suffixed <cmath> functions).
 *
 * PTV_HD expands to `__host__ __device__` under nvcc and to nothing otherwise; it may be
 * predefined (e.g. `-DPTV_HD=`) to override that choice.
 */
#ifndef ptvKernelCommon_h
#define ptvKernelCommon_h

#include <cmath>
#include <cstdint>

#ifndef PTV_HD
#if defined(__CUDACC__)
#define PTV_HD __host__ __device__
#else
#define PTV_HD
#endif
#endif

#ifndef PTV_INLINE
#define PTV_INLINE inline
#endif

/// Keeps a rarely used path (e.g. isosurfaces) out of the hot, fully inlined composite march:
/// the CPU driver inlines everything else into one function per instruction set.
#if defined(__CUDACC__)
#define PTV_NOINLINE __noinline__
#elif defined(__GNUC__)
#define PTV_NOINLINE __attribute__((noinline))
#else
#define PTV_NOINLINE
#endif

namespace ptv
{
constexpr float kPi = 3.14159265358979323846f;
constexpr float kInvPi = 0.31830988618379067154f;
constexpr float kInv4Pi = 0.07957747154594766788f;
/// Stand-in for "unbounded" ray parameters (finite, so it never produces inf - inf).
constexpr float kTMax = 1e30f;

/// Three floats; an aggregate (no constructors) so it can live in any POD parameter block.
struct Vec3
{
  float x, y, z;
};

PTV_HD PTV_INLINE Vec3 MakeVec3(float x, float y, float z)
{
  Vec3 v = { x, y, z };
  return v;
}
PTV_HD PTV_INLINE Vec3 operator+(Vec3 a, Vec3 b)
{
  return MakeVec3(a.x + b.x, a.y + b.y, a.z + b.z);
}
PTV_HD PTV_INLINE Vec3 operator-(Vec3 a, Vec3 b)
{
  return MakeVec3(a.x - b.x, a.y - b.y, a.z - b.z);
}
PTV_HD PTV_INLINE Vec3 operator-(Vec3 a)
{
  return MakeVec3(-a.x, -a.y, -a.z);
}
/// Component-wise product (colours).
PTV_HD PTV_INLINE Vec3 operator*(Vec3 a, Vec3 b)
{
  return MakeVec3(a.x * b.x, a.y * b.y, a.z * b.z);
}
PTV_HD PTV_INLINE Vec3 operator*(Vec3 a, float s)
{
  return MakeVec3(a.x * s, a.y * s, a.z * s);
}
PTV_HD PTV_INLINE Vec3 operator*(float s, Vec3 a)
{
  return MakeVec3(a.x * s, a.y * s, a.z * s);
}
PTV_HD PTV_INLINE Vec3 operator/(Vec3 a, float s)
{
  return MakeVec3(a.x / s, a.y / s, a.z / s);
}
PTV_HD PTV_INLINE Vec3& operator+=(Vec3& a, Vec3 b)
{
  a = a + b;
  return a;
}
PTV_HD PTV_INLINE Vec3& operator-=(Vec3& a, Vec3 b)
{
  a = a - b;
  return a;
}
PTV_HD PTV_INLINE Vec3& operator*=(Vec3& a, float s)
{
  a = a * s;
  return a;
}
PTV_HD PTV_INLINE Vec3& operator*=(Vec3& a, Vec3 b)
{
  a = a * b;
  return a;
}

PTV_HD PTV_INLINE float Dot(Vec3 a, Vec3 b)
{
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
PTV_HD PTV_INLINE Vec3 Cross(Vec3 a, Vec3 b)
{
  return MakeVec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
PTV_HD PTV_INLINE float LengthSquared(Vec3 a)
{
  return Dot(a, a);
}
PTV_HD PTV_INLINE float Length(Vec3 a)
{
  return sqrtf(Dot(a, a));
}
/// Unit vector along a; the zero vector when |a|^2 <= 1e-30 (or is NaN).
PTV_HD PTV_INLINE Vec3 Normalize(Vec3 a)
{
  const float len2 = Dot(a, a);
  if (!(len2 > 1e-30f))
  {
    return MakeVec3(0.f, 0.f, 0.f);
  }
  return a * (1.f / sqrtf(len2));
}
PTV_HD PTV_INLINE bool IsZero(Vec3 a)
{
  return a.x == 0.f && a.y == 0.f && a.z == 0.f;
}

/// NaN-tolerant scalar helpers with fminf/fmaxf's results (the non-NaN operand wins), written
/// as comparisons: without -ffast-math GCC turns fminf/fmaxf into library calls on x86-64,
/// which costs the per-sample code dearly.
PTV_HD PTV_INLINE float Min(float a, float b)
{
  return (a < b || b != b) ? a : b;
}
PTV_HD PTV_INLINE float Max(float a, float b)
{
  return (a > b || b != b) ? a : b;
}
/// Clamp to [lo, hi]; NaN maps to lo.
PTV_HD PTV_INLINE float Clamp(float v, float lo, float hi)
{
  return Min(Max(v, lo), hi);
}
PTV_HD PTV_INLINE int ClampInt(int v, int lo, int hi)
{
  return v < lo ? lo : (v > hi ? hi : v);
}
PTV_HD PTV_INLINE Vec3 Min(Vec3 a, Vec3 b)
{
  return MakeVec3(Min(a.x, b.x), Min(a.y, b.y), Min(a.z, b.z));
}
PTV_HD PTV_INLINE Vec3 Max(Vec3 a, Vec3 b)
{
  return MakeVec3(Max(a.x, b.x), Max(a.y, b.y), Max(a.z, b.z));
}
PTV_HD PTV_INLINE Vec3 Clamp(Vec3 v, Vec3 lo, Vec3 hi)
{
  return MakeVec3(Clamp(v.x, lo.x, hi.x), Clamp(v.y, lo.y, hi.y), Clamp(v.z, lo.z, hi.z));
}
/// a + t (b - a): exact at t = 0 and returns a exactly when a == b.
PTV_HD PTV_INLINE float Lerp(float a, float b, float t)
{
  return a + t * (b - a);
}
/// Component i (0, 1, 2) of v.
PTV_HD PTV_INLINE float Component(Vec3 v, int i)
{
  return i == 0 ? v.x : (i == 1 ? v.y : v.z);
}
}

#endif
