#include "vtkPathTracedVolumeMapper.h"

#include "ptvCpuTracer.h"
#include "ptvCudaDevice.h"
#include "ptvCudaTracer.h"
#include "ptvDenoiser.h"
#include "ptvDisplay.h"
#include "ptvFrameInputs.h"
#include "ptvKernelDispatch.h"
#include "ptvPassBuffers.h"
#include "ptvThreads.h"

#include "vtkCamera.h"
#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkMatrix4x4.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTimerLog.h"
#include "vtkVolume.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

struct vtkPathTracedVolumeMapper::vtkInternals
{
  ptv::FrameInputs Inputs;
  ptv::PassBuffers Frame;
  ptv::PassBuffers Accumulated;
  ptv::Denoiser Denoiser;
  ptv::CudaTracer Cuda;
  std::string ActiveBackend = "none";
  std::string BackendMessage; // the last backend problem reported (reported once)
  std::vector<float> DenoiseOutput;
  bool DenoisedValid = false;       // the Denoised/Guides/BlendWeights passes match the frame
  std::vector<std::string> DenoiseKey; // settings of the last denoise
  ptv::Display Display;
  ptv::TraceParams Params{};
  ptv::FrameSignature Signature;
  std::vector<float> ZBuffer;
  std::vector<float> ShownColor;
  std::vector<float> ShownDepth;
  std::string LastError;
  vtkIdType LastNonFinite = 0;
};

vtkStandardNewMacro(vtkPathTracedVolumeMapper);

namespace
{
// Colour a pass for display: opaque, [0,1], misses black.
void Colorize(int pass, const ptv::PassBuffers& acc, const double* bounds, float far,
  std::vector<float>& rgba)
{
  const int n = acc.GetWidth() * acc.GetHeight();
  const int comps = ptv::GetPassInfo(pass).Components;
  const float* data = acc.Data(pass);
  float lo = std::numeric_limits<float>::max(), hi = -lo;
  if (comps == 1 && pass != ptv::PassAlpha)
  {
    for (int i = 0; i < n; ++i)
    {
      if (ptv::IsHit(data[i], far))
      {
        lo = std::min(lo, data[i]);
        hi = std::max(hi, data[i]);
      }
    }
  }
  for (int i = 0; i < n; ++i)
  {
    rgba[4 * i + 0] = rgba[4 * i + 1] = rgba[4 * i + 2] = 0.0f;
    rgba[4 * i + 3] = 1.0f;
    float c[3] = { 0, 0, 0 };
    if (pass == ptv::PassAlpha)
    {
      c[0] = c[1] = c[2] = data[i];
    }
    else if (comps == 1)
    {
      if (ptv::IsHit(data[i], far) && hi > lo)
      {
        c[0] = c[1] = c[2] = 1.0f - 0.9f * (data[i] - lo) / (hi - lo); // near = bright
      }
    }
    else if (pass == ptv::PassNormal || pass == ptv::PassScatterNormal)
    {
      const float* v = data + 3 * i;
      if (v[0] != 0.0f || v[1] != 0.0f || v[2] != 0.0f)
      {
        for (int k = 0; k < 3; ++k)
        {
          c[k] = 0.5f * v[k] + 0.5f;
        }
      }
    }
    else if (pass == ptv::PassPosition || pass == ptv::PassScatterPosition)
    {
      const float* v = data + 3 * i;
      const int depthPass = pass == ptv::PassPosition ? ptv::PassDepth : ptv::PassScatterDepth;
      if (!ptv::IsHit(acc.Data(depthPass)[i], far))
      {
        continue; // a miss stays black (its position 0 is a real place)
      }
      for (int k = 0; k < 3; ++k)
      {
        const double extent = bounds[2 * k + 1] - bounds[2 * k];
        c[k] = extent > 0 ? static_cast<float>((v[k] - bounds[2 * k]) / extent) : 0.0f;
      }
    }
    else
    {
      std::copy(data + 3 * i, data + 3 * i + 3, c);
    }
    for (int k = 0; k < 3; ++k)
    {
      rgba[4 * i + k] = std::min(1.0f, std::max(0.0f, c[k]));
    }
    rgba[4 * i + 3] = 1.0f;
  }
}
}

