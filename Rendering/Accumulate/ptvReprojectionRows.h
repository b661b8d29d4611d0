/**
 * @file ptvReprojectionRows.h
 * @brief Private: the per-pixel step of Reprojection (ptvReprojection.h, steps 1.-4.) and the
 *        rows loop that runs it; included by ptvReprojection.cxx only, which compiles the loop
 *        for the baseline and x86-64-v3 as the tracer does.
 */
#ifndef ptvReprojectionRows_h
#define ptvReprojectionRows_h

#include "ptvReprojection.h"

#include "vtkMatrix4x4.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <numeric>

namespace ptv
{
namespace reprojection
{
constexpr float kAlbedoDifference = 0.25f;
constexpr float kToleranceScale = 3.0f;
constexpr float kRelativeTolerance = 0.05f; ///< of the point's distance
constexpr float kMinimumWeight = 1e-3f; ///< kept bilinear weight below which there is no history
constexpr float kHitCoverage = 0.2f;    ///< a hit's history covers the surface at least this much
constexpr float kMissCoverage = 0.9f;   ///< a miss's history covers the surface at most this much

/// Turn of the view (degrees) at which the history's weight reaches 0; see HistoryFade. Paired
/// runs (same samples, histories dropped) on 12-view orbits of 2, 4 and 8 degrees per frame:
/// without a fade the 4- and 8-degree orbits lost up to 1.3 dB on a frame (the head); 8 gained
/// on every orbit and frame of the head and the stent (docs/decisions.md).
constexpr double kHistoryAngle = 8.0;
constexpr double kTurnPrecision = 1e-5; ///< radians; see HistoryFade

/**
 * Factor on MaximumHistory for a view that turned by @a turn (radians: the rotation angle
 * between the two views' frames, see ViewTurn): 1 - turn / kHistoryAngle, at least 0. What the
 * history saw drifts with the turn: lights that follow the camera, highlights, content behind
 * the first event.
 */
inline float HistoryFade(double turn)
{
  // A turn within kTurnPrecision of the limit is the limit: the float camera matrices leave
  // an exact 8-degree orbit a fade of ~1e-4 otherwise, whose trace in the pixels the new frame
  // missed the denoiser's tone-mapped colour input magnifies.
  const double limit = kHistoryAngle * 3.14159265358979323846 / 180.0;
  return turn < limit - kTurnPrecision ? static_cast<float>(1.0 - turn / limit) : 0.f;
}

inline Vec3 Load3(const float* b, std::size_t i)
{
  return MakeVec3(b[3 * i], b[3 * i + 1], b[3 * i + 2]);
}

/// A camera's ray ends on its near and far planes, affine in the pixel index (x, y) (the ray
/// through the pixel's centre: GenerateRay(x + 0.5, y + 0.5)), as VTK's projections are.
struct RayPlanes
{
  Vec3 Near0, NearX, NearY, Far0, FarX, FarY;

