/**
 * @file ptvFeatures.h
 * @brief Private: GuideNet input features from the named passes, exactly as
 *        Training/ptv_training/features.py defines them (that file is the specification; a
 *        parity test compares the two).
 *
 * Channel names ("color.r", "albedo.g", "normal.x", "depth", "position.y", "scatter_normal.z",
 * "scatter_depth", "scatter_position.x", "alpha") come from the model's ptv.input_channels.
 */
#ifndef ptvFeatures_h
#define ptvFeatures_h

#include <string>
#include <vector>

namespace ptv
{
/**
 * Fill @a out (channels.size() x height x width, planar) from @a passes (indexed by PassId,
 * interleaved, bottom row first). Returns false and names the channel in @a error when a name
 * is unknown or a needed pass is missing (nullptr).
 */
bool BuildFeatures(const float* const* passes, int width, int height,
  const std::vector<std::string>& channels, float* out, std::string& error);

/// Whether @a name is a known feature channel.
bool IsFeatureChannel(const std::string& name);
}

#endif
