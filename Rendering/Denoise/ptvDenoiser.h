/**
 * @file ptvDenoiser.h
 * @brief Private: one denoised frame from the named passes -- features (ptvFeatures) ->
 *        GuideNet in ONNX Runtime (ptvGuideNetSession) or, without a usable model, a fixed
 *        guide -> bilateral grid splat/slice/blend (ptvBilateralGridRunner: CPU or CUDA).
 *
 * The fixed guide (no network) is 255 * clip(0.35 lum(albedo) + 0.35 depth + 0.3 mean(normal
 * feature)) on three levels with equal blend weights: it follows clean geometric features only,
 * so it smooths along surfaces and keeps their edges, but not shading edges inside a surface.
 */
#ifndef ptvDenoiser_h
#define ptvDenoiser_h

#include "ptvBilateralGridRunner.h"
#include "ptvFeatures.h"
#include "ptvGuideNetSession.h"
#include "ptvGuideUpsample.h"

#include <string>
#include <vector>

namespace ptv
{
struct DenoiserSettings
{
  std::string ModelFile; ///< empty: the shipped model (ptv::DefaultModelFile())
  bool UseNetwork = true; ///< false: always the fixed guide
  int Levels = 0;         ///< 0: the model's (3 for the fixed guide); 1..3, <= the model's
  double Clamp = 8.0;     ///< outlier clamp factor before splatting (0 = off)
  int Threads = 0;        ///< <= 0: every core
  bool UseCuda = false;   ///< run the grid on the CUDA device (falls back to the CPU on error)
  bool PortableKernels = false; ///< CPU grid: the baseline kernels, not this CPU's best SIMD
  /// Grid steps of the fixed guide and of given guides (a model's own steps take precedence).
  int SpatialStep[kMaxGridLevels] = { 4, 8, 16 };
  int RangeStep[kMaxGridLevels] = { 4, 8, 16 };
};

/**
 * Optional inputs that replace a stage (vtkPTVDenoiser's "Features", "Guides", "BlendWeights"):
 * the network's input instead of the features built from the passes, or the grid's guides and
 * blend weights instead of the network (then the grid runs alone and demodulates when the
 * Albedo pass is given). All interleaved (channel last), row-major, bottom row first.
 */
struct DenoiserOverrides
{
  const float* Features = nullptr; ///< FeatureWidth x FeatureHeight x FeatureChannels
  int FeatureChannels = 0, FeatureWidth = 0, FeatureHeight = 0;
  const float* Guides = nullptr; ///< width x height x GuideLevels, [0, 255]
  int GuideLevels = 0;
  const float* Weights = nullptr; ///< width x height x (GuideLevels - 1), needed when > 1 level
};

struct DenoiserTimings
{
  double Features = 0, GuideNet = 0, Splat = 0, Slice = 0; ///< ms of the last Run
  /// ms of the last Run's opacity (Run's @a alpha; 0 without): on the CPU grid only its last
  /// step (clamp, colour to 0), since the opacity rides in the colour's Splat and Slice there;
  /// on the CUDA grid or without a grid the whole of DenoiseOpacity.
  double Alpha = 0;
};

/// What a pixel's denoised value counts for, in samples of a plain pixel, when it is weighed
/// against the pixel's own mean (Run's SampleRatio step). Chosen on the Table-1 views with 3
/// edge samples among 1.5, 2, 3, 4 and 6: 4 is the least that never loses to no weighting on
/// any dataset at 256² or 512² (docs/edge-samples.md).
constexpr float kDenoisedSampleWorth = 4.f;

/// The weight of its own mean in the result of a pixel whose mean holds @a ratio times a
/// plain pixel's samples: its ratio - 1 extra samples against the denoised value's
/// kDenoisedSampleWorth; 0 for @a ratio <= 1, NaN or infinite.
inline float OwnMeanWeight(float ratio)
{
  if (!(ratio > 1.f) || !(ratio < 3.4e38f))
  {
    return 0.f;
  }
  return (ratio - 1.f) / (ratio - 1.f + kDenoisedSampleWorth);
}

class Denoiser
{
public:
  /**
   * Denoise a @a width x @a height frame from @a passes (indexed by PassId, interleaved, nullptr
   * for a missing pass) into @a out (width * height * 3), with the stages that @a given replaces
   * (may be nullptr). Returns false with @a error for unusable input (no Radiance, zero size, a
   * pass the features or the demodulation need, given features or guides of the wrong shape);
   * a model that cannot be used is not an error: the fixed guide takes over and TakeWarning()
   * says why, once.
   *
   * With @a alpha (width * height floats) the Alpha pass (then required) goes through the
   * finest level of the same grid into @a alpha (on the CPU beside the colour, in the same
   * splat and slice; on CUDA by DenoiseOpacity): the opacity to draw @a out with. Where it is 0 no pixel near this one in the finest level's space (4 pixels, a guide
   * bin) has an event, so the colour the coarser levels spread there is set to 0 as well; with
   * one level that colour is 0 already. An image model has no grid: @a alpha is then a copy of
   * the Alpha pass and the colour stays.
   *
   * With the Footprint pass (vtkPTVExpertOptions::FootprintRays) and Footprint on
   * in @a settings (the default) the pixels that it
   * marks empty space -- 0 at the pixel's four corners, its own entry and those of pixels
   * (x + 1, y), (x, y + 1), (x + 1, y + 1), clamped at the image's edge -- are set to 0 in @a out
   * (and @a alpha): the grid spreads the colour of a thin structure into the empty pixels of
   * its guide bin, which one sample cannot tell from the fringe its ray missed.
   *
   * With the SampleRatio pass (how many times a plain pixel's samples each pixel's mean holds:
   * the mapper's edge pixels hold EdgeSamples times, docs/edge-samples.md) a pixel of ratio
   * r > 1 takes OwnMeanWeight(r) of its own mean (Radiance; Alpha for @a alpha) and the rest of
   * its denoised value, before the Footprint step: the grid averages a well-sampled pixel with
   * its one-sample neighbours, and on a thin structure's fringe that loses more than the extra
   * samples' own noise. Ratios <= 1, NaN or infinite, and pixels whose own mean is not finite
   * and non-negative, keep the denoised value.
   */
  bool Run(const DenoiserSettings& settings, const float* const* passes, int width, int height,
    float* out, std::string& error, const DenoiserOverrides* given = nullptr,
    float* alpha = nullptr);


