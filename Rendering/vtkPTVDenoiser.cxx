#include "vtkPTVDenoiser.h"

#include "ptvDataDirectory.h"
#include "ptvDenoiser.h"
#include "ptvDenoiserImages.h"
#include "ptvGuideNetSession.h"
#include "ptvPassBuffers.h"

#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"

#include <algorithm>
#include <string>
#include <vector>

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

struct vtkPTVDenoiser::vtkInternals
{
  ptv::DenoiserImages Images;
  ptv::DenoiserSettings Settings; // the grid steps live here
  ptv::Denoiser Core;
  vtkNew<vtkImageData> Output;
  int Width = 0;
  int Height = 0;
};

vtkStandardNewMacro(vtkPTVDenoiser);

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
std::string vtkPTVDenoiser::GetDefaultModelFile()
{
  return ptv::DefaultModelFile();
}

//------------------------------------------------------------------------------
std::string vtkPTVDenoiser::GetRuntimeVersion()
{
  return ptv::GuideNetSession::GetRuntimeVersion();
}

//------------------------------------------------------------------------------
void vtkPTVDenoiser::SetImage(const char* name, vtkImageData* image)
{
  if (!this->Internals->Images.Set(name, image))
  {
    vtkErrorMacro(<< "Unknown image name '" << (name ? name : "(null)")
                  << "'; use the pass names of vtkPathTracedVolumeMapper (Radiance, Albedo, "
                     "Normal, Depth, ...) or "
                  << ptv::DenoiserImages::kStageNames << ".");
    return;
  }
  this->Modified();
}

//------------------------------------------------------------------------------
vtkImageData* vtkPTVDenoiser::GetImage(const char* name)
{
  return this->Internals->Images.Get(name);
}

//------------------------------------------------------------------------------
void vtkPTVDenoiser::RemoveAllImages()
{
  this->Internals->Images.Clear();
  this->Modified();
}

//------------------------------------------------------------------------------
void vtkPTVDenoiser::SetSpatialStep(int level, int step)
{
  this->SetStep(level, step, this->Internals->Settings.SpatialStep, "SetSpatialStep");
}

//------------------------------------------------------------------------------
void vtkPTVDenoiser::SetRangeStep(int level, int step)
{
  this->SetStep(level, step, this->Internals->Settings.RangeStep, "SetRangeStep");
}

//------------------------------------------------------------------------------
int vtkPTVDenoiser::GetSpatialStep(int level)
{
  return this->GetStep(level, this->Internals->Settings.SpatialStep, "GetSpatialStep");
}

//------------------------------------------------------------------------------
int vtkPTVDenoiser::GetRangeStep(int level)
{
  return this->GetStep(level, this->Internals->Settings.RangeStep, "GetRangeStep");
}

//------------------------------------------------------------------------------
void vtkPTVDenoiser::SetStep(int level, int step, int* steps, const char* what)
{
  if (level < 0 || level >= ptv::kMaxGridLevels)
  {
    vtkErrorMacro(<< what << ": level " << level << " is out of range [0, "
                  << ptv::kMaxGridLevels - 1 << "]");
    return;
  }
  step = std::min(std::max(step, 1), ptv::kMaxGridStep);
  if (steps[level] != step)
  {
    steps[level] = step;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
int vtkPTVDenoiser::GetStep(int level, const int* steps, const char* what)
{
  if (level < 0 || level >= ptv::kMaxGridLevels)
  {
    vtkErrorMacro(<< what << ": level " << level << " is out of range [0, "
                  << ptv::kMaxGridLevels - 1 << "]");
    return 0;
  }
  return steps[level];
}

//------------------------------------------------------------------------------
bool vtkPTVDenoiser::Execute()
{
  vtkInternals& in = *this->Internals;
  const float* passes[ptv::PassCount] = {};
  int w = 0, h = 0;
  ptv::DenoiserOverrides given;
  std::string error;
  if (!in.Images.Resolve(passes, w, h, given, error))
  {
    vtkErrorMacro(<< error);
    return false;
  }

  ptv::DenoiserSettings& settings = in.Settings;
  settings.ModelFile = this->ModelFile ? this->ModelFile : "";
  settings.UseNetwork = this->UseNetwork;
  settings.Levels = this->NumberOfLevels;
  settings.Clamp = this->Clamp;
  settings.Threads = this->NumberOfThreads;
  settings.PortableKernels = this->PortableKernels;
  settings.UseCuda = this->UseCuda;
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
  vtkSmartPointer<vtkFloatArray> alpha;
  if (this->DenoiseAlpha)
  {
    alpha = vtkFloatArray::SafeDownCast(in.Output->GetPointData()->GetArray("DenoisedAlpha"));
    if (!reuse || !alpha || alpha->GetNumberOfTuples() != pixels)
    {
      alpha = vtkSmartPointer<vtkFloatArray>::New();
      alpha->SetName("DenoisedAlpha");
      alpha->SetNumberOfComponents(1);
      alpha->SetNumberOfTuples(pixels);
    }
  }
  if (!in.Core.Run(settings, passes, w, h, result->GetPointer(0), error, &given,
        alpha ? alpha->GetPointer(0) : nullptr))
  {
    vtkErrorMacro(<< (this->DenoiseAlpha && !passes[ptv::PassAlpha]
                         ? "DenoiseAlpha is on but there is no 'Alpha' image"
                         : error));
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
  if (alpha)
  {
    in.Output->GetPointData()->AddArray(alpha);
    alpha->Modified();
  }
  else
  {
    in.Output->GetPointData()->RemoveArray("DenoisedAlpha");
  }
  vtkImageData* radiance = in.Images.Get("Radiance");
  in.Output->SetOrigin(radiance->GetOrigin());
  in.Output->SetSpacing(radiance->GetSpacing());
  in.Output->SetDirectionMatrix(radiance->GetDirectionMatrix());
  result->Modified();
  in.Output->Modified();
  return true;
}

//------------------------------------------------------------------------------
bool vtkPTVDenoiser::GetLastGridOnCuda()
{
  return this->Internals->Core.GetGridOnCuda();
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
double vtkPTVDenoiser::GetLastAlphaTime()
{
  return this->Internals->Core.GetTimings().Alpha;
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
  os << indent << "UseCuda: " << this->UseCuda << " (last grid on "
     << (this->Internals->Core.GetGridOnCuda() ? "CUDA" : "the CPU") << ")\n";
  os << indent << "DenoiseAlpha: " << this->DenoiseAlpha << "\n";
  const ptv::DenoiserSettings& s = this->Internals->Settings;
  for (int l = 0; l < ptv::kMaxGridLevels; ++l)
  {
    os << indent << "Level " << l << ": SpatialStep " << s.SpatialStep[l] << ", RangeStep "
       << s.RangeStep[l] << "\n";
  }
  os << indent << "Status: " << this->Internals->Core.GetStatus() << "\n";
}
