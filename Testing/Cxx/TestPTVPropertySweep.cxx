// Issue #59: random values, in and out of range, for every public property of
// vtkPathTracedVolumeMapper, on a few volumes (tiny, flat, offset, anisotropic), 64 x 64 renders.
// Run under AddressSanitizer + UndefinedBehaviorSanitizer by scripts/sanitize.sh (label cxx).
//  - every range-checked setter (EnvironmentColor per component): a value inside its range is
//    kept silently; one outside is clamped with exactly one warning; NaN keeps the current value
//    with one warning;
//  - random settings of every property, still and interactive renders: no crash, no render
//    past its bounds (frames <= MaximumStillFrames and MaximumAccumulatedFrames, one frame when
//    interactive, time within StillTimeBudget plus one frame's slack), every pass it gives is
//    finite, and a problem is reported once: rendering again unchanged reports nothing new.
#include "ptvTestCheck.h"
#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkCommand.h"
#include "vtkContourValues.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPTVExpertOptions.h"
#include "vtkPTVRenderStatistics.h"
#include "vtkPathTracedVolumeMapper.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkTimerLog.h"
#include "vtkUnsignedCharArray.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <functional>
#include <iostream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace
{
using Mapper = vtkPathTracedVolumeMapper;

/// Warnings and errors the mapper reported.
struct Reports
{
  std::vector<std::string> Texts;
  vtkNew<vtkCallbackCommand> Observer;

  explicit Reports(Mapper* mapper)
  {
    this->Observer->SetClientData(&this->Texts);
    this->Observer->SetCallback(
      [](vtkObject*, unsigned long, void* client, void* text)
      { static_cast<std::vector<std::string>*>(client)->emplace_back(static_cast<char*>(text)); });
    for (vtkObject* o : { static_cast<vtkObject*>(mapper),
           static_cast<vtkObject*>(mapper->GetExpertOptions()) })
    {
      o->AddObserver(vtkCommand::WarningEvent, this->Observer);
      o->AddObserver(vtkCommand::ErrorEvent, this->Observer);
    }
  }
  std::size_t Count() const { return this->Texts.size(); }
};

/// One range-checked numeric property: its documented range and accessors.
struct Numeric
{
  const char* Name;
  double Lo;
  double Hi;
  bool Integer;
  std::function<void(Mapper*, double)> Set;
  std::function<double(Mapper*)> Get;
};

#define PTV_INT_PROPERTY(name, lo, hi)                                                            \
  Numeric                                                                                        \
  {                                                                                              \
    #name, lo, hi, true, [](Mapper* m, double v) { m->Set##name(static_cast<int>(v)); },         \
      [](Mapper* m) { return static_cast<double>(m->Get##name()); }                              \
  }
#define PTV_DOUBLE_PROPERTY(name, lo, hi)                                                         \
  Numeric                                                                                        \
  {                                                                                              \
    #name, lo, hi, false, [](Mapper* m, double v) { m->Set##name(v); },                          \
      [](Mapper* m) { return m->Get##name(); }                                                   \
  }
#define PTV_INT_OPTION(name, lo, hi)                                                              \
  Numeric                                                                                        \
  {                                                                                              \
    #name, lo, hi, true,                                                                         \
      [](Mapper* m, double v) { m->GetExpertOptions()->Set##name(static_cast<int>(v)); },        \
      [](Mapper* m) { return static_cast<double>(m->GetExpertOptions()->Get##name()); }          \
  }
#define PTV_DOUBLE_OPTION(name, lo, hi)                                                           \
  Numeric                                                                                        \
  {                                                                                              \
    #name, lo, hi, false, [](Mapper* m, double v) { m->GetExpertOptions()->Set##name(v); },      \
      [](Mapper* m) { return m->GetExpertOptions()->Get##name(); }                               \
  }

const std::vector<Numeric>& NumericProperties()
{
  static const std::vector<Numeric> properties = {
    PTV_INT_PROPERTY(SamplesPerFrame, 1, 4096),
    PTV_INT_OPTION(MaximumAccumulatedFrames, 1, 1000000),
    PTV_INT_OPTION(MaximumHistory, 1, 1000000),
    PTV_DOUBLE_PROPERTY(StillQuality, 10.0, 100.0),
    PTV_INT_OPTION(MaximumStillFrames, 1, 1000000),
    PTV_DOUBLE_PROPERTY(StillTimeBudget, 0.0, 1e6),
    PTV_INT_OPTION(EdgeSamples, 1, 64),
    PTV_DOUBLE_OPTION(AmbientOcclusionReach, 0.0, 1.0),
    PTV_DOUBLE_PROPERTY(LightIntensity, 0.0, 1e6),
    PTV_DOUBLE_PROPERTY(EnvironmentIntensity, 0.0, 1e6),
    PTV_INT_OPTION(DenoiserNumberOfLevels, 0, 3),
    PTV_INT_PROPERTY(NumberOfThreads, 0, 1024),
    PTV_INT_PROPERTY(Backend, Mapper::BACKEND_AUTO, Mapper::BACKEND_CUDA),
  };
  return properties;
}

/// A value for @a p: inside its range, at an end, just outside, far outside, or NaN.
double Draw(const Numeric& p, std::mt19937& rng)
{
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double span = p.Hi - p.Lo;
  std::vector<double> choices = { p.Lo, p.Hi, p.Lo + unit(rng) * span, p.Lo - 1.0, p.Hi + 1.0,
    p.Lo - 1e6 * unit(rng) - 1.0, p.Hi * (2.0 + 10.0 * unit(rng)) + 1.0 };
  if (p.Integer)
  {
    choices.push_back(INT_MIN);
    choices.push_back(INT_MAX);
  }
  else
  {
    choices.push_back(std::numeric_limits<double>::quiet_NaN());
    choices.push_back(std::numeric_limits<double>::infinity());
    choices.push_back(-std::numeric_limits<double>::infinity());
  }
  double v = choices[std::uniform_int_distribution<std::size_t>(0, choices.size() - 1)(rng)];
  return p.Integer ? std::floor(v) : v;
}

/// Setting a range-checked property: kept inside the range, clamped with one warning outside,
/// NaN keeps the value with one warning.
void TestSetters(std::mt19937& rng)
{
  vtkNew<Mapper> mapper;
  Reports reports(mapper);
  for (const Numeric& p : NumericProperties())
  {
    for (int trial = 0; trial < 40; ++trial)
    {
      const double value = Draw(p, rng);
      const double before = p.Get(mapper);
      const std::size_t seen = reports.Count();
      p.Set(mapper, value);
      const double after = p.Get(mapper);
      const bool rejected = std::isnan(value) || value < p.Lo || value > p.Hi;
      const double expected =
        std::isnan(value) ? before : std::min(p.Hi, std::max(p.Lo, value));
      std::ostringstream what;
      what << "Set" << p.Name << "(" << value << "): got " << after << ", expected " << expected
           << ", " << reports.Count() - seen << " warnings";
      Check(after == expected && reports.Count() - seen == (rejected ? 1u : 0u), what.str());
      if (rejected && reports.Count() > seen)
      {
        Check(reports.Texts.back().find(std::string("Set") + p.Name) != std::string::npos,
          "the warning names the setter: " + reports.Texts.back());
      }
    }
  }
  // The colour: each component in [0, 1]; one warning per rejected component.
  mapper->GetExpertOptions()->SetEnvironmentColor(0.25, 0.5, 0.75);
  const std::size_t seen = reports.Count();
  mapper->GetExpertOptions()->SetEnvironmentColor(-1.0, std::numeric_limits<double>::quiet_NaN(),
    std::numeric_limits<double>::infinity());
  const double* rgb = mapper->GetExpertOptions()->GetEnvironmentColor();
  Check(rgb[0] == 0.0 && rgb[1] == 0.5 && rgb[2] == 1.0 && reports.Count() - seen == 3,
    "SetEnvironmentColor(-1, nan, inf) gives (0, 0.5, 1) with three warnings");
}

/// A volume of @a dims with @a spacing whose scalars are offset + a smooth field in [0, 100].
vtkSmartPointer<vtkImageData> MakeVolume(
  int nx, int ny, int nz, const double spacing[3], double offset, bool asDouble)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(nx, ny, nz);
  image->SetSpacing(spacing[0], spacing[1], spacing[2]);
  image->SetOrigin(-3.0, 5.0, 0.5);
  vtkSmartPointer<vtkDataArray> values;
  if (asDouble)
  {
    values = vtkSmartPointer<vtkDoubleArray>::New();
  }
  else
  {
    values = vtkSmartPointer<vtkUnsignedCharArray>::New();
  }
  values->SetName("values");
  values->SetNumberOfTuples(static_cast<vtkIdType>(nx) * ny * nz);
  vtkIdType id = 0;
  for (int z = 0; z < nz; ++z)
  {
    for (int y = 0; y < ny; ++y)
    {
      for (int x = 0; x < nx; ++x, ++id)
      {
        const double r = std::sqrt(
          (x - 0.5 * nx) * (x - 0.5 * nx) + (y - 0.5 * ny) * (y - 0.5 * ny) +
          (z - 0.5 * nz) * (z - 0.5 * nz));
        const double field = 100.0 * (0.5 + 0.5 * std::cos(0.4 * r));
        values->SetTuple1(id, offset + field);
      }
    }
  }
  image->GetPointData()->SetScalars(values);
  return image;
}

struct Volume
{
  const char* Name;
  vtkSmartPointer<vtkImageData> Image;
  double Offset;
};

std::vector<Volume> Volumes()
{
  const double unit[3] = { 1.0, 1.0, 1.0 };
  const double stretched[3] = { 0.5, 1.0, 8.0 };
  return {
    { "tiny 2x2x2", MakeVolume(2, 2, 2, unit, 0.0, false), 0.0 },
    { "flat 24x24x1", MakeVolume(24, 24, 1, unit, 0.0, false), 0.0 },
    { "offset double 1e10 + [0, 100]", MakeVolume(20, 20, 20, unit, 1e10, true), 1e10 },
    { "anisotropic 24x24x6, spacing (0.5, 1, 8)", MakeVolume(24, 24, 6, stretched, 0.0, false),
      0.0 },
  };
}

const char* const kPasses[] = { "Radiance", "Alpha", "Albedo", "Normal", "Depth", "Denoised",
  "Converged", "Position", "Coverage", "Footprint" };

/// Random settings of every property (costly ones kept small so a render stays short), then a
/// render: its bounds, finite passes, and nothing reported again by an unchanged re-render.
void SweepVolume(const Volume& v, std::mt19937& rng, int trials)
{
  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(v.Offset + 0.0, 0.2, 0.4, 1.0);
  color->AddRGBPoint(v.Offset + 100.0, 1.0, 0.9, 0.5);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(v.Offset + 20.0, 0.0);
  opacity->AddPoint(v.Offset + 100.0, 0.9);
  vtkNew<vtkVolumeProperty> property;
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  property->ShadeOn();
  vtkNew<Mapper> mapper;
  mapper->SetInputData(v.Image);
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(property);
  vtkNew<vtkRenderer> renderer;
  renderer->AddVolume(volume);
  vtkNew<vtkRenderWindow> window;
  window->SetSize(64, 64);
  window->AddRenderer(renderer);
  Reports reports(mapper);

  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto coin = [&]() { return unit(rng) < 0.5; };
  auto pick = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  const char* const displays[] = { nullptr, "", "Radiance", "Converged", "Denoised", "Alpha",
    "Albedo", "Normal", "Bogus" };
  const char* const models[] = { nullptr, "", "/nonexistent/model.onnx", "/tmp" };

  int traced = 0;
  for (int trial = 0; trial < trials; ++trial)
  {
    // Every numeric property: a random value (in or out of range), then the costly ones small.
    for (const Numeric& p : NumericProperties())
    {
      p.Set(mapper, Draw(p, rng));
    }
    mapper->SetSamplesPerFrame(pick(-2, 6));
    mapper->GetExpertOptions()->SetMaximumStillFrames(pick(-1, 24));
    mapper->GetExpertOptions()->SetMaximumAccumulatedFrames(pick(0, 32));
    mapper->SetStillTimeBudget(0.05 + 0.4 * unit(rng));
    mapper->SetNumberOfThreads(pick(-1, 4));
    mapper->SetSeed(static_cast<unsigned int>(rng()));
    mapper->SetTemporalReprojection(coin());
    mapper->SetConvergeStillRenders(coin());
    mapper->SetScattering(coin());
    mapper->GetExpertOptions()->SetCoverageMarch(coin());
    mapper->GetExpertOptions()->SetExpectedCoverage(coin());
    mapper->GetExpertOptions()->SetFootprintRays(coin());
    mapper->GetExpertOptions()->SetComputeEdgeSamples(coin());
    mapper->SetAmbientOcclusion(coin());
    mapper->GetExpertOptions()->SetUseRendererLight(coin());
    const double nan = std::numeric_limits<double>::quiet_NaN();
    mapper->GetExpertOptions()->SetEnvironmentColor(2.0 * unit(rng) - 0.5,
      unit(rng) < 0.2 ? nan : unit(rng),
      unit(rng) < 0.1 ? std::numeric_limits<double>::infinity() : 3.0 * unit(rng));
    mapper->GetExpertOptions()->SetUseBackgroundAsEnvironment(coin());
    mapper->GetExpertOptions()->SetEmptySpaceSkipping(coin());
    mapper->SetDenoise(coin());
    mapper->SetDenoiserModelFile(models[pick(0, 3)]);
    mapper->GetExpertOptions()->SetDenoiserUseNetwork(coin());
    mapper->SetDisplayPass(displays[pick(0, 8)]);
    const bool distributed = unit(rng) < 0.25; // one process: the piece is the whole volume
    mapper->SetDistributedVolume(distributed);
    int extent[6];
    v.Image->GetExtent(extent);
    if (distributed && coin())
    {
      for (int& e : extent)
      {
        e += pick(-3, 3); // a piece that does not match the data: an error, no crash
      }
    }
    mapper->SetPieceExtent(extent);
    v.Image->GetExtent(extent);
    mapper->SetWholeExtent(extent);
    // vtkVolumeMapper's own: blend mode (iso values on the property), cropping.
    mapper->SetBlendMode(pick(0, 5));
    property->GetIsoSurfaceValues()->SetNumberOfContours(pick(0, 2));
    property->GetIsoSurfaceValues()->SetValue(0, v.Offset + 120.0 * unit(rng) - 10.0);
    mapper->SetCropping(unit(rng) < 0.3);
    double bounds[6];
    v.Image->GetBounds(bounds);
    double planes[6];
    for (int k = 0; k < 6; ++k)
    {
      planes[k] = bounds[k & ~1] + (1.4 * unit(rng) - 0.2) * (bounds[k | 1] - bounds[k & ~1]);
    }
    mapper->SetCroppingRegionPlanes(planes);
    mapper->SetCroppingRegionFlags(coin() ? VTK_CROP_SUBVOLUME : VTK_CROP_CROSS);
    renderer->GetActiveCamera()->Azimuth(360.0 * unit(rng));
    renderer->GetActiveCamera()->Elevation(60.0 * unit(rng) - 30.0);
    renderer->GetActiveCamera()->OrthogonalizeViewUp();
    renderer->ResetCamera();
    const bool still = coin();
    window->SetDesiredUpdateRate(still ? 0.0001 : 15.0);

    std::ostringstream label;
    label << v.Name << ", trial " << trial << " (" << (still ? "still" : "interactive")
          << ", SamplesPerFrame " << mapper->GetSamplesPerFrame() << ", MaximumStillFrames "
          << mapper->GetExpertOptions()->GetMaximumStillFrames() << ", MaximumAccumulatedFrames "
          << mapper->GetExpertOptions()->GetMaximumAccumulatedFrames() << ", budget "
          << mapper->GetStillTimeBudget()
          << " s, Denoise " << mapper->GetDenoise() << ", Backend " << mapper->GetBackend()
          << ", DisplayPass " << (mapper->GetDisplayPass() ? mapper->GetDisplayPass() : "null")
          << ", Distributed " << distributed << ")";
    const double start = vtkTimerLog::GetUniversalTime();
    window->Render();
    const double seconds = vtkTimerLog::GetUniversalTime() - start;
    const int frames = mapper->GetStatistics()->GetLastRenderFrames();
    const bool converging = still && mapper->GetConvergeStillRenders();
    const int cap = std::min(mapper->GetExpertOptions()->GetMaximumStillFrames(),
      mapper->GetExpertOptions()->GetMaximumAccumulatedFrames());
    if (converging)
    {
      Check(frames <= cap, label.str() + ": " + std::to_string(frames) + " frames");
      // One frame's slack past the budget (a frame at 64 x 64 is far below 5 s, sanitizers on).
      Check(seconds <= mapper->GetStillTimeBudget() + 5.0,
        label.str() + ": " + std::to_string(seconds) + " s");
    }
    else
    {
      Check(frames <= 1, label.str() + ": " + std::to_string(frames) + " frames");
    }
    for (const char* name : kPasses)
    {
      vtkNew<vtkImageData> image;
      if (!mapper->GetPass(name, image))
      {
        continue;
      }
      vtkDataArray* values = image->GetPointData()->GetScalars();
      bool finite = values != nullptr;
      for (vtkIdType i = 0; finite && i < values->GetNumberOfValues(); ++i)
      {
        finite = std::isfinite(values->GetVariantValue(i).ToDouble());
      }
      Check(finite, label.str() + ": pass " + name + " is finite");
    }
    // Rendering again unchanged reports nothing new: each problem is said once.
    const std::size_t seen = reports.Count();
    window->SetDesiredUpdateRate(15.0);
    window->Render();
    std::string again;
    for (std::size_t i = seen; i < reports.Count(); ++i)
    {
      again += "\n  " + reports.Texts[i];
    }
    Check(reports.Count() == seen, label.str() + ": an unchanged re-render reported" + again);
    traced += mapper->GetAccumulatedFrames() > 0 ? 1 : 0;
  }
  // Most settings trace: the sweep exercises the tracer, not only the error paths.
  Check(traced >= trials / 2,
    std::string(v.Name) + ": " + std::to_string(traced) + " of " + std::to_string(trials) +
      " renders traced");
  std::cout << v.Name << ": " << trials << " trials, " << reports.Count()
            << " warnings and errors\n";

}
}

int TestPTVPropertySweep(int, char*[])
{
  std::mt19937 rng(59); // fixed: a failure names its trial and reproduces
  TestSetters(rng);
  for (const Volume& v : Volumes())
  {
    SweepVolume(v, rng, 30);
  }
  return TestResult();
}
