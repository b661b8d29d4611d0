// CPU vs CUDA: the same kernel body on both backends gives the same passes within float
// tolerance (the GPU contracts multiply-adds, so an event can land one sample apart in rare
// pixels: the first-event passes must agree almost everywhere and the 16-frame means closely).
// Without a usable CUDA device it prints "skipped: no CUDA device" and returns ctest's skip code.
#include "vtkColorTransferFunction.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPathTracedVolumeMapper.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkRTAnalyticSource.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

namespace
{
constexpr int kSkip = 125; // SKIP_RETURN_CODE in Testing/Cxx/CMakeLists.txt

struct Frames
{
  std::vector<float> Depth, Normal, Radiance;
  std::string Backend;
};

std::vector<float> Pass(vtkPathTracedVolumeMapper* mapper, const char* name)
{
  vtkNew<vtkImageData> image;
  mapper->GetPass(name, image);
  auto* a = vtkFloatArray::SafeDownCast(image->GetPointData()->GetScalars());
  return std::vector<float>(a->GetPointer(0), a->GetPointer(0) + a->GetNumberOfValues());
}

Frames Render(int backend, int frames)
{
  vtkNew<vtkRTAnalyticSource> source;
  source->SetWholeExtent(-24, 24, -24, 24, -24, 24);
  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(37, 0.2, 0.4, 1.0);
  color->AddRGBPoint(277, 1.0, 0.9, 0.5);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(37, 0.0);
  opacity->AddPoint(150, 0.0);
  opacity->AddPoint(277, 0.8);
  vtkNew<vtkVolumeProperty> property;
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  property->ShadeOn();
  property->SetInterpolationTypeToLinear();
  vtkNew<vtkPathTracedVolumeMapper> mapper;
  mapper->SetInputConnection(source->GetOutputPort());
  mapper->DenoiseOff();
  mapper->SetBackend(backend);
  mapper->SetMaximumAccumulatedFrames(frames);
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(property);
  vtkNew<vtkRenderer> renderer;
  renderer->AddVolume(volume);
  renderer->SetBackground(0.4, 0.4, 0.4);
  renderer->ResetCamera();
  vtkNew<vtkRenderWindow> window;
  window->SetSize(128, 128);
  window->AddRenderer(renderer);
  for (int i = 0; i < frames; ++i)
  {
    window->Render();
  }
  return { Pass(mapper, "Depth"), Pass(mapper, "Normal"), Pass(mapper, "Radiance"),
    mapper->GetActiveBackend() };
}

double FractionClose(const std::vector<float>& a, const std::vector<float>& b, double tol)
{
  std::size_t close = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
  {
    close += std::abs(a[i] - b[i]) <= tol * (1.0 + std::abs(a[i])) ? 1 : 0;
  }
  return a.empty() ? 0.0 : static_cast<double>(close) / a.size();
}

double Rmse(const std::vector<float>& a, const std::vector<float>& b)
{
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i)
  {
    s += (a[i] - b[i]) * static_cast<double>(a[i] - b[i]);
  }
  return a.empty() ? 0.0 : std::sqrt(s / a.size());
}
}

int TestPTVCudaParity(int, char*[])
{
  if (!vtkPathTracedVolumeMapper::GetCudaAvailable())
  {
    std::cout << "skipped: no CUDA device (" << vtkPathTracedVolumeMapper::GetCudaStatus()
              << ")\n";
    return kSkip;
  }
  int failures = 0;
  for (int frames : { 1, 16 })
  {
    const Frames cpu = Render(vtkPathTracedVolumeMapper::BACKEND_CPU, frames);
    const Frames gpu = Render(vtkPathTracedVolumeMapper::BACKEND_CUDA, frames);
    const double depth = FractionClose(cpu.Depth, gpu.Depth, 1e-4);
    const double normal = FractionClose(cpu.Normal, gpu.Normal, 1e-3);
    const double rmse = Rmse(cpu.Radiance, gpu.Radiance);
    std::cout << frames << " frame(s): backends " << cpu.Backend << "/" << gpu.Backend
              << ", depth close " << depth << ", normal close " << normal << ", radiance RMSE "
              << rmse << "\n";
    const bool ok = gpu.Backend == "CUDA" && depth >= 0.995 && normal >= 0.99 &&
      rmse <= (frames == 1 ? 0.05 : 0.02);
    failures += ok ? 0 : 1;
  }
  return failures == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