  /**
   * Whether the model @a settings name (loaded here if it is not yet) reads the feature
   * channel @a channel ("coverage": the tracer then marches for it). False with UseNetwork off
   * or a model that cannot be used (the fixed guide reads none).
   */
  bool ReadsChannel(const DenoiserSettings& settings, const std::string& channel);
  /// Whether it reads a channel whose name starts with @a prefix ("scatter_"), likewise.
  bool ReadsChannelStartingWith(const DenoiserSettings& settings, const std::string& prefix);
  /// Whether the last Run used GuideNet (else the fixed guide).
  bool GetNetworkActive() const { return this->NetworkActive; }
  /// e.g. "GuideNet <file> (CPUExecutionProvider), 3 levels" or "fixed guide: <why>".
  const std::string& GetStatus() const { return this->Status; }
  /// A warning produced by the last Run that was not taken yet (empty if none).
  std::string TakeWarning();

  int GetLevels() const { return this->Levels; }
  /// The CPU grid's instruction set in the last Run ("AVX3", "AVX2", ..., "EMU128"/"SCALAR").
  const char* GetGridKernelTarget() const { return this->Grid.GetCpuKernelTarget(); }
  /// Guides of the last Run, interleaved width * height * GetLevels(), in [0, 255].
  const std::vector<float>& GetGuides() const { return this->Guides; }
  /// Blend weights, interleaved width * height * (GetLevels() - 1).
  const std::vector<float>& GetWeights() const { return this->Weights; }
  const DenoiserTimings& GetTimings() const { return this->Timings; }
  /// Whether the last Run's grid ran on the CUDA device.
  bool GetGridOnCuda() const { return this->Grid.GetLastOnCuda(); }

private:
  /**
   * The last RunColor's finest grid level -- its guide and steps, on the device @a settings
   * asks for -- applied to the opacity @a alphaIn without demodulation or outlier clamp, into
   * @a alpha (clamped to [0, 1]), and @a color set to 0 where that is 0 (Run). Without a grid
   * in the last run (an image-to-image model) @a alpha is a copy of @a alphaIn.
   */
  void DenoiseOpacity(const DenoiserSettings& settings, const float* alphaIn, int width,
    int height, float* alpha, float* color);
  bool EnsureModel(const DenoiserSettings& settings);
  /// The network's guides and weights (NetworkActive stays true) or false after a run error.
  bool RunNetwork(const DenoiserSettings& settings, const float* const* passes, int width,
    int height, const DenoiserOverrides& given, float* out, std::string& error, bool& done);
  /// Run up to the opacity's last step: with @a alpha the CPU grid also writes the opacity
  /// through its finest level into it, unclamped (then Grid.GetLastAlphaDone()).
  bool RunColor(const DenoiserSettings& settings, const float* const* passes, int width,
    int height, float* out, std::string& error, const DenoiserOverrides* given, float* alpha);
  /// @a alpha = every @a stride th value of @a filtered (may be @a alpha itself, stride 1)
  /// clamped to [0, 1], and @a color set to 0 where that is 0.
  static void FinishOpacity(int threads, int width, int height, const float* filtered,
    int stride, float* alpha, float* color);
  /// @a color (and @a alpha, if given) moved towards the pixel's own mean @a radiance
  /// (@a alphaIn) by OwnMeanWeight(@a ratio) (Run).
  static void LeanTowardsOwnMeans(int threads, int width, int height, const float* ratio,
    const float* radiance, const float* alphaIn, float* color, float* alpha);
  /// @a color (and @a alpha, if given) set to 0 where @a footprint marks the pixel empty (Run).
  static void KeepEmptyBlack(int threads, int width, int height, const float* footprint,
    float* color, float* alpha);
  /// The fixed guide's guides and weights from albedo, depth and normal.
  bool FixedGuide(const DenoiserSettings& settings, const float* const* passes, int width,
    int height, std::string& error);

  GuideNetSession Session;
  std::string RequestedModel; // the path of the last load attempt
  std::string RequestedStamp; // its file's modification time and size then
  std::string ModelProblem;   // why the model is not usable ("" = loaded)
  int SessionThreads = -1;
  BilateralGridRunner Grid;
  FeatureBuilder FeatureMaker;
  GuideUpsampler Upsampler;
  std::vector<float> Features, NetOutput, Guides, Weights;
  std::vector<float> Replicated, Filtered, FineGuide; // DenoiseOpacity's scratch
  BilateralGridSettings LastGrid;          // what the last RunColor's grid ran
  bool LastRanGrid = false;                // false: the last RunColor had no grid (or failed)
  int Levels = 0;
  bool NetworkActive = false;
  std::string Status, Warning;
  std::string LastModelWarning, LastGridWarning; // each reason is warned about once in a row
  DenoiserTimings Timings;
};
}

#endif
