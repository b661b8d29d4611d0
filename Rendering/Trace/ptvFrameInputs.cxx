#include "ptvFrameInputs.h"

#include "Kernels/ptvOccupancy.h"
#include "Kernels/ptvShading.h"
#include "ptvScalarChannel.h"
#include "ptvSceneToKernel.h"
#include "ptvThreads.h"

#include "vtkColorTransferFunction.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkPiecewiseFunction.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <utility>

namespace ptv
{
namespace
{
constexpr int kTableSize = 4096;
constexpr int kGradientTableSize = 1024;
// Occupancy bricks of 4^3 voxels: measured against 8^3 (benchmark_tracer.py, 512², 1 thread)
// 5-8% less trace time on the three datasets; the per-brick ranges cost 8 bytes per 64 voxels.
constexpr int kBrickSize = 4;

// The property's colour (or grey) function at kTableSize points over [range[0], range[1]] as RGB.
void SampleColorFunction(vtkVolumeProperty* property, const double range[2], float* rgb)
{
  if (property->GetColorChannels(0) == 1)
  {
    std::vector<float> grey(kTableSize);
    property->GetGrayTransferFunction(0)->GetTable(range[0], range[1], kTableSize, grey.data());
    for (int i = 0; i < kTableSize; ++i)
    {
      rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = grey[i];
    }
  }
  else
  {
    property->GetRGBTransferFunction(0)->GetTable(range[0], range[1], kTableSize, rgb);
  }
}
}

//------------------------------------------------------------------------------
bool FrameInputs::UpdateTransfer(vtkVolumeProperty* property, bool skipping,
  const IsoSurfaces& dataIso, const double* isoValues, std::string& error)
{
  const IsoSurfaces iso = this->StoredIso(dataIso, isoValues);
  if (!property)
  {
    error = "the vtkVolume has no vtkVolumeProperty";
    return false;
  }
  const bool sameIso = iso.Count == this->OccupancyIso.Count &&
    std::equal(iso.Values, iso.Values + iso.Count, this->OccupancyIso.Values);
  if (property->GetMTime() <= this->TransferTime && skipping == this->TransferSkipping &&
    sameIso && !this->RGBA.empty())
  {
    return true;
  }
  this->OccupancyIso = iso;
  this->RGBA.assign(4 * kTableSize, 0.0f);
  this->StepRGBA.clear(); // rebuilt from the new table by Build
  std::vector<float> rgb(3 * kTableSize), alpha(kTableSize);
  SampleColorFunction(property, this->Range, rgb.data());
  property->GetScalarOpacity(0)->GetTable(this->Range[0], this->Range[1], kTableSize, alpha.data());
  // 2-component colour data: the colour function maps the colour channel over its own range.
  this->ColorRGBA.clear();
  if (!this->ColorScalars.empty())
  {
    std::vector<float> crgb(3 * kTableSize);
    SampleColorFunction(property, this->ColorRange, crgb.data());
    this->ColorRGBA.assign(4 * kTableSize, 1.0f);
    for (int i = 0; i < kTableSize; ++i)
    {
      std::copy(&crgb[3 * i], &crgb[3 * i] + 3, &this->ColorRGBA[4 * i]);
    }
  }
  for (int i = 0; i < kTableSize; ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      this->RGBA[4 * i + c] = rgb[3 * i + c];
    }
    this->RGBA[4 * i + 3] = std::min(1.0f, std::max(0.0f, alpha[i]));
  }
  this->OpaqueBefore.resize(kTableSize + 1);
  BuildOpaqueCounts(this->RGBA.data(), kTableSize, this->OpaqueBefore.data());

  // Gradient opacity only when it can change anything (VTK's default function is constant 1).
  this->GradientOpacity.clear();
  if (!property->GetDisableGradientOpacity(0))
  {
    // Table over [0, scalar range per unit world distance]; larger gradients clamp to the end.
    this->GradientMax = this->Range[1] - this->Range[0];
    std::vector<float> g(kGradientTableSize);
    property->GetGradientOpacity(0)->GetTable(0.0, this->GradientMax, kGradientTableSize, g.data());
    const bool constantOne =
      std::all_of(g.begin(), g.end(), [](float v) { return std::abs(v - 1.0f) < 1e-6f; });
    if (!constantOne)
    {
      this->GradientOpacity = std::move(g);
    }
  }
  this->Nearest = property->GetInterpolationType() == VTK_NEAREST_INTERPOLATION ? 1 : 0;

