#include "vtkPTVGuideNet.h"

#include "ptvDataDirectory.h"
#include "ptvGuideNetSession.h"

#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <vector>

namespace
{
const char* const OutputArrayName = "GuidesWeights";

// Layout conversions work on blocks of pixels: within a block, one channel plane at a time, so
// that C planes a power-of-two apart are never written (read) in lockstep. The plain per-pixel
// loop thrashes the cache through set aliasing for C > ~12 at 512^2/1024^2 (5x slower at C=14).
constexpr vtkIdType BlockPixels = 256;

/// Point-interleaved (n x c) -> planar (c x n).
void ToPlanar(const float* src, int c, vtkIdType n, float* dst)
{
  const vtkIdType blocks = (n + BlockPixels - 1) / BlockPixels;
  vtkSMPTools::For(0, blocks, [&](vtkIdType b0, vtkIdType b1) {
    for (vtkIdType p0 = b0 * BlockPixels; p0 < std::min(n, b1 * BlockPixels); p0 += BlockPixels)
    {
      const vtkIdType p1 = std::min(n, p0 + BlockPixels);
      for (int k = 0; k < c; ++k)
      {
        float* out = dst + k * n;
        const float* in = src + k;
        for (vtkIdType p = p0; p < p1; ++p)
        {
          out[p] = in[p * c];
        }
      }
    }
  });
}

/// Planar (c x n) -> point-interleaved (n x c).
void ToInterleaved(const float* src, int c, vtkIdType n, float* dst)
{
  const vtkIdType blocks = (n + BlockPixels - 1) / BlockPixels;
  vtkSMPTools::For(0, blocks, [&](vtkIdType b0, vtkIdType b1) {
    for (vtkIdType p0 = b0 * BlockPixels; p0 < std::min(n, b1 * BlockPixels); p0 += BlockPixels)
    {
      const vtkIdType p1 = std::min(n, p0 + BlockPixels);
      for (int k = 0; k < c; ++k)
      {
        const float* in = src + k * n;
        float* out = dst + k;
        for (vtkIdType p = p0; p < p1; ++p)
        {
          out[p * c] = in[p];
        }
      }
    }
  });
}
}

struct vtkPTVGuideNet::vtkInternals
{
  ptv::GuideNetSession Session;
  std::string LoadedFile;
  int LoadedThreads = -1;
  std::vector<float> Planar;    // C x H x W network input
  std::vector<float> PlanarOut; // (2L - 1) x H x W network output
};

vtkStandardNewMacro(vtkPTVGuideNet);

//------------------------------------------------------------------------------
vtkPTVGuideNet::vtkPTVGuideNet()
  : Internals(new vtkInternals)
{
}

//------------------------------------------------------------------------------
vtkPTVGuideNet::~vtkPTVGuideNet()
{
  this->SetModelFile(nullptr);
}

//------------------------------------------------------------------------------
std::string vtkPTVGuideNet::GetDefaultModelFile()
{
  return ptv::DataDirectory() + "/Models/guidenet.onnx";
}

//------------------------------------------------------------------------------
std::string vtkPTVGuideNet::GetRuntimeVersion()
{
  return ptv::GuideNetSession::GetRuntimeVersion();
}

//------------------------------------------------------------------------------
bool vtkPTVGuideNet::Load()
{
  vtkInternals& in = *this->Internals;
  in.Session.Unload();
  in.LoadedFile.clear();
  in.LoadedThreads = -1;
  if (!this->ModelFile || !*this->ModelFile)
  {
    vtkErrorMacro("No ModelFile set (the shipped model is " << GetDefaultModelFile() << ").");
    return false;
  }
  in.Session.SetNumberOfThreads(this->NumberOfThreads);
  std::string error;
  if (!in.Session.Load(this->ModelFile, error))
  {
    vtkErrorMacro("Cannot load GuideNet model " << error);
    return false;
  }
  in.LoadedFile = this->ModelFile;
  in.LoadedThreads = this->NumberOfThreads;
  vtkDebugMacro("Loaded " << this->ModelFile << " on " << in.Session.GetExecutionProvider());
  return true;
}

//------------------------------------------------------------------------------
bool vtkPTVGuideNet::IsLoaded() const
{
  return this->Internals->Session.IsLoaded();
}

//------------------------------------------------------------------------------
int vtkPTVGuideNet::GetNumberOfInputChannels() const
{
  return this->Internals->Session.GetNumberOfInputChannels();
}

//------------------------------------------------------------------------------
const char* vtkPTVGuideNet::GetInputChannelName(int index) const
{
  const auto& channels = this->Internals->Session.GetInputChannels();
  if (index < 0 || index >= static_cast<int>(channels.size()))
  {
    return nullptr;
  }
  return channels[index].c_str();
}

//------------------------------------------------------------------------------
int vtkPTVGuideNet::GetNumberOfLevels() const
{
  return this->Internals->Session.GetNumberOfLevels();
}

//------------------------------------------------------------------------------
int vtkPTVGuideNet::GetNumberOfOutputs() const
{
  return this->IsLoaded() ? this->Internals->Session.GetNumberOfOutputs() : 0;
}

//------------------------------------------------------------------------------
int vtkPTVGuideNet::GetSpatialStep(int level) const
{
  const auto& levels = this->Internals->Session.GetLevels();
  return level >= 0 && level < static_cast<int>(levels.size()) ? levels[level].first : 0;
}

