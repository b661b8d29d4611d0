// vtkPathTracedVolumeMapper behaviour, without baselines:
//  - accumulation counts frames, stops at MaximumAccumulatedFrames, resets on camera, transfer
//    function, light, size and setting changes, and not on DisplayPass changes;
//  - every pass is readable as a float vtkImageData with finite values of the right shape;
//  - images are bit-identical with 1 and 2 threads, and with and without empty-space skipping;
//  - bad input (NaN voxels, empty volume, one voxel, multi-component scalars, camera inside the
//    volume, zero-size viewport) gives the documented error or behaviour and never crashes;
//  - clipping planes and cropping cut the volume (kept side, restarts, bad planes reported and
//    ignored); the intensity projections render without a warning, Slice gives exactly one
//    warning naming it;
//  - IsoSurface draws the property's iso values (restarts, skipping exact, bad values warned,
//    the iso-10 sphere of a distance field at the right depth);
//  - dependent colour data (IndependentComponents off: RGB + opacity, colour value + opacity)
//    gives the data's colours; 3 components or independent components are errors.
#include "ptvTestCheck.h"
#include "ptvTestScene.h"
#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkCommand.h"
#include "vtkContourValues.h"
#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkLight.h"
#include "vtkPlane.h"
#include "vtkNew.h"
#include "vtkPTVExpertOptions.h"
#include "vtkPTVRenderStatistics.h"
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
#include "vtkWindowToImageFilter.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace
{

/// The analytic scene, tracer only (Denoise off: TestDenoise turns it on), one frame per render
/// (TestPTVStillRender tests still renders).
struct Scene : AnalyticScene
{
  explicit Scene(int size = 64)
    : AnalyticScene(size)
  {
    this->Mapper->DenoiseOff();
    this->Mapper->ConvergeStillRendersOff();
  }
};

bool AllFinite(const std::vector<float>& v)
{
  for (float x : v)
  {
    if (!std::isfinite(x))
    {
      return false;
    }
  }
  return !v.empty();
}

void TestAccumulation()
{
  Scene s;
  s.Mapper->GetExpertOptions()->SetMaximumAccumulatedFrames(3);
  s.Window->Render();
  Check(s.Mapper->GetAccumulatedFrames() == 1 && s.Mapper->GetLastRenderTraced(), "first frame");
  s.Window->Render();
  s.Window->Render();
  Check(s.Mapper->GetAccumulatedFrames() == 3, "three frames accumulate");
  s.Window->Render();
  Check(s.Mapper->GetAccumulatedFrames() == 3 && !s.Mapper->GetLastRenderTraced(),
    "no tracing past MaximumAccumulatedFrames");
  s.Mapper->SetDisplayPass("Normal");
  s.Window->Render();
  Check(s.Mapper->GetAccumulatedFrames() == 3, "DisplayPass change keeps the accumulation");
  s.Mapper->SetDisplayPass(nullptr);
  s.Mapper->GetExpertOptions()->SetMaximumAccumulatedFrames(100);
  s.Window->Render();
  vtkNew<vtkWindowToImageFilter> grab; // re-renders; VTK nudges the view angle by ~1e-8
  grab->SetInput(s.Window);
  grab->Update();
  s.Window->Render();
  Check(s.Mapper->GetAccumulatedFrames() == 6, "a window grab keeps the accumulation");

  s.Renderer->GetActiveCamera()->Azimuth(1);
  s.Window->Render();
  Check(s.Mapper->GetAccumulatedFrames() == 1, "camera change resets");
  s.Window->Render();
  s.Opacity->AddPoint(200, 0.5);
  s.Window->Render();
  Check(s.Mapper->GetAccumulatedFrames() == 1, "opacity function change resets");
  s.Window->Render();
  s.Color->AddRGBPoint(100, 1, 0, 0);
  s.Window->Render();
  Check(s.Mapper->GetAccumulatedFrames() == 1, "colour function change resets");
  s.Window->Render();
  s.Mapper->SetSeed(3);
  s.Window->Render();
  Check(s.Mapper->GetAccumulatedFrames() == 1, "seed change resets");
  s.Window->Render();
  s.Window->SetSize(70, 64);
  s.Window->Render();
  Check(s.Mapper->GetAccumulatedFrames() == 1, "viewport size change resets");
  s.Window->Render();
  vtkNew<vtkLight> light;
  light->SetPositional(true);
  light->SetPosition(0, 0, 100);
  s.Renderer->AddLight(light);
  s.Window->Render();
  Check(s.Mapper->GetAccumulatedFrames() == 1, "adding a scene light resets");
  s.Window->Render();
  light->SetPosition(0, 100, 0);
  s.Window->Render();
  Check(s.Mapper->GetAccumulatedFrames() == 1, "moving the light resets");
  s.Window->Render();
  s.Source->SetMaximum(300);
  s.Window->Render();
  Check(s.Mapper->GetAccumulatedFrames() == 1, "volume change resets");
  s.Property->SetInterpolationTypeToLinear(); // VTK's default is nearest
  s.Window->Render();
  Check(s.Mapper->GetAccumulatedFrames() == 1, "interpolation change resets (to linear)");
  const std::vector<float> linear = s.Pass("Radiance");
  s.Property->SetInterpolationTypeToNearest();
  s.Window->Render();
  Check(s.Mapper->GetAccumulatedFrames() == 1, "interpolation change resets");
  Check(s.Pass("Radiance") != linear, "nearest interpolation changes the image");
}

void TestPasses()
{
  Scene s(48);
  vtkNew<vtkTest::ErrorObserver> errors;
  s.Mapper->AddObserver(vtkCommand::ErrorEvent, errors);
  vtkNew<vtkImageData> image;
  Check(!s.Mapper->GetPass("Radiance", image), "no pass before the first render");
  s.Window->Render();
  Check(vtkPathTracedVolumeMapper::GetNumberOfPasses() == 18,
    "11 traced + 4 denoiser passes + HistoryLength + DenoisedAlpha + SampleRatio");
  // The scatter passes are kept only when asked for: an error that says how, and GetPasses
  // leaves them out.
  Check(!s.Mapper->GetPass("ScatterNormal", image), "ScatterNormal is not kept by default");
  Check(errors->CheckErrorMessage("ScatterPasses") == 0, "the error names ScatterPasses");
  vtkNew<vtkImageData> all;
  Check(s.Mapper->GetPasses(all) && all->GetPointData()->GetArray("Normal") &&
      !all->GetPointData()->GetArray("ScatterNormal") &&
      !all->GetPointData()->GetArray("ScatterDepth"),
    "GetPasses has Normal but not the scatter passes by default");
  s.Mapper->SetDisplayPass("ScatterDepth");
  s.Window->Render();
  Check(s.Mapper->GetPass("ScatterDepth", image) && s.Mapper->GetAccumulatedFrames() == 1,
    "DisplayPass ScatterDepth keeps the scatter passes (and starts again)");
  s.Mapper->SetDisplayPass(nullptr);
  s.Mapper->GetExpertOptions()->ScatterPassesOn();
  s.Window->Render();
  for (int i = 0; i < 10; ++i)
  {
    const char* name = vtkPathTracedVolumeMapper::GetPassName(i);
    Check(s.Mapper->GetPass(name, image), std::string("pass ") + name);
    vtkDataArray* a = image->GetPointData()->GetScalars();
    const int comps = a ? a->GetNumberOfComponents() : 0;
    Check(a && std::strcmp(a->GetName(), name) == 0 && a->GetNumberOfTuples() == 48 * 48 &&
        (comps == 1 || comps == 3),
      std::string("pass ") + name + " shape");
    Check(AllFinite(s.Pass(name)), std::string("pass ") + name + " finite");
  }
  Check(vtkPathTracedVolumeMapper::GetPassName(99) == nullptr, "out-of-range pass name");
  Check(!s.Mapper->GetPass("Denoised", image), "no Denoised pass with Denoise off");
  Check(errors->CheckErrorMessage("Denoise on") == 0, "the error says to turn Denoise on");
  Check(!s.Mapper->GetPass("Nope", image), "unknown pass is an error");
  Check(errors->CheckErrorMessage("'Nope'") == 0, "error names the unknown pass");
  const auto alpha = s.Pass("Alpha");
  float covered = 0;
  for (float a : alpha)
  {
    covered += a;
  }
  Check(covered > 0.05f * alpha.size() && covered < 0.95f * alpha.size(),
    "the volume covers part of the view");
}

void TestDenoise()
{
  Scene s(48);
  s.Mapper->DenoiseOn();
  s.Mapper->GetExpertOptions()->DenoiserUseNetworkOff(); // deterministic and model-independent
  s.Mapper->GetExpertOptions()->SetMaximumAccumulatedFrames(2);
  s.Window->Render();
  Check(s.Mapper->GetStatistics()->GetLastDenoiseTime() > 0.0, "a traced frame is denoised");
  Check(std::string(s.Mapper->GetDenoiserStatus()).find("fixed guide") == 0,
    "status names the fixed guide");
  const auto denoised = s.Pass("Denoised");
  const auto guides = s.Pass("Guides");
  const auto weights = s.Pass("BlendWeights");
  Check(denoised.size() == 48 * 48 * 3 && AllFinite(denoised), "Denoised pass, finite");
  Check(guides.size() == 48 * 48 * 3 && AllFinite(guides), "Guides pass, finite");
  Check(weights.size() == 48 * 48 * 2 && AllFinite(weights), "BlendWeights pass, finite");
  Check(denoised != s.Pass("Radiance"), "denoising changes the image");
  s.Window->Render();
  s.Window->Render(); // accumulation limit reached: neither traced nor denoised again
  Check(!s.Mapper->GetLastRenderTraced() && s.Mapper->GetStatistics()->GetLastDenoiseTime() == 0.0,
    "nothing new, nothing denoised");
  s.Mapper->GetExpertOptions()->SetDenoiserNumberOfLevels(1);
  s.Window->Render();
  Check(s.Mapper->GetStatistics()->GetLastDenoiseTime() > 0.0 && s.Mapper->GetAccumulatedFrames() == 2,
    "a denoiser setting re-denoises without restarting the accumulation");

  // A missing model: the fixed guide takes over with one warning.
  Scene t(32);
  t.Mapper->DenoiseOn();
  t.Mapper->SetDenoiserModelFile("/nonexistent/guidenet.onnx");
  vtkNew<vtkTest::ErrorObserver> obs;
  t.Mapper->AddObserver(vtkCommand::WarningEvent, obs);
  t.Window->Render();
  Check(obs->CheckWarningMessage("/nonexistent/guidenet.onnx") == 0, "missing model warns");
  Check(AllFinite(t.Pass("Denoised")), "missing model still denoises (fixed guide)");
}

void TestDeterminism()
{
  std::vector<float> one, two, noSkip;
  {
    Scene s;
    s.Mapper->SetNumberOfThreads(1);
    s.Window->Render();
    one = s.Pass("Radiance");
  }
  {
    Scene s;
    s.Mapper->SetNumberOfThreads(2);
    s.Window->Render();
    two = s.Pass("Radiance");
    // does not change the image, so it keeps accumulating:
    s.Mapper->GetExpertOptions()->EmptySpaceSkippingOff();
    s.Mapper->ResetAccumulation();      // start again to compare frame 0 with frame 0
    s.Window->Render();
    noSkip = s.Pass("Radiance");
  }
  Check(!one.empty() && one == two, "bit-identical with 1 and 2 threads");
  Check(two == noSkip, "bit-identical with and without empty-space skipping");
}

void TestBadInput()
{
  // NaN voxels: rendered transparent with one warning.
  {
    Scene s(32);
    vtkNew<vtkImageData> image;
    s.Source->Update();
    image->DeepCopy(s.Source->GetOutput());
    vtkDataArray* a = image->GetPointData()->GetScalars();
    for (vtkIdType i = 0; i < a->GetNumberOfTuples(); i += 7)
    {
      a->SetTuple1(i, std::numeric_limits<double>::quiet_NaN());
    }
    s.Mapper->SetInputData(image);
    vtkNew<vtkTest::ErrorObserver> obs;
    s.Mapper->AddObserver(vtkCommand::WarningEvent, obs);
    s.Window->Render();
    Check(obs->CheckWarningMessage("NaN or infinite") == 0, "NaN voxels warn");
    Check(AllFinite(s.Pass("Radiance")), "NaN voxels give a finite image");
  }
  // Empty volume: an error naming the dimensions.
  {
    Scene s(32);
    vtkNew<vtkImageData> empty;
    s.Mapper->SetInputData(empty);
    vtkNew<vtkTest::ErrorObserver> obs;
    s.Mapper->AddObserver(vtkCommand::ErrorEvent, obs);
    s.Window->Render();
    Check(obs->CheckErrorMessage("empty volume") == 0, "empty volume is an error");
    Check(s.Mapper->GetAccumulatedFrames() == 0, "nothing traced for an empty volume");
  }
  // One voxel: renders nothing (a zero-thickness box), no error.
  {
    Scene s(32);
    vtkNew<vtkImageData> one;
    one->SetDimensions(1, 1, 1);
    one->AllocateScalars(VTK_FLOAT, 1);
    one->GetPointData()->GetScalars()->SetTuple1(0, 250);
    s.Mapper->SetInputData(one);
    s.Window->Render();
    const auto alpha = s.Pass("Alpha");
    Check(AllFinite(alpha), "one voxel renders without error");
  }
  // Multi-component scalars: an error naming the component count.
  {
    Scene s(32);
    vtkNew<vtkImageData> rgb;
    rgb->SetDimensions(4, 4, 4);
    rgb->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
    s.Mapper->SetInputData(rgb);
    vtkNew<vtkTest::ErrorObserver> obs;
    s.Mapper->AddObserver(vtkCommand::ErrorEvent, obs);
    s.Window->Render();
    Check(obs->CheckErrorMessage("3 components") == 0, "multi-component scalars are an error");
  }
  // Camera inside the volume: finite output, something visible.
  {
    Scene s(32);
    s.Renderer->GetActiveCamera()->SetPosition(0, 0, 0);
    s.Renderer->GetActiveCamera()->SetFocalPoint(0, 0, 10);
    s.Renderer->ResetCameraClippingRange();
    s.Window->Render();
    Check(AllFinite(s.Pass("Radiance")), "camera inside the volume gives a finite image");
  }
  // Zero-size viewport: no frame, no error, no crash.
  {
    Scene s(32);
    s.Renderer->SetViewport(0.5, 0.5, 0.5, 0.5);
    s.Window->Render();
    Check(s.Mapper->GetAccumulatedFrames() == 0, "zero-size viewport traces nothing");
  }
}
}

