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
//    that are exact in float), and only it keeps the frame.
#include "ptvRanks.h"
#include "ptvTestCheck.h"

#include "vtkDummyController.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"

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