//------------------------------------------------------------------------------
int vtkPTVGuideNet::GetRangeStep(int level) const
{
  const auto& levels = this->Internals->Session.GetLevels();
  return level >= 0 && level < static_cast<int>(levels.size()) ? levels[level].second : 0;
}

//------------------------------------------------------------------------------
double vtkPTVGuideNet::GetGuideScale() const
{
  return this->Internals->Session.GetGuideScale();
}

//------------------------------------------------------------------------------
const char* vtkPTVGuideNet::GetExecutionProvider() const
{
  const std::string& provider = this->Internals->Session.GetExecutionProvider();
  return provider.empty() ? nullptr : provider.c_str();
}

//------------------------------------------------------------------------------
bool vtkPTVGuideNet::Run(vtkImageData* features, vtkImageData* output)
{
  vtkInternals& in = *this->Internals;
  if (!features || !output)
  {
    vtkErrorMacro("Run needs a features image and an output image.");
    return false;
  }
  if (features == output)
  {
    vtkErrorMacro("Run needs an output image distinct from the features image.");
    return false;
  }
  if (!in.Session.IsLoaded() || !this->ModelFile || in.LoadedFile != this->ModelFile ||
    in.LoadedThreads != this->NumberOfThreads)
  {
    if (!this->Load())
    {
      return false;
    }
  }
  const auto start = std::chrono::steady_clock::now();

  int dims[3];
  features->GetDimensions(dims);
  const int w = dims[0];
  const int h = dims[1];
  if (w < 1 || h < 1 || dims[2] != 1)
  {
    vtkErrorMacro("The features image must be W x H x 1, got " << dims[0] << " x " << dims[1]
                                                               << " x " << dims[2] << ".");
    return false;
  }
  vtkPointData* pd = features->GetPointData();
  vtkDataArray* array = pd->GetScalars();
  if (!array && pd->GetNumberOfArrays() == 1)
  {
    array = pd->GetArray(0);
  }
  if (!array)
  {
    vtkErrorMacro("The features image has no active scalars and "
      << pd->GetNumberOfArrays() << " point-data arrays; expected one float array.");
    return false;
  }
  const char* name = array->GetName() ? array->GetName() : "(unnamed)";
  vtkFloatArray* floats = vtkArrayDownCast<vtkFloatArray>(array);
  if (!floats)
  {
    vtkErrorMacro("Features array '" << name << "' is " << array->GetDataTypeAsString()
                                     << ", expected float.");
    return false;
  }
  const int c = this->GetNumberOfInputChannels();
  if (floats->GetNumberOfComponents() != c)
  {
    std::string channels;
    for (int k = 0; k < c; ++k)
    {
      channels += (k ? "," : "") + std::string(this->GetInputChannelName(k));
    }
    vtkErrorMacro("Features array '" << name << "' has " << floats->GetNumberOfComponents()
                                     << " components but the model " << this->ModelFile
                                     << " expects " << c << " channels: " << channels << ".");
    return false;
  }
  const vtkIdType pixels = static_cast<vtkIdType>(w) * h;
  if (floats->GetNumberOfTuples() != pixels)
  {
    vtkErrorMacro("Features array '" << name << "' has " << floats->GetNumberOfTuples()
                                     << " tuples, the image has " << pixels << " points.");
    return false;
  }

  const int o = this->GetNumberOfOutputs();
  in.Planar.resize(static_cast<size_t>(pixels) * c);
  in.PlanarOut.resize(static_cast<size_t>(pixels) * o);
  ToPlanar(floats->GetPointer(0), c, pixels, in.Planar.data());
  std::string error;
  if (!in.Session.Run(in.Planar.data(), h, w, in.PlanarOut.data(), error))
  {
    vtkErrorMacro(<< error);
    return false;
  }

  // Reuse the output's array when it already has the right shape.
  vtkSmartPointer<vtkFloatArray> result =
    vtkArrayDownCast<vtkFloatArray>(output->GetPointData()->GetArray(OutputArrayName));
  if (!result || result->GetNumberOfComponents() != o || result->GetNumberOfTuples() != pixels)
  {
    result = vtkSmartPointer<vtkFloatArray>::New();
    result->SetName(OutputArrayName);
    result->SetNumberOfComponents(o);
    result->SetNumberOfTuples(pixels);
  }
  ToInterleaved(in.PlanarOut.data(), o, pixels, result->GetPointer(0));
  result->Modified();
  output->CopyStructure(features);
  output->GetPointData()->Initialize();
  output->GetPointData()->SetScalars(result);
  output->Modified();

  this->LastRunTime =
    std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return true;
}

//------------------------------------------------------------------------------
void vtkPTVGuideNet::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ModelFile: " << (this->ModelFile ? this->ModelFile : "(none)") << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
  os << indent << "LastRunTime: " << this->LastRunTime << " ms\n";
  os << indent << "Loaded: " << (this->IsLoaded() ? "yes" : "no") << "\n";
  if (this->IsLoaded())
  {
    os << indent << "ExecutionProvider: " << this->GetExecutionProvider() << "\n";
    os << indent << "InputChannels:";
    for (int k = 0; k < this->GetNumberOfInputChannels(); ++k)
    {
      os << " " << this->GetInputChannelName(k);
    }
    os << "\n" << indent << "Levels (ss:sr):";
    for (int l = 0; l < this->GetNumberOfLevels(); ++l)
    {
      os << " " << this->GetSpatialStep(l) << ":" << this->GetRangeStep(l);
    }
    os << "\n" << indent << "GuideScale: " << this->GetGuideScale() << "\n";
  }
}
