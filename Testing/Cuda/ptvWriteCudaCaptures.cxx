// Writes the captures ptvCudaCheck runs on a GPU machine (ptvCudaCapture.h): for each dataset,
// the kernel's inputs built by the mapper's own code (ptvFrameInputs) for the project's camera
// convention (azimuth 30, elevation 15; the Python toolbox's ParaView background as the
// environment), the CPU driver's 1- and 16-spp means (baseline build: reproducible to the bit),
// GuideNet's guides of the 1-spp frame (the shipped model, 3 levels) and the CPU grid's output.
// Then it reads each file back and checks it: every array equal, and the CPU driver run again
// on the parameters read back gives the stored passes to the bit.
//
// Besides the three datasets as the report renders them, variants of the concrete take every
// other branch of the CUDA driver's uploads: a clipping plane with gradient opacity and opaque
// geometry's depths (per-pixel ray limits); isosurfaces with nearest-voxel classification;
// dependent RGBA colour data; two-component (colour channel + opacity channel) data.
//
//   ptvWriteCudaCaptures -D <data dir> -o <out dir> [--size 256] [capture ...]
//   (captures: head stent concrete concrete_clip concrete_iso concrete_rgba concrete_two;
//   default: all)
#include "Kernels/ptvTraceParams.h"
#include "ptvBilateralGridCpu.h"
#include "ptvCpuTracer.h"
#include "ptvCudaCapture.h"
#include "ptvDenoiser.h"
#include "ptvFrameInputs.h"
#include "ptvPassBuffers.h"

#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPTVTransferFunctionPreset.h"
#include "vtkPathTracedVolumeMapper.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"
#include "vtkXMLImageDataReader.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

