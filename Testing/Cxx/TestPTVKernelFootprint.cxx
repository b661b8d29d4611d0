// The Footprint field of the path-tracing kernel (ptvIntegrator.h, step 4d) on a volume with a
// straight edge, where the answer is known in closed form.
//
// Scene: a 64 x 2 x 2 grid whose scalar is its x index, so trilinear interpolation gives s = i
// exactly (i the index x of a point); the table is transparent up to s0 = 40.3 and opaque above
// it, so a ray meets opacity exactly when its i > s0. An orthographic camera looks along +z
// through it, and the grid's WorldToIndex makes i the image x coordinate of the ray: the
// camera ray of pixel column x is at i = x + jx (jx its jitter) and the ray through the pixel's
// corner at i = x. Without an occupancy grid every march visits every sample, so every camera
// ray that meets nothing is "near" and its pixel traces its corner ray. Hence, with
// FootprintRays, per pixel of column x:
//   41 <= x <= 62: the camera ray meets opacity: Footprint 1;
//   x == 40: 1 where the camera ray met opacity (jx > 0.3), else its corner (i = 40): 0;
//   x <= 39: the camera ray and the corner (i = x) miss: 0;
//   x == 63: the camera ray (i > 63) misses the grid, so it is not near anything, and the
//     pixel is taken for empty without its corner ray (which lies on the grid's face): 0.
// Without FootprintRays Footprint is 1 everywhere, and every other field is bit-identical with
// and without the rays (they draw no random numbers). The same with Shade on, where a miss also
// draws nothing. The edge is checked with the transfer table's interval counts
// (TransferTable::OpaqueBefore, as the mapper sets them) and without them (the samples' own
// opacity): on it both are exact.
//
// A thin layer (CheckThinLayer): a 2 x 2 x 64 grid whose scalar is its z index k, and a table
// (64 entries over [0, 63]) whose only non-zero opacity is entry 10, so the layer is k in
// (9, 11); the camera step is 4 voxels. The corner rays (march offset 0) sample k = 0, 4, 8, 12
// and step over it; the jittered camera rays meet it when their offset lands inside (half of
// them). With the interval counts a corner ray tests the scalar interval between samples and
// meets the layer: Footprint is 1 on every pixel. Without them it is the camera ray's own
// result, 0 where that missed -- a layer the reference shows, which the denoiser would clear.

