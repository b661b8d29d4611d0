#include "vtkPTVDenoiser.h"

#include "ptvDenoiser.h"
#include "ptvPassBuffers.h"

#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"

#include <sstream>
#include <string>
#include <vector>

struct vtkPTVDenoiser::vtkInternals
{
  vtkSmartPointer<vtkImageData> Images[ptv::PassCount];
  ptv::Denoiser Core;
  vtkNew<vtkImageData> Output;
  int Width = 0;
  int Height = 0;
  std::string Status;
};

vtkStandardNewMacro(vtkPTVDenoiser);

namespace
{
void MakeImage(vtkImageData* image, int w, int h, const char* name, int comps, const float* data)
{
  vtkNew<vtkFloatArray> array;
  array->SetName(name);
  array->SetNumberOfComponents(comps);
  array->SetNumberOfTuples(static_cast<vtkIdType>(w) * h);
  std::copy(data, data + static_cast<std::size_t>(w) * h * comps, array->GetPointer(0));
  image->Initialize();
  image->SetDimensions(w, h, 1);
  image->GetPointData()->SetScalars(array);
}
}

//------------------------------------------------------------------------------
vtkPTVDenoiser::vtkPTVDenoiser()
  : Internals(new vtkInternals)
{
}

//------------------------------------------------------------------------------
vtkPTVDenoiser::~vtkPTVDenoiser()
{
  this->SetModelFile(nullptr);
}

//------------------------------------------------------------------------------
void vtkPTVDenoiser::SetImage(const char* name, vtkImageData* image)
{
  const int pass = ptv::FindPass(name);
  if (pass < 0)
  {
    vtkErrorMacro(<< "Unknown image name '" << (name ? name : "(null)")
                  << "'; use the pass names of vtkPathTracedVolumeMapper (Radiance, Albedo, "
                     "Normal, Depth, ...).");
    return;
  }
  this->Internals->Images[pass] = image;
  this->Modified();
}

//------------------------------------------------------------------------------
vtkImageData* vtkPTVDenoiser::GetImage(const char* name)
{
  const int pass = ptv::FindPass(name);
  return pass < 0 ? nullptr : this->Internals->Images[pass].GetPointer();
}

//------------------------------------------------------------------------------
void vtkPTVDenoiser::RemoveAllImages()
{
  for (auto& image : this->Internals->Images)
  {
    image = nullptr;
  }
  this->Modified();
}

//------------------------------------------------------------------------------
bool vtkPTVDenoiser::Execute()
{
  vtkInternals& in = *this->Internals;
  const float* passes[ptv::PassCount] = {};
  int w = -1, h = -1;
  for (int p = 0; p < ptv::PassCount; ++p)
  {
    vtkImageData* image = in.Images[p];
    if (!image)
    {
      continue;
    }
    const char* name = ptv::GetPassInfo(p).Name;
    int dims[3];
    image->GetDimensions(dims);
    vtkDataArray* scalars = image->GetPointData()->GetScalars();
    if (!scalars && image->GetPointData()->GetNumberOfArrays() == 1)
    {
      scalars = image->GetPointData()->GetArray(0);
    }
    auto* floats = vtkFloatArray::SafeDownCast(scalars);
    const int comps = ptv::GetPassInfo(p).Components;
    if (!floats || floats->GetNumberOfComponents() != comps || dims[2] != 1 ||
      floats->GetNumberOfTuples() != static_cast<vtkIdType>(dims[0]) * dims[1])
    {
      vtkErrorMacro(<< "Image '" << name << "' must be a W x H x 1 image with a float array of "
                    << comps << " component(s); got "
                    << (scalars ? scalars->GetDataTypeAsString() : "no array") << " with "
                    << (scalars ? scalars->GetNumberOfComponents() : 0) << " component(s), "
                    << dims[0] << " x " << dims[1] << " x " << dims[2] << ".");
      return false;
    }
    if (w >= 0 && (dims[0] != w || dims[1] != h))
    {
      vtkErrorMacro(<< "Image '" << name << "' is " << dims[0] << " x " << dims[1]
                    << " but the other images are " << w << " x " << h << ".");
      return false;
    }
    w = dims[0];
    h = dims[1];
    passes[p] = floats->GetPointer(0);
  }
  if (w <= 0 || h <= 0)
  {
    vtkErrorMacro(<< "No usable images: set at least Radiance and Albedo (non-empty).");
    return false;
  }

  ptv::DenoiserSettings settings;
  settings.ModelFile = this->ModelFile ? this->ModelFile : "";
  settings.UseNetwork = this->UseNetwork;
  settings.Levels = this->NumberOfLevels;
  settings.Clamp = this->Clamp;
  settings.Threads = this->NumberOfThreads;
  settings.PortableKernels = this->PortableKernels;
  // The result goes straight into the output's "Denoised" array, reused while the size stays
  // (no allocation per frame); a new array is attached only after a successful run.
  const vtkIdType pixels = static_cast<vtkIdType>(w) * h;
  vtkSmartPointer<vtkFloatArray> result =
    vtkFloatArray::SafeDownCast(in.Output->GetPointData()->GetArray("Denoised"));
  int outDims[3];
  in.Output->GetDimensions(outDims);
  const bool reuse = result && result->GetNumberOfComponents() == 3 &&
    result->GetNumberOfTuples() == pixels && outDims[0] == w && outDims[1] == h;
  if (!reuse)
  {
    result = vtkSmartPointer<vtkFloatArray>::New();
    result->SetName("Denoised");
    result->SetNumberOfComponents(3);
    result->SetNumberOfTuples(pixels);
  }
  std::string error;
  if (!in.Core.Run(settings, passes, w, h, result->GetPointer(0), error))
  {
    vtkErrorMacro(<< error);
    return false;
  }
  const std::string warning = in.Core.TakeWarning();
  if (!warning.empty())
  {
    vtkWarningMacro(<< warning);
  }
  in.Width = w;
  in.Height = h;
  if (!reuse)
  {
    in.Output->Initialize();
    in.Output->SetDimensions(w, h, 1);
    in.Output->GetPointData()->SetScalars(result);
  }
  result->Modified();
  in.Output->Modified();
  return true;
}