  explicit RayPlanes(const CameraRays& c)
  {
    auto at = [&c](float px, float py, float z)
    {
      return TransformProjective(
        c.WorldFromNdc, 2.f * px / float(c.Width) - 1.f, 2.f * py / float(c.Height) - 1.f, z);
    };
    this->Near0 = at(0.5f, 0.5f, -1.f);
    this->NearX = at(1.5f, 0.5f, -1.f) - this->Near0;
    this->NearY = at(0.5f, 1.5f, -1.f) - this->Near0;
    this->Far0 = at(0.5f, 0.5f, 1.f);
    this->FarX = at(1.5f, 0.5f, 1.f) - this->Far0;
    this->FarY = at(0.5f, 1.5f, 1.f) - this->Far0;
  }
  Vec3 Near(float x, float y) const { return this->Near0 + this->NearX * x + this->NearY * y; }
  Vec3 Far(float x, float y) const { return this->Far0 + this->FarX * x + this->FarY * y; }
};

/**
 * The rotation angle (radians) from view @a a to view @a b: the angle of the rotation that takes
 * one view's frame (the image's right and up directions on the far plane, and their cross
 * product) to the other's. An orbit of 8 degrees turns it by 8 at any elevation (the central
 * ray alone turns by less, the more the orbit's axis leans toward it) and a roll counts as well;
 * a pan, a dolly or a zoom leaves it at 0. In double precision: the far plane's axes are small
 * differences of large coordinates.
 */
inline double ViewTurn(const CameraRays& a, const CameraRays& b)
{
  using Axis = std::array<double, 3>;
  auto cross = [](const Axis& u, const Axis& v) -> Axis
  { return { u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0] }; };
  auto dot = [](const Axis& u, const Axis& v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; };
  auto axes = [&](const CameraRays& c, Axis out[3])
  {
    const float* m = c.WorldFromNdc;
    auto point = [m](double x, double y, int row)
    { // z = 1: the far plane
      const double w = m[12] * x + m[13] * y + m[14] + m[15];
      return (m[4 * row] * x + m[4 * row + 1] * y + m[4 * row + 2] + m[4 * row + 3]) / w;
    };
    const double x0 = -1.0, x1 = 2.0 / c.Width - 1.0, y1 = 2.0 / c.Height - 1.0;
    for (int r = 0; r < 3; ++r)
    {
      out[0][r] = point(x1, x0, r) - point(x0, x0, r);
      out[1][r] = point(x0, y1, r) - point(x0, x0, r);
    }
    out[2] = cross(out[0], out[1]);
    for (int k = 0; k < 3; ++k)
    {
      const double n = std::sqrt(dot(out[k], out[k]));
      for (double& v : out[k])
      {
        v = n > 0.0 ? v / n : 0.0;
      }
    }
  };
  Axis p[3], q[3];
  axes(a, p);
  axes(b, q);
  // R = Q P^T: trace = 1 + 2 cos(angle); the sum of the axes' cross products is its
  // antisymmetric part, of length 2 sin(angle) (exact for small angles, where acos is not)
  double trace = 0.0;
  Axis v = { 0.0, 0.0, 0.0 };
  for (int k = 0; k < 3; ++k)
  {
    trace += dot(p[k], q[k]);
    const Axis c = cross(p[k], q[k]);
    for (int r = 0; r < 3; ++r)
    {
      v[r] += c[r];
    }
  }
  return std::atan2(0.5 * std::sqrt(dot(v, v)), 0.5 * (trace - 1.0));
}

/// Everything one frame's reprojection reads, and the per-pixel step (file comment, 1.-4.).
struct Reprojector
{
  const CameraRays& Prev;
  const CameraRays& Cur;
  RayPlanes PrevRays, CurRays;
  float NdcFromWorld[16]; ///< the previous camera's projection * view
  Vec3 PrevDirection;     ///< the previous camera's ray direction (parallel projection)
  float FootprintAt0 = 0.f, FootprintPerT = 0.f; ///< pixel size at distance t: At0 + PerT t
  float Step = 0.f;
  float Cap = 1.f;
  double Turn = 0.0; ///< the view's rotation since the previous frame (radians, ViewTurn)
  // previous accumulation
  const float* PrevRadiance;
  const float* PrevAlpha;
  const float* PrevDepth;
  const float* PrevPosition;
  const float* PrevAlbedo;
  const float* PrevCount;
  // new frame
  const float* Radiance;
  const float* Alpha;
  const float* Depth;
  const float* Albedo;
  const int* HitBegin; ///< per row: the first hit's x (width when none)
  const int* HitEnd;   ///< per row: past the last hit's x (0 when none)
  // output: Radiance and Alpha in place of the new frame's (each pixel reads only its own)
  float* OutRadiance;
  float* OutAlpha;
  float* OutCount;
  /// Per pixel, 1: the new frame alone (count 1), whatever its history; nullptr: none.
  const unsigned char* Fresh1 = nullptr;

  Reprojector(const CameraRays& prev, const CameraRays& cur)
    : Prev(prev)
    , Cur(cur)
    , PrevRays(prev)
    , CurRays(cur)
  {
    double worldFromNdc[16], ndcFromWorld[16];
    std::copy(prev.WorldFromNdc, prev.WorldFromNdc + 16, worldFromNdc);
    vtkMatrix4x4::Invert(worldFromNdc, ndcFromWorld);
    std::copy(ndcFromWorld, ndcFromWorld + 16, this->NdcFromWorld);
    this->PrevDirection = Normalize(this->PrevRays.Far0 - this->PrevRays.Near0);
    const float cx = 0.5f * float(cur.Width), cy = 0.5f * float(cur.Height);
    const Vec3 d0 = Normalize(this->CurRays.Far(cx, cy) - this->CurRays.Near(cx, cy));
    const Vec3 d1 = Normalize(this->CurRays.Far(cx + 1, cy) - this->CurRays.Near(cx + 1, cy));
    this->Turn = ViewTurn(prev, cur);
    this->FootprintAt0 = cur.Parallel ? Length(this->CurRays.NearX) : 0.f;
    this->FootprintPerT = cur.Parallel ? 0.f : Length(d1 - d0);
  }

