#include "ptvReprojection.h"

#include "ptvReprojectionRows.h"

#include "ptvKernelDispatch.h"
#include "ptvThreads.h"

#include "vtkMatrix4x4.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <numeric>

namespace ptv
{
namespace
{
using namespace reprojection;

// Scalar code compiled twice, as the tracer (ptvCpuTracer): the baseline and x86-64-v3.
__attribute__((flatten)) void ReprojectRowsBaseline(
  const Reprojector& r, int begin, int end, int* hits, int* reused)
{
  ReprojectRows(r, begin, end, hits, reused);
}

#ifdef PTV_HAS_AVX2_BUILD
PTV_AVX2_TARGET __attribute__((flatten)) void ReprojectRowsAvx2(
  const Reprojector& r, int begin, int end, int* hits, int* reused)
{
  ReprojectRows(r, begin, end, hits, reused);
}
#endif
}

//------------------------------------------------------------------------------
void Reprojection::Reproject(const CameraRays& previous, const CameraRays& current,
  float stepWorld, int maximumHistory, int previousFrames, PassBuffers& accumulated,
  PassBuffers& frame, int threads, const std::uint32_t* freshPixels, std::size_t freshCount)
{
  const int width = current.Width;
  const int height = current.Height;
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  if (!this->HasHistory())
  {
    this->Counts.assign(n, static_cast<float>(std::max(previousFrames, 1)));
  }
  this->NewCounts.resize(n);

  Reprojector r(previous, current);
  r.Step = std::isfinite(stepWorld) ? std::max(stepWorld, 0.0f) : 0.0f;
  r.Cap = static_cast<float>(std::max(maximumHistory, 1)) * HistoryFade(r.Turn);
  r.PrevRadiance = accumulated.Data(PassRadiance);
  r.PrevAlpha = accumulated.Data(PassAlpha);
  r.PrevDepth = accumulated.Data(PassDepth);
  r.PrevPosition = accumulated.Data(PassPosition);
  r.PrevAlbedo = accumulated.Data(PassAlbedo);
  r.PrevCount = this->Counts.data();
  r.Radiance = frame.Data(PassRadiance);
  r.Alpha = frame.Data(PassAlpha);
  r.Depth = frame.Data(PassDepth);
  r.Albedo = frame.Data(PassAlbedo);
  r.OutRadiance = frame.Data(PassRadiance);
  r.OutAlpha = frame.Data(PassAlpha);
  r.OutCount = this->NewCounts.data();
  if (freshCount > 0)
  {
    this->FreshMask.assign(n, 0);
    for (std::size_t e = 0; e < freshCount; ++e)
    {
      if (freshPixels[e] < n)
      {
        this->FreshMask[freshPixels[e]] = 1;
      }
    }
    r.Fresh1 = this->FreshMask.data();
  }

  this->HitBegin.assign(static_cast<std::size_t>(height), width);
  this->HitEnd.assign(static_cast<std::size_t>(height), 0);
  r.HitBegin = this->HitBegin.data();
  r.HitEnd = this->HitEnd.data();
  for (int y = 0; y < height; ++y) // (serial: a second parallel loop costs more to start)
  {
    const float* depth = r.Depth + std::size_t(y) * width;
    int x = 0;
    while (x < width && !IsHit(depth[x], current.FarDistance))
    {
      ++x;
    }
    this->HitBegin[y] = x;
    int end = width;
    while (end > x && !IsHit(depth[end - 1], current.FarDistance))
    {
      --end;
    }
    this->HitEnd[y] = x < width ? end : 0;
  }
  auto rows = &ReprojectRowsBaseline;
#ifdef PTV_HAS_AVX2_BUILD
  if (!UsePortableKernels(false) && CpuHasAvx2())
  {
    rows = &ReprojectRowsAvx2;
  }
#endif
  std::vector<int> hitRows(static_cast<std::size_t>(height), 0);
  std::vector<int> reusedRows(static_cast<std::size_t>(height), 0);
  ParallelFor(threads, 0, height, 8,
    [&](int begin, int end) { rows(r, begin, end, hitRows.data(), reusedRows.data()); });
  for (int p = 0; p < kTracedPassCount; ++p)
  {
    accumulated.Swap(p, frame); // Radiance, Alpha: the blend; the others: the view's first frame
  }
  this->Counts.swap(this->NewCounts);
  const int hits = std::accumulate(hitRows.begin(), hitRows.end(), 0);
  const int reused = std::accumulate(reusedRows.begin(), reusedRows.end(), 0);
  this->Reused = hits ? static_cast<double>(reused) / static_cast<double>(hits) : 0.0;
}

//------------------------------------------------------------------------------
void Reprojection::Accumulate(
  PassBuffers& accumulated, const PassBuffers& frame, int frames, int threads)
{
  const std::size_t n = this->Counts.size();
  const float w = 1.0f / static_cast<float>(std::max(frames, 1));
  ParallelFor(threads, std::size_t(0), n, std::size_t(4096),
    [&](std::size_t begin, std::size_t end)
    {
      float* radiance = accumulated.Data(PassRadiance);
      float* alpha = accumulated.Data(PassAlpha);
      const float* fRadiance = frame.Data(PassRadiance);
      const float* fAlpha = frame.Data(PassAlpha);
      for (std::size_t i = begin; i < end; ++i)
      {
        const float a = 1.0f / (this->Counts[i] + 1.0f);
        for (int c = 0; c < 3; ++c)
        {
          radiance[3 * i + c] += (fRadiance[3 * i + c] - radiance[3 * i + c]) * a;
        }
        alpha[i] += (fAlpha[i] - alpha[i]) * a;
        this->Counts[i] += 1.0f;
      }
      for (int p = 0; p < kTracedPassCount; ++p)
      {
        if (p == PassRadiance || p == PassAlpha)
        {
          continue;
        }
        const std::size_t c = static_cast<std::size_t>(GetPassInfo(p).Components);
        float* acc = accumulated.Data(p);
        const float* in = frame.Data(p);
        if (!acc || !in)
        {
          continue; // a pass not kept
        }
        for (std::size_t k = c * begin; k < c * end; ++k)
        {
          acc[k] += (in[k] - acc[k]) * w;
        }
      }
    });
}

//------------------------------------------------------------------------------
void Reprojection::WriteCounts(float* out, int pixels, int frames) const
{
  if (this->HasHistory() && this->Counts.size() == static_cast<std::size_t>(pixels))
  {
    std::copy(this->Counts.begin(), this->Counts.end(), out);
  }
  else
  {
    std::fill(out, out + pixels, static_cast<float>(frames));
  }
}
}