// Covered pixels (Alpha > 0) and their mean column.
std::pair<int, double> Coverage(Scene& s, int width)
{
  const auto alpha = s.Pass("Alpha");
  int n = 0;
  double x = 0.0;
  for (std::size_t i = 0; i < alpha.size(); ++i)
  {
    if (alpha[i] > 0.f)
    {
      ++n;
      x += static_cast<double>(i % width);
    }
  }
  return { n, n ? x / n : 0.0 };
}

void TestClippingCropping()
{
  Scene s(48);
  s.Window->Render(); // coverage is compared on first frames (same seed, same random numbers)
  const auto full = Coverage(s, 48);
  const auto fullRadiance = s.Pass("Radiance");

  // A plane through the centre keeps the side its normal points to.
  vtkNew<vtkPlane> plane;
  plane->SetOrigin(0, 0, 0);
  plane->SetNormal(1, 0, 0);
  s.Mapper->AddClippingPlane(plane);
  s.Window->Render();
  Check(s.Mapper->GetAccumulatedFrames() == 1, "adding a clipping plane restarts");
  const auto cut = Coverage(s, 48);
  Check(cut.first > 0 && cut.first < 0.8 * full.first, "the plane removes part of the volume");
  Check(cut.second > full.second + 2.0, "the kept part is on the normal's side (+x: right)");
  s.Window->Render();
  Check(s.Mapper->GetAccumulatedFrames() == 2, "an unchanged plane accumulates");
  plane->SetOrigin(3, 0, 0);
  s.Window->Render();
  Check(s.Mapper->GetAccumulatedFrames() == 1, "moving the plane restarts");
  plane->SetNormal(-1, 0, 0);
  plane->SetOrigin(-1000, 0, 0); // keeps x <= -1000: nothing
  s.Window->Render();
  Check(Coverage(s, 48).first == 0, "a plane keeping nothing shows nothing");
  s.Mapper->RemoveAllClippingPlanes();
  s.Window->Render();
  Check(s.Pass("Radiance") == fullRadiance, "removing the plane gives the unclipped image again");

  // A degenerate plane is reported once and ignored; a seventh plane is reported.
  vtkNew<vtkTest::ErrorObserver> obs;
  s.Mapper->AddObserver(vtkCommand::ErrorEvent, obs);
  vtkNew<vtkPlane> flat;
  flat->SetNormal(0, 0, 0);
  s.Mapper->AddClippingPlane(flat);
  s.Mapper->ResetAccumulation(); // an ignored plane changes nothing, so it would accumulate
  s.Window->Render();
  Check(obs->CheckErrorMessage("clipping plane 0 has normal (0, 0, 0)") == 0,
    "a zero normal is an error naming the plane");
  Check(Coverage(s, 48).first == full.first, "the degenerate plane is ignored");
  obs->Clear();
  s.Window->Render();
  Check(!obs->GetError(), "the same problem is not reported again");
  s.Mapper->RemoveAllClippingPlanes();
  for (int i = 0; i < 7; ++i)
  {
    vtkNew<vtkPlane> p;
    p->SetOrigin(-1000, 0, 0);
    p->SetNormal(1, 0, 0); // keeps everything
    s.Mapper->AddClippingPlane(p);
  }
  s.Window->Render();
  Check(obs->CheckErrorMessage("7 clipping planes; only the first 6") == 0, "the 6-plane limit");
  s.Mapper->RemoveAllClippingPlanes();

  // Cropping: the sub-volume keeps the centre box, flags 0 keep nothing, NaN planes are refused.
  s.Mapper->CroppingOn();
  s.Mapper->SetCroppingRegionPlanes(-8, 8, -8, 8, -8, 8);
  s.Mapper->SetCroppingRegionFlagsToSubVolume();
  s.Window->Render();
  Check(s.Mapper->GetAccumulatedFrames() == 1, "cropping restarts");
  const auto box = Coverage(s, 48);
  Check(box.first > 0 && box.first < 0.7 * full.first, "the sub-volume is smaller");
  s.Mapper->SetCroppingRegionFlags(0);
  s.Window->Render();
  Check(Coverage(s, 48).first == 0, "no region kept, nothing shown");
  s.Mapper->SetCroppingRegionFlagsToInvertedCross();
  s.Window->Render();
  const auto cross = Coverage(s, 48);
  Check(cross.first > 0 && cross.first < full.first, "the inverted cross keeps part");
  obs->Clear();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  s.Mapper->SetCroppingRegionPlanes(nan, 8, -8, 8, -8, 8);
  s.Window->Render();
  Check(obs->CheckErrorMessage("are not finite; cropping is off") == 0, "NaN crop planes");
  Check(Coverage(s, 48).first == full.first, "with cropping refused the whole volume shows");
}