  // Occupancy: per-brick value ranges depend on the voxels only (built once per volume, in
  // parallel); the signed brick distances on those ranges and the table (cheap, per table
  // change).
  this->BrickDistance.clear();
  this->TransferSkipping = skipping;
  if (skipping)
  {
    VolumeGrid grid{};
    grid.Scalars = this->GetScalarData();
    grid.Type = this->ScalarType;
    std::copy(this->Dims, this->Dims + 3, grid.Dims);
    ComputeBrickCounts(this->Dims, kBrickSize, this->BrickCounts);
    const std::size_t bricks =
      static_cast<std::size_t>(this->BrickCounts[0]) * this->BrickCounts[1] * this->BrickCounts[2];
    if (this->BrickRanges.size() != 2 * bricks)
    {
      this->BrickRanges.resize(2 * bricks);
      float* ranges = this->BrickRanges.data();
      ParallelFor(0, 0, this->BrickCounts[2], 1,
        [&](vtkIdType z0, vtkIdType z1) {
          BuildBrickRanges(
            grid, kBrickSize, static_cast<int>(z0), static_cast<int>(z1), ranges);
        });
    }
    TransferTable table{};
    table.RGBA = this->RGBA.data();
    table.Size = kTableSize;
    table.ScalarMin = this->Stored(this->Range[0]);
    table.ScalarMax = this->Stored(this->Range[1]);
    this->BrickDistance.resize(8 * bricks);
    BuildOccupancy(
      table, this->BrickCounts, this->BrickRanges.data(), this->BrickDistance.data(), &iso);
  }
  this->TransferTime = property->GetMTime();
  return true;
}

