// Denoiser, the guide's part: the model (GuideNet through ONNX Runtime, its levels and the
// channels it reads) or the fixed guide from albedo, depth and normal.
#include "ptvDenoiser.h"

#include "ptvDataDirectory.h"
#include "ptvFeatures.h"
#include "ptvKernelDispatch.h"

#include "vtkTimerLog.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <fstream>

#include <sys/stat.h>

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

/// A level whose spatial step leaves fewer grid cells than this over the image only blurs it.
constexpr double kMinimumGridCells = 16.0;

/**
 * Images of at most this many pixels run every level of the model, larger ones its default
 * ("ptv.default_levels"). The coarser levels pay most on small images and cost little there:
 * with the shipped model (trained for both counts: train.py --level-counts 1,3), on the 256^2
 * validation views all three levels gain 0.43 dB over one and 0.5-0.9 dB on the held-out
 * transfer functions, for about 1 ms (Training/results/v2_validation.md, level_dropout*);
 * on the 512^2 and 1024^2 benchmark frames they add little for 1.5x the time
 * (Testing/Benchmarks/results/denoiser_pareto.csv).
 * Training/ptv_training/bilateral_grid.py (automatic_levels) is the same rule.
 */
constexpr double kSmallImagePixels = 256.0 * 256.0;

/**
 * How many of @a count levels (finest first; the model's default, "ptv.default_levels") a
 * @a width x @a height image uses when the level count is automatic: coarser levels whose grid
 * would have fewer than kMinimumGridCells cells over the image are dropped, the finest always
 * stays (measured on the
 * head CT: at 8-24 pixels a side one level beats two by 0.3-2.2 dB; at 32 the two are level).
 * Training/ptv_training/bilateral_grid.py (fitting_levels) is the same rule.
 */