void TestBlendModes()
{
  Scene s(32);
  vtkNew<vtkTest::ErrorObserver> obs;
  s.Mapper->AddObserver(vtkCommand::WarningEvent, obs);
  s.Window->Render();
  Check(!obs->GetWarning(), "Composite: no warning");
  // The intensity projections are ray cast (test_blend_modes.py compares their images).
  for (int projection = 1; projection <= 4; ++projection)
  {
    obs->Clear();
    s.Mapper->SetBlendMode(projection);
    s.Window->Render();
    Check(!obs->GetWarning() && s.Mapper->GetAccumulatedFrames() >= 1,
      "BlendMode " + std::to_string(projection) + ": no warning, traced");
  }
  const std::pair<int, const char*> modes[] = { { 6, "Slice" } };
  for (const auto& mode : modes)
  {
    obs->Clear();
    s.Mapper->SetBlendMode(mode.first);
    s.Window->Render();
    s.Window->Render();
    const std::string text = obs->GetWarningMessage();
    const std::string want = std::string("BlendMode ") + mode.second;
    const std::size_t first = text.find("BlendMode ");
    Check(first != std::string::npos && text.find("BlendMode ", first + 1) == std::string::npos &&
        text.find(want) == first,
      std::string("one warning naming ") + mode.second + " (got: " + text + ")");
  }
  obs->Clear();
  s.Mapper->SetBlendModeToComposite();
  s.Window->Render();
  Check(!obs->GetWarning(), "back to Composite: no warning");
}

