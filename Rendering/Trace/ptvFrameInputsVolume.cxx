// FrameInputs, the volume's part: the voxels as the kernels read them (float copy, value
// ranges, the piece of a split volume) and the iso values in the voxels' storage.
#include "ptvFrameInputs.h"

#include "ptvScalarChannel.h"
#include "ptvSceneToKernel.h"
#include "ptvThreads.h"

#include "vtkDataArray.h"
#include "vtkImageData.h"

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
// A table range that is not empty (a constant channel gets +-0.5).
void WidenRange(double range[2])
{
  if (!(range[1] > range[0]))
  {
    range[0] -= 0.5;
    range[1] += 0.5;
  }
}
}

//------------------------------------------------------------------------------
bool FrameInputs::UpdateVolume(vtkImageData* image, vtkDataArray* scalars, bool dependent,
  std::string& error, vtkIdType& nonFinite)
{
  nonFinite = 0;
  std::ostringstream msg;
  if (!image)
  {
    error = "no input image (the mapper needs a vtkImageData)";
    return false;
  }
  int dims[3];
  image->GetDimensions(dims);
  if (dims[0] < 1 || dims[1] < 1 || dims[2] < 1)
  {
    msg << "empty volume (dimensions " << dims[0] << " x " << dims[1] << " x " << dims[2] << ")";
    error = msg.str();
    return false;
  }
  if (!scalars)
  {
    error = "the input has no point scalars to render (set the active scalars or choose an "
            "array with SelectScalarArray)";
    return false;
  }
  const int comps = scalars->GetNumberOfComponents();
  if (comps != 1 && !(dependent && (comps == 2 || comps == 4)))
  {
    msg << "array '" << (scalars->GetName() ? scalars->GetName() : "(unnamed)") << "' has "
        << comps << " components; the mapper renders single-component scalars, or dependent "
        << "colour data (vtkVolumeProperty IndependentComponents off) with 2 (colour value, "
        << "opacity value) or 4 (red, green, blue, opacity value) components"
        << (dependent ? "" : " (IndependentComponents is on)")
        << "; extract one component with vtkImageExtractComponents";
    error = msg.str();
    return false;
  }
  const vtkIdType n = static_cast<vtkIdType>(dims[0]) * dims[1] * dims[2];
  if (scalars->GetNumberOfTuples() != n)
  {
    msg << "array '" << (scalars->GetName() ? scalars->GetName() : "(unnamed)") << "' has "
        << scalars->GetNumberOfTuples() << " values but the image has " << n << " points";
    error = msg.str();
    return false;
  }
  const vtkMTimeType t = std::max(image->GetMTime(), scalars->GetMTime());
  if (scalars == this->VolumeArray && t <= this->VolumeTime && dependent == this->Dependent &&
    this->GetScalarData())
  {
    return true;
  }
  // The opacity channel (the last component) drives opacity, gradients and the occupancy. An
  // 8- or 16-bit (or plain float) channel is read in place; others are copied as float.
  this->InPlace = nullptr;
  std::vector<float>().swap(this->Scalars);
  double range[2];
  ChannelRangeOf(scalars, comps - 1, range, nonFinite);
  if (nonFinite == n)
  {
    error = "every voxel is NaN or infinite: nothing to render";
    return false;
  }
  const int inPlace = comps == 1 ? InPlaceScalarType(scalars, range, nonFinite) : -1;
  if (inPlace >= 0)
  {
    this->InPlace = scalars;
    this->ScalarType = inPlace;
    this->Shift = 0.0;
    this->Scale = 1.0;
  }
  else
  {
    this->Scalars.resize(static_cast<std::size_t>(n));
    StoreChannel(
      scalars, comps - 1, 1.0f, this->Scalars.data(), 1, range, this->Shift, this->Scale);
    this->ScalarType = kScalarFloat;
  }
  WidenRange(range);
  // Dependent colour: the colour channel (2 components, mapped by the colour function over its
  // own range) or RGB (4 components; unsigned char divided by 255, clamped to [0, 1]).
  this->ColorScalars.clear();
  this->Colors.clear();
  vtkIdType ignored = 0;
  if (comps == 2)
  {
    this->ColorScalars.resize(static_cast<std::size_t>(n));
    CopyChannel(scalars, 0, 1.0f, this->ColorScalars.data(), 1, this->ColorRange, ignored,
      this->ColorShift, this->ColorScale);
    if (!std::isfinite(this->ColorRange[0]))
    {
      this->ColorRange[0] = 0.0;
      this->ColorRange[1] = 1.0;
    }
    WidenRange(this->ColorRange);
  }
  else if (comps == 4)
  {
    this->Colors.resize(3 * static_cast<std::size_t>(n));
    const float scale = scalars->GetDataType() == VTK_UNSIGNED_CHAR ? 1.0f / 255.0f : 1.0f;
    double unused[2], shift, factor;
    for (int c = 0; c < 3; ++c)
    {
      CopyChannel(scalars, c, scale, this->Colors.data() + c, 3, unused, ignored, shift, factor);
    }
    for (float& v : this->Colors)
    {
      v = v == v ? std::min(1.0f, std::max(0.0f, v)) : 0.0f;
    }
  }
  this->Dependent = dependent;
  std::copy(dims, dims + 3, this->Dims);
  std::copy(range, range + 2, this->Range);
  std::copy(range, range + 2, this->LocalRange);
  std::copy(this->ColorRange, this->ColorRange + 2, this->LocalColorRange);
  this->Whole = false;
  this->VolumeArray = scalars;
  this->VolumeTime = t;
  ++this->VolumeVersion;
  this->TransferTime = 0; // the tables span the scalar range: rebuild them
  this->BrickRanges.clear();
  return true;
}

