#include "vtkPathTracedVolumeMapper.h"

#include "ptvBackend.h"
#include "ptvCpuTracer.h"
#include "ptvCudaDevice.h"
#include "ptvFrameLoop.h"
#include "ptvKernelDispatch.h"
#include "ptvSceneRequest.h"
#include "ptvSceneToKernel.h"
#include "vtkPTVExpertOptions.h"
#include "vtkPTVRenderStatistics.h"

#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkSmartPointer.h"
#include "vtkPointData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>

struct vtkPathTracedVolumeMapper::vtkInternals
{
  ptv::FrameLoop Loop;
  std::string BlendProblem;  // the blend-mode problem last reported
  std::string ClipProblems;  // the clipping/cropping problems last reported
  vtkSmartPointer<vtkMultiProcessController> Controller; // several processes (ptvRanks.h)
  vtkNew<vtkPTVExpertOptions> Options;
  vtkNew<vtkPTVRenderStatistics> Statistics;
};

vtkStandardNewMacro(vtkPathTracedVolumeMapper);

static_assert(ptv::kBackendAuto == vtkPathTracedVolumeMapper::BACKEND_AUTO &&
    ptv::kBackendCpu == vtkPathTracedVolumeMapper::BACKEND_CPU &&
    ptv::kBackendCuda == vtkPathTracedVolumeMapper::BACKEND_CUDA,
  "ptvBackend.h numbers the backends as the public class");

//------------------------------------------------------------------------------
vtkPathTracedVolumeMapper::vtkPathTracedVolumeMapper()
  : Internals(new vtkInternals)
{
  const ptv::FrameRequest defaults{};
  const ptv::FrameSettings& scene = defaults.Scene;
  this->SamplesPerFrame = scene.SamplesPerFrame;
  this->TemporalReprojection = defaults.TemporalReprojection;
  this->ConvergeStillRenders = defaults.ConvergeStillRenders;
  this->StillQuality = defaults.StillQuality;
  this->StillTimeBudget = defaults.StillTimeBudget;
  this->Seed = scene.Seed;
  this->Scattering = scene.Scattering;
  this->AmbientOcclusion = scene.AmbientOcclusion;
  this->LightIntensity = scene.LightIntensity;
  this->EnvironmentIntensity = scene.EnvironmentIntensity;
  this->Denoise = defaults.Denoise;
  this->NumberOfThreads = defaults.Threads;
  this->Backend = defaults.Backend;
  this->DistributedVolume = defaults.Distributed;
  std::copy(scene.PieceExtent, scene.PieceExtent + 6, this->PieceExtent);
  std::copy(scene.WholeExtent, scene.WholeExtent + 6, this->WholeExtent);
}

//------------------------------------------------------------------------------
vtkPathTracedVolumeMapper::~vtkPathTracedVolumeMapper()
{
  this->SetDisplayPass(nullptr);
  this->SetDenoiserModelFile(nullptr);
}

//------------------------------------------------------------------------------
vtkPTVExpertOptions* vtkPathTracedVolumeMapper::GetExpertOptions()
{
  return this->Internals->Options;
}

//------------------------------------------------------------------------------
vtkPTVRenderStatistics* vtkPathTracedVolumeMapper::GetStatistics()
{
  return this->Internals->Statistics;
}

