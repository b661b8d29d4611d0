#include "ptvDenoiserImages.h"

#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkPointData.h"

#include <cstring>
#include <sstream>

namespace ptv
{
namespace
{
const char* const kExtraNames[] = { "Features", "Guides", "BlendWeights" };

/// One image's float array; @a why says what is wrong when it returns nullptr.
vtkFloatArray* ImageArray(vtkImageData* image, const char* name, std::string& why)
{
  int dims[3];
  image->GetDimensions(dims);
  vtkDataArray* scalars = image->GetPointData()->GetScalars();
  if (!scalars && image->GetPointData()->GetNumberOfArrays() == 1)
  {
    scalars = image->GetPointData()->GetArray(0);
  }
  std::ostringstream s;
  s << "Image '" << name << "' ";
  if (dims[0] < 1 || dims[1] < 1 || dims[2] != 1)
  {
    s << "must be a W x H x 1 image (W, H >= 1); got " << dims[0] << " x " << dims[1] << " x "
      << dims[2] << ".";
  }
  else if (!scalars)
  {
    s << "has no point array (no active scalars and not exactly one array).";
  }
  else if (!vtkFloatArray::SafeDownCast(scalars))
  {
    s << "holds " << scalars->GetDataTypeAsString() << " values ('"
      << (scalars->GetName() ? scalars->GetName() : "unnamed") << "'); expected float.";
  }
  else if (scalars->GetNumberOfTuples() != static_cast<vtkIdType>(dims[0]) * dims[1])
  {
    s << "has " << scalars->GetNumberOfTuples() << " tuples for " << dims[0] << " x " << dims[1]
      << " points.";
  }
  else
  {
    return vtkFloatArray::SafeDownCast(scalars);
  }
  why = s.str();
  return nullptr;
}

std::string Size(int w, int h)
{
  return std::to_string(w) + " x " + std::to_string(h);
}
}

//------------------------------------------------------------------------------
int DenoiserImages::FindExtra(const char* name)
{
  for (int e = 0; e < ExtraCount; ++e)
  {
    if (name && std::strcmp(name, kExtraNames[e]) == 0)
    {
      return e;
    }
  }
  return -1;
}

//------------------------------------------------------------------------------
bool DenoiserImages::Set(const char* name, vtkImageData* image)
{
  const int extra = FindExtra(name); // before the passes: the mapper has output passes so named
  const int pass = extra < 0 ? FindPass(name) : -1;
  if (pass < 0 && extra < 0)
  {
    return false;
  }
  (pass >= 0 ? this->Passes[pass] : this->Extras[extra]) = image;
  return true;
}

//------------------------------------------------------------------------------
vtkImageData* DenoiserImages::Get(const char* name) const
{
  const int extra = FindExtra(name);
  const int pass = extra < 0 ? FindPass(name) : -1;
  return pass >= 0 ? this->Passes[pass].GetPointer()
                   : (extra >= 0 ? this->Extras[extra].GetPointer() : nullptr);
}

//------------------------------------------------------------------------------
void DenoiserImages::Clear()
{
  for (auto& image : this->Passes)
  {
    image = nullptr;
  }
  for (auto& image : this->Extras)
  {
    image = nullptr;
  }
}

//------------------------------------------------------------------------------
bool DenoiserImages::Resolve(const float* passes[PassCount], int& width, int& height,
  DenoiserOverrides& given, std::string& error) const
{
  int w = -1, h = -1;
  for (int p = 0; p < PassCount; ++p)
  {
    passes[p] = nullptr;
    vtkImageData* image = this->Passes[p];
    if (!image)
    {
      continue;
    }
    const char* name = GetPassInfo(p).Name;
    vtkFloatArray* floats = ImageArray(image, name, error);
    if (!floats)
    {
      return false;
    }
    const int comps = GetPassInfo(p).Components;
    if (floats->GetNumberOfComponents() != comps)
    {
      error = std::string("Image '") + name + "' has " +
        std::to_string(floats->GetNumberOfComponents()) + " components; the pass has " +
        std::to_string(comps) + ".";
      return false;
    }
    int dims[3];
    image->GetDimensions(dims);
    if (w >= 0 && (dims[0] != w || dims[1] != h))
    {
      error = std::string("Image '") + name + "' is " + Size(dims[0], dims[1]) +
        " but the other images are " + Size(w, h) + ".";
      return false;
    }
    w = dims[0];
    h = dims[1];
    passes[p] = floats->GetPointer(0);
  }
  if (!passes[PassRadiance])
  {
    error = "No Radiance image: set at least Radiance (and Albedo, Normal, Depth, ... as the "
            "model needs).";
    return false;
  }
  width = w;
  height = h;

  // The images that replace a stage: Features at the network's size (checked against the model
  // later), Guides and BlendWeights at the frame's.
  given = DenoiserOverrides{};
  vtkFloatArray* extras[ExtraCount] = {};
  for (int e = 0; e < ExtraCount; ++e)
  {
    if (!this->Extras[e])
    {
      continue;
    }
    extras[e] = ImageArray(this->Extras[e], kExtraNames[e], error);
    if (!extras[e])
    {
      return false;
    }
    int dims[3];
    this->Extras[e]->GetDimensions(dims);
    if (e == ExtraFeatures)
    {
      given.Features = extras[e]->GetPointer(0);
      given.FeatureChannels = extras[e]->GetNumberOfComponents();
      given.FeatureWidth = dims[0];
      given.FeatureHeight = dims[1];
    }
    else if (dims[0] != w || dims[1] != h)
    {
      error = std::string("Image '") + kExtraNames[e] + "' is " + Size(dims[0], dims[1]) +
        " but the passes are " + Size(w, h) + ".";
      return false;
    }
  }
  if (!extras[ExtraGuides])
  {
    if (extras[ExtraWeights])
    {
      error = "Image 'BlendWeights' is set without 'Guides'.";
      return false;
    }
    return true;
  }
  given.Guides = extras[ExtraGuides]->GetPointer(0);
  given.GuideLevels = extras[ExtraGuides]->GetNumberOfComponents();
  if (extras[ExtraWeights])
  {
    const int comps = extras[ExtraWeights]->GetNumberOfComponents();
    if (comps != given.GuideLevels - 1)
    {
      error = "Image 'BlendWeights' has " + std::to_string(comps) + " components; " +
        std::to_string(given.GuideLevels) + " levels of 'Guides' need " +
        std::to_string(given.GuideLevels - 1) + ".";
      return false;
    }
    given.Weights = extras[ExtraWeights]->GetPointer(0);
  }
  return true;
}
}
