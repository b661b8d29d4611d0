// Unit test of ptvRanks (issue #60): the processes that trace one frame together.
// Alone (no controller, and a vtkDummyController of one process) every call is a no-op:
// rank 0 of 1, the requested threads, sample blocks frame * samples, no piece stream, Share /
// AllTrue / Agree return their input, GatherFrame keeps the frame.
// With N > 1 processes (TestPTVRanksMPI.cxx runs this under mpirun -np 2):
//  - FirstSample: process r traces block f N + r (distributed: every process block f);
//    PieceStream: 0, distributed r + 1;
//  - Share: the minimum of the lower and the maximum of the upper ends of every range, bounds
//    and extent, and ok only when every process is ok; AllTrue likewise;
//  - Agree: process 0's value everywhere;
//  - GatherFrame: process 0 holds the mean of the processes' traced passes (exactly, for values
//    that are exact in float), and only it keeps the frame;
//  - distributed GatherFrame (direct send, issue #62): process 0's frame is bit for bit the
//    pieces composited in view order on one process (CompositePieces of every piece, what the
//    gather on process 0 did), with and without the scatter passes, on an image whose pixels
//    do not divide among the processes; every process receives at most 2 images' passes
//    (process 0: its share of every piece and the others' composited shares).
#include "ptvRanks.h"
#include "ptvTestCheck.h"

#include "vtkDummyController.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"

#include <random>
#include <string>
#include <vector>

namespace
{
void TestAlone(ptv::Ranks& ranks, const std::string& label)
{
  Check(ranks.GetRank() == 0 && ranks.GetSize() == 1 && !ranks.IsParallel() && ranks.Shows(),
    label + ": rank 0 of 1, shows");
  Check(ranks.Threads(3) == 3 && ranks.Threads(0) == 0, label + ": threads as requested");
  Check(ranks.FirstSample(5, 4) == 20 && ranks.PieceStream() == 0u,
    label + ": frame 5 of 4 samples starts at sample 20, no piece stream");
  double ranges[4] = { 1, 2, 3, 4 }, bounds[6] = { 0, 1, 0, 1, 0, 1 },
         extent[6] = { 0, 9, 0, 9, 0, 9 };
  Check(ranks.Share(true, ranges, bounds, extent) && !ranks.Share(false, ranges, bounds, extent) &&
      ranges[3] == 4 && bounds[1] == 1 && extent[5] == 9,
    label + ": Share returns ok and keeps the values");
  Check(ranks.AllTrue(true) && !ranks.AllTrue(false) && ranks.Agree(7) == 7,
    label + ": AllTrue and Agree return their input");
  ptv::PassBuffers frame;
  frame.Resize(2, 2);
  frame.Data(ptv::PassAlpha)[3] = 0.25f;
  ptv::PieceView piece;
  Check(ranks.GatherFrame(frame, ptv::kTracedPassCount, piece, 1) &&
      frame.Data(ptv::PassAlpha)[3] == 0.25f,
    label + ": GatherFrame keeps the frame");
}
}

/// Piece @a rank's frame of @a width x @a height: reproducible samples, hits and misses.
void PieceFrame(int rank, int width, int height, float far, ptv::PassBuffers& frame)
{
  frame.Resize(width, height);
  std::mt19937 rng(1234u + static_cast<unsigned int>(rank));
  std::uniform_real_distribution<float> u(0.f, 1.f);
  auto vec = [&]() { return ptv::MakeVec3(u(rng), u(rng), u(rng)); };
  for (int i = 0; i < width * height; ++i)
  {
    ptv::PixelSample s;
    const bool hit = u(rng) < 0.7f;
    s.Alpha = hit ? u(rng) : 0.f;
    s.Radiance = hit ? vec() : ptv::MakeVec3(0.f, 0.f, 0.f);
    s.Albedo = vec();
    s.Depth1 = hit ? far * u(rng) * 0.5f : far;
    s.Position1 = vec();
    s.Normal1 = vec();
    s.Depth2 = hit ? far * u(rng) * 0.9f : far;
    s.Position2 = vec();
    s.Normal2 = vec();
    s.Coverage = s.Alpha;
    s.Footprint = hit ? 1.f : 0.f;
    frame.Store(i, s);
  }
}

