/**
 * @file ptvGuideNetMetadata.h
 * @brief Private: the metadata a denoiser model carries (Training/ptv_training/export_onnx.py
 *        writes it) -- its format, input channels, grid levels, guide scale and stride, default
 *        level count, demodulation and padding outputs -- read and checked, without ONNX Runtime.
 */
#ifndef ptvGuideNetMetadata_h
#define ptvGuideNetMetadata_h

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace ptv
{
/// The metadata keys and format values Training/ptv_training/export_onnx.py writes.
constexpr const char* kFormatKey = "ptv.format";
constexpr const char* kChannelsKey = "ptv.input_channels";
constexpr const char* kLevelsKey = "ptv.levels";
constexpr const char* kGuideScaleKey = "ptv.guide_scale";
constexpr const char* kDemodulateKey = "ptv.demodulate";
constexpr const char* kGuideStrideKey = "ptv.guide_stride";
constexpr const char* kDefaultLevelsKey = "ptv.default_levels";
constexpr const char* kOutputsKey = "ptv.outputs";
constexpr int kMaxGuideStride = 16;
constexpr const char* kFormatValue = "guidenet-v1";
constexpr const char* kImageFormatValue = "denoiser-v1"; // an image-to-image network (baseline)

/// What a model's metadata says (GuideNetSession holds the same once the model is loaded).
struct GuideNetMetadata
{
  bool Image = false; ///< an image-to-image model (denoiser-v1): no grid levels
  std::vector<std::string> Channels;
  bool HaveChannels = false;
  std::vector<std::pair<int, int>> Levels; ///< (spatial step, range step), finest first
  bool HaveLevels = false;
  double GuideScale = 255.0;
  int GuideStride = 1;
  int DefaultLevels = 0; ///< 0: every level of the model
  bool Demodulate = true;
  int64_t OutputPadding = 0; ///< the trailing "pad..." names of ptv.outputs
};

/// Looks up one metadata @a key into @a value; false when the model does not have it.
using MetadataLookup = std::function<bool(const char* key, std::string& value)>;

/// The model's metadata through @a lookup; each problem is appended to @a problems.
GuideNetMetadata ReadGuideNetMetadata(
  const MetadataLookup& lookup, std::vector<std::string>& problems);

/// @a items joined with @a sep.
std::string Join(const std::vector<std::string>& items, const char* sep);
}

#endif
