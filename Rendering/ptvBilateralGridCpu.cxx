#include "ptvBilateralGridCpu.h"

#include "vtkSMPTools.h"

#include <algorithm>
#include <chrono>
#include <string>
#include <thread>

namespace ptv
{
namespace
{
double MillisecondsSince(std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
    .count();
}
}

//------------------------------------------------------------------------------
template <typename T>
void BilateralGridCpu::Fit(std::vector<T>& buffer, std::size_t size)
{
  if (buffer.size() != size)
  {
    std::vector<T>(size).swap(buffer); // exact size; also releases a larger buffer
    if (size > 0)
    {
      ++this->Allocations;
    }
  }
}

//------------------------------------------------------------------------------
void BilateralGridCpu::Apply(const BilateralGridSettings& settings, int width, int height,
  const float* radiance, const float* albedo, const float* guides, const float* weights,
  float* out)
{
  const int levels = ClampedLevels(settings);
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);

  // Buffers: reallocated only when a size changes.
  this->Fit(this->Demodulated, pixels * 3);
  this->Fit(this->Guides, pixels * static_cast<std::size_t>(levels));
  this->Fit(this->RowLuminance, static_cast<std::size_t>(height));
  this->Fit(this->RowLit, static_cast<std::size_t>(height));
  for (int l = 0; l < kMaxGridLevels; ++l)
  {
    GridLevel& g = this->Levels[l];
    if (l >= levels)
    {
      this->Fit(this->Values[l], 0);
      this->Fit(this->Weights[l], 0);
      g = GridLevel{};
      continue;
    }
    g = LevelGeometry(settings, l, width, height);
    const std::size_t cells = static_cast<std::size_t>(g.Width) *
      static_cast<std::size_t>(g.Height) * static_cast<std::size_t>(g.Depth);
    this->Fit(this->Values[l], cells * 3);
    this->Fit(this->Weights[l], cells);
    g.Values = this->Values[l].data();
    g.Weights = this->Weights[l].data();
  }

  int threads = settings.Threads;
  std::string backend = vtkSMPTools::GetBackend() ? vtkSMPTools::GetBackend() : "Sequential";
  if (backend == "Sequential" && threads != 1)
  {
    backend = "STDThread";
  }
  if (threads <= 0)
  {
    threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  }

  float* demod = this->Demodulated.data();
  float* guidePlanes = this->Guides.data();
  double* rowLuminance = this->RowLuminance.data();
  std::size_t* rowLit = this->RowLit.data();
  GridLevel* grid = this->Levels;
  const double clamp = settings.Clamp;

  vtkSMPTools::LocalScope(vtkSMPTools::Config{ threads, backend, false },
    [&]()
    {
      // Phase 1: sanitise + demodulate, row sums of luminance, guide planes; then the clamp.
      auto start = std::chrono::steady_clock::now();
      vtkSMPTools::For(0, height, 1,
        [&](vtkIdType rowBegin, vtkIdType rowEnd)
        {
          for (vtkIdType y = rowBegin; y < rowEnd; ++y)
          {
            double sum = 0.0;
            std::size_t lit = 0;
            for (int x = 0; x < width; ++x)
            {
              const std::size_t p = static_cast<std::size_t>(y) * width + x;
              const Vec3 d = Demodulate(radiance + 3 * p, albedo ? albedo + 3 * p : nullptr);
              demod[3 * p + 0] = d.x;
              demod[3 * p + 1] = d.y;
              demod[3 * p + 2] = d.z;
              const float lum = Luminance(d);
              sum += static_cast<double>(lum);
              lit += lum > 0.f ? 1 : 0;
              for (int l = 0; l < levels; ++l)
              {
                guidePlanes[l * pixels + p] = guides[p * levels + l];
              }
            }
            rowLuminance[y] = sum;
            rowLit[y] = lit;
          }
        });
      double total = 0.0;
      std::size_t litPixels = 0;
      for (int y = 0; y < height; ++y)
      {
        total += rowLuminance[y];
        litPixels += rowLit[y];
      }
      const double mean = litPixels > 0 ? total / static_cast<double>(litPixels) : 0.0;
      const float limit = ptv::OutlierLimit(mean, clamp);
      if (limit > 0.f)
      {
        vtkSMPTools::For(0, height, 1,
          [&](vtkIdType rowBegin, vtkIdType rowEnd)
          {
            float* first = demod + 3 * static_cast<std::size_t>(rowBegin) * width;
            float* last = demod + 3 * static_cast<std::size_t>(rowEnd) * width;
            for (float* d = first; d != last; ++d)
            {
              *d = *d < limit ? *d : limit; // D >= 0 is never NaN here
            }
          });
      }
      this->Timings.Demodulate = MillisecondsSince(start);

      // Phase 2: splat, a gather per grid column; parallel over grid rows.
      start = std::chrono::steady_clock::now();
      for (int l = 0; l < levels; ++l)
      {
        GridLevel& g = grid[l];
        const float* guide = guidePlanes + l * pixels;
        vtkSMPTools::For(0, g.Height, 1,
          [&](vtkIdType jBegin, vtkIdType jEnd)
          {
            for (vtkIdType j = jBegin; j < jEnd; ++j)
            {
              for (int i = 0; i < g.Width; ++i)
              {
                SplatCell(demod, guide, width, height, g, i, static_cast<int>(j));
              }
            }
          });
      }
      this->Timings.Splat = MillisecondsSince(start);

      // Phase 3: slice every level, blend, re-modulate; parallel over image rows.
      start = std::chrono::steady_clock::now();
      vtkSMPTools::For(0, height, 1,
        [&](vtkIdType rowBegin, vtkIdType rowEnd)
        {
          for (vtkIdType yy = rowBegin; yy < rowEnd; ++yy)
          {
            const int y = static_cast<int>(yy);
            float v[kMaxGridLevels] = { 0.f, 0.f, 0.f };
            for (int l = 0; l < levels; ++l)
            {
              v[l] = PixelToGrid(y, grid[l].SpatialStep);
            }
            for (int x = 0; x < width; ++x)
            {
              const std::size_t p = static_cast<std::size_t>(y) * width + x;
              Vec3 s[kMaxGridLevels] = { MakeVec3(0.f, 0.f, 0.f), MakeVec3(0.f, 0.f, 0.f),
                MakeVec3(0.f, 0.f, 0.f) };
              for (int l = 0; l < levels; ++l)
              {
                const GridLevel& g = grid[l];
                s[l] = SliceLevel(g, PixelToGrid(x, g.SpatialStep), v[l],
                  GuideToGrid(guidePlanes[l * pixels + p], g.RangeStep));
              }
              const float* w = weights ? weights + p * (levels - 1) : nullptr;
              const float w1 = levels >= 2 && w ? w[0] : 0.f;
              const float w2 = levels >= 3 && w ? w[1] : 0.f;
              const Vec3 r = Remodulate(
                Blend(s[0], s[1], s[2], levels, w1, w2), albedo ? albedo + 3 * p : nullptr);
              out[3 * p + 0] = r.x;
              out[3 * p + 1] = r.y;
              out[3 * p + 2] = r.z;
            }
          }
        });
      this->Timings.Slice = MillisecondsSince(start);
    });
}
}
