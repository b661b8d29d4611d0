/**
 * @file ptvFeatures.h
 * @brief Private: GuideNet input features from the named passes, exactly as
 *        Training/ptv_training/features.py defines them (that file is the specification; a
 *        parity test compares the two), optionally box-averaged to the network's resolution.
 *
 * Channel names ("color.r", "albedo.g", "normal.x", "depth", "position.y", "scatter_normal.z",
 * "scatter_depth", "scatter_position.x", "alpha", "coverage", "history") come from the model's
 * ptv.input_channels.
 *
 * With a guide stride s > 1 (the model's ptv.guide_stride, Training/ptv_training/guidenet.py)
 * each output pixel (i, j) of the ceil(H / s) x ceil(W / s) planes is the mean of the features of
 * the s x s block of pixels (s i + dy, s j + dx), indices clamped to the image (edge replicated).
 * Work is threaded over output rows (ptvThreads.h); buffers are kept between frames. The
 * features can be made a band of rows at a time (Prepare, then Rows): the network runs in bands
 * and so never needs them for the whole image.
 */
#ifndef ptvFeatures_h
#define ptvFeatures_h

#include <cstddef>
#include <string>
#include <vector>

namespace ptv
{
class FeatureBuilder
{
public:
  FeatureBuilder();
  ~FeatureBuilder();

  /**
   * Fill @a out (channels.size() planes of ceil(height / stride) x ceil(width / stride), planar)
   * from @a passes (indexed by PassId, interleaved, bottom row first). Returns false and names
   * the channel in @a error when a name is unknown or a needed pass is missing (nullptr).
   * @a threads <= 0: every core. @a portable: the baseline build of the vectorised row kernel
   * (ptvFeatureRows.h) instead of this CPU's best instruction set.
   */
  bool Build(const float* const* passes, int width, int height,
    const std::vector<std::string>& channels, int stride, int threads, bool portable, float* out,
    std::string& error);

  /**
   * Build's first half: check the channels and passes (false and @a error as Build) and reduce
   * what spans the image (the depth channels' ranges). The passes must stay until the last Rows.
   */
  bool Prepare(const float* const* passes, int width, int height,
    const std::vector<std::string>& channels, int stride, int threads, std::string& error);

  /**
   * Build's second half: rows [@a first, @a last) of the reduced planes into @a out
   * (channels.size() planes of (last - first) x ceil(width / stride)); the same values as those
   * rows of Build's planes.
   */
  void Rows(int first, int last, int threads, bool portable, float* out);

private:
  struct Plan; // one channel: what it reads and, for depth/position, its hit test and range
  std::vector<Plan> Plans;
  std::vector<float> RowLow, RowHigh, RowFar; // per-row reductions
  std::vector<unsigned char> RowAny;
  std::vector<float> Scratch; // one image row per block of output rows
  std::vector<const float*> Passes; // Prepare's, by PassId
  int Width = 0, Height = 0, Stride = 1;
};

/// Whether @a name is a known feature channel.
bool IsFeatureChannel(const std::string& name);

/// ceil(n / stride), the size of a feature plane along an axis of n pixels.
inline int ReducedSize(int n, int stride)
{
  return (n + stride - 1) / stride;
}
}

#endif
