// TestPTVRanks.cxx's checks across processes: run under mpirun -np 2, 4, 8
// (PTV.MPI.TestPTVRanks*). Every process runs them; process 0 reports the total of failures and
// sets the exit code. With --traffic SIZE REPEATS it is instead the split composite's benchmark
// (Testing/Benchmarks/split_composite.py): every process composites a SIZE x SIZE frame of its
// piece REPEATS times; process 0 prints one JSON line with each process's bytes received per
// composite and the median composite time in milliseconds. With --giant-split it runs
// TestPTVSplitGiantVolume.cxx instead (a 1024^3 16-bit volume split across the processes).
#include "ptvRanks.h"

#include "vtkMPIController.h"
#include "vtkNew.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

int TestPTVRanksWith(vtkMultiProcessController* controller);
int TestPTVSplitGiantVolume(vtkMultiProcessController* controller);
void PieceFrame(int rank, int width, int height, float far, ptv::PassBuffers& frame);

namespace
{
int Traffic(vtkMultiProcessController* controller, int size, int repeats)
{
  ptv::Ranks ranks;
  ranks.SetController(controller);
  ranks.SetDistributed(true);
  const int r = ranks.GetRank(), n = ranks.GetSize();
  ptv::PieceView piece;
  piece.Box = { { 10.0 * r, 10.0 * r + 9, 0, 9, 0, 9 } };
  piece.Eye[0] = -100;
  piece.Eye[1] = piece.Eye[2] = 5;
  piece.Far = 100.f;
  ptv::PassBuffers frame(ptv::PassSet::Traced);
  frame.SetScatterPasses(false); // the default passes
  std::vector<double> ms;
  for (int k = 0; k < repeats; ++k)
  {
    PieceFrame(r, size, size, piece.Far, frame); // the composite overwrites process 0's
    controller->Barrier();
    const auto start = std::chrono::steady_clock::now();
    ranks.GatherFrame(frame, ptv::kTracedPassCount, piece, 1);
    controller->Barrier();
    ms.push_back(
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(ms.begin(), ms.end());
  const double bytes = static_cast<double>(ranks.GetLastBytesReceived());
  std::vector<double> all(static_cast<std::size_t>(n));
  controller->Gather(&bytes, all.data(), 1, 0);
  if (r == 0)
  {
    std::cout << "{\"ranks\": " << n << ", \"size\": " << size << ", \"median_ms\": "
              << ms[ms.size() / 2] << ", \"bytes_received\": [";
    for (int k = 0; k < n; ++k)
    {
      std::cout << (k ? ", " : "") << all[k];
    }
    std::cout << "]}" << std::endl;
  }
  return 0;
}
}

int main(int argc, char* argv[])
{
  vtkNew<vtkMPIController> controller;
  controller->Initialize(&argc, &argv);
  if (controller->GetNumberOfProcesses() < 2)
  {
    std::cerr << "FAILED: run under mpirun with at least 2 processes\n";
    controller->Finalize();
    return EXIT_FAILURE;
  }
  if (argc == 4 && std::string(argv[1]) == "--traffic")
  {
    Traffic(controller, std::max(std::atoi(argv[2]), 1), std::max(std::atoi(argv[3]), 1));
    controller->Finalize();
    return EXIT_SUCCESS;
  }
  const bool giant = argc == 2 && std::string(argv[1]) == "--giant-split";
  const int mine = giant ? TestPTVSplitGiantVolume(controller) : TestPTVRanksWith(controller);
  int total = 0;
  controller->AllReduce(&mine, &total, 1, vtkCommunicator::SUM_OP);
  if (controller->GetLocalProcessId() == 0)
  {
    std::cout << controller->GetNumberOfProcesses() << " processes, " << total
              << " failed checks\n";
  }
  controller->Finalize();
  return total == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