  /**
   * The fraction c of previous pixel j that saw the surface at point @a p, the rest seeing the
   * background: its mean depth is c d + (1 - c) far (d: the point's distance from the previous
   * camera) and its mean position c p (a miss stores 0), within @a tolerance (given squared).
   * @a invSpan is 1 / (far - d) (> 0), @a most the largest c that depth tolerance allows. -1
   * when the pixel saw something else (a surface in front, or at another place). Written
   * with selects, not branches: on noisy first events the outcomes are random, and mispredicted
   * branches were most of this step's time.
   */
  float Coverage(std::size_t j, Vec3 p, float invSpan, float most, float tolerance2) const
  {
    const float c = (this->Prev.FarDistance - this->PrevDepth[j]) * invSpan;
    const Vec3 off = Load3(this->PrevPosition, j) - p * c;
    const float there = LengthSquared(off) <= tolerance2 ? std::min(c, 1.f) : -1.f;
    const float seen = c < 0.05f ? 0.f : there; // below 0.05: the background
    return c <= most ? seen : -1.f;             // (not NaN and) no surface in front
  }

  /// Whether previous pixel j's albedo agrees with the new pixel's @a albedo (times the
  /// pixel's coverage of the surface, as its mean is).
  bool SameAlbedo(std::size_t j, Vec3 albedo) const
  {
    const Vec3 da = Load3(this->PrevAlbedo, j) - albedo;
    return (std::abs(da.x) <= kAlbedoDifference) & (std::abs(da.y) <= kAlbedoDifference) &
      (std::abs(da.z) <= kAlbedoDifference);
  }

  /// The nearest depth of the hits among pixel (x, y)'s eight neighbours (0: none).
  float NeighbourDepth(int x, int y) const
  {
    bool near = false; // within a row's span of hits (most background is not: cheap)
    for (int py = std::max(y - 1, 0); py <= std::min(y + 1, this->Cur.Height - 1); ++py)
    {
      near = near || (x + 1 >= this->HitBegin[py] && x - 1 < this->HitEnd[py]);
    }
    if (!near)
    {
      return 0.f;
    }
    float nearest = 0.f;
    for (int dy = -1; dy <= 1; ++dy)
    {
      const int py = y + dy;
      for (int dx = -1; dx <= 1; ++dx)
      {
        const int px = x + dx;
        if (px < 0 || py < 0 || px >= this->Cur.Width || py >= this->Cur.Height)
        {
          continue;
        }
        const float d = this->Depth[std::size_t(py) * this->Cur.Width + px];
        if (IsHit(d, this->Cur.FarDistance) && (nearest == 0.f || d < nearest))
        {
          nearest = d;
        }
      }
    }
    return nearest;
  }

  /// Pixel (x, y): 0 background, 1 no history, 2 kept its history.
  int Pixel(int x, int y) const
  {
    const int width = this->Cur.Width, height = this->Cur.Height;
    const std::size_t i = std::size_t(y) * width + x;
    float depth = this->Depth[i];
    const bool hit = IsHit(depth, this->Cur.FarDistance);
    if (!hit)
    {
      depth = this->NeighbourDepth(x, y); // a miss beside a surface may partly cover it
      if (depth == 0.f)
      {
        this->Fresh(i);
        return 0;
      }
    }
    if (!(this->Cap > 0.f) || (this->Fresh1 && this->Fresh1[i]))
    {
      this->Fresh(i); // the camera turned too far for any history, or the caller said so
      return 1;
    }
    const float fx = float(x), fy = float(y);
    const Vec3 pNear = this->CurRays.Near(fx, fy);
    const Vec3 p = (this->Cur.Parallel ? pNear : this->Cur.Eye) +
      Normalize(this->CurRays.Far(fx, fy) - pNear) * depth;

    const float* m = this->NdcFromWorld;
    const float w = m[12] * p.x + m[13] * p.y + m[14] * p.z + m[15];
    float u = -2.f, v = -2.f;
    if (w > 0.f)
    {
      const float invW = 1.f / w;
      u = 0.5f * ((m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3]) * invW + 1.f) * width - 0.5f;
      v = 0.5f * ((m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7]) * invW + 1.f) * height - 0.5f;
    }
    if (!(u > -1.f && u < float(width) && v > -1.f && v < float(height)))
    {
      this->Fresh(i);
      return 1;
    }
    const float distance = this->Prev.Parallel
      ? Dot(p - this->PrevRays.Near(u, v), this->PrevDirection)
      : Length(p - this->Prev.Eye);
    const float tolerance =
      kToleranceScale * (this->Step + this->FootprintAt0 + this->FootprintPerT * depth) +
      kRelativeTolerance * depth;
    const Vec3 albedo = Load3(this->Albedo, i);
    if (!(distance < this->Prev.FarDistance))
    {
      this->Fresh(i);
      return 1;
    }
    const float invSpan = 1.f / (this->Prev.FarDistance - distance);
    const float most = 1.f + tolerance * invSpan;

