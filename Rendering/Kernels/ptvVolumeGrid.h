/**
 * @file ptvVolumeGrid.h
 * @brief A scalar volume as a flat array plus its world<->index mapping; sampling and
 *        ray/box intersection in index space.
 *
 * Index space: voxel (i, j, k) sits at the point (i, j, k); the volume occupies the box
 * [0, Dims-1] on each axis and voxel values are stored x fastest:
 * Scalars[i + Dims[0] * (j + Dims[1] * k)] (64-bit offsets, so > 2^31 voxels are fine).
 * The voxels are floats or, read in place from the input array, 8- or 16-bit integers
 * (ScalarType): every read converts one voxel to float, exactly, before any arithmetic, so an
 * integer volume samples bit for bit as its float copy would.
 *
 * WorldToIndex is a row-major 3x4 affine matrix [M | t]: index = M * world + t.
 * NormalToWorld is (A^{-1})^T with A = M^{-1} the index-to-world linear part, i.e. simply M^T:
 * it maps an index-space gradient (d scalar / d index) to the world-space gradient
 * (d scalar / d world), whose direction is the normal and whose length is the gradient magnitude
 * in world units. ComputeNormalToWorld() fills it from WorldToIndex.
 *
 * Ray parameters: the integrator transforms a unit world direction with TransformVector(), so
 * the index-space ray o + t d keeps t in world distance units.
 */
#ifndef ptvVolumeGrid_h
#define ptvVolumeGrid_h

#include "ptvKernelCommon.h"

namespace ptv
{
/// How VolumeGrid::Scalars are stored.
enum ScalarType : int
{
  kScalarFloat = 0,
  kScalarUInt8 = 1,
  kScalarInt8 = 2,
  kScalarUInt16 = 3,
  kScalarInt16 = 4
};

/// Bytes per voxel of a ScalarType.
PTV_HD PTV_INLINE int ScalarTypeSize(int type)
{
  return type == kScalarUInt8 || type == kScalarInt8 ? 1
    : (type == kScalarUInt16 || type == kScalarInt16 ? 2 : 4);
}

struct VolumeGrid
{
  const void* Scalars;   ///< Dims[0]*Dims[1]*Dims[2] values of type Type, x fastest
  int Type = kScalarFloat; ///< ScalarType of Scalars
  int Dims[3];           ///< voxel counts, each >= 1
  float WorldToIndex[12]; ///< row-major 3x4 affine: index = M world + t
  float NormalToWorld[9]; ///< row-major 3x3 (A^{-1})^T = M^T: index gradient -> world gradient
  /// Dependent colour data (vtkVolumeProperty IndependentComponents off), same layout as
  /// Scalars, which then hold the opacity channel: RGB in [0, 1] per voxel (3 floats, 4-component
  /// data), or the colour channel mapped by TraceParams::ColorTable (1 float, 2-component data).
  /// nullptr when the colour comes from the transfer function of Scalars.
  const float* Colors = nullptr;
  const float* ColorScalars = nullptr;
};

/// m * (p, 1) for a row-major 3x4 matrix.
PTV_HD PTV_INLINE Vec3 TransformPoint(const float m[12], Vec3 p)
{
  return MakeVec3(m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3],
    m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7], m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11]);
}

/// m * (v, 0) for a row-major 3x4 matrix (the translation column is ignored).
PTV_HD PTV_INLINE Vec3 TransformVector(const float m[12], Vec3 v)
{
  return MakeVec3(m[0] * v.x + m[1] * v.y + m[2] * v.z, m[4] * v.x + m[5] * v.y + m[6] * v.z,
    m[8] * v.x + m[9] * v.y + m[10] * v.z);
}

/// m * v for a row-major 3x3 matrix.
PTV_HD PTV_INLINE Vec3 MultiplyMatrix3(const float m[9], Vec3 v)
{
  return MakeVec3(m[0] * v.x + m[1] * v.y + m[2] * v.z, m[3] * v.x + m[4] * v.y + m[5] * v.z,
    m[6] * v.x + m[7] * v.y + m[8] * v.z);
}

