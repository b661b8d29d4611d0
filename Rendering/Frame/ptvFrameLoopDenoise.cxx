// FrameLoop, the denoiser on the accumulation and the shown image's mix of the denoised
// image and the raw mean (ptvConvergence); ptvFrameLoop.h lists the stages.
#include "ptvFrameLoop.h"

#include "ptvEdgeSamples.h"

#include "ptvKernelDispatch.h"

#include "vtkImageData.h"
#include "vtkRenderer.h"
#include "vtkTimerLog.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <string>

namespace ptv
{
namespace
{
double Now()
{
  return vtkTimerLog::GetUniversalTime();
}
}

//------------------------------------------------------------------------------
DenoiserSettings FrameLoop::SettingsOf(const FrameRequest& request) const
{
  DenoiserSettings settings = request.Denoiser;
  settings.Threads = request.Threads;
  settings.UseCuda = this->GetActiveBackend() == "CUDA"; // the grid follows the tracer
  return settings;
}

//------------------------------------------------------------------------------
bool FrameLoop::DenoiseFrame(const FrameRequest& request, FrameMessages& messages)
{
  const std::vector<std::string> key = { request.Denoiser.ModelFile,
    std::to_string(request.Denoiser.Levels), std::to_string(request.Threads),
    request.Denoiser.UseNetwork ? "net" : "fixed" };
  if (this->DenoisedValid && key == this->DenoiseKey)
  {
    return true; // nothing new to denoise
  }
  const DenoiserSettings settings = this->SettingsOf(request);
  PassBuffers& acc = this->Accumulated;
  const int width = acc.GetWidth();
  const int height = acc.GetHeight();
  const float* passes[PassCount] = {};
  for (int p = 0; p < kTracedPassCount; ++p)
  {
    passes[p] = acc.Data(p);
  }
  if (this->Denoising.ReadsChannelStartingWith(settings, "history"))
  {
    this->FillCountPasses(); // a model's "history" channel
  }
  passes[PassHistoryLength] = acc.Data(PassHistoryLength);
  // The SampleRatio pass is not given: leaning the edge pixels towards their own means cost
  // the held-out narrow bands 1.1 dB of the shown first frame (docs/decisions.md).
  const double start = Now();
  std::string error;
  // With the opacity it is drawn with: Alpha through the same grid (one frame's alpha is 0 or 1
  // per pixel, which would punch the denoised image back to its coverage).
  if (!this->Denoising.Run(settings, passes, width, height, acc.Data(PassDenoised), error,
        nullptr, acc.Data(PassDenoisedAlpha)))
  {
    messages.emplace_back(true, "Denoising failed: " + error);
    return false;
  }
  const std::string warning = this->Denoising.TakeWarning();
  if (!warning.empty())
  {
    messages.emplace_back(false, warning);
  }
  this->DenoisedValid = true;
  this->GuidePassesValid = false; // copied from the denoiser's when read (GetPasses)
  this->CombinedValid = false;
  this->DenoiseKey = key;
  this->LastDenoiseTime += 1000.0 * (Now() - start);
  return true;
}

//------------------------------------------------------------------------------
void FrameLoop::FillGuidePasses()
{
  if (!this->DenoisedValid || this->GuidePassesValid)
  {
    return;
  }
  // Guides (one level per component) and blend weights, zero-padded to 3 and 2 components.
  PassBuffers& acc = this->Accumulated;
  const int levels = this->Denoising.GetLevels();
  const std::vector<float>& guideIn = this->Denoising.GetGuides();
  const std::vector<float>& weightIn = this->Denoising.GetWeights();
  float* guides = acc.Ensure(PassGuides);
  float* weights = acc.Ensure(PassBlendWeights);
  const std::size_t n =
    static_cast<std::size_t>(acc.GetWidth()) * static_cast<std::size_t>(acc.GetHeight());
  for (std::size_t k = 0; k < n; ++k)
  {
    for (int l = 0; l < 3; ++l)
    {
      guides[3 * k + l] = l < levels ? guideIn[k * levels + l] : 0.0f;
    }
    for (int l = 0; l < 2; ++l)
    {
      weights[2 * k + l] = l < levels - 1 ? weightIn[k * (levels - 1) + l] : 0.0f;
    }
  }
  this->GuidePassesValid = true;
}

//------------------------------------------------------------------------------
void FrameLoop::Combine(const FrameRequest& request, FrameMessages& messages)
{
  if (this->AccumulatedFrames == 0 || !this->Parallel.Shows()) // the others keep no passes
  {
    return;
  }
  const bool denoised = request.Denoise && this->DenoiseFrame(request, messages);
  // Only still renders need the estimate (their stopping rule): interactive frames skip it.
  const bool estimate = request.Still;
  if (this->CombinedValid && this->CombinedWithDenoiser == denoised &&
    (this->CombinedWithEstimate || !estimate))
  {
    return;
  }
  PassBuffers& acc = this->Accumulated;
  Convergence::Images images;
  images.Pixels =
    static_cast<std::size_t>(acc.GetWidth()) * static_cast<std::size_t>(acc.GetHeight());
  images.Mean = acc.Data(PassRadiance); // M, when the accumulation has no history
  if (denoised)
  {
    this->ConvergedAlpha.resize(images.Pixels);
    images.Denoised = acc.Data(PassDenoised);
    images.Shown = acc.Data(PassConverged);
    images.Alpha = acc.Data(PassAlpha);
    images.DenoisedAlpha = acc.Data(PassDenoisedAlpha);
    images.ShownAlpha = this->ConvergedAlpha.data();
  }
  this->EstimatedQuality =
    this->Converging.Combine(images, this->AccumulatedFrames, request.Threads, estimate);
  this->CombinedWithEstimate = estimate;
  this->CombinedValid = true;
  this->CombinedWithDenoiser = denoised;
}
}
