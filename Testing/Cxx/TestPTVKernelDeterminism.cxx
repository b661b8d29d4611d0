// Determinism and convergence of the path-tracing kernel (Rendering/Kernels).
//
// Scene: a 48^3 "sphere" volume (value 100 in the core, falling linearly to 0 over the outer 6
// voxels of a radius-16 ball, 0 in the margins), rotated and anisotropically scaled into world
// space, with a two-band table (a faint blue band around 35, an opaque orange band above 75),
// seen by a perspective camera.
//  (a) the same (pixel, frame, seed) gives a bit-identical PixelSample, also when the image is
//      traced in another order; another frame or seed gives a different one;
//  (b) empty-space skipping on vs off gives bit-identical images (two configurations: directional
//      light + AO + scattering; positional light + gradient opacity + MaxDistance + first hit);
//      the octant skip distances equal a brute-force one-sided chessboard distance on random
//      grids;
//  (c) the running mean over N frames converges to a 4096-frame reference (independent frames)
//      with RMSE ~ N^-1/2: the least-squares slope of log RMSE vs log N, N = 4..256, is in
//      [-0.6, -0.4];
//  (d) a camera inside the volume gives finite output and hits at the first sample;
//  (e) rays that miss the box, or are clipped to zero length by MaxDistance, give exactly the
//      documented miss values;
//  (f) the CPU driver (ptvCpuTracer): each instruction-set build gives bit-identical frames on 1
//      and 2 threads; the baseline build equals the kernel called pixel by pixel; the dispatched
//      build (AVX2 where the CPU has it) matches the baseline up to rounding. FMA contraction
//      changes values by a few ulps (relative 1e-4 is ~1000 ulps of headroom); a difference that
//      large only arises where those bits flip a branch (event threshold, roulette, skipping
//      bookkeeping), so at most 1% of the pixels may differ by more than that.
#include "Kernels/ptvIntegrator.h"
#include "ptvCpuTracer.h"
#include "ptvPassBuffers.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <utility>
#include <vector>

namespace
{
constexpr int kDim = 48;
constexpr int kTable = 64;

struct Scene
{
  std::vector<float> Voxels;
  std::vector<float> Table;
  std::vector<float> GradientTable;
  std::vector<int8_t> BrickDistance;
  double IndexToWorld[3][4]; // world = A index + o
  ptv::TraceParams P;
};

using Mat4 = double[4][4];

void Multiply(const Mat4 a, const Mat4 b, Mat4 out)
{
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
    {
      out[r][c] = 0.0;
      for (int k = 0; k < 4; ++k)
        out[r][c] += a[r][k] * b[k][c];
    }
}

bool Invert(const Mat4 m, Mat4 inv)
{
  double a[4][8];
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 8; ++c)
      a[r][c] = c < 4 ? m[r][c] : (c - 4 == r ? 1.0 : 0.0);
  for (int c = 0; c < 4; ++c)
  {
    int pivot = c;
    for (int r = c + 1; r < 4; ++r)
      if (std::fabs(a[r][c]) > std::fabs(a[pivot][c]))
        pivot = r;
    if (std::fabs(a[pivot][c]) < 1e-300)
      return false;
    for (int k = 0; k < 8; ++k)
      std::swap(a[c][k], a[pivot][k]);
    const double d = a[c][c];
    for (int k = 0; k < 8; ++k)
      a[c][k] /= d;
    for (int r = 0; r < 4; ++r)
      if (r != c)
      {
        const double f = a[r][c];
        for (int k = 0; k < 8; ++k)
          a[r][k] -= f * a[c][k];
      }
  }
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      inv[r][c] = a[r][c + 4];
  return true;
}