//------------------------------------------------------------------------------
vtkPathTracedVolumeMapper::vtkPathTracedVolumeMapper()
  : Internals(new vtkInternals)
{
}

//------------------------------------------------------------------------------
vtkPathTracedVolumeMapper::~vtkPathTracedVolumeMapper()
{
  this->SetDisplayPass(nullptr);
  this->SetDenoiserModelFile(nullptr);
}

//------------------------------------------------------------------------------
const char* vtkPathTracedVolumeMapper::GetDenoiserStatus()
{
  return this->Internals->Denoiser.GetStatus().c_str();
}

//------------------------------------------------------------------------------
int vtkPathTracedVolumeMapper::FillInputPortInformation(int vtkNotUsed(port), vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
  return 1;
}

//------------------------------------------------------------------------------
int vtkPathTracedVolumeMapper::GetNumberOfPasses()
{
  return ptv::PassCount;
}

//------------------------------------------------------------------------------
const char* vtkPathTracedVolumeMapper::GetPassName(int index)
{
  return (index >= 0 && index < ptv::PassCount) ? ptv::GetPassInfo(index).Name : nullptr;
}

//------------------------------------------------------------------------------
const char* vtkPathTracedVolumeMapper::GetCpuKernelTarget()
{
  return ptv::TracerKernelTarget(ptv::UsePortableKernels(false));
}

//------------------------------------------------------------------------------
const char* vtkPathTracedVolumeMapper::GetActiveBackend()
{
  return this->Internals->ActiveBackend.c_str();
}

//------------------------------------------------------------------------------
bool vtkPathTracedVolumeMapper::GetCudaAvailable()
{
  return ptv::QueryCudaDevices().DeviceCount > 0;
}

//------------------------------------------------------------------------------
const char* vtkPathTracedVolumeMapper::GetCudaStatus()
{
  return ptv::QueryCudaDevices().Message.c_str();
}

//------------------------------------------------------------------------------
void vtkPathTracedVolumeMapper::ResetAccumulation()
{
  this->AccumulatedFrames = 0;
  this->Internals->Signature.Clear();
}

//------------------------------------------------------------------------------
bool vtkPathTracedVolumeMapper::GetPass(const char* name, vtkImageData* output)
{
  const int pass = ptv::FindPass(name);
  if (pass < 0)
  {
    vtkErrorMacro(<< "Unknown pass '" << (name ? name : "(null)") << "'; see GetPassName().");
    return false;
  }
  if (!output)
  {
    vtkErrorMacro(<< "GetPass needs an output vtkImageData.");
    return false;
  }
  if (this->AccumulatedFrames == 0)
  {
    vtkErrorMacro(<< "Pass '" << name << "' is not available before the first render.");
    return false;
  }
  if (pass >= ptv::kTracedPassCount && !this->Internals->DenoisedValid)
  {
    vtkErrorMacro(<< "Pass '" << name << "' is produced by the denoiser; turn Denoise on and "
                  << "render first.");
    return false;
  }
  const ptv::PassBuffers& acc = this->Internals->Accumulated;
  const int comps = ptv::GetPassInfo(pass).Components;
  const vtkIdType n = static_cast<vtkIdType>(acc.GetWidth()) * acc.GetHeight();
  vtkNew<vtkFloatArray> array;
  array->SetName(name);
  array->SetNumberOfComponents(comps);
  array->SetNumberOfTuples(n);
  std::copy(acc.Data(pass), acc.Data(pass) + n * comps, array->GetPointer(0));
  output->Initialize();
  output->SetDimensions(acc.GetWidth(), acc.GetHeight(), 1);
  output->SetOrigin(0, 0, 0);
  output->SetSpacing(1, 1, 1);
  output->GetPointData()->SetScalars(array);
  return true;
}

