#include "ptvEdgeSamples.h"

#include "ptvKernelDispatch.h"
#include "ptvPassBuffers.h"
#include "ptvThreads.h"

#include "vtkType.h"

#include <algorithm>
#include <cstdlib>

namespace ptv
{
namespace
{
/// The stream of the extra samples: the frame's seed hashed with this ("EDGE").
constexpr uint32_t kEdgeStream = 0x45444745u;

/**
 * (x, y) offsets in [0, 1) of @a count points that cover the unit square evenly, the first at
 * (0, 0): an m x m grid when @a count is m squared, else the rank-1 lattice (k / count,
 * k g / count mod 1) whose generator g has the largest distance between neighbouring points
 * (on the torus). Shifted by a uniform random point, each is uniform over the pixel.
 */
std::vector<float> LatticeOffsets(int count)
{
  std::vector<float> out(2 * static_cast<std::size_t>(count), 0.f);
  int m = 1;
  while ((m + 1) * (m + 1) <= count)
  {
    ++m;
  }
  if (m * m == count)
  {
    for (int k = 0; k < count; ++k)
    {
      out[2 * k] = static_cast<float>(k % m) / static_cast<float>(m);
      out[2 * k + 1] = static_cast<float>(k / m) / static_cast<float>(m);
    }
    return out;
  }
  int best = 1;
  double bestDistance = -1.0;
  for (int g = 1; g < count; ++g)
  {
    double nearest = 2.0;
    for (int k = 1; k < count; ++k) // distance from point 0 (the lattice is a group)
    {
      double dx = static_cast<double>(k) / count;
      double dy = static_cast<double>((k * g) % count) / count;
      dx = std::min(dx, 1.0 - dx);
      dy = std::min(dy, 1.0 - dy);
      nearest = std::min(nearest, dx * dx + dy * dy);
    }
    if (nearest > bestDistance)
    {
      bestDistance = nearest;
      best = g;
    }
  }
  for (int k = 0; k < count; ++k)
  {
    out[2 * k] = static_cast<float>(k) / static_cast<float>(count);
    out[2 * k + 1] = static_cast<float>((k * best) % count) / static_cast<float>(count);
  }
  return out;
}

/// The edge pixels [e0, e1) of @a edges, traced with @a p (the extra samples' stream); the
/// frame samples' own jitter comes from @a frameSeed's. Into @a out: the frame, whose edge
/// pixels become the mean of all their samples, or with @a list every extra sample into an entry
/// of its own (TraceEdgeSampleList's layout). Inlined into both builds below, like
/// ptvCpuTracer's tiles, so each compiles the whole estimator for its instruction set.
inline void TraceEdges(const TraceParams& p, uint32_t frameSeed, unsigned int firstSample,
  int samples, int edgeSamples, const float* offsets, const std::uint32_t* edges, vtkIdType e0,
  vtkIdType e1, bool list, PassBuffers& out)
{
  const TracedPassPlanes planes = out.Planes();
  const uint32_t width = static_cast<uint32_t>(p.Camera.Width);
  const float total = static_cast<float>(samples) * static_cast<float>(edgeSamples);
  const std::size_t extra = static_cast<std::size_t>(edgeSamples - 1);
  for (vtkIdType e = e0; e < e1; ++e)
  {
    const uint32_t pixel = edges[e];
    const int x = static_cast<int>(pixel % width);
    const int y = static_cast<int>(pixel / width);
    PixelSample acc{};
    if (!list)
    {
      acc = LoadSample(planes, pixel);
      ScaleSample(acc, static_cast<float>(samples)); // the frame's sum
    }
    float corner = -1.f; // step 4d's corner ray, traced at most once for the pixel
    for (int s = 0; s < samples; ++s)
    {
      const uint32_t frameSample = firstSample + static_cast<uint32_t>(s);
      // The frame sample's own jitter (TraceCameraRay's first two draws), which the extra
      // samples complete into a lattice shifted by it: each is uniform over the pixel, and
      // together they cover it evenly.
      Rng main = MakeRng(pixel, frameSample, frameSeed);
      const float mx = NextFloat(main);
      const float my = NextFloat(main);
      const uint32_t base = frameSample * kMaxEdgeSamples;
      for (int k = 1; k < edgeSamples; ++k)
      {
        const float sx = mx + offsets[2 * k];
        const float sy = my + offsets[2 * k + 1];
        const float jitter[2] = { sx < 1.f ? sx : sx - 1.f, sy < 1.f ? sy : sy - 1.f };
        const PixelSample one =
          TracePixel(p, x, y, base + static_cast<uint32_t>(k), jitter, &corner);
        if (list) // entry (e x samples + s) x (edgeSamples - 1) + k - 1
        {
          const std::size_t sample =
            static_cast<std::size_t>(e) * static_cast<std::size_t>(samples) +
            static_cast<std::size_t>(s);
          StoreSample(planes, sample * extra + static_cast<std::size_t>(k - 1), one);
        }
        else
        {
          AddSample(acc, one);
        }
      }
    }
    if (!list)
    {
      ScaleSample(acc, 1.f / total);
      StoreSample(planes, pixel, acc);
    }
  }
}

using EdgesFunction = void (*)(const TraceParams&, uint32_t, unsigned int, int, int,
  const float*, const std::uint32_t*, vtkIdType, vtkIdType, bool, PassBuffers&);

#ifdef PTV_HAS_AVX2_BUILD
PTV_AVX2_TARGET __attribute__((flatten)) void TraceEdgesAvx2(const TraceParams& params,
  uint32_t frameSeed, unsigned int firstSample, int samples, int edgeSamples,
  const float* offsets, const std::uint32_t* edges, vtkIdType e0, vtkIdType e1, bool list,
  PassBuffers& out)
{
  TraceEdges(params, frameSeed, firstSample, samples, edgeSamples, offsets, edges, e0, e1, list,
    out);
}
#endif

__attribute__((flatten)) void TraceEdgesBaseline(const TraceParams& params,
  uint32_t frameSeed, unsigned int firstSample, int samples, int edgeSamples,
  const float* offsets, const std::uint32_t* edges, vtkIdType e0, vtkIdType e1, bool list,
  PassBuffers& out)
{
  TraceEdges(params, frameSeed, firstSample, samples, edgeSamples, offsets, edges, e0, e1, list,
    out);
}

EdgesFunction SelectEdges(bool portable)
{
#ifdef PTV_HAS_AVX2_BUILD
  if (!portable && CpuHasAvx2())
  {
    return &TraceEdgesAvx2;
  }
#endif
  (void)portable;
  return &TraceEdgesBaseline;
}
}

//------------------------------------------------------------------------------
void FindEdgePixels(
  const float* coverage, int width, int height, int threads, std::vector<std::uint32_t>& edges)
{
  edges.clear();
  if (width <= 0 || height <= 0)
  {
    return;
  }
  const std::size_t w = static_cast<std::size_t>(width);
  // Per pixel: 1 where its column (rows y-r..y+r) has a high value, 2 a low one.
  std::vector<unsigned char> columns(w * static_cast<std::size_t>(height));
  std::vector<unsigned char> mask(columns.size());
  const float high = kEdgeHigh;
  const int r = kEdgeRadius;
  ParallelFor(threads, 0, height, 16,
    [&](int y0, int y1)
    {
      for (int y = y0; y < y1; ++y)
      {
        const int ya = std::max(y - r, 0), yb = std::min(y + r, height - 1);
        for (std::size_t x = 0; x < w; ++x)
        {
          unsigned char bits = 0;
          for (int yy = ya; yy <= yb; ++yy)
          {
            const float c = coverage[static_cast<std::size_t>(yy) * w + x];
            bits |= (c >= high ? 1 : 0) | (c < kEdgeLow ? 2 : 0);
          }
          columns[static_cast<std::size_t>(y) * w + x] = bits;
        }
      }
    });
  ParallelFor(threads, 0, height, 16,
    [&](int y0, int y1)
    {
      for (int y = y0; y < y1; ++y)
      {
        const unsigned char* row = columns.data() + static_cast<std::size_t>(y) * w;
        unsigned char* out = mask.data() + static_cast<std::size_t>(y) * w;
        if (r == 1) // the rule's 3x3: three reads (an inner loop costs 2.5x this pass)
        {
          for (std::size_t x = 0; x < w; ++x)
          {
            const unsigned char bits =
              row[x] | row[x > 0 ? x - 1 : x] | row[x + 1 < w ? x + 1 : x];
            out[x] = bits == 3 ? 1 : 0;
          }
          continue;
        }
        const std::size_t rr = static_cast<std::size_t>(r);
        for (std::size_t x = 0; x < w; ++x)
        {
          unsigned char bits = 0;
          for (std::size_t xx = x > rr ? x - rr : 0; xx <= std::min(x + rr, w - 1); ++xx)
          {
            bits |= row[xx];
          }
          out[x] = bits == 3 ? 1 : 0;
        }
      }
    });
  for (std::size_t i = 0; i < mask.size(); ++i)
  {
    if (mask[i])
    {
      edges.push_back(static_cast<std::uint32_t>(i));
    }
  }
}

//------------------------------------------------------------------------------
namespace
{
/// TraceEdgeSamples and TraceEdgeSampleList: the extra samples' stream and lattice, threaded.
void TraceExtraSamples(const TraceParams& params, unsigned int firstSample, int samples,
  int edgeSamples, const std::vector<std::uint32_t>& edges, int threads, bool portable, bool list,
  PassBuffers& out)
{
  const EdgesFunction trace = SelectEdges(portable);
  const std::vector<float> offsets = LatticeOffsets(edgeSamples);
  TraceParams extra = params; // the extra samples' own stream
  extra.Seed = params.Seed ^ PcgHash(kEdgeStream);
  const std::uint32_t* indices = edges.data();
  ParallelFor(threads, vtkIdType(0), static_cast<vtkIdType>(edges.size()), vtkIdType(16),
    [&](vtkIdType e0, vtkIdType e1)
    {
      trace(extra, params.Seed, firstSample, samples, edgeSamples, offsets.data(), indices, e0,
        e1, list, out);
    });
}
}

//------------------------------------------------------------------------------
void TraceEdgeSamples(const TraceParams& params, unsigned int firstSample, int samples,
  int edgeSamples, const std::vector<std::uint32_t>& edges, int threads, bool portable,
  PassBuffers& frame)
{
  if (edges.empty() || samples < 1 || edgeSamples < 2)
  {
    return;
  }
  TraceExtraSamples(params, firstSample, samples, std::min(edgeSamples, kMaxEdgeSamples), edges,
    threads, portable, false, frame);
}

//------------------------------------------------------------------------------
std::size_t EdgeSampleListSize(std::size_t edges, int samples, int edgeSamples)
{
  if (samples < 1 || edgeSamples < 2)
  {
    return 0;
  }
  return edges * static_cast<std::size_t>(samples) *
    static_cast<std::size_t>(std::min(edgeSamples, kMaxEdgeSamples) - 1);
}

//------------------------------------------------------------------------------
void TraceEdgeSampleList(const TraceParams& params, unsigned int firstSample, int samples,
  int edgeSamples, const std::vector<std::uint32_t>& edges, int threads, bool portable,
  PassBuffers& list)
{
  const std::size_t size = EdgeSampleListSize(edges.size(), samples, edgeSamples);
  list.Resize(static_cast<int>(size), size > 0 ? 1 : 0);
  if (size == 0)
  {
    return;
  }
  TraceExtraSamples(params, firstSample, samples, std::min(edgeSamples, kMaxEdgeSamples), edges,
    threads, portable, true, list);
}

//------------------------------------------------------------------------------
void MergeEdgeSamples(PassBuffers& list, int samples, int edgeSamples,
  const std::vector<std::uint32_t>& edges, int threads, PassBuffers& frame)
{
  const std::size_t size = EdgeSampleListSize(edges.size(), samples, edgeSamples);
  if (size == 0 ||
    static_cast<std::size_t>(list.GetWidth()) * static_cast<std::size_t>(list.GetHeight()) != size)
  {
    return;
  }
  const std::size_t extra = static_cast<std::size_t>(std::min(edgeSamples, kMaxEdgeSamples) - 1);
  const float total = static_cast<float>(samples) * static_cast<float>(extra + 1);
  const TracedPassPlanes from = list.Planes();
  const TracedPassPlanes to = frame.Planes();
  ParallelFor(threads, vtkIdType(0), static_cast<vtkIdType>(edges.size()), vtkIdType(64),
    [&](vtkIdType e0, vtkIdType e1)
    {
      for (vtkIdType e = e0; e < e1; ++e)
      {
        PixelSample acc = LoadSample(to, edges[e]);
        ScaleSample(acc, static_cast<float>(samples)); // the frame's sum
        const std::size_t count = static_cast<std::size_t>(samples) * extra;
        const std::size_t first = static_cast<std::size_t>(e) * count;
        for (std::size_t i = 0; i < count; ++i)
        {
          AddSample(acc, LoadSample(from, first + i));
        }
        ScaleSample(acc, 1.f / total);
        StoreSample(to, edges[e], acc);
      }
    });
}
}