//------------------------------------------------------------------------------
const char* vtkPathTracedVolumeMapper::GetDenoiserStatus()
{
  return this->Internals->Loop.GetDenoiserStatus().c_str();
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
  return this->Internals->Loop.GetActiveBackend().c_str();
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
  this->Internals->Loop.ResetAccumulation();
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
    vtkErrorMacro(<< "Pass '" << name << "' is not available" << this->NoFrameReason());
    return false;
  }
  if (ptv::IsDenoiserPass(pass) && !this->Internals->Loop.GetDenoisedValid())
  {
    vtkErrorMacro(<< "Pass '" << name << "' is produced by the denoiser; turn Denoise on and "
                  << "render first.");
    return false;
  }
  const ptv::PassBuffers& acc = this->Internals->Loop.GetPasses();
  if (!acc.Data(pass))
  {
    vtkErrorMacro(<< "Pass '" << name << "' is not kept; turn on the expert option "
                  << "ScatterPasses (GetExpertOptions()->ScatterPassesOn()) and render again.");
    return false;
  }
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
const char* vtkPathTracedVolumeMapper::NoFrameReason() const
{
  return this->RenderFailed ? ": the last render traced no frame (see the error it reported)."
                            : " before the first render.";
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
    vtkErrorMacro(<< "Passes are not available" << this->NoFrameReason());
    return false;
  }
  const ptv::PassBuffers& acc = this->Internals->Loop.GetPasses();
  const vtkIdType n = static_cast<vtkIdType>(acc.GetWidth()) * acc.GetHeight();
  output->Initialize();
  output->SetDimensions(acc.GetWidth(), acc.GetHeight(), 1);
  output->SetOrigin(0, 0, 0);
  output->SetSpacing(1, 1, 1);
  for (int pass = 0; pass < ptv::PassCount; ++pass)
  {
    if ((ptv::IsDenoiserPass(pass) && !this->Internals->Loop.GetDenoisedValid()) ||
      !acc.Data(pass))
    {
      continue; // not made (Denoise off) or not kept (ScatterPasses off)
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
  vtkImageData* input = vtkImageData::SafeDownCast(this->GetDataSetInput());
  const int* w = this->WholeExtent;
  if (this->DistributedVolume && input && w[0] <= w[1] && w[2] <= w[3] && w[4] <= w[5])
  {
    // Process 0 draws the whole composited volume: its bounds (its corners' physical points,
    // which share the input's origin, spacing and direction), not this piece's.
    for (int a = 0; a < 3; ++a)
    {
      this->Bounds[2 * a] = VTK_DOUBLE_MAX;
      this->Bounds[2 * a + 1] = VTK_DOUBLE_MIN;
    }
    for (int corner = 0; corner < 8; ++corner)
    {
      const double ijk[3] = { static_cast<double>(w[(corner & 1) ? 1 : 0]),
        static_cast<double>(w[(corner & 2) ? 3 : 2]),
        static_cast<double>(w[(corner & 4) ? 5 : 4]) };
      double xyz[3];
      input->TransformContinuousIndexToPhysicalPoint(ijk, xyz);
      for (int a = 0; a < 3; ++a)
      {
        this->Bounds[2 * a] = std::min(this->Bounds[2 * a], xyz[a]);
        this->Bounds[2 * a + 1] = std::max(this->Bounds[2 * a + 1], xyz[a]);
      }
    }
    bounds = this->Bounds;
  }
  const bool finite = std::all_of(bounds, bounds + 6, [](double v) { return std::isfinite(v); });
  if (finite)
  {
    this->Internals->Loop.ReportOnce("", "non-finite"); // fixed: a later error is new again
    return bounds;
  }
  std::ostringstream msg;
  vtkImageData* image = vtkImageData::SafeDownCast(this->GetDataSetInput());
  const std::string geometry = image ? ptv::NonFiniteGeometry(image) : std::string();
  if (!geometry.empty())
  {
    msg << geometry << ": nothing is rendered";
  }
  else
  {
    msg << "non-finite volume bounds (" << bounds[0] << ", " << bounds[1] << ", " << bounds[2]
        << ", " << bounds[3] << ", " << bounds[4] << ", " << bounds[5]
        << "): nothing is rendered";
  }
  if (this->Internals->Loop.ReportOnce(msg.str()))
  {
    vtkErrorMacro(<< msg.str());
  }
  return bounds;
}

//------------------------------------------------------------------------------
void vtkPathTracedVolumeMapper::Render(vtkRenderer* ren, vtkVolume* vol)
{
  ptv::FrameLoop& loop = this->Internals->Loop;
  if (ren && vol)
  {
    if (vtkAlgorithm* producer = this->GetInputAlgorithm())
    {
      producer->Update();
    }
    vtkImageData* image = vtkImageData::SafeDownCast(this->GetInput());
    int cellFlag = 0;
    vtkDataArray* scalars = image ? this->GetScalars(image, this->ScalarMode,
                                      this->ArrayAccessMode, this->ArrayId, this->ArrayName, cellFlag)
                                  : nullptr;
    ptv::FrameRequest request;
    ptv::FrameSettings& scene = request.Scene;
    vtkPTVExpertOptions* options = this->Internals->Options;
    scene.Seed = this->Seed;
    scene.SamplesPerFrame = this->SamplesPerFrame;
    scene.Scattering = this->Scattering;
    scene.CoverageMarch = options->GetCoverageMarch(); // the frame loop adds its model's need
    scene.ExpectedCoverage = options->GetExpectedCoverage();
    scene.FootprintRays = options->GetFootprintRays(); // and the denoiser's
    scene.AmbientOcclusion = this->AmbientOcclusion;
    scene.AmbientOcclusionReach = options->GetAmbientOcclusionReach();
    scene.UseRendererLight = options->GetUseRendererLight();
    scene.LightIntensity = this->LightIntensity;
    options->GetEnvironmentColor(scene.EnvironmentColor);
    scene.UseBackgroundAsEnvironment = options->GetUseBackgroundAsEnvironment();
    scene.EnvironmentIntensity = this->EnvironmentIntensity;
    scene.EmptySpaceSkipping = options->GetEmptySpaceSkipping();
    request.MaximumAccumulatedFrames = options->GetMaximumAccumulatedFrames();
    request.TemporalReprojection = this->TemporalReprojection;
    request.MaximumHistory = options->GetMaximumHistory();
    request.Threads = this->NumberOfThreads;
    request.Controller = this->Internals->Controller;
    request.Distributed = this->DistributedVolume != 0;
    if (this->DistributedVolume)
    {
      std::copy(this->PieceExtent, this->PieceExtent + 6, scene.PieceExtent);
      std::copy(this->WholeExtent, this->WholeExtent + 6, scene.WholeExtent);
    }
    request.Backend = this->Backend;
    request.Denoise = this->Denoise;
    request.EdgeSamples = options->GetEdgeSamples();
    request.ComputeEdgeSamples = options->GetComputeEdgeSamples();
    request.Denoiser.ModelFile = this->DenoiserModelFile ? this->DenoiserModelFile : "";
    request.Denoiser.UseNetwork = options->GetDenoiserUseNetwork();
    request.Denoiser.Levels = options->GetDenoiserNumberOfLevels();
    request.DisplayPass = this->DisplayPass ? this->DisplayPass : "";
    request.ScatterPasses = options->GetScatterPasses();
    request.Still = this->ConvergeStillRenders && vol->GetAllocatedRenderTime() >= 1.0;
    request.StillQuality = this->StillQuality;
    request.MaximumStillFrames = options->GetMaximumStillFrames();
    request.StillTimeBudget = this->StillTimeBudget;
    request.Progress = [this](double fraction)
    {
      // ParaView's progress bar shows this text (vtkPVProgressHandler).
      const ptv::FrameLoop& l = this->Internals->Loop;
      std::ostringstream text;
      text << "Path tracing a still: " << l.GetAccumulatedFrames() << " frames";
      if (l.GetEstimatedQuality() > 0.0)
      {
        text << ", " << std::fixed << std::setprecision(1) << l.GetEstimatedQuality() << " of "
             << this->StillQuality << " dB";
      }
      this->SetProgressText(text.str().c_str());
      this->UpdateProgress(fraction);
    };
    request.Abort = [ren]()
    {
      vtkRenderWindow* window = ren->GetRenderWindow();
      return window && window->CheckAbortStatus() != 0;
    };
    ptv::GatherClipping(this, scene, this->Internals->ClipProblems);
    ptv::GatherBlendMode(this, this->DistributedVolume != 0, vol->GetProperty(), scene,
      this->Internals->BlendProblem);
    request.Denoise = request.Denoise && scene.Projection == 0; // a projection has no noise

    ptv::FrameMessages messages;
    loop.Render(ren, vol, image, scalars, cellFlag != 0, request, messages);
    this->RenderFailed = loop.GetAccumulatedFrames() == 0;
    for (const auto& message : messages)
    {
      if (message.first)
      {
        vtkErrorMacro(<< message.second);
      }
      else
      {
        vtkWarningMacro(<< message.second);
      }
    }
  }
  this->AccumulatedFrames = loop.GetAccumulatedFrames();
  this->LastRenderTraced = loop.GetLastRenderTraced();
  this->EstimatedQuality = loop.GetEstimatedQuality();
  this->StillConverged = loop.GetStillConverged();
  this->Internals->Statistics->Update(loop.GetLastRenderFrames(), loop.GetLastTraceTime(),
    loop.GetLastDenoiseTime(), loop.GetLastReprojectionTime(), loop.GetReprojectionReuse(),
    loop.GetLastEdgeFraction());
}

//------------------------------------------------------------------------------
void vtkPathTracedVolumeMapper::ReleaseGraphicsResources(vtkWindow* window)
{
  this->Internals->Loop.ReleaseGraphicsResources(window);
  this->Superclass::ReleaseGraphicsResources(window);
}

//------------------------------------------------------------------------------
void vtkPathTracedVolumeMapper::SetController(vtkMultiProcessController* controller)
{
  if (this->Internals->Controller != controller)
  {
    this->Internals->Controller = controller;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
vtkMultiProcessController* vtkPathTracedVolumeMapper::GetController()
{
  return this->Internals->Controller;
}

//------------------------------------------------------------------------------
void vtkPathTracedVolumeMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SamplesPerFrame: " << this->SamplesPerFrame << "\n";
  os << indent << "TemporalReprojection: " << this->TemporalReprojection << "\n";
  os << indent << "ConvergeStillRenders: " << this->ConvergeStillRenders << "\n";
  os << indent << "StillQuality: " << this->StillQuality << " dB\n";
  os << indent << "StillTimeBudget: " << this->StillTimeBudget << " s\n";
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "Scattering: " << this->Scattering << "\n";
  os << indent << "AmbientOcclusion: " << this->AmbientOcclusion << "\n";
  os << indent << "LightIntensity: " << this->LightIntensity << "\n";
  os << indent << "EnvironmentIntensity: " << this->EnvironmentIntensity << "\n";
  os << indent << "Denoise: " << this->Denoise << "\n";
  os << indent << "DenoiserModelFile: "
     << (this->DenoiserModelFile ? this->DenoiserModelFile : "(shipped model)") << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
  os << indent << "DisplayPass: "
     << (this->DisplayPass && *this->DisplayPass ? this->DisplayPass : "(the default)") << "\n";
  os << indent << "Backend: "
     << (this->Backend == BACKEND_CPU ? "CPU" : (this->Backend == BACKEND_CUDA ? "CUDA" : "Auto"))
     << " (last frame: " << this->Internals->Loop.GetActiveBackend() << ")\n";
  os << indent << "ExpertOptions:\n";
  this->Internals->Options->PrintSelf(os, indent.GetNextIndent());
  os << indent << "Controller: "
     << (this->Internals->Controller
            ? std::to_string(this->Internals->Controller->GetNumberOfProcesses()) + " processes"
            : std::string("(none)"))
     << "\n";
  os << indent << "DistributedVolume: " << this->DistributedVolume << "\n";
  os << indent << "PieceExtent: " << this->PieceExtent[0] << ", " << this->PieceExtent[1] << ", "
     << this->PieceExtent[2] << ", " << this->PieceExtent[3] << ", " << this->PieceExtent[4]
     << ", " << this->PieceExtent[5] << "\n";
  os << indent << "WholeExtent: " << this->WholeExtent[0] << ", " << this->WholeExtent[1] << ", "
     << this->WholeExtent[2] << ", " << this->WholeExtent[3] << ", " << this->WholeExtent[4]
     << ", " << this->WholeExtent[5] << "\n";
  os << indent << "AccumulatedFrames: " << this->AccumulatedFrames << "\n";
  os << indent << "EstimatedQuality: " << this->EstimatedQuality << " dB\n";
  os << indent << "DenoiserStatus: " << this->Internals->Loop.GetDenoiserStatus() << "\n";
  os << indent << "Statistics:\n";
  this->Internals->Statistics->PrintSelf(os, indent.GetNextIndent());
  os << indent << "CpuKernelTarget: " << vtkPathTracedVolumeMapper::GetCpuKernelTarget() << "\n";
  os << indent << "CUDA: " << vtkPathTracedVolumeMapper::GetCudaStatus() << "\n";
}