namespace
{
using namespace ptv;

const int kPassOf[CapturedPassCount] = { PassRadiance, PassDepth, PassNormal };

/// One capture: a dataset and what is switched on.
struct Variant
{
  const char* Name;
  const char* Dataset;
  bool ClipGradientDepth; ///< a clipping plane, gradient opacity, opaque geometry's depths
  bool IsoNearest;        ///< one isosurface, nearest-voxel classification
  int ColorComponents;    ///< 0: scalars; 2 or 4: dependent colour data built from the scalars
};

const Variant kVariants[] = {
  { "head", "head", false, false, 0 },
  { "stent", "stent", false, false, 0 },
  { "concrete", "concrete", false, false, 0 },
  { "concrete_clip", "concrete", true, false, 0 },
  { "concrete_iso", "concrete", false, true, 0 },
  { "concrete_rgba", "concrete", false, false, 4 },
  { "concrete_two", "concrete", false, false, 2 },
};

/// Dependent colour data from @a image's scalars s (normalised to t in [0, 1] over their range
/// [lo, hi]): 4 components (t, 1 - t, 0.5 + 0.5 t, s) or 2 (lo + hi - s as the colour channel,
/// s as the opacity channel).
vtkSmartPointer<vtkImageData> ColorData(vtkImageData* image, int components)
{
  vtkDataArray* scalars = image->GetPointData()->GetScalars();
  double range[2];
  scalars->GetRange(range);
  const double span = range[1] > range[0] ? range[1] - range[0] : 1.0;
  vtkNew<vtkFloatArray> data;
  data->SetName("colour");
  data->SetNumberOfComponents(components);
  data->SetNumberOfTuples(scalars->GetNumberOfTuples());
  for (vtkIdType i = 0; i < scalars->GetNumberOfTuples(); ++i)
  {
    const double v = scalars->GetComponent(i, 0);
    const double t = (v - range[0]) / span;
    if (components == 4)
    {
      const float rgba[4] = { static_cast<float>(t), static_cast<float>(1.0 - t),
        static_cast<float>(0.5 + 0.5 * t), static_cast<float>(v) };
      data->SetTypedTuple(i, rgba);
    }
    else
    {
      // The colour channel reversed over the same range, so the preset's colours vary on it.
      const float two[2] = { static_cast<float>(range[0] + range[1] - v), static_cast<float>(v) };
      data->SetTypedTuple(i, two);
    }
  }
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->CopyStructure(image);
  out->GetPointData()->SetScalars(data);
  return out;
}

template <typename T>
std::vector<T> Copy(const T* p, std::size_t n)
{
  return p ? std::vector<T>(p, p + n) : std::vector<T>();
}

/// The arrays behind @a p, copied into @a c (its Params keep pointing at the originals until
/// PointParams).
void CopyInputs(const TraceParams& p, TraceCapture& c)
{
  const std::size_t voxels = static_cast<std::size_t>(p.Volume.Dims[0]) * p.Volume.Dims[1] *
    static_cast<std::size_t>(p.Volume.Dims[2]);
  const std::size_t pixels = static_cast<std::size_t>(p.Camera.Width) * p.Camera.Height;
  const std::size_t bricks =
    static_cast<std::size_t>(p.Occupancy.Bricks[0]) * p.Occupancy.Bricks[1] * p.Occupancy.Bricks[2];
  c.Params = p;
  // The voxels as float whatever their type (a capture stores floats; PointParams says so).
  c.Scalars.resize(p.Volume.Scalars ? voxels : 0);
  for (std::size_t v = 0; v < c.Scalars.size(); ++v)
  {
    c.Scalars[v] = WithScalars(p.Volume,
      [&](const auto* data) { return static_cast<float>(data[v]); });
  }
  c.Colors = Copy(p.Volume.Colors, 3 * voxels);
  c.ColorScalars = Copy(p.Volume.ColorScalars, voxels);
  c.TransferRGBA = Copy(p.Transfer.RGBA, 4 * static_cast<std::size_t>(p.Transfer.Size));
  c.GradientOpacity = Copy(p.Transfer.GradientOpacity, p.Transfer.GradientSize);
  c.StepRGBA = Copy(p.Transfer.StepRGBA, 4 * static_cast<std::size_t>(p.Transfer.Size));
  c.ShadowAlpha = Copy(p.Transfer.ShadowAlpha, p.Transfer.Size);
  c.ColorTableRGBA = Copy(p.ColorTable.RGBA, 4 * static_cast<std::size_t>(p.ColorTable.Size));
  c.MaxDistance = Copy(p.MaxDistance, pixels);
  c.Occupancy = Copy(p.Occupancy.Distance, 8 * bricks);
  PointParams(c);
}

/// Trace @a samples spp with the CPU driver's baseline build; the captured passes.
void TraceCpu(const TraceParams& p, int samples, PassBuffers& out, std::vector<float>* passes)
{
  out.Resize(p.Camera.Width, p.Camera.Height);
  TraceFrameCpu(p, 0, samples, 0, /*portable=*/true, out);
  const std::size_t pixels = static_cast<std::size_t>(p.Camera.Width) * p.Camera.Height;
  for (int k = 0; k < CapturedPassCount; ++k)
  {
    const int n = GetPassInfo(kPassOf[k]).Components;
    passes[k] = Copy(out.Data(kPassOf[k]), n * pixels);
  }
}

bool Fail(const std::string& what)
{
  std::cerr << "ERROR: " << what << "\n";
  return false;
}

bool Capture(const std::string& dataDir, const Variant& variant, int size, TraceCapture& c)
{
  const std::string name = variant.Dataset;
  vtkNew<vtkXMLImageDataReader> reader;
  const std::string file = dataDir + "/" + name + ".vti";
  if (!reader->CanReadFile(file.c_str()))
  {
    return Fail("cannot read " + file + " (scripts/fetch_datasets.py fetches it)");
  }
  reader->SetFileName(file.c_str());
  reader->Update();
  vtkSmartPointer<vtkImageData> image = reader->GetOutput();
  double range[2];
  image->GetPointData()->GetScalars()->GetRange(range);
  if (variant.ColorComponents)
  {
    image = ColorData(image, variant.ColorComponents);
  }

  vtkNew<vtkVolumeProperty> property;
  vtkNew<vtkPTVTransferFunctionPreset> presets;
  presets->SetFileName(
    (vtkPTVTransferFunctionPreset::GetDefaultPresetDirectory() + "/" + name + ".json").c_str());
  if (!presets->Load() || presets->GetNumberOfPresets() < 1 ||
    !presets->ApplyPreset(presets->GetPresetName(0), property))
  {
    return Fail("no transfer-function preset for " + name);
  }
  property->ShadeOn();
  property->SetInterpolationTypeToLinear();
  if (variant.IsoNearest)
  {
    property->SetInterpolationTypeToNearest();
  }
  if (variant.ClipGradientDepth)
  {
    vtkPiecewiseFunction* gradient = property->GetGradientOpacity(0);
    gradient->RemoveAllPoints();
    gradient->AddPoint(0.0, 0.2);
    gradient->AddPoint(0.05 * (range[1] - range[0]), 1.0);
    property->DisableGradientOpacityOff();
  }
  if (variant.ColorComponents == 2)
  {
    // A colour ramp over the colour channel's range (the preset's colours barely vary on it).
    vtkColorTransferFunction* color = property->GetRGBTransferFunction(0);
    color->RemoveAllPoints();
    color->AddRGBPoint(range[0], 1.0, 0.1, 0.1);
    color->AddRGBPoint(0.5 * (range[0] + range[1]), 0.1, 1.0, 0.1);
    color->AddRGBPoint(range[1], 0.1, 0.1, 1.0);
  }
  property->SetIndependentComponents(variant.ColorComponents == 0);
  vtkNew<vtkPathTracedVolumeMapper> mapper; // the volume's bounds; never rendered
  mapper->SetInputData(image);
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(property);
  vtkNew<vtkRenderer> renderer;
  renderer->AddVolume(volume);
  renderer->SetBackground(0.32, 0.34, 0.43); // pathtracedvolume.scene.BACKGROUND
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->SetPosition(0, -1, 0);
  camera->SetFocalPoint(0, 0, 0);
  camera->SetViewUp(0, 0, 1);
  camera->Azimuth(30);
  camera->Elevation(15);
  camera->OrthogonalizeViewUp();
  renderer->ResetCamera();
  renderer->ResetCameraClippingRange();

  FrameInputs inputs;
  FrameSettings settings;
  std::vector<float> zbuffer;
  if (variant.ClipGradientDepth)
  {
    double bounds[6];
    volume->GetBounds(bounds);
    settings.ClipPlaneCount = 1; // keeps x >= the centre: n.x + d >= 0
    const double plane[4] = { 1.0, 0.0, 0.0, -0.5 * (bounds[0] + bounds[1]) };
    std::copy(plane, plane + 4, settings.ClipPlanes[0]);
    // Opaque geometry over the left third (window depth 0.99), nothing elsewhere.
    zbuffer.assign(static_cast<std::size_t>(size) * size, 1.0f);
    for (int y = 0; y < size; ++y)
    {
      std::fill_n(zbuffer.begin() + static_cast<std::ptrdiff_t>(y) * size, size / 3, 0.99f);
    }
  }
  if (variant.IsoNearest)
  {
    // The median voxel: half the voxels lie on each side of that surface.
    vtkDataArray* scalars = image->GetPointData()->GetScalars();
    std::vector<double> sample;
    for (vtkIdType i = 0; i < scalars->GetNumberOfTuples(); i += 97)
    {
      sample.push_back(scalars->GetComponent(i, 0));
    }
    std::nth_element(sample.begin(), sample.begin() + sample.size() / 2, sample.end());
    settings.Iso.Count = 1;
    settings.Iso.Values[0] = static_cast<float>(sample[sample.size() / 2]);
  }
  std::string error;
  vtkIdType nonFinite = 0;
  TraceParams params{};
  FrameSignature signature;
  if (!inputs.UpdateVolume(image, image->GetPointData()->GetScalars(),
        variant.ColorComponents != 0, error, nonFinite) ||
    !inputs.UpdateTransfer(
      property, settings.EmptySpaceSkipping, settings.Iso, settings.IsoValues, error) ||
    !inputs.Build(renderer, volume, image, settings, size, size, zbuffer, params, signature,
      error))
  {
    return Fail(std::string(variant.Name) + ": " + error);
  }
  // Each variant must take the branch it is for (a capture that silently lost it checks less).
  const TraceParams& q = params;
  const bool took = (!variant.ClipGradientDepth ||
                      (q.Clip.PlaneCount == 1 && q.Transfer.GradientOpacity && q.MaxDistance)) &&
    (!variant.IsoNearest || (q.Iso.Count == 1 && q.Nearest)) &&
    (variant.ColorComponents != 4 || q.Volume.Colors) &&
    (variant.ColorComponents != 2 || (q.Volume.ColorScalars && q.ColorTable.RGBA));
  if (!took)
  {
    return Fail(std::string(variant.Name) + ": the scene does not exercise what it is for");
  }
  c.Name = variant.Name;
  CopyInputs(params, c);

  PassBuffers frame;
  for (int k = 1; k >= 0; --k) // the 1-spp frame last: its passes feed the denoiser
  {
    TraceCpu(c.Params, c.Samples[k], frame, c.Cpu[k]);
  }

  // GuideNet's guides of the 1-spp frame (the shipped model; 3 levels).
  const float* passes[PassCount] = {};
  for (int pass = 0; pass < kTracedPassCount; ++pass)
  {
    passes[pass] = frame.Data(pass);
  }
  Denoiser denoiser;
  DenoiserSettings denoise;
  denoise.Levels = 3;
  const std::size_t pixels = static_cast<std::size_t>(size) * size;
  std::vector<float> denoised(3 * pixels);
  if (!denoiser.Run(denoise, passes, size, size, denoised.data(), error))
  {
    return Fail(name + ": denoiser: " + error);
  }
  if (!denoiser.GetNetworkActive() || denoiser.GetLevels() != 3)
  {
    return Fail(name + ": the shipped model did not run: " + denoiser.GetStatus());
  }
  c.GuideLevels = denoiser.GetLevels();
  c.Guides = denoiser.GetGuides();
  c.Weights = denoiser.GetWeights();
  c.Radiance = Copy(frame.Data(PassRadiance), 3 * pixels);
  c.Albedo = Copy(frame.Data(PassAlbedo), 3 * pixels);

  BilateralGridCpu grid;
  BilateralGridSettings gs;
  std::copy(c.SpatialStep, c.SpatialStep + kMaxGridLevels, gs.SpatialStep);
  std::copy(c.RangeStep, c.RangeStep + kMaxGridLevels, gs.RangeStep);
  gs.Clamp = c.Clamp;
  const std::vector<float> first = FirstGuide(c);
  for (int k = 0; k < 2; ++k)
  {
    gs.Levels = k == 0 ? 1 : c.GuideLevels;
    c.GridCpu[k].resize(3 * pixels);
    grid.Apply(gs, size, size, c.Radiance.data(), c.Albedo.data(),
      k == 0 ? first.data() : c.Guides.data(), k == 0 ? nullptr : c.Weights.data(),
      c.GridCpu[k].data());
  }
  return true;
}

/// Read @a file back: every array as written, and the CPU driver on the parameters read back
/// reproduces the stored passes exactly.
bool Verify(const std::string& file, const TraceCapture& written)
{
  TraceCapture c;
  std::string error;
  if (!ReadCapture(file, c, error))
  {
    return Fail(error);
  }
  const bool same = c.Name == written.Name &&
    std::memcmp(&c.Params.Camera, &written.Params.Camera, sizeof(CameraRays)) == 0 &&
    c.Scalars == written.Scalars && c.TransferRGBA == written.TransferRGBA &&
    c.StepRGBA == written.StepRGBA && c.ShadowAlpha == written.ShadowAlpha &&
    c.Occupancy == written.Occupancy && c.Guides == written.Guides &&
    c.Weights == written.Weights && c.Radiance == written.Radiance &&
    c.Albedo == written.Albedo && c.GridCpu[0] == written.GridCpu[0] &&
    c.GridCpu[1] == written.GridCpu[1];
  if (!same)
  {
    return Fail(file + ": read back differs from what was written");
  }
  PassBuffers frame;
  for (int k = 0; k < 2; ++k)
  {
    std::vector<float> again[CapturedPassCount];
    TraceCpu(c.Params, c.Samples[k], frame, again);
    for (int pass = 0; pass < CapturedPassCount; ++pass)
    {
      if (again[pass] != c.Cpu[k][pass])
      {
        return Fail(file + ": tracing the parameters read back does not reproduce pass " +
          std::to_string(pass) + " at " + std::to_string(c.Samples[k]) + " spp");
      }
    }
  }
  return true;
}
}