//------------------------------------------------------------------------------
bool vtkPathTracedVolumeMapper::GetPasses(vtkImageData* output)
{
  if (!output)
  {
    vtkErrorMacro(<< "GetPasses needs an output vtkImageData.");
    return false;
  }
  if (this->AccumulatedFrames == 0)
  {
    vtkErrorMacro(<< "Passes are not available before the first render.");
    return false;
  }
  const ptv::PassBuffers& acc = this->Internals->Accumulated;
  const vtkIdType n = static_cast<vtkIdType>(acc.GetWidth()) * acc.GetHeight();
  output->Initialize();
  output->SetDimensions(acc.GetWidth(), acc.GetHeight(), 1);
  output->SetOrigin(0, 0, 0);
  output->SetSpacing(1, 1, 1);
  for (int pass = 0; pass < ptv::PassCount; ++pass)
  {
    if (pass >= ptv::kTracedPassCount && !this->Internals->DenoisedValid)
    {
      continue;
    }
    const int comps = ptv::GetPassInfo(pass).Components;
    vtkNew<vtkFloatArray> array;
    array->SetName(ptv::GetPassInfo(pass).Name);
    array->SetNumberOfComponents(comps);
    array->SetNumberOfTuples(n);
    std::copy(acc.Data(pass), acc.Data(pass) + n * comps, array->GetPointer(0));
    output->GetPointData()->AddArray(array);
  }
  output->GetPointData()->SetActiveScalars(ptv::GetPassInfo(0).Name);
  return true;
}

//------------------------------------------------------------------------------
double* vtkPathTracedVolumeMapper::GetBounds()
{
  double* bounds = this->Superclass::GetBounds();
  std::string& last = this->Internals->LastError;
  const bool finite = std::all_of(bounds, bounds + 6, [](double v) { return std::isfinite(v); });
  if (finite)
  {
    if (last.rfind("non-finite", 0) == 0)
    {
      last.clear(); // the input was fixed: a later error is reported again
    }
    return bounds;
  }
  std::ostringstream msg;
  vtkImageData* image = vtkImageData::SafeDownCast(this->GetDataSetInput());
  const double* spacing = image ? image->GetSpacing() : nullptr;
  const double* origin = image ? image->GetOrigin() : nullptr;
  auto allFinite = [](const double* v) { return std::isfinite(v[0] + v[1] + v[2]); };
  if (spacing && !allFinite(spacing))
  {
    msg << "non-finite image spacing (" << spacing[0] << ", " << spacing[1] << ", " << spacing[2]
        << "): nothing is rendered";
  }
  else if (origin && !allFinite(origin))
  {
    msg << "non-finite image origin (" << origin[0] << ", " << origin[1] << ", " << origin[2]
        << "): nothing is rendered";
  }
  else
  {
    msg << "non-finite volume bounds (" << bounds[0] << ", " << bounds[1] << ", " << bounds[2]
        << ", " << bounds[3] << ", " << bounds[4] << ", " << bounds[5]
        << "): nothing is rendered";
  }
  if (msg.str() != last)
  {
    vtkErrorMacro(<< msg.str());
    last = msg.str();
  }
  return bounds;
}

