// The CUDA driver behind ptvCudaBilateralGrid.h: the CPU driver's three phases
// (ptvBilateralGridCpu.cxx) as kernels over the same functions of Kernels/ptvBilateralGrid.h.
#include "ptvCudaBilateralGrid.h"
#include "ptvCudaBuffer.h"

#include <cuda_runtime.h>

#include <chrono>
#include <cstddef>
#include <vector>

namespace ptv
{
namespace
{
constexpr int kBlock = 128;

int Blocks(std::size_t n)
{
  return static_cast<int>((n + kBlock - 1) / kBlock);
}

// Phase 1a: sanitise + demodulate, and de-interleave the guides into planes.
__global__ void DemodulateKernel(const float* radiance, const float* albedo, const float* guides,
  int levels, std::size_t pixels, float* demod, float* guidePlanes)
{
  const std::size_t p = static_cast<std::size_t>(blockIdx.x) * blockDim.x + threadIdx.x;
  if (p >= pixels)
  {
    return;
  }
  const Vec3 d = Demodulate(radiance + 3 * p, albedo ? albedo + 3 * p : nullptr);
  demod[3 * p + 0] = d.x;
  demod[3 * p + 1] = d.y;
  demod[3 * p + 2] = d.z;
  for (int l = 0; l < levels; ++l)
  {
    guidePlanes[l * pixels + p] = guides[p * levels + l];
  }
}

// Phase 1b: per row, the double sum of luminance(D) over x ascending and the lit count -- the
// CPU's exact order, so the host's sum over rows reproduces its outlier limit.
__global__ void RowLuminanceKernel(
  const float* demod, int width, int height, double* rowSum, unsigned long long* rowLit)
{
  const int y = static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
  if (y >= height)
  {
    return;
  }
  double sum = 0.0;
  unsigned long long lit = 0;
  for (int x = 0; x < width; ++x)
  {
    const float* d = demod + 3 * (static_cast<std::size_t>(y) * width + x);
    const float lum = Luminance(MakeVec3(d[0], d[1], d[2]));
    sum += static_cast<double>(lum);
    lit += lum > 0.f ? 1 : 0;
  }
  rowSum[y] = sum;
  rowLit[y] = lit;
}

// Phase 1c: the outlier clamp.
__global__ void ClampKernel(float* demod, std::size_t values, float limit)
{
  const std::size_t i = static_cast<std::size_t>(blockIdx.x) * blockDim.x + threadIdx.x;
  if (i < values)
  {
    demod[i] = demod[i] < limit ? demod[i] : limit;
  }
}

// Phase 2: one thread per grid column (i, j) of one level.
__global__ void SplatKernel(const float* demod, const float* guide, int width, int height,
  GridLevel g)
{
  const int column = static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
  if (column >= g.Width * g.Height)
  {
    return;
  }
  SplatCell(demod, guide, width, height, g, column % g.Width, column / g.Width);
}

// Phase 3: per pixel, slice every level, blend, re-modulate.
struct SliceArgs
{
  GridLevel Levels[kMaxGridLevels];
  int Count;
  int Width, Height;
  const float* GuidePlanes;
  const float* Weights;
  const float* Albedo;
  float* Out;
};

__global__ void SliceKernel(SliceArgs a)
{
  const std::size_t pixels = static_cast<std::size_t>(a.Width) * a.Height;
  const std::size_t p = static_cast<std::size_t>(blockIdx.x) * blockDim.x + threadIdx.x;
  if (p >= pixels)
  {
    return;
  }
  const int x = static_cast<int>(p % a.Width);
  const int y = static_cast<int>(p / a.Width);
  Vec3 s[kMaxGridLevels] = { MakeVec3(0.f, 0.f, 0.f), MakeVec3(0.f, 0.f, 0.f),
    MakeVec3(0.f, 0.f, 0.f) };
  for (int l = 0; l < a.Count; ++l)
  {
    const GridLevel& g = a.Levels[l];
    s[l] = SliceLevel(g, PixelToGrid(x, g.SpatialStep), PixelToGrid(y, g.SpatialStep),
      GuideToGrid(a.GuidePlanes[l * pixels + p], g.RangeStep));
  }
  const float* w = a.Weights ? a.Weights + p * (a.Count - 1) : nullptr;
  const float w1 = a.Count >= 2 && w ? w[0] : 0.f;
  const float w2 = a.Count >= 3 && w ? w[1] : 0.f;
  const Vec3 r = Remodulate(
    Blend(s[0], s[1], s[2], a.Count, w1, w2), a.Albedo ? a.Albedo + 3 * p : nullptr);
  a.Out[3 * p + 0] = r.x;
  a.Out[3 * p + 1] = r.y;
  a.Out[3 * p + 2] = r.z;
}

double MillisecondsSince(std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
    .count();
}
}

struct CudaBilateralGrid::Internals
{
  DeviceBuffer Radiance, Albedo, Guides, Weights, Demodulated, GuidePlanes, RowSum, RowLit, Out;
  DeviceBuffer Values[kMaxGridLevels], CellWeights[kMaxGridLevels];
  std::vector<double> RowSumHost;
  std::vector<unsigned long long> RowLitHost;
};

//------------------------------------------------------------------------------
CudaBilateralGrid::CudaBilateralGrid()
  : Impl(new Internals)
{
}

//------------------------------------------------------------------------------
CudaBilateralGrid::~CudaBilateralGrid()
{
  this->Release();
}

//------------------------------------------------------------------------------
void CudaBilateralGrid::Release()
{
  Internals& in = *this->Impl;
  for (DeviceBuffer* b : { &in.Radiance, &in.Albedo, &in.Guides, &in.Weights, &in.Demodulated,
         &in.GuidePlanes, &in.RowSum, &in.RowLit, &in.Out })
  {
    b->Free();
  }
  for (int l = 0; l < kMaxGridLevels; ++l)
  {
    in.Values[l].Free();
    in.CellWeights[l].Free();
  }
}

//------------------------------------------------------------------------------
bool CudaBilateralGrid::Apply(const BilateralGridSettings& settings, int width, int height,
  const float* radiance, const float* albedo, const float* guides, const float* weights,
  float* out, std::string& error)
{
  Internals& in = *this->Impl;
  auto ok = [&error](cudaError_t e, const char* what) { return CudaOk(e, what, error); };
  this->Timings = BilateralGridTimings{};
  const int levels = ClampedLevels(settings);
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  const std::size_t rgb = 3 * pixels * sizeof(float);

  // Phase 1: upload, demodulate, row sums; the limit on the host; clamp.
  auto start = std::chrono::steady_clock::now();
  if (!ok(in.Radiance.Upload(radiance, rgb), "radiance upload") ||
    (albedo && !ok(in.Albedo.Upload(albedo, rgb), "albedo upload")) ||
    !ok(in.Guides.Upload(guides, pixels * levels * sizeof(float)), "guide upload") ||
    (weights && levels > 1 &&
      !ok(in.Weights.Upload(weights, pixels * (levels - 1) * sizeof(float)), "weight upload")) ||
    !ok(in.Demodulated.Fit(rgb), "buffer") ||
    !ok(in.GuidePlanes.Fit(pixels * levels * sizeof(float)), "buffer") ||
    !ok(in.RowSum.Fit(height * sizeof(double)), "buffer") ||
    !ok(in.RowLit.Fit(height * sizeof(unsigned long long)), "buffer") ||
    !ok(in.Out.Fit(rgb), "buffer"))
  {
    return false;
  }
  const float* dAlbedo = albedo ? in.Albedo.As<float>() : nullptr;
  float* demod = in.Demodulated.As<float>();
  float* planes = in.GuidePlanes.As<float>();
  DemodulateKernel<<<Blocks(pixels), kBlock>>>(
    in.Radiance.As<float>(), dAlbedo, in.Guides.As<float>(), levels, pixels, demod, planes);
  RowLuminanceKernel<<<Blocks(height), kBlock>>>(
    demod, width, height, in.RowSum.As<double>(), in.RowLit.As<unsigned long long>());
  in.RowSumHost.resize(height);
  in.RowLitHost.resize(height);
  if (!ok(cudaGetLastError(), "demodulate launch") ||
    !ok(cudaMemcpy(in.RowSumHost.data(), in.RowSum.Ptr, height * sizeof(double),
          cudaMemcpyDeviceToHost),
      "row sums") ||
    !ok(cudaMemcpy(in.RowLitHost.data(), in.RowLit.Ptr, height * sizeof(unsigned long long),
          cudaMemcpyDeviceToHost),
      "row counts"))
  {
    return false;
  }
  double total = 0.0;
  unsigned long long lit = 0;
  for (int y = 0; y < height; ++y)
  {
    total += in.RowSumHost[y];
    lit += in.RowLitHost[y];
  }
  const float limit =
    OutlierLimit(lit > 0 ? total / static_cast<double>(lit) : 0.0, settings.Clamp);
  if (limit > 0.f)
  {
    ClampKernel<<<Blocks(3 * pixels), kBlock>>>(demod, 3 * pixels, limit);
  }
  this->Timings.Demodulate = MillisecondsSince(start);

  // Phase 2: splat every level.
  start = std::chrono::steady_clock::now();
  SliceArgs args{};
  args.Count = levels;
  for (int l = 0; l < levels; ++l)
  {
    GridLevel& g = args.Levels[l];
    g = LevelGeometry(settings, l, width, height);
    const std::size_t cells = static_cast<std::size_t>(g.Width) * g.Height * g.Depth;
    if (!ok(in.Values[l].Fit(3 * cells * sizeof(float)), "grid") ||
      !ok(in.CellWeights[l].Fit(cells * sizeof(float)), "grid"))
    {
      return false;
    }
    g.Values = in.Values[l].As<float>();
    g.Weights = in.CellWeights[l].As<float>();
    const std::size_t columns = static_cast<std::size_t>(g.Width) * g.Height;
    SplatKernel<<<Blocks(columns), kBlock>>>(demod, planes + l * pixels, width, height, g);
  }
  if (!ok(cudaGetLastError(), "splat launch") || !ok(cudaDeviceSynchronize(), "splat"))
  {
    return false;
  }
  this->Timings.Splat = MillisecondsSince(start);

  // Phase 3: slice, blend, re-modulate; download.
  start = std::chrono::steady_clock::now();
  args.Width = width;
  args.Height = height;
  args.GuidePlanes = planes;
  args.Weights = weights && levels > 1 ? in.Weights.As<float>() : nullptr;
  args.Albedo = dAlbedo;
  args.Out = in.Out.As<float>();
  SliceKernel<<<Blocks(pixels), kBlock>>>(args);
  if (!ok(cudaGetLastError(), "slice launch") ||
    !ok(cudaMemcpy(out, in.Out.Ptr, rgb, cudaMemcpyDeviceToHost), "result download"))
  {
    return false;
  }
  this->Timings.Slice = MillisecondsSince(start);
  return true;
}
}