int main(int argc, char* argv[])
{
  std::string dataDir, outDir;
  int size = 256;
  std::vector<std::string> names; // captures to write
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if ((a == "-D" || a == "-o" || a == "--size") && i + 1 < argc)
    {
      const std::string v = argv[++i];
      if (a == "-D")
      {
        dataDir = v;
      }
      else if (a == "-o")
      {
        outDir = v;
      }
      else
      {
        size = std::atoi(v.c_str());
      }
    }
    else if (a == "-h" || a == "--help")
    {
      std::cout << "usage: ptvWriteCudaCaptures -D <data dir> -o <out dir> [--size N] "
                   "[capture ...]\n(captures:";
      for (const Variant& v : kVariants)
      {
        std::cout << " " << v.Name;
      }
      std::cout << "; default: all; size 256)\n";
      return EXIT_SUCCESS;
    }
    else
    {
      names.push_back(a);
    }
  }
  if (dataDir.empty() || outDir.empty() || size < 8 || size > 4096)
  {
    std::cerr << "ERROR: need -D <data dir> and -o <out dir>, and a --size in 8..4096 (got "
              << size << ")\n";
    return EXIT_FAILURE;
  }
  if (names.empty())
  {
    for (const Variant& v : kVariants)
    {
      names.emplace_back(v.Name);
    }
  }
  for (const std::string& name : names)
  {
    const Variant* variant = nullptr;
    for (const Variant& v : kVariants)
    {
      variant = name == v.Name ? &v : variant;
    }
    if (!variant)
    {
      std::cerr << "ERROR: no capture called " << name << " (--help lists them)\n";
      return EXIT_FAILURE;
    }
    TraceCapture c;
    std::string error;
    const std::string file = outDir + "/" + name + ".ptvcap";
    if (!Capture(dataDir, *variant, size, c))
    {
      return EXIT_FAILURE;
    }
    // A capture that shows nothing would check nothing.
    std::size_t hits = 0;
    for (float depth : c.Cpu[0][CapturedDepth])
    {
      hits += depth < kHitFraction * c.Params.Camera.FarDistance ? 1 : 0;
    }
    const double covered = static_cast<double>(hits) / c.Cpu[0][CapturedDepth].size();
    if (covered < 0.05)
    {
      std::cerr << "ERROR: " << name << ": only " << 100 * covered << " % of the pixels see it\n";
      return EXIT_FAILURE;
    }
    if (!WriteCapture(file, c, error))
    {
      std::cerr << "ERROR: " << error << "\n";
      return EXIT_FAILURE;
    }
    if (!Verify(file, c))
    {
      return EXIT_FAILURE;
    }
    std::cout << file << ": " << size << "x" << size << ", volume " << c.Params.Volume.Dims[0]
              << "x" << c.Params.Volume.Dims[1] << "x" << c.Params.Volume.Dims[2]
              << ", " << static_cast<int>(100 * covered + 0.5) << " % of the pixels hit, guides "
              << c.GuideLevels << " levels; read back and re-traced: identical\n";
  }
  return EXIT_SUCCESS;
}
