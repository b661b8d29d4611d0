#include "ptvDenoiser.h"

#include <cmath>

#include "ptvFeatures.h"
#include "ptvKernelDispatch.h"
#include "ptvPassBuffers.h"
#include "vtkPTVGuideNet.h"

#include "vtkTimerLog.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <fstream>

namespace ptv
{
namespace
{
double NowMs()
{
  return 1000.0 * vtkTimerLog::GetUniversalTime();
}

const std::vector<std::string> kFixedGuideChannels = { "albedo.r", "albedo.g", "albedo.b",
  "depth", "normal.x", "normal.y", "normal.z" };
}

//------------------------------------------------------------------------------
std::string Denoiser::TakeWarning()
{
  std::string w;
  w.swap(this->Warning);
  return w;
}

//------------------------------------------------------------------------------
bool Denoiser::EnsureModel(const DenoiserSettings& settings)
{
  const std::string path =
    settings.ModelFile.empty() ? vtkPTVGuideNet::GetDefaultModelFile() : settings.ModelFile;
  if (path == this->RequestedModel && settings.Threads == this->SessionThreads)
  {
    return this->ModelProblem.empty();
  }
  this->RequestedModel = path;
  this->SessionThreads = settings.Threads;
  this->ModelProblem.clear();
  if (!std::ifstream(path).good())
  {
    this->ModelProblem = "no GuideNet model at '" + path + "'";
  }
  else
  {
    this->Session.SetNumberOfThreads(settings.Threads > 0 ? settings.Threads : 0);
    std::string error;
    if (!this->Session.Load(path, error))
    {
      this->ModelProblem = error;
    }
    else
    {
      for (const std::string& c : this->Session.GetInputChannels())
      {
        if (!IsFeatureChannel(c))
        {
          this->ModelProblem =
            "model '" + path + "' asks for the unknown feature channel '" + c + "'";
          this->Session.Unload();
          break;
        }
      }
    }
  }
  return this->ModelProblem.empty();
}

//------------------------------------------------------------------------------
bool Denoiser::Run(const DenoiserSettings& settings, const float* const* passes, int width,
  int height, float* out, std::string& error)
{
  this->Timings = DenoiserTimings{};
  if (width <= 0 || height <= 0)
  {
    error = "cannot denoise an empty image (" + std::to_string(width) + " x " +
      std::to_string(height) + ")";
    return false;
  }
  if (!passes[PassRadiance] || !passes[PassAlbedo])
  {
    error = "denoising needs the Radiance and Albedo passes";
    return false;
  }
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);