/// Distributed GatherFrame against the pieces composited on one process.
void TestComposite(ptv::Ranks& ranks, bool scatter, const std::string& label)
{
  const int r = ranks.GetRank(), n = ranks.GetSize();
  const int width = 7, height = 5; // 35 pixels: shares of 17 and 18 (2), 8 and 9 (4), 4 and 5 (8)
  const float far = 100.f;
  std::vector<ptv::PieceBox> boxes(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k)
  {
    boxes[k] = { { 10.0 * k, 10.0 * k + 9, 0, 9, 0, 9 } };
  }
  ptv::PieceView piece;
  piece.Box = boxes[r];
  piece.Eye[0] = -100;
  piece.Eye[1] = piece.Eye[2] = 5;
  piece.Far = far;
  ptv::PassBuffers frame(ptv::PassSet::Traced);
  frame.SetScatterPasses(scatter);
  PieceFrame(r, width, height, far, frame);
  ranks.SetDistributed(true);
  const bool keeps = ranks.GatherFrame(frame, ptv::kTracedPassCount, piece, 1);
  ranks.SetDistributed(false);
  Check(keeps == (r == 0), label + ": only process 0 keeps the composited frame");
  std::size_t floats = 0;
  for (int p = 0; p < ptv::kTracedPassCount; ++p)
  {
    floats += frame.Data(p) ? static_cast<std::size_t>(ptv::GetPassInfo(p).Components) : 0;
  }
  const std::size_t image = sizeof(float) * floats * static_cast<std::size_t>(width * height);
  Check(ranks.GetLastBytesReceived() > 0 && ranks.GetLastBytesReceived() <= 2 * image,
    label + ": received " + std::to_string(ranks.GetLastBytesReceived()) + " bytes, at most 2 x " +
      std::to_string(image));
  if (r != 0)
  {
    return;
  }
  std::vector<ptv::PassBuffers> pieces(
    static_cast<std::size_t>(n), ptv::PassBuffers(ptv::PassSet::Traced));
  std::vector<std::vector<float>> all(ptv::kTracedPassCount);
  std::vector<const float*> gathered(ptv::kTracedPassCount, nullptr);
  for (int k = 0; k < n; ++k)
  {
    pieces[k].SetScatterPasses(scatter);
    PieceFrame(k, width, height, far, pieces[k]);
    for (int p = 0; p < ptv::kTracedPassCount; ++p)
    {
      if (const float* d = pieces[k].Data(p))
      {
        all[p].insert(all[p].end(), d, d + ptv::GetPassInfo(p).Components * width * height);
      }
    }
  }
  for (int p = 0; p < ptv::kTracedPassCount; ++p)
  {
    gathered[p] = all[p].empty() ? nullptr : all[p].data();
  }
  const std::vector<int> order = ptv::ViewOrder(boxes, piece.Eye, piece.Dir, false);
  ptv::PassBuffers expected(ptv::PassSet::Traced);
  expected.SetScatterPasses(scatter);
  expected.Resize(width, height);
  ptv::CompositePieces(gathered, static_cast<std::size_t>(width * height), order,
    std::vector<float>(static_cast<std::size_t>(n), far), far, 1, expected);
  bool same = true;
  for (int p = 0; p < ptv::kTracedPassCount; ++p)
  {
    const float* a = frame.Data(p);
    const float* b = expected.Data(p);
    same = same && (a == nullptr) == (b == nullptr) &&
      (a == nullptr) == (!scatter && ptv::IsScatterPass(p));
    for (int i = 0; a && b && i < ptv::GetPassInfo(p).Components * width * height; ++i)
    {
      same = same && a[i] == b[i];
    }
  }
  Check(same,
    label + ": the composited frame is the pieces composited on one process, bit for bit");
}

