// Backend choice (CPU-side logic, runs everywhere): the decision table, and on this machine a
// CUDA request without a usable device gives one clear error and the CPU image, bit for bit.
#include "ptvTestCheck.h"
#include "ptvTracerRunner.h"

#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkCommand.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPTVDenoiser.h"
#include "vtkPathTracedVolumeMapper.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkRTAnalyticSource.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkTestErrorObserver.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

namespace
{

std::vector<float> RenderRadiance(int backend, vtkTest::ErrorObserver* errors, std::string& used)
{
  vtkNew<vtkRTAnalyticSource> source;
  source->SetWholeExtent(-10, 10, -10, 10, -10, 10);
  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(37, 0.2, 0.4, 1.0);
  color->AddRGBPoint(277, 1.0, 0.9, 0.5);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(37, 0.0);
  opacity->AddPoint(277, 0.7);
  vtkNew<vtkVolumeProperty> property;
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  property->ShadeOn();
  vtkNew<vtkPathTracedVolumeMapper> mapper;
  mapper->ConvergeStillRendersOff(); // frame by frame
  mapper->SetInputConnection(source->GetOutputPort());
  mapper->DenoiseOff();
  mapper->SetBackend(backend);
  mapper->AddObserver(vtkCommand::ErrorEvent, errors);
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(property);
  vtkNew<vtkRenderer> renderer;
  renderer->AddVolume(volume);
  renderer->ResetCamera();
  vtkNew<vtkRenderWindow> window;
  window->SetSize(40, 30);
  window->AddRenderer(renderer);
  window->Render();
  window->Render();
  used = mapper->GetActiveBackend();
  vtkNew<vtkImageData> image;
  if (!mapper->GetPass("Radiance", image))
  {
    return {};
  }
  auto* a = vtkFloatArray::SafeDownCast(image->GetPointData()->GetScalars());
  return std::vector<float>(a->GetPointer(0), a->GetPointer(0) + a->GetNumberOfValues());
}
}

/// vtkPTVDenoiser's grid alone (given guides) on a 9 x 5 ramp, 1 level, optionally asking for
/// CUDA; @a warnings observes the warnings.
std::vector<float> DenoiseRamp(bool useCuda, vtkTest::ErrorObserver* warnings)
{
  auto image = [](int components, float scale)
  {
    vtkNew<vtkImageData> im;
    im->SetDimensions(9, 5, 1);
    vtkNew<vtkFloatArray> a;
    a->SetNumberOfComponents(components);
    a->SetNumberOfTuples(45);
    for (vtkIdType i = 0; i < a->GetNumberOfValues(); ++i)
    {
      a->SetValue(i, scale * static_cast<float>(i % 17) / 17.f);
    }
    im->GetPointData()->SetScalars(a);
    return vtkSmartPointer<vtkImageData>(im.GetPointer());
  };
  vtkNew<vtkPTVDenoiser> grid;
  grid->SetUseCuda(useCuda);
  if (warnings)
  {
    grid->AddObserver(vtkCommand::WarningEvent, warnings);
  }
  grid->SetImage("Radiance", image(3, 2.f));
  grid->SetImage("Albedo", image(3, 1.f));
  grid->SetImage("Guides", image(1, 255.f));
  if (!grid->Execute() || grid->GetLastGridOnCuda())
  {
    return {};
  }
  auto* a = vtkFloatArray::SafeDownCast(grid->GetOutput()->GetPointData()->GetScalars());
  return std::vector<float>(a->GetPointer(0), a->GetPointer(0) + a->GetNumberOfValues());
}

int TestPTVBackend(int, char*[])
{
  using ptv::ResolveBackend;
  std::string m;
  Check(ResolveBackend(vtkPathTracedVolumeMapper::BACKEND_CPU, true, "x", m) == vtkPathTracedVolumeMapper::BACKEND_CPU && m.empty(),
    "CPU requested, device present: CPU");
  Check(ResolveBackend(vtkPathTracedVolumeMapper::BACKEND_CPU, false, "x", m) == vtkPathTracedVolumeMapper::BACKEND_CPU && m.empty(),
    "CPU requested, no device: CPU");
  Check(ResolveBackend(vtkPathTracedVolumeMapper::BACKEND_AUTO, true, "x", m) == vtkPathTracedVolumeMapper::BACKEND_CUDA && m.empty(),
    "Auto, device present: CUDA");
  Check(ResolveBackend(vtkPathTracedVolumeMapper::BACKEND_AUTO, false, "x", m) == vtkPathTracedVolumeMapper::BACKEND_CPU && m.empty(),
    "Auto, no device: CPU, silently");
  Check(ResolveBackend(vtkPathTracedVolumeMapper::BACKEND_CUDA, true, "x", m) == vtkPathTracedVolumeMapper::BACKEND_CUDA && m.empty(),
    "CUDA requested, device present: CUDA");
  Check(ResolveBackend(vtkPathTracedVolumeMapper::BACKEND_CUDA, false, "no driver (error 35)", m) == vtkPathTracedVolumeMapper::BACKEND_CPU &&
      m.find("no driver (error 35)") != std::string::npos,
    "CUDA requested, no device: CPU with a message naming why");

  const bool cuda = vtkPathTracedVolumeMapper::GetCudaAvailable();
  std::cout << "CUDA: " << vtkPathTracedVolumeMapper::GetCudaStatus() << "\n";
  vtkNew<vtkTest::ErrorObserver> cpuErrors, autoErrors, cudaErrors;
  std::string cpuUsed, autoUsed, cudaUsed;
  const auto cpu =
    RenderRadiance(vtkPathTracedVolumeMapper::BACKEND_CPU, cpuErrors, cpuUsed);
  const auto automatic =
    RenderRadiance(vtkPathTracedVolumeMapper::BACKEND_AUTO, autoErrors, autoUsed);
  const auto requested =
    RenderRadiance(vtkPathTracedVolumeMapper::BACKEND_CUDA, cudaErrors, cudaUsed);
  Check(cpuUsed == "CPU" && !cpuErrors->GetError(), "CPU backend renders on the CPU");
  Check(!autoErrors->GetError(), "Auto never errors");
  Check(autoUsed == (cuda ? "CUDA" : "CPU"), "Auto picks " + autoUsed);
  if (!cuda)
  {
    Check(cudaUsed == "CPU", "CUDA without a device renders on the CPU");
    const std::string text = cudaErrors->GetErrorMessage();
    const std::string key = "the CUDA backend was requested but";
    std::size_t count = 0;
    for (std::size_t at = text.find(key); at != std::string::npos; at = text.find(key, at + 1))
    {
      ++count;
    }
    Check(count == 1, "CUDA without a device: one error over two frames, naming the request (" +
        std::to_string(count) + ")");
    Check(!cpu.empty() && requested == cpu && automatic == cpu,
      "the fallback image is the CPU image, bit for bit");

    // The bilateral grid: UseCuda without a device is a warning naming why, then the CPU result.
    const std::vector<float> plain = DenoiseRamp(false, nullptr);
    vtkNew<vtkTest::ErrorObserver> gridWarnings;
    const std::vector<float> fallback = DenoiseRamp(true, gridWarnings);
    const std::string gridText = gridWarnings->GetWarningMessage();
    Check(gridText.find("bilateral grid on CUDA failed (") != std::string::npos &&
        gridText.find("using the CPU") != std::string::npos,
      "grid UseCuda without a device reports it: " + gridText);
    Check(!plain.empty() && fallback == plain, "grid fallback is the CPU result, bit for bit");
  }
  return TestResult();
}
