// A 1024^3 unsigned 16-bit volume (2 GiB, issue #62) split across the processes
// (DistributedVolume; ptvMpiTests --giant-split under mpirun, PTV.MPI.TestPTVSplitGiantVolume):
// each process builds only its slab of z (plus 2 ghost layers), a sphere shell of radius 400,
// and renders it with the others. The camera looks along -x with z up, so the image's lower and
// upper halves come from different processes' pieces. Checks: both halves of process 0's
// composited frame are covered (every piece reached it), no process reports an error, and each
// process renders its 1 GiB piece with less than 512 MiB of extra peak memory (the piece read in
// place; its float copy alone would be 2 GiB).
#include "ptvTestCheck.h"
#include "ptvTestMemory.h"

#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkPathTracedVolumeMapper.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTestErrorObserver.h"
#include "vtkUnsignedShortArray.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>

/// The checks on this process; the number of failures.
int TestPTVSplitGiantVolume(vtkMultiProcessController* controller)
{
  const int r = controller->GetLocalProcessId(), n = controller->GetNumberOfProcesses();
  const std::string label = "rank " + std::to_string(r) + " of " + std::to_string(n);
  constexpr int side = 1024, ghosts = 2;
  const int z0 = side * r / n, z1 = side * (r + 1) / n - 1; // this piece
  const int in0 = std::max(z0 - ghosts, 0), in1 = std::min(z1 + ghosts, side - 1);
  vtkNew<vtkImageData> image;
  image->SetExtent(0, side - 1, 0, side - 1, in0, in1);
  vtkNew<vtkUnsignedShortArray> shorts;
  shorts->SetName("shell");
  shorts->SetNumberOfTuples(vtkIdType(side) * side * (in1 - in0 + 1));
  unsigned short* v = shorts->GetPointer(0);
  vtkIdType i = 0;
  for (int z = in0; z <= in1; ++z)
  {
    for (int y = 0; y < side; ++y)
    {
      const double ry = (y - 512.0) * (y - 512.0) + (z - 512.0) * (z - 512.0);
      for (int x = 0; x < side; ++x, ++i)
      {
        const double d = std::sqrt(ry + (x - 512.0) * (x - 512.0));
        v[i] = static_cast<unsigned short>(std::abs(d - 400.0) < 24.0 ? 3000 : 100);
      }
    }
  }
  image->GetPointData()->SetScalars(shorts);

  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(0, 0.2, 0.4, 1.0);
  color->AddRGBPoint(3000, 1.0, 0.9, 0.5);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0, 0.0);
  opacity->AddPoint(1500, 0.0);
  opacity->AddPoint(3000, 0.8);
  vtkNew<vtkVolumeProperty> property;
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  property->ShadeOn();
  vtkNew<vtkPathTracedVolumeMapper> mapper;
  vtkNew<vtkTest::ErrorObserver> errors;
  mapper->AddObserver(vtkCommand::ErrorEvent, errors);
  mapper->AddObserver(vtkCommand::WarningEvent, errors);
  mapper->SetInputData(image);
  mapper->SetController(controller);
  mapper->DistributedVolumeOn();
  mapper->SetPieceExtent(0, side - 1, 0, side - 1, z0, z1);
  mapper->SetWholeExtent(0, side - 1, 0, side - 1, 0, side - 1);
  mapper->DenoiseOff();
  mapper->ConvergeStillRendersOff();
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(property);
  vtkNew<vtkRenderer> renderer;
  renderer->AddVolume(volume);
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->SetFocalPoint(511.5, 511.5, 511.5);
  camera->SetPosition(4000.0, 511.5, 511.5);
  camera->SetViewUp(0, 0, 1);
  renderer->ResetCamera();
  vtkNew<vtkRenderWindow> window;
  window->SetSize(64, 64);
  window->AddRenderer(renderer);

  const double held = StatusBytes("VmRSS");
  ResetPeakMemory();
  window->Render();
  const double extra = StatusBytes("VmHWM") - held;
  std::cout << label << ": piece z " << z0 << "-" << z1 << ", " << held / 1048576.0
            << " MiB held, " << extra / 1048576.0 << " MiB extra peak for the render\n";
  Check(held > 0.0 && extra < 512.0 * 1048576.0,
    label + ": its 1 GiB piece renders with " + std::to_string(extra / 1048576.0) +
      " MiB of extra peak memory (< 512)");
  Check(errors->GetError() == 0 && errors->GetWarning() == 0,
    label + ": no error or warning (" + errors->GetErrorMessage() + errors->GetWarningMessage() +
      ")");
  if (r == 0)
  {
    vtkNew<vtkImageData> pass;
    Check(mapper->GetPass("Alpha", pass), label + ": the composited frame's Alpha");
    auto* alpha = vtkFloatArray::SafeDownCast(pass->GetPointData()->GetScalars());
    double lower = 0.0, upper = 0.0;
    for (vtkIdType p = 0; alpha && p < alpha->GetNumberOfValues(); ++p)
    {
      (p < alpha->GetNumberOfValues() / 2 ? lower : upper) += alpha->GetValue(p);
    }
    const double half = 64.0 * 32.0;
    Check(lower > 0.1 * half && upper > 0.1 * half,
      label + ": both halves covered (" + std::to_string(lower / half) + ", " +
        std::to_string(upper / half) + " of their pixels): every piece is in the frame");
  }
  return failures;
}
