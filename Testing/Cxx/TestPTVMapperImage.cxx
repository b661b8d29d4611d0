// Regression images of vtkPathTracedVolumeMapper. One function, many cases (argv: the case
// name), each compared with Testing/Data/Baseline/TestPTVMapperImage_<case>.png:
//   synthetic_1spp, synthetic_256spp     a synthetic two-band volume, fixed seed
//   head_1spp, head_256spp               the head CT with its paper preset
//   pass_<Name>                          each auxiliary pass shown through DisplayPass
//   sphere                               an opaque polygonal sphere intersecting the volume
//   head_1spp_fixedguide                 the denoiser's fixed guide (no network) on 1 spp
//   head_clip_16spp                      a clipping plane through the centre (normal (1, .3, 0))
//   head_crop_16spp, head_cropfence_16spp cropping: sub-volume, and fence (non-convex)
//   head_iso_16spp                       IsoSurface blend mode: skin (-300 HU) and bone (700 HU)
//   rgba_16spp                           dependent RGBA colour data (IndependentComponents off):
//                                        colour from position, opacity channel from the
//                                        synthetic source
// The tracer is deterministic (seeded per pixel and frame), so the threshold only absorbs
// OpenGL differences; a real change of the estimator moves many pixels and fails.
#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkContourValues.h"
#include "vtkImageData.h"
#include "vtkPointData.h"
#include "vtkDataArray.h"
#include "vtkNew.h"
#include "vtkPTVExpertOptions.h"
#include "vtkPlane.h"
#include "vtkPTVTransferFunctionPreset.h"
#include "vtkPathTracedVolumeMapper.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRTAnalyticSource.h"
#include "vtkRegressionTestImage.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSphereSource.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"
#include "vtkXMLImageDataReader.h"

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <string>

namespace
{
std::string ArgAfter(int argc, char* argv[], const std::string& flag)
{
  for (int i = 1; i + 1 < argc; ++i)
  {
    if (flag == argv[i])
    {
      return argv[i + 1];
    }
  }
  return {};
}

// The last argument not belonging to a -X flag is the case name.
std::string CaseName(int argc, char* argv[])
{
  std::string name;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a.size() == 2 && a[0] == '-')
    {
      ++i;
      continue;
    }
    name = a;
  }
  return name;
}

void SyntheticTransfer(vtkVolumeProperty* property)
{
  // The paper's two bands on the wavelet's range (~37..277): outer yellow 0.7, inner white 1.0.
  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(0, 1, 1, 0);
  color->AddRGBPoint(209.9, 1, 1, 0);
  color->AddRGBPoint(210, 1, 1, 1);
  color->AddRGBPoint(300, 1, 1, 1);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0, 0);
  opacity->AddPoint(159.9, 0);
  opacity->AddPoint(160, 0.7);
  opacity->AddPoint(185, 0.7);
  opacity->AddPoint(185.1, 0);
  opacity->AddPoint(209.9, 0);
  opacity->AddPoint(210, 1);
  opacity->AddPoint(300, 1);
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
}
}