//------------------------------------------------------------------------------
void vtkPathTracedVolumeMapper::Render(vtkRenderer* ren, vtkVolume* vol)
{
  vtkInternals& in = *this->Internals;
  this->LastRenderTraced = false;
  this->LastTraceTime = 0.0;
  this->LastDenoiseTime = 0.0;
  auto report = [this, &in](const std::string& error)
  {
    if (error != in.LastError)
    {
      vtkErrorMacro(<< error);
      in.LastError = error;
    }
  };

  if (!ren || !vol)
  {
    return;
  }
  if (vtkAlgorithm* producer = this->GetInputAlgorithm())
  {
    producer->Update();
  }
  vtkImageData* image = vtkImageData::SafeDownCast(this->GetInput());
  int cellFlag = 0;
  vtkDataArray* scalars = image ? this->GetScalars(image, this->ScalarMode, this->ArrayAccessMode,
                                    this->ArrayId, this->ArrayName, cellFlag)
                                : nullptr;
  std::string error;
  if (scalars && cellFlag)
  {
    report("cell scalars are not supported; convert them with vtkCellDataToPointData");
    return;
  }
  vtkIdType nonFinite = 0;
  if (!in.Inputs.UpdateVolume(image, scalars, error, nonFinite) ||
    !in.Inputs.UpdateTransfer(vol->GetProperty(), this->EmptySpaceSkipping, error))
  {
    report(error);
    return;
  }
  if (nonFinite > 0 && nonFinite != in.LastNonFinite)
  {
    vtkWarningMacro(<< nonFinite << " voxels are NaN or infinite; they are rendered transparent.");
  }
  in.LastNonFinite = nonFinite;

  int width = 0, height = 0, x0 = 0, y0 = 0;
  ren->GetTiledSizeAndOrigin(&width, &height, &x0, &y0);
  if (width <= 0 || height <= 0)
  {
    return; // a zero-size viewport shows nothing; not an error
  }

  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  in.ZBuffer.resize(pixels);
  if (!ptv::Display::ReadDepth(ren, x0, y0, width, height, in.ZBuffer.data()))
  {
    in.ZBuffer.clear(); // no opaque-geometry clipping this frame
  }

  ptv::FrameSettings settings;
  settings.Seed = this->Seed;
  settings.SamplesPerFrame = this->SamplesPerFrame;
  settings.Scattering = this->Scattering;
  settings.AmbientOcclusion = this->AmbientOcclusion;
  settings.UseRendererLight = this->UseRendererLight;
  settings.LightIntensity = this->LightIntensity;
  std::copy(this->EnvironmentColor, this->EnvironmentColor + 3, settings.EnvironmentColor);
  settings.UseBackgroundAsEnvironment = this->UseBackgroundAsEnvironment;
  settings.EnvironmentIntensity = this->EnvironmentIntensity;
  settings.EmptySpaceSkipping = this->EmptySpaceSkipping;

  ptv::FrameSignature signature;
  if (!in.Inputs.Build(ren, vol, image, settings, width, height, in.ZBuffer, in.Params, signature,
        error))
  {
    report(error);
    return;
  }
  in.LastError.clear();
  if (!signature.Matches(in.Signature)) // compared with the frame that started the accumulation,
  {                                       // so slow drifts cannot pile up unnoticed
    this->AccumulatedFrames = 0;
    in.Signature = std::move(signature);
  }

  if (this->AccumulatedFrames < this->MaximumAccumulatedFrames)
  {
    const double start = vtkTimerLog::GetUniversalTime();
    in.Frame.Resize(width, height);
    in.Accumulated.Resize(width, height);
    const unsigned int firstSample =
      static_cast<unsigned int>(this->AccumulatedFrames) * this->SamplesPerFrame;
    std::string message;
    int backend = ptv::ResolveBackend(this->Backend,
      vtkPathTracedVolumeMapper::GetCudaAvailable(), vtkPathTracedVolumeMapper::GetCudaStatus(),
      message);
    if (backend == ptv::BackendCuda &&
      !in.Cuda.Trace(in.Params, in.Inputs.GetVolumeVersion(), firstSample,
        this->SamplesPerFrame, in.Frame, message))
    {
      message = "CUDA tracing failed (" + message + "); tracing on the CPU";
      backend = ptv::BackendCpu;
    }
    if (!message.empty() && message != in.BackendMessage)
    {
      vtkErrorMacro(<< message);
    }
    in.BackendMessage = message;
    if (backend == ptv::BackendCpu)
    {
      ptv::TraceFrameCpu(in.Params, firstSample, this->SamplesPerFrame, this->NumberOfThreads,
        ptv::UsePortableKernels(false), in.Frame);
    }
    in.ActiveBackend = backend == ptv::BackendCuda ? "CUDA" : "CPU";
    ++this->AccumulatedFrames;
    in.Accumulated.Accumulate(in.Frame, this->AccumulatedFrames);
    this->LastTraceTime = 1000.0 * (vtkTimerLog::GetUniversalTime() - start);
    this->LastRenderTraced = true;
    in.DenoisedValid = false;
  }
  if (this->Denoise)
  {
    this->DenoiseFrame(width, height);
  }

  // What to show: the (denoised) radiance, premultiplied and blended, or a colourised pass.
  int shown = this->Denoise && in.DenoisedValid ? ptv::PassDenoised : ptv::PassRadiance;
  if (this->DisplayPass && *this->DisplayPass)
  {
    shown = ptv::FindPass(this->DisplayPass);
    if (shown < 0)
    {
      report(std::string("unknown DisplayPass '") + this->DisplayPass + "'; showing Radiance");
      shown = ptv::PassRadiance;
    }
    else if (shown >= ptv::kTracedPassCount && !in.DenoisedValid)
    {
      report(std::string("DisplayPass '") + this->DisplayPass + "' needs Denoise on");
      shown = ptv::PassRadiance;
    }
  }
  in.ShownColor.resize(4 * pixels);
  in.ShownDepth.assign(pixels, 1.0f);
  const ptv::PassBuffers& acc = in.Accumulated;
  if (shown == ptv::PassRadiance || shown == ptv::PassDenoised)
  {
    const float* rgb = acc.Data(shown);
    const float* alpha = acc.Data(ptv::PassAlpha);
    for (std::size_t i = 0; i < pixels; ++i)
    {
      std::copy(rgb + 3 * i, rgb + 3 * i + 3, &in.ShownColor[4 * i]);
      in.ShownColor[4 * i + 3] = alpha[i];
    }
  }
  else
  {
    Colorize(shown, acc, in.Inputs.GetWorldBounds(), in.Params.Camera.FarDistance, in.ShownColor);
  }

  // Window depth of the first event, so later geometry and picking see the volume. Only the
  // last two rows of the projection matter (z and w); rows of pixels run in parallel.
  const double aspect = static_cast<double>(width) / static_cast<double>(height);
  vtkMatrix4x4* toNdc =
    ren->GetActiveCamera()->GetCompositeProjectionTransformMatrix(aspect, -1, 1);
  double zRow[4], wRow[4];
  for (int c = 0; c < 4; ++c)
  {
    zRow[c] = toNdc->GetElement(2, c);
    wRow[c] = toNdc->GetElement(3, c);
  }
  const float* depth = acc.Data(ptv::PassDepth);
  const float far = in.Params.Camera.FarDistance;
  const ptv::CameraRays& camera = in.Params.Camera;
  float* shownDepth = in.ShownDepth.data();
  ptv::WithThreads(this->NumberOfThreads,
    [&]()
    {
      vtkSMPTools::For(0, height, 16,
        [&](vtkIdType yBegin, vtkIdType yEnd)
        {
          for (vtkIdType y = yBegin; y < yEnd; ++y)
          {
            for (int x = 0; x < width; ++x)
            {
              const std::size_t i = static_cast<std::size_t>(y) * width + x;
              if (!ptv::IsHit(depth[i], far))
              {
                continue;
              }
              ptv::Vec3 o, d;
              ptv::GenerateRay(camera, x + 0.5f, static_cast<float>(y) + 0.5f, o, d);
              const ptv::Vec3 p = o + d * depth[i];
              const double z = zRow[0] * p.x + zRow[1] * p.y + zRow[2] * p.z + zRow[3];
              const double w = wRow[0] * p.x + wRow[1] * p.y + wRow[2] * p.z + wRow[3];
              if (w != 0.0)
              {
                shownDepth[i] =
                  static_cast<float>(std::min(1.0, std::max(0.0, 0.5 * (z / w) + 0.5)));
              }
            }
          }
        });
    });
  in.Display.Draw(ren, width, height, in.ShownColor.data(), in.ShownDepth.data());
}

