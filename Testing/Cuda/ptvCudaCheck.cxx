// The CUDA path on real scenes, without VTK: reads captures (ptvWriteCudaCaptures), runs the
// CUDA tracer and grid drivers on the captured inputs and compares them with the CPU drivers'
// results stored there, with TestPTVCudaParity's criteria (ptvCudaParity.h); --bench then times
// both drivers on the device at several image sizes. Built with nvcc alone (see Testing/Cuda/README.md), so it
// runs on a GPU machine that has no VTK.
//
//   ptvCudaCheck [--cpu-only] [--bench] [--sizes 256 512 1024] [--repeats 15] file.ptvcap ...
//
// --cpu-only checks the captures on the host (the kernel body compiled here, baseline
// instruction set, must reproduce the stored CPU passes on a subset of rows to the bit) and
// needs no device. Without a usable CUDA device it prints "skipped: no CUDA device" and exits
// 125 (ctest's skip code in Testing/Cuda/CMakeLists.txt) after the host check.
#include "Kernels/ptvIntegrator.h"
#include "ptvBilateralGridSettings.h"
#include "ptvCudaBilateralGrid.h"
#include "ptvCudaCapture.h"
#include "ptvCudaDevice.h"
#include "ptvCudaParity.h"
#include "ptvCudaTracer.h"
#include "ptvPassBuffers.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