int FittingLevels(
  const std::vector<std::pair<int, int>>& steps, int count, int width, int height)
{
  while (count > 1 && count <= static_cast<int>(steps.size()))
  {
    const double step = steps[static_cast<std::size_t>(count - 1)].first;
    if ((width / step) * (height / step) >= kMinimumGridCells)
    {
      break;
    }
    --count;
  }
  return count;
}
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
    settings.ModelFile.empty() ? DefaultModelFile() : settings.ModelFile;
  // The file's identity: a model that failed is tried again once its file changes (written
  // later, replaced), not on every frame.
  struct stat info;
  const std::string stamp = ::stat(path.c_str(), &info) == 0
    ? std::to_string(info.st_mtime) + ":" + std::to_string(info.st_size)
    : std::string("none");
  if (path == this->RequestedModel && settings.Threads == this->SessionThreads &&
    (this->ModelProblem.empty() || stamp == this->RequestedStamp))
  {
    return this->ModelProblem.empty();
  }
  this->RequestedModel = path;
  this->RequestedStamp = stamp;
  this->SessionThreads = settings.Threads;
  this->ModelProblem.clear();
  if (!std::ifstream(path).good())
  {
    this->ModelProblem = "no GuideNet model at '" + path + "' (missing or unreadable)";
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
bool Denoiser::ReadsChannel(const DenoiserSettings& settings, const std::string& channel)
{
  if (!settings.UseNetwork || !this->EnsureModel(settings))
  {
    return false;
  }
  const std::vector<std::string>& channels = this->Session.GetInputChannels();
  return std::find(channels.begin(), channels.end(), channel) != channels.end();
}

//------------------------------------------------------------------------------
bool Denoiser::ReadsChannelStartingWith(
  const DenoiserSettings& settings, const std::string& prefix)
{
  if (!settings.UseNetwork || !this->EnsureModel(settings))
  {
    return false;
  }
  const std::vector<std::string>& channels = this->Session.GetInputChannels();
  return std::any_of(channels.begin(), channels.end(),
    [&](const std::string& c) { return c.compare(0, prefix.size(), prefix) == 0; });
}

//------------------------------------------------------------------------------
bool Denoiser::RunNetwork(const DenoiserSettings& settings, const float* const* passes, int width,
  int height, const DenoiserOverrides& given, float* out, std::string& error, bool& done)
{
  const double t0 = NowMs();
  const bool portable = UsePortableKernels(settings.PortableKernels);
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  // Features at the network's resolution (the model's guide stride): given, or built from the
  // passes. Then GuideNet, then its outputs upsampled into the grid's guides and weights.
  const std::vector<std::string>& channels = this->Session.GetInputChannels();
  const int stride = this->Session.GetGuideStride();
  const int netWidth = ReducedSize(width, stride);
  const int netHeight = ReducedSize(height, stride);
  const std::size_t netPixels = static_cast<std::size_t>(netWidth) * netHeight;
  // Made a band at a time when the network runs in bands: never kept for the whole image.
  const bool bands = !given.Features && this->Session.RunsInBands(netHeight, netWidth);
  if (bands)
  {
    std::vector<float>().swap(this->Features);
  }
  else
  {
    this->Features.resize(channels.size() * netPixels);
  }
  if (given.Features)
  {
    if (given.FeatureChannels != static_cast<int>(channels.size()))
    {
      std::string names;
      for (const std::string& c : channels)
      {
        names += (names.empty() ? "" : ",") + c;
      }
      error = "'Features' has " + std::to_string(given.FeatureChannels) + " components but the model " +
        this->RequestedModel + " expects " + std::to_string(channels.size()) + " channels: " + names;
      return false;
    }
    if (given.FeatureWidth != netWidth || given.FeatureHeight != netHeight)
    {
      error = "'Features' is " + std::to_string(given.FeatureWidth) + " x " +
        std::to_string(given.FeatureHeight) + " but the model runs at 1/" +
        std::to_string(stride) + " resolution: expected " + std::to_string(netWidth) + " x " +
        std::to_string(netHeight) + " for a " + std::to_string(width) + " x " +
        std::to_string(height) + " frame";
      return false;
    }
    const std::size_t c = channels.size();
    for (std::size_t k = 0; k < netPixels; ++k) // interleaved -> planar
    {
      for (std::size_t ci = 0; ci < c; ++ci)
      {
        this->Features[ci * netPixels + k] = given.Features[k * c + ci];
      }
    }
  }
  else if (bands ? !this->FeatureMaker.Prepare(passes, width, height, channels, stride,
                     settings.Threads, error)
                 : !this->FeatureMaker.Build(passes, width, height, channels, stride,
                     settings.Threads, portable, this->Features.data(), error))
  {
    return false; // a pass the model needs is missing: the caller's input is incomplete
  }
  const double featureMs = NowMs() - t0;
  double bandFeatureMs = 0.0; // the bands' features, made during the run
  const int modelLevels = this->Session.GetNumberOfLevels();
  this->NetOutput.resize(static_cast<std::size_t>(this->Session.GetNumberOfOutputs()) * netPixels);
  std::string runError;
  const double runStart = NowMs();
  const bool ran = bands
    ? this->Session.Run(
        [&](int first, int last, float* planes)
        {
          const double start = NowMs();
          this->FeatureMaker.Rows(first, last, settings.Threads, portable, planes);
          bandFeatureMs += NowMs() - start;
        },
        netHeight, netWidth, this->NetOutput.data(), runError)
    : this->Session.Run(this->Features.data(), netHeight, netWidth, this->NetOutput.data(),
        runError);
  this->Timings.Features = featureMs + bandFeatureMs;
  const double t1 = runStart + bandFeatureMs; // GuideNet's time: the run's, less its features
  if (!ran)
  {
    this->NetworkActive = false;
    this->ModelProblem = runError;
    this->RequestedModel.clear(); // retry the load next time
    return true;
  }
  const std::string source = this->RequestedModel + " (" +
    this->Session.GetExecutionProvider() + ")" + (given.Features ? ", given features" : "");
  if (this->Session.IsImageModel())
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
    this->Status = "image model " + source + ", no grid";
    done = true;
    return true;
  }
  const bool small = static_cast<double>(width) * static_cast<double>(height) <= kSmallImagePixels;
  const int levels = settings.Levels > 0
    ? std::min(settings.Levels, modelLevels)
    : FittingLevels(this->Session.GetLevels(),
        small ? modelLevels : this->Session.GetDefaultLevels(), width, height);
  this->Levels = levels;
  this->Guides.resize(n * levels);
  this->Weights.resize(n * std::max(levels - 1, 0));
  // Fewer levels than the model: the first levels-1 weights, the last level takes the rest.
  this->Upsampler.Run(this->NetOutput.data(), netWidth, netHeight, stride, width, height, levels,
    modelLevels, static_cast<float>(this->Session.GetGuideScale()), settings.Threads, portable,
    this->Guides.data(), this->Weights.data());
  if (bands)
  {
    std::vector<float>().swap(this->NetOutput); // upsampled: not kept for a big image
  }
  this->Timings.GuideNet = NowMs() - t1;
  this->Status = "GuideNet " + source + ", " + std::to_string(levels) + " levels" +
    (stride > 1 ? ", guides at 1/" + std::to_string(stride) + " resolution" : "") +
    (this->Session.GetDemodulate() ? "" : ", no demodulation");
  return true;
}

//------------------------------------------------------------------------------
bool Denoiser::FixedGuide(const DenoiserSettings& settings, const float* const* passes,
  int width, int height, std::string& error)
{
  const double t0 = NowMs();
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  this->Features.resize(kFixedGuideChannels.size() * n);
  if (!this->FeatureMaker.Build(passes, width, height, kFixedGuideChannels, 1, settings.Threads,
        UsePortableKernels(settings.PortableKernels), this->Features.data(), error))
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
  return true;
}
}
