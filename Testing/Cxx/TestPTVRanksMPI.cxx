// TestPTVRanks.cxx's checks across processes: run under mpirun -np 2 (PTV.MPI.TestPTVRanks).
// Every process runs them; process 0 reports the total of failures and sets the exit code.
#include "vtkMPIController.h"
#include "vtkNew.h"

#include <cstdlib>
#include <iostream>

int TestPTVRanksWith(vtkMultiProcessController* controller);

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
  const int mine = TestPTVRanksWith(controller);
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