//------------------------------------------------------------------------------
bool FrameInputs::Build(vtkRenderer* ren, vtkVolume* vol, vtkImageData* image,
  const FrameSettings& settings, int width, int height, const std::vector<float>& zbuffer,
  TraceParams& p, FrameSignature& signature, std::string& error)
{
  p = TraceParams{};
  signature.Clear();

  // Volume: voxels and index <-> world.
  VolumeGrid& g = p.Volume;
  g.Scalars = this->GetScalarData();
  g.Type = this->ScalarType;
  std::copy(this->Dims, this->Dims + 3, g.Dims);
  if (!this->ColorScalars.empty() && !this->ColorRGBA.empty())
  {
    g.ColorScalars = this->ColorScalars.data();
    p.ColorTable.RGBA = this->ColorRGBA.data();
    p.ColorTable.Size = kTableSize;
    p.ColorTable.ScalarMin = static_cast<float>((this->ColorRange[0] - this->ColorShift) *
      this->ColorScale);
    p.ColorTable.ScalarMax = static_cast<float>((this->ColorRange[1] - this->ColorShift) *
      this->ColorScale);
    p.ColorTable.GradientOpacity = nullptr;
    p.ColorTable.GradientSize = 0;
    p.ColorTable.GradientMax = 1.0f;
  }
  g.Colors = this->Colors.empty() ? nullptr : this->Colors.data();
  double step = 0.0;
  if (!SetVolumeTransform(image, vol, g, step, signature, error))
  {
    return false;
  }
  vol->GetBounds(this->WorldBounds);
  if (this->Whole)
  {
    std::copy(this->WholeBounds, this->WholeBounds + 6, this->WorldBounds);
    signature.AddApproximate(this->WorldBounds, 6);
  }
  if (!this->SetPiece(settings, image, p, signature, error))
  {
    return false;
  }
  SetClipping(settings, image, g, p.Clip, signature);
  p.Iso = this->StoredIso(settings.Iso, settings.IsoValues);
  const double isoCount = static_cast<double>(p.Iso.Count);
  signature.AddExact(&isoCount, 1);
  for (int i = 0; i < p.Iso.Count; ++i)
  {
    const double v = p.Iso.Values[i];
    signature.AddExact(&v, 1);
  }
  p.Projection = p.Iso.Count > 0 ? 0 : settings.Projection;
  const double limit = std::numeric_limits<float>::max();
  const double averageRange[3] = { static_cast<double>(p.Projection),
    std::max(-limit, std::min(limit, (settings.AverageRange[0] - this->Shift) * this->Scale)),
    std::max(-limit, std::min(limit, (settings.AverageRange[1] - this->Shift) * this->Scale)) };
  p.AverageLo = static_cast<float>(averageRange[1]);
  p.AverageHi = static_cast<float>(averageRange[2]);
  signature.AddExact(averageRange, 3);

  // Transfer function.
  vtkVolumeProperty* prop = vol->GetProperty();
  TransferTable& tf = p.Transfer;
  tf.RGBA = this->RGBA.data();
  tf.Size = kTableSize;
  tf.ScalarMin = this->Stored(this->Range[0]);
  tf.ScalarMax = this->Stored(this->Range[1]);
  tf.GradientOpacity = this->GradientOpacity.empty() ? nullptr : this->GradientOpacity.data();
  tf.GradientSize = kGradientTableSize;
  tf.GradientMax = static_cast<float>(this->GradientMax * this->Scale); // stored units
  tf.OpaqueBefore = this->OpaqueBefore.data();
  if (settings.EmptySpaceSkipping && !this->BrickDistance.empty())
  {
    p.Occupancy.Distance = this->BrickDistance.data();
    p.Occupancy.BrickSize = kBrickSize;
    std::copy(this->BrickCounts, this->BrickCounts + 3, p.Occupancy.Bricks);
  }
  const double transferTime = static_cast<double>(prop->GetMTime());
  signature.AddExact(&transferTime, 1);
  const double volumeTime = static_cast<double>(this->VolumeVersion);
  signature.AddExact(&volumeTime, 1);

  // Camera, light and environment.
  double worldFromNdc[16];
  SetCamera(ren, width, height, p.Camera, worldFromNdc, signature);
  SetLighting(ren, settings, this->WorldBounds, p, signature);

  // Sampling and shading.
  p.StepWorld = static_cast<float>(step);
  p.ShadowStepScale = kShadowStepScale;
  p.RouletteThreshold = kRouletteThreshold;
  p.UnitDistance = static_cast<float>(std::max(1e-12, prop->GetScalarOpacityUnitDistance(0)));
  this->SetStepTables(p);
  p.Shade = prop->GetShade(0) ? 1 : 0;
  p.Ambient = static_cast<float>(prop->GetAmbient(0));
  p.Diffuse = static_cast<float>(prop->GetDiffuse(0));
  p.Specular = static_cast<float>(prop->GetSpecular(0));
  p.SpecularPower = static_cast<float>(prop->GetSpecularPower(0));
  p.Scattering = settings.Scattering ? 1 : 0;
  p.ExpectedCoverage = settings.ExpectedCoverage ? 1 : 0;
  const double coverage = static_cast<double>(p.ExpectedCoverage);
  signature.AddExact(&coverage, 1);
  // Not in the signature: a frame without the march stores Alpha as its Coverage, whose
  // expectation is the same opacity, and no other pass changes; so turning Denoise (and with
  // it a coverage model's march) on or off keeps the accumulation, as it always has.
  p.CoverageMarch = settings.CoverageMarch ? 1 : 0;
  // Not in the signature either: a frame without the rays stores Footprint 1 (not known to be
  // empty), which only keeps the accumulated mean above 0, where the denoiser keeps the pixel.
  p.FootprintRays = settings.FootprintRays ? 1 : 0;
  // Reach 0 sees no occluder at all (the unoccluded environment); 1 or more: the whole volume.
  const double reach = settings.AmbientOcclusionReach;
  p.AmbientOcclusion = settings.AmbientOcclusion && reach > 0.0 ? 1 : 0;
  if (p.AmbientOcclusion && reach < 1.0)
  {
    const double* b = this->WorldBounds;
    const double diagonal = std::sqrt((b[1] - b[0]) * (b[1] - b[0]) +
      (b[3] - b[2]) * (b[3] - b[2]) + (b[5] - b[4]) * (b[5] - b[4]));
    p.EnvironmentReach = static_cast<float>(std::max(reach * diagonal, 1e-30));
  }
  p.Nearest = this->Nearest;
  p.Seed = settings.Seed;
  const double misc[6] = { static_cast<double>(settings.Seed),
    static_cast<double>(settings.SamplesPerFrame), settings.Scattering ? 1.0 : 0.0,
    static_cast<double>(p.AmbientOcclusion), static_cast<double>(this->Nearest),
    static_cast<double>(p.EnvironmentReach) };
  signature.AddExact(misc, 6);

  // Opaque geometry: rays stop at the window depth already drawn.
  p.MaxDistance = SetGeometryLimits(zbuffer, p.Camera, worldFromNdc, this->MaxDistance, signature)
    ? this->MaxDistance.data()
    : nullptr;
  return true;
}

//------------------------------------------------------------------------------
void FrameInputs::SetStepTables(TraceParams& p)
{
  TransferTable& tf = p.Transfer;
  if (tf.GradientOpacity || !tf.RGBA || tf.Size <= 0)
  {
    return; // the gradient factor scales alpha before the correction: corrected per sample
  }
  const float camera = StepOverUnit(p, p.StepWorld);
  const float shadow = StepOverUnit(p, ShadowStep(p));
  if (this->StepRGBA.empty() || camera != this->StepTableKey[0] ||
    shadow != this->StepTableKey[1])
  {
    this->StepRGBA.resize(4 * static_cast<std::size_t>(tf.Size));
    this->ShadowAlpha.resize(static_cast<std::size_t>(tf.Size));
    BuildStepTables(tf, camera, shadow, this->StepRGBA.data(), this->ShadowAlpha.data());
    this->StepTableKey[0] = camera;
    this->StepTableKey[1] = shadow;
  }
  tf.StepRGBA = this->StepRGBA.data();
  tf.ShadowAlpha = this->ShadowAlpha.data();
}
}