#include "Kernels/ptvIntegrator.h"
#include "ptvTestKernelCamera.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace
{
constexpr int kImage = 64;
constexpr float kEdge = 40.3f; // the scalar (= index x) above which the table is opaque

struct EdgeVolume
{
  std::vector<float> Voxels = std::vector<float>(64 * 2 * 2);
  float Table[8] = { 0.8f, 0.5f, 0.25f, 0.f, 0.8f, 0.5f, 0.25f, 0.9f };
  float StepTable[8];
  float ShadowTable[2];
  int Counts[3];
  ptv::TraceParams P;
};

void MakeEdgeVolume(EdgeVolume& v)
{
  for (std::size_t n = 0; n < v.Voxels.size(); ++n)
  {
    v.Voxels[n] = static_cast<float>(n % 64); // x fastest: the scalar is the index x
  }
  ptv::TraceParams& p = v.P;
  p = ptv::TraceParams{};
  p.Volume.Scalars = v.Voxels.data();
  p.Volume.Dims[0] = 64;
  p.Volume.Dims[1] = p.Volume.Dims[2] = 2;
  // i = 32 (x + 1): world x in [-1, 1] is the image's width, and i is the image x coordinate;
  // j = y / 40 + 0.5 and k = z (z in [0, 1]) keep every ray inside the grid.
  const float w2i[12] = { 32.f, 0.f, 0.f, 32.f, 0.f, 1.f / 40.f, 0.f, 0.5f, 0.f, 0.f, 1.f, 0.f };
  for (int i = 0; i < 12; ++i)
  {
    p.Volume.WorldToIndex[i] = w2i[i];
  }
  ptv::ComputeNormalToWorld(p.Volume);
  p.Transfer.RGBA = v.Table;
  p.Transfer.Size = 2;
  p.Transfer.ScalarMin = kEdge; // below it: entry 0, transparent
  p.Transfer.ScalarMax = 63.f;
  p.Occupancy.Distance = nullptr;
  OrthographicAlongZ(p, kImage);
  p.KeyLight.Radiance = ptv::MakeVec3(1.f, 1.f, 1.f);
  p.StepWorld = 0.02f;
  p.ShadowStepScale = 2.f;
  p.UnitDistance = 0.5f;
  p.Shade = 0;
  p.Diffuse = 1.f;
  p.Scattering = 1;
  p.MaxDistance = nullptr;
  p.Seed = 99u;
  SetStepTables(p, v.StepTable, v.ShadowTable);
}

/// Every field but Footprint, for a bitwise comparison.
std::vector<float> Fields(const ptv::PixelSample& s)
{
  return { s.Radiance.x, s.Radiance.y, s.Radiance.z, s.Alpha, s.Albedo.x, s.Albedo.y, s.Albedo.z,
    s.Depth1, s.Position1.x, s.Position1.y, s.Position1.z, s.Normal1.x, s.Normal1.y, s.Normal1.z,
    s.Depth2, s.Position2.x, s.Position2.y, s.Position2.z, s.Normal2.x, s.Normal2.y,
    s.Normal2.z, s.Coverage };
}

bool CheckEdge(bool shade, bool counts)
{
  EdgeVolume v;
  MakeEdgeVolume(v);
  v.P.Shade = shade ? 1 : 0;
  if (counts)
  {
    ptv::BuildOpaqueCounts(v.Table, 2, v.Counts);
    v.P.Transfer.OpaqueBefore = v.Counts;
  }
  ptv::TraceParams rays = v.P;
  rays.FootprintRays = 1;
  long wrong = 0, differ = 0, notOne = 0, edgeMet = 0, edgeMissed = 0;
  for (uint32_t frame = 0; frame < 4; ++frame)
  {
    for (int y = 0; y < kImage; ++y)
    {
      for (int x = 0; x < kImage; ++x)
      {
        const ptv::PixelSample off = ptv::TracePixel(v.P, x, y, frame);
        const ptv::PixelSample on = ptv::TracePixel(rays, x, y, frame);
        notOne += off.Footprint != 1.f ? 1 : 0;
        differ += Fields(off) != Fields(on) ? 1 : 0;
        const bool met = on.Depth1 < ptv::kHitFraction * v.P.Camera.FarDistance;
        float expected = x >= 41 && x <= 62 ? 1.f : 0.f;
        if (x == 40)
        {
          expected = met ? 1.f : 0.f;
          (met ? edgeMet : edgeMissed) += 1;
        }
        const bool bad = on.Footprint != expected || (x >= 41 && x <= 62 && !met) ||
          ((x <= 39 || x == 63) && met);
        wrong += bad ? 1 : 0;
      }
    }
  }
  std::printf("edge, Shade %d, interval counts %d: Footprint off != 1: %ld; other fields differing: %ld; Footprint "
              "or coverage wrong: %ld; edge column met %ld / missed %ld\n",
    shade ? 1 : 0, counts ? 1 : 0, notOne, differ, wrong, edgeMet, edgeMissed);
  // The edge column's rays meet opacity with probability 0.7 (jx > 0.3): both cases occur.
  return notOne == 0 && differ == 0 && wrong == 0 && edgeMet > 0 && edgeMissed > 0;
}

bool CheckThinLayer()
{
  EdgeVolume v;
  MakeEdgeVolume(v);
  ptv::TraceParams& p = v.P;
  std::vector<float> voxels(2 * 2 * 64);
  for (std::size_t n = 0; n < voxels.size(); ++n)
  {
    voxels[n] = static_cast<float>(n / 4); // x and y fastest: the scalar is the index z
  }
  p.Volume.Scalars = voxels.data();
  p.Volume.Dims[0] = p.Volume.Dims[1] = 2;
  p.Volume.Dims[2] = 64;
  const float w2i[12] = { 1.f / 40.f, 0.f, 0.f, 0.5f, 0.f, 1.f / 40.f, 0.f, 0.5f, 0.f, 0.f, 21.f,
    0.f }; // k = 21 z: the grid spans z in [0, 3]
  for (int i = 0; i < 12; ++i)
  {
    p.Volume.WorldToIndex[i] = w2i[i];
  }
  ptv::ComputeNormalToWorld(p.Volume);
  std::vector<float> table(4 * 64, 0.f), step(4 * 64), shadow(64);
  table[4 * 10 + 0] = table[4 * 10 + 1] = table[4 * 10 + 2] = 1.f;
  table[4 * 10 + 3] = 0.9f;
  p.Transfer.RGBA = table.data();
  p.Transfer.Size = 64;
  p.Transfer.ScalarMin = 0.f;
  p.Transfer.ScalarMax = 63.f;
  p.StepWorld = 4.f / 21.f; // 4 voxels
  SetStepTables(p, step.data(), shadow.data());
  p.FootprintRays = 1;
  std::vector<int> counts(65);
  ptv::BuildOpaqueCounts(table.data(), 64, counts.data());
  ptv::TraceParams plain = p;
  p.Transfer.OpaqueBefore = counts.data();
  long notOne = 0, met = 0, missed = 0, wrongPlain = 0;
  for (uint32_t frame = 0; frame < 4; ++frame)
  {
    for (int y = 0; y < kImage; ++y)
    {
      for (int x = 0; x < kImage; ++x)
      {
        const ptv::PixelSample s = ptv::TracePixel(p, x, y, frame);
        const ptv::PixelSample q = ptv::TracePixel(plain, x, y, frame);
        const bool hit = s.Depth1 < ptv::kHitFraction * p.Camera.FarDistance;
        (hit ? met : missed) += 1;
        notOne += s.Footprint != 1.f ? 1 : 0;
        wrongPlain += q.Footprint != (hit ? 1.f : 0.f) ? 1 : 0;
      }
    }
  }
  std::printf("thin layer: camera rays met %ld / missed %ld; Footprint != 1 with the interval "
              "counts %ld; without them Footprint != the camera ray's own result %ld\n",
    met, missed, notOne, wrongPlain);
  // Half of the camera rays meet the layer (their offset lands in (9, 11) out of 4 voxels).
  return met > 0 && missed > 0 && notOne == 0 && wrongPlain == 0;
}
}

int TestPTVKernelFootprint(int, char*[])
{
  bool ok = CheckEdge(false, true);
  ok = CheckEdge(true, true) && ok;
  ok = CheckEdge(false, false) && ok;
  ok = CheckThinLayer() && ok;
  std::printf(ok ? "TestPTVKernelFootprint passed\n" : "TestPTVKernelFootprint FAILED\n");
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