int TestPTVMapperImage(int argc, char* argv[])
{
  const std::string name = CaseName(argc, argv);
  const bool head = name.rfind("head", 0) == 0;
  const bool accumulate = name.find("256spp") != std::string::npos;
  const bool sixteen = name.find("16spp") != std::string::npos;
  // head_1spp_fixedguide is a head case too (name starts with "head").
  std::cout << "case: " << name << "\n";

  vtkNew<vtkVolumeProperty> property;
  property->SetInterpolationTypeToLinear();
  property->ShadeOn();
  vtkNew<vtkPathTracedVolumeMapper> mapper;
  mapper->ConvergeStillRendersOff(); // the baselines' sample counts, one frame per render
  vtkNew<vtkImageData> rgba; // the rgba case's input
  mapper->SetSeed(7);
  mapper->SetDenoise(name == "head_1spp_fixedguide"); // tracer images are compared undenoised
  // the fixed guide does not change when a model ships
  mapper->GetExpertOptions()->DenoiserUseNetworkOff();
  if (head)
  {
    const std::string file = ArgAfter(argc, argv, "-D") + "/head.vti";
    vtkNew<vtkXMLImageDataReader> reader;
    if (!reader->CanReadFile(file.c_str()))
    {
      std::cerr << "missing dataset " << file << " (run scripts/fetch_datasets.py)\n";
      return EXIT_FAILURE;
    }
    reader->SetFileName(file.c_str());
    mapper->SetInputConnection(reader->GetOutputPort());
    vtkNew<vtkPTVTransferFunctionPreset> presets;
    presets->SetFileName(
      (vtkPTVTransferFunctionPreset::GetDefaultPresetDirectory() + "/head.json").c_str());
    if (!presets->Load() || !presets->ApplyPreset("Head Two-Band (paper)", property))
    {
      return EXIT_FAILURE;
    }
  }
  else if (name == "rgba_16spp")
  {
    // RGB from the position, the opacity channel = the synthetic source mapped to 0..255.
    vtkNew<vtkRTAnalyticSource> source;
    source->SetWholeExtent(-24, 24, -24, 24, -24, 24);
    source->Update();
    vtkDataArray* values = source->GetOutput()->GetPointData()->GetScalars();
    rgba->SetExtent(-24, 24, -24, 24, -24, 24);
    rgba->AllocateScalars(VTK_UNSIGNED_CHAR, 4);
    auto* v = static_cast<unsigned char*>(rgba->GetScalarPointer());
    for (int k = 0; k < 49; ++k)
      for (int j = 0; j < 49; ++j)
        for (int i = 0; i < 49; ++i)
        {
          const vtkIdType id = i + 49 * (j + 49 * k);
          unsigned char* t = v + 4 * id;
          t[0] = static_cast<unsigned char>(i * 255 / 48);
          t[1] = static_cast<unsigned char>(j * 255 / 48);
          t[2] = static_cast<unsigned char>(255 - k * 255 / 48);
          const double a = (values->GetTuple1(id) - 37.0) / (277.0 - 37.0);
          t[3] = static_cast<unsigned char>(255.0 * std::min(1.0, std::max(0.0, a)));
        }
    mapper->SetInputData(rgba);
    property->IndependentComponentsOff();
    vtkNew<vtkPiecewiseFunction> opacity;
    opacity->AddPoint(0, 0.0);
    opacity->AddPoint(120, 0.0);
    opacity->AddPoint(200, 0.8);
    opacity->AddPoint(255, 0.8);
    property->SetScalarOpacity(opacity);
    property->SetScalarOpacityUnitDistance(2.0);
  }
  else
  {
    vtkNew<vtkRTAnalyticSource> source;
    source->SetWholeExtent(-24, 24, -24, 24, -24, 24);
    source->Update();
    mapper->SetInputConnection(source->GetOutputPort());
    SyntheticTransfer(property);
    property->SetScalarOpacityUnitDistance(2.0);
  }
  if (name.rfind("pass_", 0) == 0)
  {
    mapper->SetDisplayPass(name.substr(5).c_str());
  }

  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(property);
  vtkNew<vtkRenderer> renderer;
  renderer->AddVolume(volume);
  renderer->SetBackground(0.3, 0.3, 0.35); // also the environment light
  if (name == "sphere")
  {
    vtkNew<vtkSphereSource> sphere;
    sphere->SetCenter(-24, 0, 10); // half inside the volume, half outside it
    sphere->SetRadius(12);
    sphere->SetThetaResolution(48);
    sphere->SetPhiResolution(48);
    vtkNew<vtkPolyDataMapper> sphereMapper;
    sphereMapper->SetInputConnection(sphere->GetOutputPort());
    vtkNew<vtkActor> actor;
    actor->SetMapper(sphereMapper);
    actor->GetProperty()->SetColor(0.2, 0.5, 1.0);
    renderer->AddActor(actor);
  }
  vtkCamera* camera = renderer->GetActiveCamera();
  if (head)
  {
    camera->SetPosition(0, -1, 0);
    camera->SetFocalPoint(0, 0, 0);
    camera->SetViewUp(0, 0, 1);
    camera->Azimuth(30);
  }
  else
  {
    camera->Azimuth(30);
    camera->Elevation(20);
  }
  renderer->ResetCamera();

  vtkNew<vtkRenderWindow> window;
  window->SetSize(200, 200);
  window->SetMultiSamples(0);
  window->AddRenderer(renderer);
  if (name == "head_clip_16spp")
  {
    const double* b = volume->GetBounds();
    vtkNew<vtkPlane> plane;
    plane->SetOrigin((b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2);
    plane->SetNormal(1, 0.3, 0);
    mapper->AddClippingPlane(plane);
  }
  if (name.rfind("head_crop", 0) == 0)
  {
    // Planes in the image's coordinates: the central 50% on x, 60% on y and z.
    const double* b = volume->GetBounds();
    mapper->CroppingOn();
    mapper->SetCroppingRegionPlanes(b[0] + 0.25 * (b[1] - b[0]), b[0] + 0.75 * (b[1] - b[0]),
      b[2] + 0.2 * (b[3] - b[2]), b[2] + 0.8 * (b[3] - b[2]), b[4] + 0.2 * (b[5] - b[4]),
      b[4] + 0.8 * (b[5] - b[4]));
    if (name == "head_cropfence_16spp")
    {
      mapper->SetCroppingRegionFlagsToFence();
    }
    else
    {
      mapper->SetCroppingRegionFlagsToSubVolume();
    }
  }
  if (name == "head_iso_16spp")
  {
    mapper->SetBlendModeToIsoSurface();
    property->GetIsoSurfaceValues()->SetValue(0, -300.0);
    property->GetIsoSurfaceValues()->SetValue(1, 700.0);
  }
  const int frames = accumulate ? 256 : (sixteen ? 16 : 1);
  mapper->GetExpertOptions()->SetMaximumAccumulatedFrames(frames);
  for (int i = 0; i < frames; ++i)
  {
    window->Render();
  }
  if (mapper->GetAccumulatedFrames() != frames)
  {
    std::cerr << "expected " << frames << " accumulated frames, got "
              << mapper->GetAccumulatedFrames() << "\n";
    return EXIT_FAILURE;
  }
  const int result = vtkRegressionTestImageThreshold(window, 0.05);
  return result == vtkRegressionTester::PASSED ? EXIT_SUCCESS : EXIT_FAILURE;
}
