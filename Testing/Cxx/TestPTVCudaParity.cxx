// CPU vs CUDA: the same kernel body on both backends gives the same passes within float
// tolerance (the GPU contracts multiply-adds, so an event can land one sample apart in rare
// pixels: the first-event passes must agree almost everywhere and the 16-frame means closely).
// The bilateral grid (same inputs to both drivers) must agree to float rounding: both run the
// same per-cell / per-pixel functions in the same order; only FMA contraction on the GPU differs.
// Without a usable CUDA device it prints "skipped: no CUDA device" and returns ctest's skip code.
#include "vtkColorTransferFunction.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "ptvCudaParity.h"
#include "vtkPTVDenoiser.h"
#include "vtkPTVExpertOptions.h"
#include "vtkPathTracedVolumeMapper.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkRTAnalyticSource.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <random>
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
  mapper->ConvergeStillRendersOff(); // frame by frame
  mapper->SetInputConnection(source->GetOutputPort());
  mapper->DenoiseOff();
  mapper->SetBackend(backend);
  mapper->GetExpertOptions()->SetMaximumAccumulatedFrames(frames);
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
}

/// A W x H image with one float array of @a components per pixel.
vtkSmartPointer<vtkImageData> Image(int w, int h, const std::vector<float>& values, int components)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(w, h, 1);
  vtkNew<vtkFloatArray> a;
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(static_cast<vtkIdType>(w) * h);
  std::copy(values.begin(), values.begin() + a->GetNumberOfValues(), a->GetPointer(0));
  image->GetPointData()->SetScalars(a);
  return image;
}

/// vtkPTVDenoiser's grid alone (given guides) on the CPU vs CUDA, random frames (odd size, a firefly, 1 and 3 levels,
/// demodulated or not): the number of cases whose max |CPU - CUDA| exceeds 1e-5 of the range.
int GridParity()
{
  const int w = 131, h = 67;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  std::mt19937 rng(5);
  std::exponential_distribution<float> light(1.0f);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  std::vector<float> radiance(3 * n), albedo(3 * n), guides(3 * n), weights(2 * n);
  std::generate(radiance.begin(), radiance.end(), [&] { return light(rng); });
  radiance[300] = 1e4f; // a firefly for the outlier clamp
  std::generate(albedo.begin(), albedo.end(), [&] { return unit(rng); });
  std::generate(guides.begin(), guides.end(), [&] { return 255.f * unit(rng); });
  std::generate(weights.begin(), weights.end(), [&] { return 0.5f * unit(rng); });
  int failures = 0;
  for (int levels : { 1, 3 })
  {
    for (bool demodulate : { true, false })
    {
      std::vector<float> result[2];
      bool onCuda[2] = { false, false };
      for (int backend = 0; backend < 2; ++backend)
      {
        vtkNew<vtkPTVDenoiser> grid;
        grid->SetUseCuda(backend == 1);
        grid->SetImage("Radiance", Image(w, h, radiance, 3));
        grid->SetImage("Albedo", demodulate ? Image(w, h, albedo, 3) : nullptr);
        grid->SetImage("Guides", Image(w, h, guides, levels));
        grid->SetImage("BlendWeights", levels > 1 ? Image(w, h, weights, levels - 1) : nullptr);
        grid->Execute();
        auto* a = vtkFloatArray::SafeDownCast(grid->GetOutput()->GetPointData()->GetScalars());
        result[backend].assign(a->GetPointer(0), a->GetPointer(0) + a->GetNumberOfValues());
        onCuda[backend] = grid->GetLastGridOnCuda();
      }
      const auto range = std::minmax_element(result[0].begin(), result[0].end());
      float diff = 0.f;
      for (std::size_t i = 0; i < result[0].size(); ++i)
      {
        diff = std::max(diff, std::abs(result[0][i] - result[1][i]));
      }
      const double relative = diff / std::max(1e-30f, *range.second - *range.first);
      std::cout << "grid L=" << levels << (demodulate ? " demodulated" : " radiance")
                << ": ran on " << (onCuda[1] ? "CUDA" : "the CPU (CUDA failed)")
                << ", max |CPU - CUDA| / range " << relative << "\n";
      failures += !onCuda[0] && onCuda[1] && relative <= ptv::parity::kGridRelative ? 0 : 1;
    }
  }
  return failures;
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
    const double depth = ptv::parity::FractionClose(
      cpu.Depth.data(), gpu.Depth.data(), cpu.Depth.size(), ptv::parity::kDepthTolerance);
    const double normal = ptv::parity::FractionClose(
      cpu.Normal.data(), gpu.Normal.data(), cpu.Normal.size(), ptv::parity::kNormalTolerance);
    const double rmse =
      ptv::parity::Rmse(cpu.Radiance.data(), gpu.Radiance.data(), cpu.Radiance.size());
    std::cout << frames << " frame(s): backends " << cpu.Backend << "/" << gpu.Backend
              << ", depth close " << depth << ", normal close " << normal << ", radiance RMSE "
              << rmse << "\n";
    const bool ok =
      gpu.Backend == "CUDA" && ptv::parity::TraceAgrees(depth, normal, rmse, frames);
    failures += ok ? 0 : 1;
  }
  failures += GridParity();
  return failures == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