namespace
{
using namespace ptv;
constexpr int kSkip = 125;

double Median(std::vector<double> v)
{
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

/// The host's build of the kernel body on every 8th row: the stored CPU passes to the bit.
bool HostCheck(const TraceCapture& c)
{
  const int w = c.Width(), h = c.Height();
  std::size_t rows = 0, differ = 0;
  for (int k = 0; k < 2; ++k)
  {
    for (int y = 0; y < h; y += 8, ++rows)
    {
      for (int x = 0; x < w; ++x)
      {
        const PixelSample s = TracePixelMean(c.Params, 0, c.Samples[k], x, y);
        const std::size_t i = static_cast<std::size_t>(y) * w + x;
        const float values[7] = { s.Radiance.x, s.Radiance.y, s.Radiance.z, s.Depth1, s.Normal1.x,
          s.Normal1.y, s.Normal1.z };
        const float stored[7] = { c.Cpu[k][CapturedRadiance][3 * i],
          c.Cpu[k][CapturedRadiance][3 * i + 1], c.Cpu[k][CapturedRadiance][3 * i + 2],
          c.Cpu[k][CapturedDepth][i], c.Cpu[k][CapturedNormal][3 * i],
          c.Cpu[k][CapturedNormal][3 * i + 1], c.Cpu[k][CapturedNormal][3 * i + 2] };
        for (int v = 0; v < 7; ++v)
        {
          differ += values[v] == stored[v] ? 0 : 1;
        }
      }
    }
  }
  std::cout << c.Name << ": host kernel body on " << rows << " rows: " << differ
            << " values differ from the stored CPU passes\n";
  return differ == 0;
}

/// CUDA tracer vs the stored CPU passes (ptvCudaParity.h).
bool TraceParity(const TraceCapture& c)
{
  bool ok = true;
  CudaTracer tracer;
  PassBuffers out;
  out.Resize(c.Width(), c.Height());
  for (int k = 0; k < 2; ++k)
  {
    std::string error;
    if (!tracer.Trace(c.Params, 1, 0, c.Samples[k], out, error))
    {
      std::cout << c.Name << ": CUDA trace failed: " << error << "\n";
      return false;
    }
    const std::vector<float>* cpu = c.Cpu[k];
    const double depth = parity::FractionClose(cpu[CapturedDepth].data(), out.Data(PassDepth),
      cpu[CapturedDepth].size(), parity::kDepthTolerance);
    const double normal = parity::FractionClose(cpu[CapturedNormal].data(),
      out.Data(PassNormal), cpu[CapturedNormal].size(), parity::kNormalTolerance);
    const double rmse = parity::Rmse(
      cpu[CapturedRadiance].data(), out.Data(PassRadiance), cpu[CapturedRadiance].size());
    const bool pass = parity::TraceAgrees(depth, normal, rmse, c.Samples[k]);
    std::cout << c.Name << " trace " << c.Samples[k] << " spp: depth close " << depth
              << ", normal close " << normal << ", radiance RMSE " << rmse
              << (pass ? "  ok" : "  FAILED") << "\n";
    ok = ok && pass;
  }
  return ok;
}

BilateralGridSettings GridSettings(const TraceCapture& c, int levels)
{
  BilateralGridSettings s;
  s.Levels = levels;
  std::copy(c.SpatialStep, c.SpatialStep + kMaxGridLevels, s.SpatialStep);
  std::copy(c.RangeStep, c.RangeStep + kMaxGridLevels, s.RangeStep);
  s.Clamp = c.Clamp;
  return s;
}

/// CUDA grid vs the stored CPU grid: max |CPU - CUDA| / range (ptvCudaParity.h).
bool GridParity(const TraceCapture& c)
{
  bool ok = true;
  CudaBilateralGrid grid;
  const std::vector<float> first = FirstGuide(c);
  const int w = c.Width(), h = c.Height();
  for (int k = 0; k < 2; ++k)
  {
    const int levels = k == 0 ? 1 : c.GuideLevels;
    std::vector<float> out(c.GridCpu[k].size(), std::nanf(""));
    std::string error;
    if (!grid.Apply(GridSettings(c, levels), w, h, c.Radiance.data(), c.Albedo.data(),
          k == 0 ? first.data() : c.Guides.data(), k == 0 ? nullptr : c.Weights.data(),
          out.data(), error))
    {
      std::cout << c.Name << ": CUDA grid failed: " << error << "\n";
      return false;
    }
    const auto range = std::minmax_element(c.GridCpu[k].begin(), c.GridCpu[k].end());
    double diff = 0.0;
    for (std::size_t i = 0; i < out.size(); ++i)
    {
      const double d = std::abs(static_cast<double>(out[i]) - c.GridCpu[k][i]);
      diff = std::isnan(d) ? INFINITY : std::max(diff, d);
    }
    const double relative = diff / std::max(1e-30, double(*range.second - *range.first));
    const bool pass = relative <= parity::kGridRelative;
    std::cout << c.Name << " grid " << levels << " level(s): max |CPU - CUDA| / range "
              << relative << (pass ? "  ok" : "  FAILED") << "\n";
    ok = ok && pass;
  }
  return ok;
}

/// @a v (W x H x n, x fastest) resized to S x S by nearest neighbour.
std::vector<float> Resample(const std::vector<float>& v, int w, int h, int n, int s)
{
  std::vector<float> out(static_cast<std::size_t>(s) * s * n);
  for (int y = 0; y < s; ++y)
  {
    const int sy = static_cast<int>(static_cast<long long>(y) * h / s);
    for (int x = 0; x < s; ++x)
    {
      const int sx = static_cast<int>(static_cast<long long>(x) * w / s);
      std::copy_n(&v[(static_cast<std::size_t>(sy) * w + sx) * n], n,
        &out[(static_cast<std::size_t>(y) * s + x) * n]);
    }
  }
  return out;
}

/// Median timings of the CUDA drivers at each size: the 1-spp trace and the grid (1 and all
/// levels). The camera is square, so its matrix serves every square size.
void Bench(const TraceCapture& c, const std::vector<int>& sizes, int repeats)
{
  CudaTracer tracer;
  CudaBilateralGrid grid;
  for (int s : sizes)
  {
    TraceParams p = c.Params;
    p.Camera.Width = p.Camera.Height = s;
    p.MaxDistance = nullptr; // per-pixel limits belong to the captured size (none here)
    PassBuffers out;
    out.Resize(s, s);
    std::vector<double> wall, kernel, upload, download;
    std::string error;
    for (int r = -3; r < repeats; ++r)
    {
      const auto start = std::chrono::steady_clock::now();
      if (!tracer.Trace(p, 1, static_cast<unsigned int>(r + 3), 1, out, error))
      {
        std::cout << "trace failed: " << error << "\n";
        return;
      }
      const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
          .count();
      if (r >= 0) // the first three warm up (volume upload, module load)
      {
        wall.push_back(ms);
        kernel.push_back(tracer.GetLastTimings().Kernel);
        upload.push_back(tracer.GetLastTimings().Upload);
        download.push_back(tracer.GetLastTimings().Download);
      }
    }
    const double pixels = static_cast<double>(s) * s;
    std::printf("| %s | %d | trace 1 spp | %.3f | kernel %.3f, upload %.3f, download %.3f |"
                " %.1f Mpx/s (kernel) |\n",
      c.Name.c_str(), s, Median(wall), Median(kernel), Median(upload), Median(download),
      pixels / Median(kernel) / 1e3);

    const std::vector<float> radiance = Resample(c.Radiance, c.Width(), c.Height(), 3, s);
    const std::vector<float> albedo = Resample(c.Albedo, c.Width(), c.Height(), 3, s);
    const std::vector<float> guides =
      Resample(c.Guides, c.Width(), c.Height(), c.GuideLevels, s);
    const std::vector<float> weights =
      Resample(c.Weights, c.Width(), c.Height(), c.GuideLevels - 1, s);
    const std::vector<float> first = Resample(FirstGuide(c), c.Width(), c.Height(), 1, s);
    std::vector<float> denoised(3 * static_cast<std::size_t>(s) * s);
    for (int levels : { 1, c.GuideLevels })
    {
      std::vector<double> total, demodulate, splat, slice;
      for (int r = -3; r < repeats; ++r)
      {
        const auto start = std::chrono::steady_clock::now();
        if (!grid.Apply(GridSettings(c, levels), s, s, radiance.data(), albedo.data(),
              levels == 1 ? first.data() : guides.data(), levels == 1 ? nullptr : weights.data(),
              denoised.data(), error))
        {
          std::cout << "grid failed: " << error << "\n";
          return;
        }
        const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
            .count();
        if (r >= 0)
        {
          total.push_back(ms);
          demodulate.push_back(grid.GetLastTimings().Demodulate);
          splat.push_back(grid.GetLastTimings().Splat);
          slice.push_back(grid.GetLastTimings().Slice);
        }
      }
      std::printf("| %s | %d | grid %d level(s) | %.3f | demodulate %.3f, splat %.3f, slice %.3f"
                  " | %.2f ns/px |\n",
        c.Name.c_str(), s, levels, Median(total), Median(demodulate), Median(splat),
        Median(slice), Median(total) * 1e6 / pixels);
    }
  }
}
}

int main(int argc, char* argv[])
{
  bool cpuOnly = false, bench = false;
  int repeats = 15;
  std::vector<int> sizes;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--cpu-only")
    {
      cpuOnly = true;
    }
    else if (a == "--bench")
    {
      bench = true;
    }
    else if (a == "--repeats" && i + 1 < argc)
    {
      repeats = std::max(1, std::atoi(argv[++i]));
    }
    else if (a == "--sizes")
    {
      while (i + 1 < argc && std::atoi(argv[i + 1]) > 0)
      {
        sizes.push_back(std::atoi(argv[++i]));
      }
    }
    else if (a == "-h" || a == "--help")
    {
      std::cout << "usage: ptvCudaCheck [--cpu-only] [--bench] [--sizes N ...] [--repeats N] "
                   "file.ptvcap ...\n";
      return EXIT_SUCCESS;
    }
    else
    {
      files.push_back(a);
    }
  }
  if (files.empty())
  {
    std::cerr << "ERROR: no capture files given (ptvWriteCudaCaptures writes them)\n";
    return EXIT_FAILURE;
  }
  if (sizes.empty())
  {
    sizes = { 256, 512, 1024 };
  }
  std::vector<TraceCapture> captures(files.size());
  bool ok = true;
  for (std::size_t f = 0; f < files.size(); ++f)
  {
    std::string error;
    if (!ReadCapture(files[f], captures[f], error))
    {
      std::cerr << "ERROR: " << error << "\n";
      return EXIT_FAILURE;
    }
    ok = HostCheck(captures[f]) && ok;
  }
  if (cpuOnly)
  {
    return ok ? EXIT_SUCCESS : EXIT_FAILURE;
  }
  const CudaDeviceQuery& device = QueryCudaDevices();
  if (device.DeviceCount < 1)
  {
    std::cout << "skipped: no CUDA device (" << device.Message << ")\n";
    return ok ? kSkip : EXIT_FAILURE;
  }
  std::cout << device.Message << "\n";
  for (const TraceCapture& c : captures)
  {
    ok = TraceParity(c) && ok;
    ok = GridParity(c) && ok;
  }
  if (bench)
  {
    std::cout << "\n| dataset | size | stage | median ms | parts (median ms) | rate |\n"
                 "|---|---|---|---|---|---|\n";
    for (const TraceCapture& c : captures)
    {
      Bench(c, sizes, repeats);
    }
  }
  std::cout << (ok ? "all checks passed" : "SOME CHECKS FAILED") << "\n";
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