void TestIsosurface()
{
  // The RT source spans ~37..277: an iso value of 200 is a closed surface around the centre.
  Scene s(48);
  s.Window->Render();
  const auto composite = s.Pass("Radiance");
  vtkNew<vtkTest::ErrorObserver> obs;
  s.Mapper->AddObserver(vtkCommand::WarningEvent, obs);
  s.Mapper->SetBlendModeToIsoSurface();
  s.Property->GetIsoSurfaceValues()->SetValue(0, 200.0);
  s.Window->Render();
  Check(!obs->GetWarning(), "IsoSurface with a value: no warning");
  Check(s.Mapper->GetAccumulatedFrames() == 1, "the blend mode restarts the accumulation");
  const auto iso = Coverage(s, 48);
  Check(iso.first > 48 * 48 / 20 && s.Pass("Radiance") != composite,
    "the isosurface is drawn and differs from the composite image");
  s.Property->GetIsoSurfaceValues()->SetValue(0, 250.0);
  s.Window->Render();
  Check(s.Mapper->GetAccumulatedFrames() == 1, "a new iso value restarts");
  const auto inner = Coverage(s, 48);
  Check(inner.first > 0 && inner.first < iso.first, "a higher value is a smaller surface");

  // Bit-identical with and without empty-space skipping (the occupancy follows the iso values).
  s.Property->GetIsoSurfaceValues()->SetValue(1, 180.0);
  s.Window->Render();
  const auto skipped = s.Pass("Radiance");
  s.Mapper->GetExpertOptions()->EmptySpaceSkippingOff();
  s.Mapper->ResetAccumulation(); // skipping does not sign the accumulation: compare first frames
  s.Window->Render();
  Check(s.Pass("Radiance") == skipped, "isosurfaces: skipping does not change the image");
  s.Mapper->GetExpertOptions()->EmptySpaceSkippingOn();

  // Bad iso values: NaN is ignored with one warning; no values draws nothing, one warning.
  obs->Clear();
  s.Property->GetIsoSurfaceValues()->SetNumberOfContours(1);
  s.Property->GetIsoSurfaceValues()->SetValue(0, std::numeric_limits<double>::quiet_NaN());
  s.Window->Render();
  s.Window->Render();
  Check(obs->CheckWarningMessage("iso value 0 is nan; it is ignored") == 0, "NaN iso value");
  Check(Coverage(s, 48).first == 0, "only a NaN value: nothing drawn");
  obs->Clear();
  s.Property->GetIsoSurfaceValues()->SetNumberOfContours(0);
  s.Window->Render();
  Check(obs->CheckWarningMessage("without iso values draws nothing") == 0, "no iso values");
  s.Mapper->SetBlendModeToComposite();
  s.Window->Render();
  Check(s.Pass("Radiance") == composite, "back to Composite: the composite image again");

  // Geometry: a distance field (value = distance to the centre) with iso value 10 is a sphere of
  // radius 10; a narrow perspective camera on the +z axis, 50 from the centre, sees the centre
  // pixel's first hit at depth 40 (its jitter moves the ray < 0.11 off the axis: < 0.001). Linear interpolation of the distance field between samples and
  // trilinear interpolation inside cells are accurate to ~0.05 voxel along this axis.
  vtkNew<vtkImageData> field;
  field->SetDimensions(33, 33, 33);
  field->AllocateScalars(VTK_FLOAT, 1);
  float* f = static_cast<float*>(field->GetScalarPointer());
  for (int k = 0; k < 33; ++k)
    for (int j = 0; j < 33; ++j)
      for (int i = 0; i < 33; ++i)
        f[i + 33 * (j + 33 * k)] =
          static_cast<float>(std::sqrt((i - 16.0) * (i - 16.0) + (j - 16.0) * (j - 16.0) +
            (k - 16.0) * (k - 16.0)));
  Scene d(33); // odd size: one pixel on the axis
  d.Mapper->SetInputData(field);
  d.Opacity->RemoveAllPoints();
  d.Opacity->AddPoint(0, 1.0);
  d.Opacity->AddPoint(30, 1.0);
  d.Property->SetInterpolationTypeToLinear(); // (VTK's default is nearest: a staircase)
  d.Mapper->SetBlendModeToIsoSurface();
  d.Property->GetIsoSurfaceValues()->SetValue(0, 10.0);
  vtkCamera* camera = d.Renderer->GetActiveCamera();
  camera->SetFocalPoint(16, 16, 16);
  camera->SetPosition(16, 16, 66);
  camera->SetViewUp(0, 1, 0);
  camera->SetViewAngle(10);
  d.Renderer->ResetCameraClippingRange();
  d.Window->Render();
  const auto depth = d.Pass("Depth");
  const float centre = depth[16 * 33 + 16];
  std::cout << "isosurface sphere: centre depth " << centre << " (expected 40)\n";
  Check(std::fabs(centre - 40.f) < 0.1f, "the iso-10 sphere of a distance field is at depth 40");
}