    // 2. the four pixels around the point
    const int x0 = static_cast<int>(u + 1.f) - 1; // floor: u, v > -1 here (and no libm call)
    const int y0 = static_cast<int>(v + 1.f) - 1;
    const float tx = u - float(x0), ty = v - float(y0);
    float weight[4];
    std::size_t index[4];
    float total = 0.f;
    const float tolerance2 = tolerance * tolerance;
    for (int k = 0; k < 4; ++k)
    {
      const int px = x0 + (k & 1), py = y0 + (k >> 1);
      weight[k] = ((k & 1) ? tx : 1.f - tx) * ((k >> 1) ? ty : 1.f - ty);
      index[k] = std::size_t(std::min(std::max(py, 0), height - 1)) * width +
        std::size_t(std::min(std::max(px, 0), width - 1));
      const bool inside = (px >= 0) & (py >= 0) & (px < width) & (py < height);
      const float c = this->Coverage(index[k], p, invSpan, most, tolerance2);
      // A hit needs the surface over most of the pixel; a miss beside it, not all of it (a
      // pixel covered before is a disocclusion: the background shows through now).
      const bool same = inside &
        (hit ? (c >= kHitCoverage) & this->SameAlbedo(index[k], albedo * c)
             : (c >= 0.f) & (c <= kMissCoverage));
      weight[k] = same ? weight[k] : 0.f;
      total += weight[k];
    }
    if (!(total >= kMinimumWeight))
    {
      this->Fresh(i);
      return 1;
    }
    const float norm = 1.f / total;
    float count = 0.f;
    for (int k = 0; k < 4; ++k)
    {
      count += weight[k] * this->PrevCount[index[k]];
    }
    count = std::min(count * norm, this->Cap);

    // 3. Radiance and Alpha of the history
    float h[4] = { 0.f, 0.f, 0.f, 0.f };
    for (int k = 0; k < 4; ++k)
    {
      const float wk = weight[k] * norm;
      const float* r = this->PrevRadiance + 3 * index[k];
      h[0] += wk * r[0];
      h[1] += wk * r[1];
      h[2] += wk * r[2];
      h[3] += wk * this->PrevAlpha[index[k]];
    }
    // 4. the new frame joins it
    const float a = 1.f / (count + 1.f);
    const float* f = this->Radiance + 3 * i;
    float* out = this->OutRadiance + 3 * i;
    for (int c = 0; c < 3; ++c)
    {
      out[c] = h[c] + (f[c] - h[c]) * a;
    }
    this->OutAlpha[i] = h[3] + (this->Alpha[i] - h[3]) * a;
    this->OutCount[i] = count + 1.f;
    return 2;
  }

  /// No history: the new frame alone (its Radiance and Alpha are the output already).
  void Fresh(std::size_t i) const { this->OutCount[i] = 1.f; }
};

/// Rows [begin, end) of the frame; per row, the hits and the pixels that kept a history. Only
/// the pixels within one of the hits of the row and its two neighbours are looked at: the
/// others are background (Pixel() would find neither a hit nor a hit beside them).
inline void ReprojectRows(const Reprojector& r, int begin, int end, int* hits, int* reused)
{
  const int width = r.Cur.Width, height = r.Cur.Height;
  for (int y = begin; y < end; ++y)
  {
    int first = width, last = 0; // the span of hits of rows y - 1 .. y + 1, widened by one
    for (int py = std::max(y - 1, 0); py <= std::min(y + 1, height - 1); ++py)
    {
      if (r.HitBegin[py] < r.HitEnd[py])
      {
        first = std::min(first, std::max(r.HitBegin[py] - 1, 0));
        last = std::max(last, std::min(r.HitEnd[py] + 1, width));
      }
    }
    first = std::min(first, last); // no hits: the whole row is background
    float* count = r.OutCount + std::size_t(y) * width;
    std::fill(count, count + first, 1.f);
    int h = 0, kept = 0;
    for (int x = first; x < last; ++x)
    {
      const int kind = r.Pixel(x, y);
      h += kind > 0 ? 1 : 0;
      kept += kind > 1 ? 1 : 0;
    }
    std::fill(count + last, count + width, 1.f);
    hits[y] = h;
    reused[y] = kept;
  }
}
}
}

#endif