/// Set g.NormalToWorld = M^T from g.WorldToIndex = [M | t].
PTV_HD PTV_INLINE void ComputeNormalToWorld(VolumeGrid& g)
{
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 3; ++c)
    {
      g.NormalToWorld[3 * r + c] = g.WorldToIndex[4 * c + r];
    }
  }
}

/// fn(data) with Scalars as a pointer to their type: the one place that reads Type.
template <typename Fn>
PTV_HD PTV_INLINE float WithScalars(const VolumeGrid& g, const Fn& fn)
{
  switch (g.Type)
  {
    case kScalarUInt8:
      return fn(static_cast<const uint8_t*>(g.Scalars));
    case kScalarInt8:
      return fn(static_cast<const int8_t*>(g.Scalars));
    case kScalarUInt16:
      return fn(static_cast<const uint16_t*>(g.Scalars));
    case kScalarInt16:
      return fn(static_cast<const int16_t*>(g.Scalars));
    default:
      return fn(static_cast<const float*>(g.Scalars));
  }
}

PTV_HD PTV_INLINE float VoxelValue(const VolumeGrid& g, int i, int j, int k)
{
  const int64_t offset = static_cast<int64_t>(i) +
    static_cast<int64_t>(g.Dims[0]) * (static_cast<int64_t>(j) +
                                         static_cast<int64_t>(g.Dims[1]) * k);
  return WithScalars(g, [&](const auto* data) { return static_cast<float>(data[offset]); });
}

/// Lower cell corner i0, upper corner i1 and weight f for coordinate x on an axis of n voxels
/// (clamp-to-edge: x is first clamped to [0, n-1]; NaN behaves as 0).
PTV_HD PTV_INLINE void CellCoordinate(float x, int n, int& i0, int& i1, float& f)
{
  const float xc = Clamp(x, 0.f, static_cast<float>(n - 1));
  i0 = static_cast<int>(xc); // xc >= 0, so truncation is floor
  if (i0 > n - 2)
  {
    i0 = n >= 2 ? n - 2 : 0;
  }
  i1 = i0 + 1 < n ? i0 + 1 : i0;
  f = xc - static_cast<float>(i0);
}

/// The cell of a trilinear sample: the lower corner's offset, the offsets to the upper corner
/// along x, y and z (0 on a one-voxel axis) and the weights.
struct TrilinearCell
{
  int64_t Base, Ox, Oy, Oz;
  float Fx, Fy, Fz;
};

/// The cell around an index-space point for channel data[stride * voxel] (clamp-to-edge).
PTV_HD PTV_INLINE TrilinearCell FindCell(const VolumeGrid& g, int stride, Vec3 p)
{
  int i0, i1, j0, j1, k0, k1;
  TrilinearCell c;
  CellCoordinate(p.x, g.Dims[0], i0, i1, c.Fx);
  CellCoordinate(p.y, g.Dims[1], j0, j1, c.Fy);
  CellCoordinate(p.z, g.Dims[2], k0, k1, c.Fz);
  const int64_t row = g.Dims[0];
  const int64_t slice = row * g.Dims[1];
  c.Base = stride * (i0 + row * j0 + slice * k0);
  c.Ox = stride * (i1 - i0);
  c.Oy = stride * row * (j1 - j0);
  c.Oz = stride * slice * (k1 - k0);
  return c;
}

/// A cell's eight voxels as float: x fastest, then y, then z.
struct CellCorners
{
  float V[8];
};

template <typename T>
PTV_HD PTV_INLINE CellCorners LoadCorners(const T* data, const TrilinearCell& c)
{
  const T* v = data + c.Base;
  const int64_t o[8] = { 0, c.Ox, c.Oy, c.Oy + c.Ox, c.Oz, c.Oz + c.Ox, c.Oy + c.Oz,
    c.Oy + c.Oz + c.Ox };
  CellCorners out;
  for (int n = 0; n < 8; ++n)
  {
    out.V[n] = static_cast<float>(v[o[n]]);
  }
  return out;
}