//------------------------------------------------------------------------------
vtkImageData* vtkPTVDenoiser::GetOutput()
{
  return this->Internals->Output;
}

//------------------------------------------------------------------------------
void vtkPTVDenoiser::GetGuides(vtkImageData* output)
{
  vtkInternals& in = *this->Internals;
  if (output && in.Width > 0 && in.Core.GetLevels() > 0) // none from an image model
  {
    MakeImage(output, in.Width, in.Height, "Guides", in.Core.GetLevels(),
      in.Core.GetGuides().data());
  }
}

//------------------------------------------------------------------------------
void vtkPTVDenoiser::GetBlendWeights(vtkImageData* output)
{
  vtkInternals& in = *this->Internals;
  if (output && in.Width > 0 && in.Core.GetLevels() > 1)
  {
    MakeImage(output, in.Width, in.Height, "BlendWeights", in.Core.GetLevels() - 1,
      in.Core.GetWeights().data());
  }
}

//------------------------------------------------------------------------------
bool vtkPTVDenoiser::GetNetworkActive()
{
  return this->Internals->Core.GetNetworkActive();
}

//------------------------------------------------------------------------------
const char* vtkPTVDenoiser::GetStatus()
{
  return this->Internals->Core.GetStatus().c_str();
}

//------------------------------------------------------------------------------
const char* vtkPTVDenoiser::GetKernelTarget()
{
  return this->Internals->Core.GetGridKernelTarget();
}

//------------------------------------------------------------------------------
double vtkPTVDenoiser::GetLastFeatureTime()
{
  return this->Internals->Core.GetTimings().Features;
}

//------------------------------------------------------------------------------
double vtkPTVDenoiser::GetLastGuideNetTime()
{
  return this->Internals->Core.GetTimings().GuideNet;
}

//------------------------------------------------------------------------------
double vtkPTVDenoiser::GetLastSplatTime()
{
  return this->Internals->Core.GetTimings().Splat;
}

//------------------------------------------------------------------------------
double vtkPTVDenoiser::GetLastSliceTime()
{
  return this->Internals->Core.GetTimings().Slice;
}

//------------------------------------------------------------------------------
void vtkPTVDenoiser::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ModelFile: " << (this->ModelFile ? this->ModelFile : "(shipped model)") << "\n";
  os << indent << "UseNetwork: " << this->UseNetwork << "\n";
  os << indent << "NumberOfLevels: " << this->NumberOfLevels << "\n";
  os << indent << "Clamp: " << this->Clamp << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
  os << indent << "PortableKernels: " << this->PortableKernels << "\n";
  os << indent << "Status: " << this->Internals->Core.GetStatus() << "\n";
}