ptv::Vec3 V(double x, double y, double z)
{
  return ptv::MakeVec3(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
}

/// Perspective camera (OpenGL conventions) at eye looking at target; fills p.Camera.
void SetCamera(ptv::TraceParams& p, const double eye[3], const double target[3], double fovY,
  int width, int height)
{
  double f[3] = { target[0] - eye[0], target[1] - eye[1], target[2] - eye[2] };
  double n = std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
  for (double& v : f)
    v /= n;
  double up[3] = { 0.0, 0.0, 1.0 };
  if (std::fabs(f[2]) > 0.9)
  {
    up[1] = 1.0;
    up[2] = 0.0;
  }
  double s[3] = { f[1] * up[2] - f[2] * up[1], f[2] * up[0] - f[0] * up[2],
    f[0] * up[1] - f[1] * up[0] };
  n = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
  for (double& v : s)
    v /= n;
  const double u[3] = { s[1] * f[2] - s[2] * f[1], s[2] * f[0] - s[0] * f[2],
    s[0] * f[1] - s[1] * f[0] };
  Mat4 view = { { s[0], s[1], s[2], -(s[0] * eye[0] + s[1] * eye[1] + s[2] * eye[2]) },
    { u[0], u[1], u[2], -(u[0] * eye[0] + u[1] * eye[1] + u[2] * eye[2]) },
    { -f[0], -f[1], -f[2], f[0] * eye[0] + f[1] * eye[1] + f[2] * eye[2] }, { 0, 0, 0, 1 } };
  const double zn = 0.1, zf = 200.0;
  const double t = 1.0 / std::tan(0.5 * fovY * 3.14159265358979 / 180.0);
  const double aspect = static_cast<double>(width) / height;
  Mat4 proj = { { t / aspect, 0, 0, 0 }, { 0, t, 0, 0 },
    { 0, 0, (zf + zn) / (zn - zf), 2 * zf * zn / (zn - zf) }, { 0, 0, -1, 0 } };
  Mat4 pv, inv;
  Multiply(proj, view, pv);
  Invert(pv, inv);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      p.Camera.WorldFromNdc[4 * r + c] = static_cast<float>(inv[r][c]);
  p.Camera.Eye = V(eye[0], eye[1], eye[2]);
  p.Camera.Parallel = 0;
  p.Camera.Width = width;
  p.Camera.Height = height;
  p.Camera.FarDistance = static_cast<float>(zf);
}

void WorldCentre(const Scene& s, double c[3])
{
  for (int r = 0; r < 3; ++r)
    c[r] = s.IndexToWorld[r][3] +
      0.5 * (kDim - 1) * (s.IndexToWorld[r][0] + s.IndexToWorld[r][1] + s.IndexToWorld[r][2]);
}

void MakeScene(Scene& s, int width, int height)
{
  s.Voxels.resize(static_cast<size_t>(kDim) * kDim * kDim);
  const double c = 0.5 * (kDim - 1), radius = 16.0;
  for (int k = 0; k < kDim; ++k)
    for (int j = 0; j < kDim; ++j)
      for (int i = 0; i < kDim; ++i)
      {
        const double r = std::sqrt((i - c) * (i - c) + (j - c) * (j - c) + (k - c) * (k - c));
        const double v = 100.0 * std::fmin(1.0, std::fmax(0.0, (radius - r) / 6.0));
        s.Voxels[i + kDim * (j + kDim * static_cast<size_t>(k))] = static_cast<float>(v);
      }
  s.Table.resize(4 * kTable);
  for (int i = 0; i < kTable; ++i)
  {
    const double sv = 100.0 * i / (kTable - 1);
    float* e = &s.Table[4 * i];
    if (sv >= 25.0 && sv <= 45.0)
    {
      e[0] = 0.2f, e[1] = 0.4f, e[2] = 0.9f, e[3] = 0.3f;
    }
    else if (sv >= 75.0)
    {
      e[0] = 0.95f, e[1] = 0.6f, e[2] = 0.2f, e[3] = 0.9f;
    }
    else
    {
      e[0] = 0.5f, e[1] = 0.5f, e[2] = 0.5f, e[3] = 0.f;
    }
  }
  s.GradientTable = { 0.2f, 0.6f, 1.f, 1.f };

  // index -> world: rotation by 30 degrees about z times diag(0.5, 0.5, 0.6), plus an offset.
  const double ca = std::cos(3.14159265358979 / 6), sa = std::sin(3.14159265358979 / 6);
  const double a[3][3] = { { 0.5 * ca, -0.5 * sa, 0.0 }, { 0.5 * sa, 0.5 * ca, 0.0 },
    { 0.0, 0.0, 0.6 } };
  const double o[3] = { -5.0, -12.0, -14.0 };
  for (int r = 0; r < 3; ++r)
  {
    for (int cc = 0; cc < 3; ++cc)
      s.IndexToWorld[r][cc] = a[r][cc];
    s.IndexToWorld[r][3] = o[r];
  }
  Mat4 i2w = { { a[0][0], a[0][1], a[0][2], o[0] }, { a[1][0], a[1][1], a[1][2], o[1] },
    { a[2][0], a[2][1], a[2][2], o[2] }, { 0, 0, 0, 1 } };
  Mat4 w2i;
  Invert(i2w, w2i);

  ptv::TraceParams& p = s.P;
  p = ptv::TraceParams{};
  p.Volume.Scalars = s.Voxels.data();
  p.Volume.Dims[0] = p.Volume.Dims[1] = p.Volume.Dims[2] = kDim;
  for (int r = 0; r < 3; ++r)
    for (int cc = 0; cc < 4; ++cc)
      p.Volume.WorldToIndex[4 * r + cc] = static_cast<float>(w2i[r][cc]);
  ptv::ComputeNormalToWorld(p.Volume);
  p.Transfer.RGBA = s.Table.data();
  p.Transfer.Size = kTable;
  p.Transfer.ScalarMin = 0.f;
  p.Transfer.ScalarMax = 100.f;
  p.Transfer.GradientOpacity = nullptr;
  p.Occupancy.Distance = nullptr;

  double centre[3];
  WorldCentre(s, centre);
  const double eye[3] = { centre[0] + 40.0, centre[1] - 30.0, centre[2] + 20.0 };
  SetCamera(p, eye, centre, 30.0, width, height);

  p.KeyLight.Positional = 0;
  p.KeyLight.Direction = ptv::Normalize(V(-1.0, 0.5, -1.0));
  p.KeyLight.Radiance = V(1.2, 1.2, 1.1);
  p.Environment = V(0.3, 0.35, 0.4);
  p.StepWorld = 0.5f;
  p.ShadowStepScale = 2.f;
  p.UnitDistance = 0.5f;
  p.Shade = 1;
  p.Ambient = 0.1f;
  p.Diffuse = 0.7f;
  p.Specular = 0.3f;
  p.SpecularPower = 20.f;
  p.Scattering = 1;
  p.AmbientOcclusion = 1;
  p.MaxDistance = nullptr;
  p.Seed = 42u;
  p.Frame = 0u;
}

void EnableSkipping(Scene& s, int brickSize)
{
  int bricks[3];
  ptv::ComputeBrickCounts(s.P.Volume.Dims, brickSize, bricks);
  const size_t count = static_cast<size_t>(bricks[0]) * bricks[1] * bricks[2];
  s.BrickDistance.assign(8 * count, 0);
  std::vector<float> ranges(2 * count);
  ptv::BuildBrickRanges(s.P.Volume, brickSize, 0, bricks[2], ranges.data());
  ptv::BuildOccupancy(s.P.Transfer, bricks, ranges.data(), s.BrickDistance.data());
  s.P.Occupancy = ptv::MakeOccupancyGrid(s.P.Volume, brickSize, s.BrickDistance.data());
}

void Render(const ptv::TraceParams& p, std::vector<ptv::PixelSample>& img)
{
  img.resize(static_cast<size_t>(p.Camera.Width) * p.Camera.Height);
  for (int y = 0; y < p.Camera.Height; ++y)
    for (int x = 0; x < p.Camera.Width; ++x)
      img[static_cast<size_t>(y) * p.Camera.Width + x] = ptv::TracePixel(p, x, y);
}

bool Same(const ptv::PixelSample& a, const ptv::PixelSample& b)
{
  return std::memcmp(&a, &b, sizeof(ptv::PixelSample)) == 0;
}

bool SameImage(const std::vector<ptv::PixelSample>& a, const std::vector<ptv::PixelSample>& b)
{
  return a.size() == b.size() &&
    std::memcmp(a.data(), b.data(), a.size() * sizeof(ptv::PixelSample)) == 0;
}

bool Finite(const ptv::PixelSample& s)
{
  const float* f = reinterpret_cast<const float*>(&s);
  for (size_t i = 0; i < sizeof(s) / sizeof(float); ++i)
    if (!std::isfinite(f[i]))
      return false;
  return true;
}

double Seconds(std::chrono::steady_clock::time_point t0)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

bool TestRepeatability()
{
  Scene s;
  MakeScene(s, 64, 64);
  bool ok = true;
  const ptv::PixelSample a = ptv::TracePixel(s.P, 32, 32);
  const ptv::PixelSample b = ptv::TracePixel(s.P, 32, 32);
  ptv::TraceParams q = s.P;
  q.Frame = 1u;
  const ptv::PixelSample c = ptv::TracePixel(q, 32, 32);
  q = s.P;
  q.Seed = 43u;
  const ptv::PixelSample d = ptv::TracePixel(q, 32, 32);
  ok = ok && a.Alpha == 1.f && Same(a, b) && !Same(a, c) && !Same(a, d);

  // Tracing order does not matter: forward vs reverse order over the whole image.
  std::vector<ptv::PixelSample> fwd, rev(64 * 64);
  Render(s.P, fwd);
  for (int i = 64 * 64 - 1; i >= 0; --i)
    rev[i] = ptv::TracePixel(s.P, i % 64, i / 64);
  const bool order = SameImage(fwd, rev);
  std::printf("(a) centre pixel: alpha %g depth1 %.4f depth2 %.4f radiance (%.4f %.4f %.4f); "
              "repeat identical %d, frame+1 differs %d, seed+1 differs %d, order-independent %d\n",
    a.Alpha, a.Depth1, a.Depth2, a.Radiance.x, a.Radiance.y, a.Radiance.z, Same(a, b),
    !Same(a, c), !Same(a, d), order);
  return ok && order;
}

bool CompareSkipping(Scene& s, const char* name, int brickSize)
{
  const int w = s.P.Camera.Width, h = s.P.Camera.Height;
  bool ok = true;
  double tOff = 0.0, tOn = 0.0;
  int hits = 0, events = 0;
  for (uint32_t frame = 0; frame < 2; ++frame)
  {
    s.P.Frame = frame;
    std::vector<ptv::PixelSample> off, on;
    s.P.Occupancy.Distance = nullptr;
    auto t0 = std::chrono::steady_clock::now();
    Render(s.P, off);
    tOff += Seconds(t0);
    EnableSkipping(s, brickSize);
    t0 = std::chrono::steady_clock::now();
    Render(s.P, on);
    tOn += Seconds(t0);
    ok = ok && SameImage(off, on);
    for (const ptv::PixelSample& px : off)
    {
      hits += px.Depth1 < s.P.Camera.FarDistance;
      events += px.Alpha > 0.f;
    }
  }
  s.P.Occupancy.Distance = nullptr;
  // Over (brick, octant) entries: empty, and occupied with a forward occupied cube (radius >= 1).
  int empty = 0, thick = 0;
  for (int8_t d : s.BrickDistance)
  {
    empty += d > 0;
    thick += d < 0;
  }
  std::printf("(b) %s: %dx%d x 2 frames, %d first hits, %d events, %d of %zu (brick, octant) "
              "entries (size %d) empty, %d inside occupied cubes; identical %d (%.3f s without "
              "skipping, %.3f s with)\n",
    name, w, h, hits, events, empty, s.BrickDistance.size(), brickSize, thick, ok, tOff, tOn);
  // The comparison must be non-trivial: hits and misses, empty bricks to skip and occupied
  // cubes to cross in one step.
  return ok && hits > w * h / 4 && hits < 2 * w * h && empty > 0 && thick > 0;
}

/// Octant distances (ptvOccupancy.h) against brute force: for brick b and octant signs s, the
/// bricks ahead are b + delta s with every delta >= 0; an empty brick's value is the smallest
/// chessboard distance to an occupied brick ahead, an occupied brick's is minus (the smallest
/// distance to an empty brick ahead - 1); 127 (or -127) when there is none, and capped there.
bool TestOctantDistances()
{
  const int b[3] = { 9, 6, 11 };
  const int n = b[0] * b[1] * b[2];
  uint32_t state = 777u;
  bool ok = true;
  int deepest = 0, farthest = 0;
  for (int density : { 0, 3, 30, 97, 100 })
  {
    std::vector<uint8_t> flags(n);
    for (int i = 0; i < n; ++i)
    {
      state = state * 1664525u + 1013904223u;
      flags[i] = static_cast<int>((state >> 8) % 100) < density ? 1 : 0;
    }
    // A solid occupied block so that some radii exceed 1.
    for (int z = 2; z < 9 && density == 30; ++z)
      for (int y = 0; y < 6; ++y)
        for (int x = 1; x < 8; ++x)
          flags[x + b[0] * (y + b[1] * z)] = 1;
    std::vector<int8_t> d(8 * static_cast<size_t>(n));
    ptv::OctantDistances(b, flags.data(), d.data());
    for (int octant = 0; octant < 8; ++octant)
    {
      const int s[3] = { octant & 1 ? -1 : 1, octant & 2 ? -1 : 1, octant & 4 ? -1 : 1 };
      for (int i = 0; i < n; ++i)
      {
        const int p[3] = { i % b[0], (i / b[0]) % b[1], i / (b[0] * b[1]) };
        int nearest = 255; // to a brick ahead of the other kind
        for (int q = 0; q < n; ++q)
        {
          const int r[3] = { q % b[0], (q / b[0]) % b[1], q / (b[0] * b[1]) };
          int dist = 0;
          bool ahead = true;
          for (int a = 0; a < 3; ++a)
          {
            const int delta = (r[a] - p[a]) * s[a];
            ahead = ahead && delta >= 0;
            dist = std::max(dist, delta);
          }
          if (ahead && flags[q] != flags[i])
          {
            nearest = std::min(nearest, dist);
          }
        }
        const int want = flags[i] ? -(std::min(nearest, 128) - 1) : std::min(nearest, 127);
        ok = ok && d[8 * static_cast<size_t>(i) + octant] == want;
        deepest = std::max(deepest, flags[i] && want > -127 ? -want : 0);
        farthest = std::max(farthest, !flags[i] && want < 127 ? want : 0);
      }
    }
  }
  std::printf("(b) octant distances equal brute force on 5 random 9x6x11 grids, 8 octants: %d "
              "(largest occupied radius %d, largest finite empty distance %d)\n",
    ok, deepest, farthest);
  return ok && deepest >= 2 && farthest >= 2;
}

bool TestSkipping()
{
  bool ok = TestOctantDistances();
  Scene s;
  MakeScene(s, 64, 64);
  ok = CompareSkipping(s, "directional light, AO, scattering", 8) && ok;

  Scene t;
  MakeScene(t, 64, 64);
  double centre[3];
  WorldCentre(t, centre);
  t.P.KeyLight.Positional = 1;
  t.P.KeyLight.Position = V(centre[0] + 3.0, centre[1] - 15.0, centre[2] + 2.0);
  t.P.KeyLight.Radiance = V(2.0, 2.0, 2.0);
  t.P.Transfer.GradientOpacity = t.GradientTable.data();
  t.P.Transfer.GradientSize = static_cast<int>(t.GradientTable.size());
  t.P.Transfer.GradientMax = 30.f;
  t.P.Scattering = 0;
  std::vector<float> maxDistance(64 * 64);
  for (int i = 0; i < 64 * 64; ++i)
    maxDistance[i] = (i % 64) < 40 ? 1e30f : 50.f + 0.1f * (i / 64); // clip the right part
  t.P.MaxDistance = maxDistance.data();
  ok = CompareSkipping(t, "point light, gradient opacity, MaxDistance, first hit", 3) && ok;
  return ok;
}

bool TestConvergence()
{
  const int w = 24, h = 24, maxN = 256, refFrames = 4096;
  Scene s;
  MakeScene(s, w, h);
  EnableSkipping(s, 8);
  const size_t n = static_cast<size_t>(w) * h;
  std::vector<double> ref(4 * n, 0.0), sum(4 * n, 0.0);
  std::vector<ptv::PixelSample> img;
  auto t0 = std::chrono::steady_clock::now();
  for (int f = 0; f < refFrames; ++f)
  {
    s.P.Frame = static_cast<uint32_t>(100000 + f); // independent of the frames below
    Render(s.P, img);
    for (size_t i = 0; i < n; ++i)
    {
      ref[4 * i + 0] += img[i].Radiance.x / refFrames;
      ref[4 * i + 1] += img[i].Radiance.y / refFrames;
      ref[4 * i + 2] += img[i].Radiance.z / refFrames;
      ref[4 * i + 3] += img[i].Alpha / static_cast<double>(refFrames);
    }
  }
  const double tRef = Seconds(t0);
  std::vector<double> logN, logE;
  std::printf("(c) running mean vs %d-frame reference, %dx%d pixels x RGBA (%.2f s):\n", refFrames,
    w, h, tRef);
  for (int f = 0; f < maxN; ++f)
  {
    s.P.Frame = static_cast<uint32_t>(f);
    Render(s.P, img);
    for (size_t i = 0; i < n; ++i)
    {
      sum[4 * i + 0] += img[i].Radiance.x;
      sum[4 * i + 1] += img[i].Radiance.y;
      sum[4 * i + 2] += img[i].Radiance.z;
      sum[4 * i + 3] += img[i].Alpha;
    }
    const int frames = f + 1;
    if (frames >= 4 && (frames & (frames - 1)) == 0)
    {
      double se = 0.0;
      for (size_t i = 0; i < 4 * n; ++i)
      {
        const double e = sum[i] / frames - ref[i];
        se += e * e;
      }
      const double rmse = std::sqrt(se / (4 * n));
      std::printf("    N = %3d  RMSE %.6f  RMSE*sqrt(N) %.5f\n", frames, rmse,
        rmse * std::sqrt(frames));
      logN.push_back(std::log(frames));
      logE.push_back(std::log(rmse));
    }
  }
  const double m = static_cast<double>(logN.size());
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (size_t i = 0; i < logN.size(); ++i)
  {
    sx += logN[i];
    sy += logE[i];
    sxx += logN[i] * logN[i];
    sxy += logN[i] * logE[i];
  }
  const double slope = (m * sxy - sx * sy) / (m * sxx - sx * sx);
  std::printf("    fitted slope of log RMSE vs log N: %.4f (required [-0.6, -0.4])\n", slope);
  return slope >= -0.6 && slope <= -0.4;
}

bool TestCameraInside()
{
  Scene s;
  MakeScene(s, 32, 32);
  EnableSkipping(s, 8);
  double centre[3];
  WorldCentre(s, centre);
  const double target[3] = { centre[0] + 1.0, centre[1] + 0.3, centre[2] - 0.2 };
  SetCamera(s.P, centre, target, 60.0, 32, 32);
  std::vector<ptv::PixelSample> img;
  Render(s.P, img);
  int finite = 0, hitsAtFirstSample = 0, events = 0;
  float maxDepth1 = 0.f;
  for (const ptv::PixelSample& px : img)
  {
    finite += Finite(px);
    hitsAtFirstSample += px.Depth1 >= 0.f && px.Depth1 < s.P.StepWorld;
    events += px.Alpha == 1.f && px.Depth2 >= px.Depth1 && px.Depth2 < s.P.Camera.FarDistance;
    maxDepth1 = std::fmax(maxDepth1, px.Depth1);
  }
  std::printf("(d) camera inside: %d/%zu finite, %d first hits within one step (max depth1 "
              "%.4f), %d events\n",
    finite, img.size(), hitsAtFirstSample, maxDepth1, events);
  const int n = static_cast<int>(img.size());
  return finite == n && hitsAtFirstSample == n && events == n;
}

bool IsMiss(const ptv::PixelSample& s, float far)
{
  return Same(s, ptv::MissSample(far)) && ptv::IsZero(s.Radiance) && s.Alpha == 0.f &&
    s.Depth1 == far && s.Depth2 == far && ptv::IsZero(s.Normal1) && ptv::IsZero(s.Normal2) &&
    ptv::IsZero(s.Position1) && ptv::IsZero(s.Position2) && ptv::IsZero(s.Albedo);
}

bool TestMiss()
{
  Scene s;
  MakeScene(s, 16, 16);
  double centre[3];
  WorldCentre(s, centre);
  const double eye[3] = { centre[0] + 40.0, centre[1] - 30.0, centre[2] + 20.0 };
  const double away[3] = { eye[0] + 40.0, eye[1] - 30.0, eye[2] + 20.0 }; // looking away
  SetCamera(s.P, eye, away, 30.0, 16, 16);
  std::vector<ptv::PixelSample> img;
  Render(s.P, img);
  int misses = 0;
  for (const ptv::PixelSample& px : img)
    misses += IsMiss(px, s.P.Camera.FarDistance);

  // Looking at the volume, but opaque geometry at distance 0 clips every ray.
  Scene t;
  MakeScene(t, 16, 16);
  std::vector<float> zero(16 * 16, 0.f);
  t.P.MaxDistance = zero.data();
  Render(t.P, img);
  int clipped = 0;
  for (const ptv::PixelSample& px : img)
    clipped += IsMiss(px, t.P.Camera.FarDistance);
  std::printf("(e) camera looking away: %d/256 exact miss values; MaxDistance = 0: %d/256\n",
    misses, clipped);
  return misses == 256 && clipped == 256;
}
}