/// The trilinear blend of a cell's corners (one expression for every voxel type, so an integer
/// volume rounds as its float copy).
PTV_HD PTV_INLINE float BlendCorners(const CellCorners& v, const TrilinearCell& c)
{
  const float c00 = Lerp(v.V[0], v.V[1], c.Fx);
  const float c10 = Lerp(v.V[2], v.V[3], c.Fx);
  const float c01 = Lerp(v.V[4], v.V[5], c.Fx);
  const float c11 = Lerp(v.V[6], v.V[7], c.Fx);
  return Lerp(Lerp(c00, c10, c.Fy), Lerp(c01, c11, c.Fy), c.Fz);
}

/// Trilinear interpolation of channel data[stride * voxel] at an index-space point,
/// clamp-to-edge outside [0, Dims-1].
template <typename T>
PTV_HD PTV_INLINE float SampleTrilinearArray(const VolumeGrid& g, const T* data, int stride, Vec3 p)
{
  const TrilinearCell c = FindCell(g, stride, p);
  return BlendCorners(LoadCorners(data, c), c);
}

/// The corners of an 8- or 16-bit volume's cell, read out of line: the float path, inlined
/// into every march, stays as small as it was; the blend stays inline, where it rounds alike.
PTV_HD PTV_INLINE PTV_NOINLINE CellCorners LoadIntegerCorners(
  const VolumeGrid& g, const TrilinearCell& c)
{
  CellCorners out{};
  WithScalars(g,
    [&](const auto* data)
    {
      out = LoadCorners(data, c);
      return 0.f;
    });
  return out;
}

/// Trilinear interpolation of the scalars at an index-space point (clamp-to-edge).
PTV_HD PTV_INLINE float SampleTrilinear(const VolumeGrid& g, Vec3 p)
{
  const TrilinearCell c = FindCell(g, 1, p);
  if (g.Type == kScalarFloat)
  {
    return BlendCorners(LoadCorners(static_cast<const float*>(g.Scalars), c), c);
  }
  if (g.Type == kScalarUInt16) // CT's own type: inline as well
  {
    return BlendCorners(LoadCorners(static_cast<const std::uint16_t*>(g.Scalars), c), c);
  }
  return BlendCorners(LoadIntegerCorners(g, c), c);
}

/// Channel data[stride * voxel] of the voxel nearest to an index-space point (clamped).
template <typename T>
PTV_HD PTV_INLINE float SampleNearestArray(const VolumeGrid& g, const T* data, int stride, Vec3 p)
{
  const int i = static_cast<int>(Clamp(p.x + 0.5f, 0.f, static_cast<float>(g.Dims[0] - 1)));
  const int j = static_cast<int>(Clamp(p.y + 0.5f, 0.f, static_cast<float>(g.Dims[1] - 1)));
  const int k = static_cast<int>(Clamp(p.z + 0.5f, 0.f, static_cast<float>(g.Dims[2] - 1)));
  return static_cast<float>(data[stride *
    (static_cast<int64_t>(i) +
      static_cast<int64_t>(g.Dims[0]) *
        (static_cast<int64_t>(j) + static_cast<int64_t>(g.Dims[1]) * k))]);
}

/// SampleNearest of 8- and 16-bit voxels, out of line (see LoadIntegerCorners).
PTV_HD PTV_INLINE PTV_NOINLINE float SampleNearestInteger(const VolumeGrid& g, Vec3 p)
{
  return WithScalars(g, [&](const auto* data) { return SampleNearestArray(g, data, 1, p); });
}

/// Value of the voxel nearest to an index-space point (clamped to the grid).
PTV_HD PTV_INLINE float SampleNearest(const VolumeGrid& g, Vec3 p)
{
  return g.Type == kScalarFloat ? SampleNearestArray(g, static_cast<const float*>(g.Scalars), 1, p)
                                : SampleNearestInteger(g, p);
}