//------------------------------------------------------------------------------
void FrameInputs::SetWholeVolume(
  const double ranges[4], const double bounds[6], const double extent[6])
{
  const double* range = ranges ? ranges : this->LocalRange;
  const double* colorRange = ranges ? ranges + 2 : this->LocalColorRange;
  if (!std::equal(range, range + 2, this->Range) ||
    !std::equal(colorRange, colorRange + 2, this->ColorRange))
  {
    std::copy(range, range + 2, this->Range);
    std::copy(colorRange, colorRange + 2, this->ColorRange);
    this->TransferTime = 0; // the tables span the range: rebuild them
  }
  this->Whole = bounds != nullptr && extent != nullptr;
  if (this->Whole)
  {
    std::copy(bounds, bounds + 6, this->WholeBounds);
    std::copy(extent, extent + 6, this->WholeExtent);
  }
}

//------------------------------------------------------------------------------
void FrameInputs::GetLocalRanges(double ranges[4]) const
{
  std::copy(this->LocalRange, this->LocalRange + 2, ranges);
  std::copy(this->LocalColorRange, this->LocalColorRange + 2, ranges + 2);
}

//------------------------------------------------------------------------------
PieceView FrameInputs::GetPieceView(const TraceParams& p) const
{
  PieceView view;
  view.Box = this->OwnBox;
  const Vec3 eye = TransformPoint(p.Volume.WorldToIndex, p.Camera.Eye);
  Vec3 origin, dir;
  GenerateRay(p.Camera, 0.5f * static_cast<float>(p.Camera.Width),
    0.5f * static_cast<float>(p.Camera.Height), origin, dir);
  const Vec3 d = TransformVector(p.Volume.WorldToIndex, dir);
  const float e[3] = { eye.x, eye.y, eye.z };
  const float v[3] = { d.x, d.y, d.z };
  for (int a = 0; a < 3; ++a)
  {
    view.Eye[a] = e[a] + this->IndexOffset[a];
    view.Dir[a] = v[a];
  }
  view.Parallel = p.Camera.Parallel != 0;
  view.Far = p.Camera.FarDistance;
  return view;
}

//------------------------------------------------------------------------------
bool FrameInputs::SetPiece(const FrameSettings& settings, vtkImageData* image, TraceParams& p,
  FrameSignature& signature, std::string& error)
{
  int extent[6];
  image->GetExtent(extent);
  const double input[6] = { static_cast<double>(extent[0]), static_cast<double>(extent[1]),
    static_cast<double>(extent[2]), static_cast<double>(extent[3]),
    static_cast<double>(extent[4]), static_cast<double>(extent[5]) };
  const int* piece = settings.PieceExtent;
  const bool whole = piece[0] > piece[1] || piece[2] > piece[3] || piece[4] > piece[5];
  // The piece must lie inside the input (its ghost layers around it) and the whole volume.
  const std::pair<const double*, const char*> outers[2] = { { input, "the input's extent" },
    { this->Whole ? this->WholeExtent : nullptr, "the WholeExtent" } };
  for (const auto& outer : outers)
  {
    const double* o = outer.first;
    for (int a = 0; !whole && o && a < 3; ++a)
    {
      if (piece[2 * a] < o[2 * a] || piece[2 * a + 1] > o[2 * a + 1])
      {
        std::ostringstream msg;
        msg << "PieceExtent (" << piece[0] << ", " << piece[1] << ", " << piece[2] << ", "
            << piece[3] << ", " << piece[4] << ", " << piece[5] << ") is not inside "
            << outer.second << " (" << o[0] << ", " << o[1] << ", " << o[2] << ", " << o[3]
            << ", " << o[4] << ", " << o[5] << ")";
        error = msg.str();
        return false;
      }
    }
  }
  const int* own = whole ? extent : piece;
  p.CameraBoxed = whole || std::equal(piece, piece + 6, extent) ? 0 : 1;
  for (int i = 0; i < 6; ++i)
  {
    const double first = extent[2 * (i / 2)]; // the kernel's index 0
    this->OwnBox[i] = own[i];
    p.CameraBox[i] = static_cast<float>(own[i] - first);
    p.WholeBox[i] = static_cast<float>((this->Whole ? this->WholeExtent[i] : own[i]) - first);
  }
  for (int a = 0; a < 3; ++a)
  {
    this->IndexOffset[a] = extent[2 * a];
  }
  if (this->Whole)
  {
    signature.AddExact(this->WholeExtent, 6);
  }
  signature.AddExact(this->OwnBox.data(), 6);
  return true;
}

//------------------------------------------------------------------------------
float FrameInputs::Stored(double value) const
{
  return static_cast<float>((value - this->Shift) * this->Scale);
}

//------------------------------------------------------------------------------
IsoSurfaces FrameInputs::StoredIso(const IsoSurfaces& iso, const double* values) const
{
  IsoSurfaces out = iso;
  for (int i = 0; i < iso.Count; ++i)
  {
    // The double value when it is the float one's source (a caller that set only the floats
    // gets those), the float one as it is when not finite (+inf: crosses nothing).
    const double v = values && static_cast<float>(values[i]) == iso.Values[i]
      ? values[i]
      : static_cast<double>(iso.Values[i]);
    out.Values[i] = std::isfinite(v) ? this->Stored(v) : iso.Values[i];
  }
  return out;
}
}
