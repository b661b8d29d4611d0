// Edge samples of a volume split into pieces (Rendering/Trace/ptvEdgeSamples.h, TraceEdgeSampleList and
// MergeEdgeSamples; the frame loop's distributed path).
//
// Scene: a 64 x 2 x 4 grid seen along +z by an orthographic camera (ptvTestKernelCamera.h); the
// image x coordinate of a ray is the grid's index i, and the scalar is i on the back layers
// (k = 2, 3) and i - 100 on the front ones (k = 0, 1). The table is transparent below 40.3 and
// opaque from 40.3001 on, so nothing in front of k = 1.5 can be seen, every ray that meets the
// volume has its event where it first meets it, and behind k = 1.5 the volume has an edge near
// column 40 plus the slope of the interpolation between the layers: a band of edge pixels
// whose rays meet the volume, or not, depending on where in the pixel they pass.
//
// 1. One process: a frame's mean of 1 or 2 samples plus TraceEdgeSampleList and
//    MergeEdgeSamples equals TraceEdgeSamples' frame in every traced pass (float rounding:
//    the sum's order is the same), for 2, 3, 4 and 8 edge samples; a list of another size
//    changes nothing.
// 2. Two pieces split at k = 1.5 (TraceParams::CameraBox, PieceStream 1 and 2), each tracing
//    its list, composited front first (CompositePieces, as Ranks::GatherFrame does): entry by
//    entry the composite has the whole volume's first hit (Depth, Albedo, first-hit position)
//    and Footprint -- the pieces traced the same extra rays (jitter, march offset) as the whole
//    volume's list, and every hit lies in the back piece, so the composite's hits all come
//    through the front piece's misses. Its opacities (Alpha, Coverage) are those of the same
//    rays: the table's opaque part is fully opaque per step.
#include "Kernels/ptvIntegrator.h"
#include "ptvEdgeSamples.h"
#include "ptvPassBuffers.h"
#include "ptvPieces.h"
#include "ptvTestCheck.h"
#include "ptvTestKernelCamera.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace
{
constexpr int kImage = 64;
constexpr float kEdge = 40.3f;

struct Scene
{
  std::vector<float> Voxels = std::vector<float>(64 * 2 * 4);
  float Table[8] = { 0.8f, 0.5f, 0.25f, 0.f, 0.8f, 0.5f, 0.25f, 1.f };
  float StepTable[8];
  float ShadowTable[2];
  ptv::TraceParams P;
};

void MakeScene(Scene& v)
{
  for (std::size_t n = 0; n < v.Voxels.size(); ++n)
  {
    const std::size_t i = n % 64, k = n / (64 * 2);
    v.Voxels[n] = static_cast<float>(i) - (k < 2 ? 100.f : 0.f);
  }
  ptv::TraceParams& p = v.P;
  p = ptv::TraceParams{};
  p.Volume.Scalars = v.Voxels.data();
  p.Volume.Dims[0] = 64;
  p.Volume.Dims[1] = 2;
  p.Volume.Dims[2] = 4;
  // i = 32 (x + 1), j = y / 40 + 0.5, k = 3 z (z in [0, 1]): every ray crosses the grid in z.
  const float w2i[12] = { 32.f, 0.f, 0.f, 32.f, 0.f, 1.f / 40.f, 0.f, 0.5f, 0.f, 0.f, 3.f, 0.f };
  for (int i = 0; i < 12; ++i)
  {
    p.Volume.WorldToIndex[i] = w2i[i];
  }
  ptv::ComputeNormalToWorld(p.Volume);
  p.Transfer.RGBA = v.Table;
  p.Transfer.Size = 2;
  p.Transfer.ScalarMin = kEdge; // below it: transparent (entry 0)
  p.Transfer.ScalarMax = kEdge + 1e-4f; // above it: opaque (entry 1), whatever the step
  p.Occupancy.Distance = nullptr;
  OrthographicAlongZ(p, kImage);
  p.KeyLight.Radiance = ptv::MakeVec3(1.f, 1.f, 1.f);
  p.StepWorld = 0.02f;
  p.ShadowStepScale = 2.f;
  p.UnitDistance = 0.5f;
  p.Shade = 1;
  p.Diffuse = 1.f;
  p.Scattering = 1;
  p.CoverageMarch = 1;
  p.FootprintRays = 1;
  p.MaxDistance = nullptr;
  p.Seed = 1234u;
  SetStepTables(p, v.StepTable, v.ShadowTable);
}

/// A frame of @a samples samples from sample index @a first.
void TraceFrame(const ptv::TraceParams& p, unsigned int first, int samples, ptv::PassBuffers& out)
{
  out.Resize(kImage, kImage);
  for (int y = 0; y < kImage; ++y)
  {
    for (int x = 0; x < kImage; ++x)
    {
      out.Store(y * kImage + x, ptv::TracePixelMean(p, first, samples, x, y));
    }
  }
}

float Tolerance(float v)
{
  return 2e-5f * std::max(1.f, std::fabs(v));
}

/// 1.: list + merge on one process equals TraceEdgeSamples.
void OneProcess(const Scene& v)
{
  for (int samples : { 1, 2 })
  {
    ptv::PassBuffers frame;
    TraceFrame(v.P, 7u, samples, frame);
    std::vector<std::uint32_t> edges;
    ptv::FindEdgePixels(frame.Data(ptv::PassCoverage), kImage, kImage, 1, edges);
    Check(edges.size() >= static_cast<std::size_t>(kImage),
      "the scene has an edge in every row: " + std::to_string(edges.size()) + " edge pixels");
    for (int edgeSamples : { 2, 3, 4, 8 })
    {
      ptv::PassBuffers direct = frame, merged = frame;
      ptv::TraceEdgeSamples(v.P, 7u, samples, edgeSamples, edges, 2, false, direct);
      ptv::PassBuffers list;
      ptv::TraceEdgeSampleList(v.P, 7u, samples, edgeSamples, edges, 2, false, list);
      const std::size_t size = ptv::EdgeSampleListSize(edges.size(), samples, edgeSamples);
      Check(size == edges.size() * samples * (edgeSamples - 1) &&
          static_cast<std::size_t>(list.GetWidth()) == size && list.GetHeight() == 1,
        "the list has an entry per extra sample");
      ptv::PassBuffers wrong = frame;
      ptv::MergeEdgeSamples(list, samples + 1, edgeSamples, edges, 1, wrong);
      ptv::MergeEdgeSamples(list, samples, edgeSamples, edges, 2, merged);
      int differ = 0, changed = 0, untouched = 0;
      for (int pass = 0; pass < ptv::kTracedPassCount; ++pass)
      {
        const std::size_t n = static_cast<std::size_t>(kImage * kImage) *
          static_cast<std::size_t>(ptv::GetPassInfo(pass).Components);
        for (std::size_t i = 0; i < n; ++i)
        {
          const float a = direct.Data(pass)[i], b = merged.Data(pass)[i];
          differ += std::fabs(a - b) <= Tolerance(a) ? 0 : 1;
          changed += a != frame.Data(pass)[i] ? 1 : 0;
          untouched += wrong.Data(pass)[i] == frame.Data(pass)[i] ? 0 : 1;
        }
      }
      const std::string what =
        std::to_string(samples) + " sample(s), " + std::to_string(edgeSamples) + " edge samples";
      Check(differ == 0, what + ": list + merge = TraceEdgeSamples (" + std::to_string(differ) +
          " values differ)");
      Check(changed > 0, what + ": the edge samples change the frame");
      Check(untouched == 0, what + ": a list of another size changes nothing");
    }
  }
}

/// 2.: two pieces' lists composited = the whole volume's list, entry by entry, where the
/// pieces' own random numbers cannot matter.
void TwoPieces(const Scene& v)
{
  const int samples = 1, edgeSamples = 4;
  ptv::PassBuffers frame;
  TraceFrame(v.P, 3u, samples, frame);
  std::vector<std::uint32_t> edges;
  ptv::FindEdgePixels(frame.Data(ptv::PassCoverage), kImage, kImage, 1, edges);
  ptv::TraceParams front = v.P, back = v.P;
  const float whole[6] = { 0.f, 63.f, 0.f, 1.f, 0.f, 3.f };
  for (int i = 0; i < 6; ++i)
  {
    front.WholeBox[i] = back.WholeBox[i] = whole[i];
    front.CameraBox[i] = back.CameraBox[i] = whole[i];
  }
  front.CameraBoxed = back.CameraBoxed = 1;
  front.CameraBox[5] = 1.5f; // k in [0, 1.5]: nothing visible
  back.CameraBox[4] = 1.5f;  // k in [1.5, 3]: the edge
  front.PieceStream = 1u;
  back.PieceStream = 2u;
  ptv::PassBuffers all, lists[2];
  ptv::TraceEdgeSampleList(v.P, 3u, samples, edgeSamples, edges, 2, false, all);
  ptv::TraceEdgeSampleList(front, 3u, samples, edgeSamples, edges, 2, false, lists[0]);
  ptv::TraceEdgeSampleList(back, 3u, samples, edgeSamples, edges, 1, false, lists[1]);
  const std::size_t entries = static_cast<std::size_t>(all.GetWidth());
  // What Gather leaves on process 0: each pass of every piece, piece after piece (back first
  // here: the order comes from ViewOrder, not from the ranks).
  std::vector<std::vector<float>> passes(ptv::kTracedPassCount);
  std::vector<const float*> gathered(ptv::kTracedPassCount);
  for (int p = 0; p < ptv::kTracedPassCount; ++p)
  {
    const std::size_t n = entries * static_cast<std::size_t>(ptv::GetPassInfo(p).Components);
    for (int piece : { 1, 0 })
    {
      passes[p].insert(passes[p].end(), lists[piece].Data(p), lists[piece].Data(p) + n);
    }
    gathered[p] = passes[p].data();
  }
  const float far = v.P.Camera.FarDistance;
  ptv::PassBuffers composite;
  composite.Resize(static_cast<int>(entries), 1);
  ptv::CompositePieces(gathered, entries, { 1, 0 }, { far, far }, far, 1, composite);

  const int checked[] = { ptv::PassDepth, ptv::PassAlbedo, ptv::PassAlpha, ptv::PassCoverage,
    ptv::PassFootprint };
  int differ = 0, hits = 0, misses = 0, frontHits = 0;
  for (std::size_t e = 0; e < entries; ++e)
  {
    const bool hit = all.Data(ptv::PassDepth)[e] < ptv::kHitFraction * far;
    (hit ? hits : misses) += 1;
    frontHits += lists[0].Data(ptv::PassDepth)[e] < ptv::kHitFraction * far ? 1 : 0;
    for (int pass : checked)
    {
      const int c = ptv::GetPassInfo(pass).Components;
      for (int j = 0; j < c; ++j)
      {
        const float a = all.Data(pass)[c * e + j], b = composite.Data(pass)[c * e + j];
        if (!(std::fabs(a - b) <= 1e-4f * std::max(1.f, std::fabs(a))))
        {
          if (differ < 5)
          {
            std::cout << "entry " << e << " pass " << ptv::GetPassInfo(pass).Name << ": whole "
                      << a << ", pieces " << b << "\n";
          }
          ++differ;
        }
      }
    }
  }
  Check(hits > 0 && misses > 0,
    "the extra samples both hit and miss the edge: " + std::to_string(hits) + " / " +
      std::to_string(misses));
  Check(frontHits == 0, "the front piece holds nothing visible");
  Check(differ == 0,
    "composited pieces' list = the whole volume's, entry by entry (" + std::to_string(differ) +
      " values differ)");
}
}

int TestPTVEdgeSamplePieces(int, char*[])
{
  Scene v;
  MakeScene(v);
  OneProcess(v);
  TwoPieces(v);
  std::cout << (failures == 0 ? "TestPTVEdgeSamplePieces passed\n"
                              : "TestPTVEdgeSamplePieces FAILED\n");
  return TestResult();
}