bool SameFrame(const ptv::PassBuffers& a, const ptv::PassBuffers& b)
{
  const size_t pixels = static_cast<size_t>(a.GetWidth()) * a.GetHeight();
  for (int pass = 0; pass < ptv::kTracedPassCount; ++pass)
  {
    const size_t n = pixels * ptv::GetPassInfo(pass).Components;
    if (std::memcmp(a.Data(pass), b.Data(pass), n * sizeof(float)) != 0)
      return false;
  }
  return true;
}

bool TestCpuDriver()
{
  Scene s;
  MakeScene(s, 64, 64);
  EnableSkipping(s, 8);
  const int w = s.P.Camera.Width, h = s.P.Camera.Height;
  ptv::PassBuffers frames[2][2]; // [portable][threads - 1]
  for (int portable = 0; portable < 2; ++portable)
    for (int threads = 1; threads <= 2; ++threads)
    {
      ptv::PassBuffers& f = frames[portable][threads - 1];
      f.Resize(w, h);
      ptv::TraceFrameCpu(s.P, 7u, 2, threads, portable == 1, f);
    }
  // The baseline build against the kernel itself (mean of frames 7 and 8 per pixel).
  ptv::PassBuffers direct;
  direct.Resize(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      direct.Store(y * w + x, ptv::TracePixelMean(s.P, 7u, 2, x, y));
  const bool threadsSame = SameFrame(frames[0][0], frames[0][1]) &&
    SameFrame(frames[1][0], frames[1][1]);
  const bool baselineExact = SameFrame(frames[1][0], direct);
  int differing = 0, events = 0;
  for (int i = 0; i < w * h; ++i)
  {
    bool differs = false;
    for (int pass = 0; pass < ptv::kTracedPassCount; ++pass)
    {
      const int c = ptv::GetPassInfo(pass).Components;
      for (int k = 0; k < c; ++k)
      {
        const float a = frames[0][0].Data(pass)[i * c + k];
        const float b = frames[1][0].Data(pass)[i * c + k];
        differs = differs || !(std::fabs(a - b) <= 1e-4f * (1.f + std::fabs(b)));
      }
    }
    differing += differs;
    events += frames[1][0].Data(ptv::PassAlpha)[i] > 0.f;
  }
  const bool close = differing <= w * h / 100;
  std::printf("(f) CPU driver: dispatched build %s; 1 vs 2 threads bit-identical %d; baseline "
              "== kernel %d; %d of %d pixels (%d with events) differ between builds beyond 1e-4\n",
    ptv::TracerKernelTarget(false), threadsSame, baselineExact, differing, w * h, events);
  return threadsSame && baselineExact && close && events > w * h / 10;
}

int TestPTVKernelDeterminism(int, char*[])
{
  bool ok = true;
  ok = TestRepeatability() && ok;
  ok = TestSkipping() && ok;
  ok = TestConvergence() && ok;
  ok = TestCameraInside() && ok;
  ok = TestMiss() && ok;
  ok = TestCpuDriver() && ok;
  std::printf(ok ? "TestPTVKernelDeterminism passed\n" : "TestPTVKernelDeterminism FAILED\n");
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
