#include "ptvDenoiser.h"

#include "ptvFeatures.h"
#include "ptvKernelDispatch.h"
#include "ptvPassBuffers.h"
#include "ptvThreads.h"

#include "vtkTimerLog.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace ptv
{
namespace
{
double NowMs()
{
  return 1000.0 * vtkTimerLog::GetUniversalTime();
}
}

//------------------------------------------------------------------------------
bool Denoiser::Run(const DenoiserSettings& settings, const float* const* passes, int width,
  int height, float* out, std::string& error, const DenoiserOverrides* given, float* alpha)
{
  if (alpha && !passes[PassAlpha])
  {
    error = "the denoised opacity needs the Alpha pass";
    return false;
  }
  if (!this->RunColor(settings, passes, width, height, out, error, given, alpha))
  {
    return false;
  }
  const double start = NowMs();
  if (alpha && this->LastRanGrid && this->Grid.GetLastAlphaDone())
  {
    // The CPU grid filtered the opacity beside the colour (its time is in Splat and Slice).
    FinishOpacity(settings.Threads, width, height, alpha, 1, alpha, out);
  }
  else if (alpha)
  {
    this->DenoiseOpacity(settings, passes[PassAlpha], width, height, alpha, out);
  }
  if (passes[PassSampleRatio])
  {
    LeanTowardsOwnMeans(settings.Threads, width, height, passes[PassSampleRatio],
      passes[PassRadiance], passes[PassAlpha], out, alpha);
  }
  if (passes[PassFootprint]) // pixels it marks empty stay black
  {
    KeepEmptyBlack(settings.Threads, width, height, passes[PassFootprint], out, alpha);
  }
  this->Timings.Alpha = alpha ? NowMs() - start : 0.0;
  return true;
}

//------------------------------------------------------------------------------
bool Denoiser::RunColor(const DenoiserSettings& settings, const float* const* passes, int width,
  int height, float* out, std::string& error, const DenoiserOverrides* given, float* alpha)
{
  this->Timings = DenoiserTimings{};
  this->LastRanGrid = false;
  if (width <= 0 || height <= 0)
  {
    error = "cannot denoise an empty image (" + std::to_string(width) + " x " +
      std::to_string(height) + ")";
    return false;
  }
  if (!passes[PassRadiance])
  {
    error = "denoising needs the Radiance pass";
    return false;
  }
  const DenoiserOverrides none;
  const DenoiserOverrides& g = given ? *given : none;
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  BilateralGridSettings grid;
  grid.Clamp = settings.Clamp;
  grid.Threads = settings.Threads;
  grid.Portable = UsePortableKernels(settings.PortableKernels);
  std::copy(settings.SpatialStep, settings.SpatialStep + kMaxGridLevels, grid.SpatialStep);
  std::copy(settings.RangeStep, settings.RangeStep + kMaxGridLevels, grid.RangeStep);

  // Guides and weights: given, GuideNet's, or the fixed guide's.
  bool demodulate = true;
  if (g.Guides)
  {
    const int levels = g.GuideLevels;
    if (levels < 1 || levels > kMaxGridLevels)
    {
      error = "'Guides' has " + std::to_string(levels) + " components; 1 to " +
        std::to_string(kMaxGridLevels) + " (one per grid level) are possible";
      return false;
    }
    if (settings.Levels > 0 && settings.Levels != levels)
    {
      error = "'Guides' has " + std::to_string(levels) + " components but NumberOfLevels is " +
        std::to_string(settings.Levels) + " (0 takes the guides' count)";
      return false;
    }
    if (levels > 1 && !g.Weights)
    {
      error = std::to_string(levels) + " levels of 'Guides' need 'BlendWeights' (" +
        std::to_string(levels - 1) + " components)";
      return false;
    }
    this->NetworkActive = false;
    this->Levels = levels;
    this->Guides.assign(g.Guides, g.Guides + n * levels);
    if (levels > 1)
    {
      this->Weights.assign(g.Weights, g.Weights + n * (levels - 1));
    }
    else
    {
      this->Weights.clear();
    }
    demodulate = passes[PassAlbedo] != nullptr;
    this->Status = "given guides, " + std::to_string(levels) + " levels" +
      (demodulate ? "" : ", no demodulation (no Albedo)");
  }
  else
  {
    this->NetworkActive = settings.UseNetwork && this->EnsureModel(settings);
    if (this->NetworkActive)
    {
      bool done = false; // an image model's output is the result
      if (!this->RunNetwork(settings, passes, width, height, g, out, error, done))
      {
        return false;
      }
      if (done)
      {
        return true;
      }
      if (this->NetworkActive)
      {
        this->LastModelWarning.clear(); // a model that fails again is reported again
        for (int l = 0; l < this->Levels; ++l) // the model's steps
        {
          grid.SpatialStep[l] = this->Session.GetLevels()[l].first;
          grid.RangeStep[l] = this->Session.GetLevels()[l].second;
        }
      }
    }
    if (!this->NetworkActive)
    {
      const std::string why = settings.UseNetwork ? this->ModelProblem : "UseNetwork is off";
      if (settings.UseNetwork && why != this->LastModelWarning)
      {
        this->Warning = why + "; denoising with a fixed guide (no network)" +
          (g.Features ? ", the given 'Features' unused" : ""); // the first warning of a Run
        this->LastModelWarning = why;
      }
      this->Status = "fixed guide: " + why;
      if (!this->FixedGuide(settings, passes, width, height, error))
      {
        error = "the fixed guide (" + why + ") cannot run: " + error;
        this->Warning.clear(); // the error says it all
        return false;
      }
    }
    // A model says whether it was trained on radiance / albedo; the fixed guide demodulates.
    demodulate = !this->NetworkActive || this->Session.GetDemodulate();
    if (demodulate && !passes[PassAlbedo])
    {
      error = std::string(this->NetworkActive ? "the model" : "the fixed guide") +
        " divides the radiance by the Albedo pass, which is missing";
      return false;
    }
  }

  grid.Levels = this->Levels;
  const float* albedo = demodulate ? passes[PassAlbedo] : nullptr;
  const float* weights = this->Levels > 1 ? this->Weights.data() : nullptr;
  std::string cudaError;
  this->Grid.Apply(grid, settings.UseCuda, width, height, passes[PassRadiance], albedo,
    this->Guides.data(), weights, out, cudaError, alpha ? passes[PassAlpha] : nullptr, alpha);
  if (settings.UseCuda && !this->Grid.GetLastOnCuda() && cudaError != this->LastGridWarning)
  {
    this->Warning += (this->Warning.empty() ? "" : "\n") +
      std::string("bilateral grid on CUDA failed (") + cudaError + "); using the CPU";
    this->LastGridWarning = cudaError;
  }
  const BilateralGridTimings& t = this->Grid.GetLastTimings();
  this->Timings.Splat = t.Demodulate + t.Splat;
  this->Timings.Slice = t.Slice;
  this->LastGrid = grid;
  this->LastRanGrid = true;
  return true;
}

//------------------------------------------------------------------------------
void Denoiser::DenoiseOpacity(const DenoiserSettings& settings, const float* alphaIn, int width,
  int height, float* alpha, float* color)
{
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  if (!this->LastRanGrid)
  {
    std::copy(alphaIn, alphaIn + n, alpha);
    return;
  }
  // The finest level alone: an opacity's edges are the grid's finest features, and on the 256^2
  // Table-1 views all levels drew the window within 0.1 dB of it for twice the time
  // (research/benchmarks/shown_alpha.py, 2026-12-03).
  const int threads = settings.Threads;
  const std::size_t levels = static_cast<std::size_t>(this->Levels);
  this->Replicated.resize(3 * n);
  this->Filtered.resize(3 * n);
  this->FineGuide.resize(levels > 1 ? n : 0);
  float* rgb = this->Replicated.data();
  float* fine = this->FineGuide.data();
  const float* guides = this->Guides.data();
  ParallelFor(threads, std::size_t{ 0 }, n, std::size_t{ 1 } << 15,
    [&](std::size_t begin, std::size_t end)
    {
      for (std::size_t i = begin; i < end; ++i)
      {
        rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = alphaIn[i];
        if (levels > 1)
        {
          fine[i] = guides[i * levels];
        }
      }
    });
  BilateralGridSettings grid = this->LastGrid;
  grid.Clamp = 0.0; // an opacity has no fireflies
  grid.Threads = threads;
  grid.Levels = 1;
  std::string cudaError; // a failing device falls back to the CPU, as in Run (warned there)
  this->Grid.Apply(grid, settings.UseCuda, width, height, rgb, nullptr,
    levels > 1 ? fine : guides, nullptr, this->Filtered.data(), cudaError);
  FinishOpacity(threads, width, height, this->Filtered.data(), 3, alpha, color);
}

//------------------------------------------------------------------------------
void Denoiser::LeanTowardsOwnMeans(int threads, int width, int height, const float* ratio,
  const float* radiance, const float* alphaIn, float* color, float* alpha)
{
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  ParallelFor(threads, std::size_t{ 0 }, n, std::size_t{ 1 } << 15,
    [&](std::size_t begin, std::size_t end)
    {
      for (std::size_t i = begin; i < end; ++i)
      {
        const float w = OwnMeanWeight(ratio[i]);
        if (w == 0.f)
        {
          continue;
        }
        const float* own = radiance + 3 * i;
        bool usable = true;
        for (int c = 0; c < 3; ++c)
        {
          usable = usable && own[c] >= 0.f && own[c] < 3.4e38f; // not NaN, negative or Inf
        }
        if (!usable)
        {
          continue;
        }
        for (int c = 0; c < 3; ++c)
        {
          color[3 * i + c] += w * (own[c] - color[3 * i + c]);
        }
        if (alpha && alphaIn && alphaIn[i] == alphaIn[i]) // a NaN opacity keeps the denoised one
        {
          alpha[i] += w * (std::min(1.f, std::max(0.f, alphaIn[i])) - alpha[i]);
        }
      }
    });
}

//------------------------------------------------------------------------------
void Denoiser::KeepEmptyBlack(int threads, int width, int height, const float* footprint,
  float* color, float* alpha)
{
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  const std::size_t w = static_cast<std::size_t>(width);
  ParallelFor(threads, std::size_t{ 0 }, n, std::size_t{ 1 } << 15,
    [&](std::size_t begin, std::size_t end)
    {
      for (std::size_t i = begin; i < end; ++i)
      {
        const std::size_t x = i % w;
        const std::size_t right = x + 1 < w ? 1 : 0;     // the corner (x + 1, y)
        const std::size_t below = i + w < n ? w : 0;     // the corner (x, y + 1)
        const bool covered = footprint[i] > 0.f || footprint[i + right] > 0.f ||
          footprint[i + below] > 0.f || footprint[i + below + right] > 0.f;
        if (!covered) // NaN counts as empty: the pass is 0 or 1 (means of them)
        {
          color[3 * i] = color[3 * i + 1] = color[3 * i + 2] = 0.0f;
          if (alpha)
          {
            alpha[i] = 0.0f;
          }
        }
      }
    });
}

//------------------------------------------------------------------------------
void Denoiser::FinishOpacity(int threads, int width, int height, const float* filtered,
  int stride, float* alpha, float* color)
{
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  ParallelFor(threads, std::size_t{ 0 }, n, std::size_t{ 1 } << 15,
    [&](std::size_t begin, std::size_t end)
    {
      for (std::size_t i = begin; i < end; ++i)
      {
        alpha[i] = std::min(1.0f, std::max(0.0f, filtered[stride * i]));
        if (alpha[i] == 0.0f) // no event near: what is here came from the coarser levels
        {
          color[3 * i] = color[3 * i + 1] = color[3 * i + 2] = 0.0f;
        }
      }
    });
}
}