/**
 * Index-space gradient (scalar units per voxel) by central differences of *trilinear* samples
 * one voxel either side: g_x = (S(p + e_x) - S(p - e_x)) / 2, etc. Exact for fields linear in
 * the voxel data; continuous in p. Samples outside the grid clamp to the edge, so on the
 * boundary the difference is one-sided and halved. Map to world with MultiplyMatrix3(
 * g.NormalToWorld, ...). Costs six trilinear samples.
 */
PTV_HD PTV_INLINE Vec3 GradientIndex(const VolumeGrid& g, Vec3 p)
{
  const float gx = SampleTrilinear(g, MakeVec3(p.x + 1.f, p.y, p.z)) -
    SampleTrilinear(g, MakeVec3(p.x - 1.f, p.y, p.z));
  const float gy = SampleTrilinear(g, MakeVec3(p.x, p.y + 1.f, p.z)) -
    SampleTrilinear(g, MakeVec3(p.x, p.y - 1.f, p.z));
  const float gz = SampleTrilinear(g, MakeVec3(p.x, p.y, p.z + 1.f)) -
    SampleTrilinear(g, MakeVec3(p.x, p.y, p.z - 1.f));
  return MakeVec3(0.5f * gx, 0.5f * gy, 0.5f * gz);
}

/// Component-wise reciprocals 1 / d (infinite for zero components): computed once per ray and
/// shared by IntersectBox and March.
PTV_HD PTV_INLINE Vec3 Reciprocal(Vec3 d)
{
  return MakeVec3(1.f / d.x, 1.f / d.y, 1.f / d.z);
}

/// ClipSlab with the reciprocal inv = 1 / d already computed.
PTV_HD PTV_INLINE bool ClipSlabInv(
  float o, float d, float inv, float lo, float hi, float& t0, float& t1)
{
  if (d == 0.f)
  {
    return o >= lo && o <= hi; // parallel: inside the slab for all t, or never
  }
  float ta = (lo - o) * inv;
  float tb = (hi - o) * inv;
  if (ta > tb)
  {
    const float tmp = ta;
    ta = tb;
    tb = tmp;
  }
  t0 = Max(t0, ta);
  t1 = Min(t1, tb);
  return t0 <= t1;
}

/// Clip [t0, t1] by the slab lo <= o + t d <= hi on one axis; false when the slab is missed.
PTV_HD PTV_INLINE bool ClipSlab(float o, float d, float lo, float hi, float& t0, float& t1)
{
  return ClipSlabInv(o, d, 1.f / d, lo, hi, t0, t1);
}

/**
 * Slab-method intersection of the line o + t d (index space) with the box [0, Dims-1].
 * On success tEnter <= tExit bound the overlap (tEnter may be negative when o is inside);
 * returns false when the line misses the box or the box lies entirely behind (tExit < 0).
 * Zero direction components are handled exactly (inside/outside that slab for all t).
 * invD = Reciprocal(d).
 */
PTV_HD PTV_INLINE bool IntersectBox(
  const VolumeGrid& g, Vec3 o, Vec3 d, Vec3 invD, float& tEnter, float& tExit)
{
  float t0 = -kTMax;
  float t1 = kTMax;
  if (!ClipSlabInv(o.x, d.x, invD.x, 0.f, static_cast<float>(g.Dims[0] - 1), t0, t1) ||
    !ClipSlabInv(o.y, d.y, invD.y, 0.f, static_cast<float>(g.Dims[1] - 1), t0, t1) ||
    !ClipSlabInv(o.z, d.z, invD.z, 0.f, static_cast<float>(g.Dims[2] - 1), t0, t1) ||
    t1 < 0.f)
  {
    return false;
  }
  tEnter = t0;
  tExit = t1;
  return true;
}

/// IntersectBox computing the reciprocals itself.
PTV_HD PTV_INLINE bool IntersectBox(
  const VolumeGrid& g, Vec3 o, Vec3 d, float& tEnter, float& tExit)
{
  return IntersectBox(g, o, d, Reciprocal(d), tEnter, tExit);
}
}

#endif