// A 24^3 ball of colour data: last component = opacity channel (255 inside radius 9, else 0),
// colour from x (red ramp, 4 components) or the colour channel = x (2 components).
vtkSmartPointer<vtkImageData> ColourBall(int comps)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(24, 24, 24);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, comps);
  auto* v = static_cast<unsigned char*>(image->GetScalarPointer());
  for (int k = 0; k < 24; ++k)
    for (int j = 0; j < 24; ++j)
      for (int i = 0; i < 24; ++i)
      {
        unsigned char* t = v + comps * (i + 24 * (j + 24 * k));
        const double r2 = (i - 11.5) * (i - 11.5) + (j - 11.5) * (j - 11.5) + (k - 11.5) * (k - 11.5);
        const unsigned char red = static_cast<unsigned char>(i * 255 / 23);
        if (comps == 4)
        {
          t[0] = red;
          t[1] = 40;
          t[2] = static_cast<unsigned char>(255 - red);
        }
        else
        {
          t[0] = static_cast<unsigned char>(i);
        }
        t[comps - 1] = r2 < 81.0 ? 255 : 0;
      }
  return image;
}

void TestColourVolumes()
{
  for (int comps : { 4, 2 })
  {
    Scene s(48);
    s.Mapper->SetInputData(ColourBall(comps));
    s.Property->IndependentComponentsOff();
    s.Property->SetInterpolationTypeToLinear();
    s.Opacity->RemoveAllPoints();
    s.Opacity->AddPoint(0, 0.0);
    s.Opacity->AddPoint(100, 0.0);
    s.Opacity->AddPoint(200, 1.0);
    s.Color->RemoveAllPoints(); // 2 components: blue at x = 0 to red at x = 23
    s.Color->AddRGBPoint(0, 0.0, 0.16, 1.0);
    s.Color->AddRGBPoint(23, 1.0, 0.16, 0.0);
    s.Renderer->GetActiveCamera()->SetPosition(11.5, 11.5, 80);
    s.Renderer->GetActiveCamera()->SetFocalPoint(11.5, 11.5, 11.5);
    s.Renderer->GetActiveCamera()->SetViewUp(0, 1, 0);
    s.Renderer->ResetCamera();
    vtkNew<vtkTest::ErrorObserver> obs;
    s.Mapper->AddObserver(vtkCommand::ErrorEvent, obs);
    s.Window->Render();
    Check(!obs->GetError(), std::to_string(comps) + "-component colour data renders");
    const auto albedo = s.Pass("Albedo");
    const auto depth = s.Pass("Depth");
    double left = 0, right = 0, green = 0;
    int nl = 0, nr = 0;
    for (int y = 0; y < 48; ++y)
      for (int x = 0; x < 48; ++x)
      {
        const int i = y * 48 + x;
        if (albedo.empty() || !(depth[i] < 1e6f) || (albedo[3 * i] == 0 && albedo[3 * i + 2] == 0))
          continue;
        (x < 24 ? left : right) += albedo[3 * i];
        (x < 24 ? nl : nr) += 1;
        green += albedo[3 * i + 1];
      }
    std::cout << comps << " components: mean red left " << left / std::max(nl, 1) << ", right "
              << right / std::max(nr, 1) << ", green " << green / std::max(nl + nr, 1) << "\n";
    Check(nl > 20 && nr > 20 && right / nr > left / nl + 0.3,
      std::to_string(comps) + " components: the colour follows the data (red grows with x)");
    Check(std::fabs(green / (nl + nr) - 40.0 / 255.0) < 0.02 ||
        std::fabs(green / (nl + nr) - 0.16) < 0.02,
      std::to_string(comps) + " components: green is the data's / the colour function's");
  }
  // 3 dependent components, or colour data with IndependentComponents on: errors.
  for (bool dependent : { true, false })
  {
    Scene s(32);
    s.Mapper->SetInputData(ColourBall(dependent ? 4 : 4));
    if (!dependent)
    {
      s.Property->IndependentComponentsOn();
    }
    else
    {
      auto three = vtkSmartPointer<vtkImageData>::New();
      three->SetDimensions(4, 4, 4);
      three->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
      s.Mapper->SetInputData(three);
      s.Property->IndependentComponentsOff();
    }
    vtkNew<vtkTest::ErrorObserver> obs;
    s.Mapper->AddObserver(vtkCommand::ErrorEvent, obs);
    s.Window->Render();
    Check(obs->CheckErrorMessage(dependent ? "has 3 components" : "IndependentComponents is on") ==
        0,
      dependent ? "3 dependent components: error" : "independent colour data: error");
  }
}

int TestPTVMapperBehavior(int, char*[])
{
  TestAccumulation();
  TestPasses();
  TestDenoise();
  TestDeterminism();
  TestBadInput();
  TestClippingCropping();
  TestBlendModes();
  TestIsosurface();
  TestColourVolumes();
  return TestResult();
}