/// The checks with @a controller's processes (also called by the MPI driver); the number of
/// failures on this process.
int TestPTVRanksWith(vtkMultiProcessController* controller)
{
  ptv::Ranks ranks;
  ranks.SetController(controller);
  const int r = ranks.GetRank(), n = ranks.GetSize();
  const std::string label = "rank " + std::to_string(r) + " of " + std::to_string(n);
  if (n == 1)
  {
    TestAlone(ranks, label);
    return failures;
  }
  Check(ranks.IsParallel() && ranks.Shows() == (r == 0), label + ": parallel, rank 0 shows");
  Check(ranks.FirstSample(3, 2) == static_cast<unsigned int>((3 * n + r) * 2) &&
      ranks.PieceStream() == 0u,
    label + ": whole volume: block f N + r, no piece stream");
  ranks.SetDistributed(true);
  Check(ranks.FirstSample(3, 2) == 6u && ranks.PieceStream() == static_cast<unsigned int>(r + 1),
    label + ": distributed: the frame's block, piece stream r + 1");
  ranks.SetDistributed(false);

  // Share: process r has range [r, 10 + r], bounds [-r, r] ..., extent [r, 20 + r] ...
  double ranges[4] = { 1.0 * r, 10.0 + r, 100.0 - r, 100.0 + r };
  double bounds[6] = { -1.0 * r, 1.0 * r, -2.0 * r, 2.0 * r, 0, 1 };
  double extent[6] = { 1.0 * r, 20.0 + r, 0, 5, 0, 5 };
  const bool shared = ranks.Share(r != 1, ranges, bounds, extent);
  Check(!shared, label + ": Share is not ok when one process is not");
  Check(ranges[0] == 0 && ranges[1] == 10 + (n - 1) && ranges[2] == 100 - (n - 1) &&
      ranges[3] == 100 + (n - 1) && bounds[0] == -(n - 1) && bounds[1] == n - 1 &&
      extent[0] == 0 && extent[1] == 20 + (n - 1),
    label + ": Share gives the union of the ranges, bounds and extents");
  Check(ranks.AllTrue(true) && !ranks.AllTrue(r != n - 1), label + ": AllTrue");
  Check(ranks.Agree(40 + r) == 40, label + ": Agree gives process 0's value");
  std::vector<std::uint32_t> values = { static_cast<std::uint32_t>(r), 9u };
  ranks.Agree(values);
  Check(values.size() == 2 && values[0] == 0u && values[1] == 9u,
    label + ": Agree gives process 0's values");

  // GatherFrame: pass value r + 1 at every entry; the mean is (n + 1) / 2, exact in float.
  ptv::PassBuffers frame;
  frame.Resize(3, 2);
  for (int p = 0; p < ptv::kTracedPassCount; ++p)
  {
    float* d = frame.Data(p);
    for (std::size_t i = 0; i < 6u * ptv::GetPassInfo(p).Components; ++i)
    {
      d[i] = static_cast<float>(r + 1);
    }
  }
  ptv::PieceView piece;
  const bool keeps = ranks.GatherFrame(frame, ptv::kTracedPassCount, piece, 1);
  Check(keeps == (r == 0), label + ": only process 0 keeps the gathered frame");
  if (r == 0)
  {
    bool mean = true;
    for (int p = 0; p < ptv::kTracedPassCount; ++p)
    {
      const float* d = frame.Data(p);
      for (std::size_t i = 0; i < 6u * ptv::GetPassInfo(p).Components; ++i)
      {
        mean = mean && d[i] == 0.5f * static_cast<float>(n + 1);
      }
    }
    Check(mean, label + ": the gathered frame is the mean of the processes' frames");
  }
  TestComposite(ranks, true, label + ", split");
  TestComposite(ranks, false, label + ", split without scatter passes");
  return failures;
}

int TestPTVRanks(int, char*[])
{
  {
    ptv::Ranks ranks;
    TestAlone(ranks, "no controller");
  }
  vtkNew<vtkDummyController> dummy;
  TestPTVRanksWith(dummy);
  return TestResult();
}