//------------------------------------------------------------------------------
void vtkPathTracedVolumeMapper::DenoiseFrame(int width, int height)
{
  vtkInternals& in = *this->Internals;
  const std::vector<std::string> key = { this->DenoiserModelFile ? this->DenoiserModelFile : "",
    std::to_string(this->DenoiserNumberOfLevels), std::to_string(this->NumberOfThreads),
    this->DenoiserUseNetwork ? "net" : "fixed" };
  if (in.DenoisedValid && key == in.DenoiseKey)
  {
    return; // nothing new to denoise
  }
  ptv::DenoiserSettings settings;
  settings.ModelFile = key[0];
  settings.Levels = this->DenoiserNumberOfLevels;
  settings.UseNetwork = this->DenoiserUseNetwork;
  settings.Threads = this->NumberOfThreads;
  settings.UseCuda = in.ActiveBackend == "CUDA"; // the grid follows the tracer's backend
  ptv::PassBuffers& acc = in.Accumulated;
  const float* passes[ptv::PassCount] = {};
  for (int p = 0; p < ptv::kTracedPassCount; ++p)
  {
    passes[p] = acc.Data(p);
  }
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  const double start = vtkTimerLog::GetUniversalTime();
  std::string error;
  if (!in.Denoiser.Run(settings, passes, width, height, acc.Data(ptv::PassDenoised), error))
  {
    vtkErrorMacro(<< "Denoising failed: " << error);
    return;
  }
  const std::string warning = in.Denoiser.TakeWarning();
  if (!warning.empty())
  {
    vtkWarningMacro(<< warning);
  }
  // Guides (one level per component) and blend weights, zero-padded to 3 and 2 components.
  const int levels = in.Denoiser.GetLevels();
  float* guides = acc.Data(ptv::PassGuides);
  float* weights = acc.Data(ptv::PassBlendWeights);
  for (std::size_t k = 0; k < n; ++k)
  {
    for (int l = 0; l < 3; ++l)
    {
      guides[3 * k + l] = l < levels ? in.Denoiser.GetGuides()[k * levels + l] : 0.0f;
    }
    for (int l = 0; l < 2; ++l)
    {
      weights[2 * k + l] = l < levels - 1 ? in.Denoiser.GetWeights()[k * (levels - 1) + l] : 0.0f;
    }
  }
  in.DenoisedValid = true;
  in.DenoiseKey = key;
  this->LastDenoiseTime = 1000.0 * (vtkTimerLog::GetUniversalTime() - start);
}