  // Guides and weights: GuideNet, or the fixed guide.
  double t0 = NowMs();
  const bool portable = UsePortableKernels(settings.PortableKernels); // features and grid
  this->NetworkActive = settings.UseNetwork && this->EnsureModel(settings);
  BilateralGridSettings grid;
  grid.Clamp = settings.Clamp;
  grid.Threads = settings.Threads;
  if (this->NetworkActive)
  {
    // Features at the network's resolution (the model's guide stride), GuideNet, then its
    // outputs upsampled into the grid's interleaved guides and weights.
    const std::vector<std::string>& channels = this->Session.GetInputChannels();
    const int stride = this->Session.GetGuideStride();
    const int netWidth = ReducedSize(width, stride);
    const int netHeight = ReducedSize(height, stride);
    const std::size_t netPixels = static_cast<std::size_t>(netWidth) * netHeight;
    this->Features.resize(channels.size() * netPixels);
    if (!this->FeatureMaker.Build(passes, width, height, channels, stride, settings.Threads,
          portable, this->Features.data(), error))
    {
      return false; // a pass the model needs is missing: the caller's input is incomplete
    }
    const double t1 = NowMs();
    this->Timings.Features = t1 - t0;
    const int modelLevels = this->Session.GetNumberOfLevels();
    this->NetOutput.resize(static_cast<std::size_t>(this->Session.GetNumberOfOutputs()) * netPixels);
    std::string runError;
    if (!this->Session.Run(this->Features.data(), netHeight, netWidth, this->NetOutput.data(),
          runError))
    {
      this->NetworkActive = false;
      this->ModelProblem = runError;
      this->RequestedModel.clear(); // retry the load next time
    }
    else if (this->Session.IsImageModel())
    {
      // An image-to-image model (the U-Net baseline): its output is the result; no grid.
      this->Timings.GuideNet = NowMs() - t1;
      const float* planes = this->NetOutput.data();
      for (std::size_t k = 0; k < n; ++k)
      {
        for (int c = 0; c < 3; ++c)
        {
          const float v = planes[c * n + k];
          out[3 * k + c] = std::isfinite(v) && v > 0.f ? v : 0.f;
        }
      }
      this->Levels = 0;
      this->Status = "image model " + this->RequestedModel + " (" +
        this->Session.GetExecutionProvider() + "), no grid";
      return true;
    }
    else
    {
      const int levels = settings.Levels > 0 ? std::min(settings.Levels, modelLevels) : modelLevels;
      this->Levels = levels;
      this->Guides.resize(n * levels);
      this->Weights.resize(n * std::max(levels - 1, 0));
      for (int l = 0; l < levels; ++l)
      {
        grid.SpatialStep[l] = this->Session.GetLevels()[l].first;
        grid.RangeStep[l] = this->Session.GetLevels()[l].second;
      }
      // Fewer levels than the model: the first levels-1 weights, the last level takes the rest.
      this->Upsampler.Run(this->NetOutput.data(), netWidth, netHeight, stride, width, height,
        levels, modelLevels, static_cast<float>(this->Session.GetGuideScale()), settings.Threads,
        this->Guides.data(), this->Weights.data());
      this->Timings.GuideNet = NowMs() - t1;
      this->Status = "GuideNet " + this->RequestedModel + " (" +
        this->Session.GetExecutionProvider() + "), " + std::to_string(levels) + " levels" +
        (stride > 1 ? ", guides at 1/" + std::to_string(stride) + " resolution" : "") +
        (this->Session.GetDemodulate() ? "" : ", no demodulation");
    }
  }
  if (!this->NetworkActive)
  {
    const std::string why = settings.UseNetwork ? this->ModelProblem : "UseNetwork is off";
    if (settings.UseNetwork && why != this->LastWarned)
    {
      this->Warning = why + "; denoising with a fixed guide (no network)";
      this->LastWarned = why;
    }
    this->Status = "fixed guide: " + why;
    this->Features.resize(kFixedGuideChannels.size() * n);
    if (!this->FeatureMaker.Build(passes, width, height, kFixedGuideChannels, 1,
          settings.Threads, portable, this->Features.data(), error))
    {
      return false;
    }
    const int levels = settings.Levels > 0 ? settings.Levels : 3;
    this->Levels = levels;
    this->Guides.resize(n * levels);
    this->Weights.assign(n * std::max(levels - 1, 0), 1.0f / static_cast<float>(levels));
    const float* f = this->Features.data();
    for (std::size_t k = 0; k < n; ++k)
    {
      const float albedo = 0.2126f * f[k] + 0.7152f * f[n + k] + 0.0722f * f[2 * n + k];
      const float normal = (f[4 * n + k] + f[5 * n + k] + f[6 * n + k]) / 3.0f;
      const float g = 0.35f * albedo + 0.35f * f[3 * n + k] + 0.3f * normal;
      for (int l = 0; l < levels; ++l)
      {
        this->Guides[k * levels + l] = 255.0f * std::min(1.0f, std::max(0.0f, g));
      }
    }
    this->Timings.Features = NowMs() - t0;
  }

  grid.Levels = this->Levels;
  grid.Portable = portable;
  // A model says whether it was trained on radiance / albedo; the fixed guide demodulates.
  const bool demodulate = !this->NetworkActive || this->Session.GetDemodulate();
  const float* albedo = demodulate ? passes[PassAlbedo] : nullptr;
  const float* weights = this->Levels > 1 ? this->Weights.data() : nullptr;
  std::string cudaError;
  this->Grid.Apply(grid, settings.UseCuda, width, height, passes[PassRadiance], albedo,
    this->Guides.data(), weights, out, cudaError);
  if (settings.UseCuda && !this->Grid.GetLastOnCuda() && cudaError != this->LastWarned)
  {
    this->Warning = "bilateral grid on CUDA failed (" + cudaError + "); using the CPU";
    this->LastWarned = cudaError;
  }
  const BilateralGridTimings& t = this->Grid.GetLastTimings();
  this->Timings.Splat = t.Demodulate + t.Splat;
  this->Timings.Slice = t.Slice;
  return true;
}
}