//------------------------------------------------------------------------------
void vtkPathTracedVolumeMapper::ReleaseGraphicsResources(vtkWindow* window)
{
  this->Internals->Display.ReleaseGraphicsResources(window);
  this->Internals->Cuda.Release();
  this->Superclass::ReleaseGraphicsResources(window);
}

//------------------------------------------------------------------------------
void vtkPathTracedVolumeMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SamplesPerFrame: " << this->SamplesPerFrame << "\n";
  os << indent << "MaximumAccumulatedFrames: " << this->MaximumAccumulatedFrames << "\n";
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "Scattering: " << this->Scattering << "\n";
  os << indent << "AmbientOcclusion: " << this->AmbientOcclusion << "\n";
  os << indent << "UseRendererLight: " << this->UseRendererLight << "\n";
  os << indent << "LightIntensity: " << this->LightIntensity << "\n";
  os << indent << "EnvironmentColor: " << this->EnvironmentColor[0] << ", "
     << this->EnvironmentColor[1] << ", " << this->EnvironmentColor[2] << "\n";
  os << indent << "UseBackgroundAsEnvironment: " << this->UseBackgroundAsEnvironment << "\n";
  os << indent << "EnvironmentIntensity: " << this->EnvironmentIntensity << "\n";
  os << indent << "EmptySpaceSkipping: " << this->EmptySpaceSkipping << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
  os << indent << "Denoise: " << this->Denoise << "\n";
  os << indent << "DenoiserModelFile: "
     << (this->DenoiserModelFile ? this->DenoiserModelFile : "(shipped model)") << "\n";
  os << indent << "DenoiserUseNetwork: " << this->DenoiserUseNetwork << "\n";
  os << indent << "DenoiserNumberOfLevels: " << this->DenoiserNumberOfLevels << "\n";
  os << indent << "DenoiserStatus: " << this->Internals->Denoiser.GetStatus() << "\n";
  os << indent << "DisplayPass: " << (this->DisplayPass ? this->DisplayPass : "(Radiance)")
     << "\n";
  os << indent << "AccumulatedFrames: " << this->AccumulatedFrames << "\n";
  os << indent << "Backend: "
     << (this->Backend == BACKEND_CPU ? "CPU" : (this->Backend == BACKEND_CUDA ? "CUDA" : "Auto"))
     << " (last frame: " << this->Internals->ActiveBackend << ")\n";
  os << indent << "CpuKernelTarget: " << vtkPathTracedVolumeMapper::GetCpuKernelTarget() << "\n";
  os << indent << "CUDA: " << vtkPathTracedVolumeMapper::GetCudaStatus() << "\n";
}
