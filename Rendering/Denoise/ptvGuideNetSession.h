/**
 * @file ptvGuideNetSession.h
 * @brief Private: one GuideNet ONNX model loaded in ONNX Runtime (CPU, or CUDA when the runtime
 *        offers it), validated against its "ptv.*" metadata, run on planar float buffers.
 *
 * The model contract ("guidenet-v1", written by Training/ptv_training/export_onnx.py):
 *  - one float input, rank 4, [1, C, H, W] (H and W may be dynamic), C = number of names in the
 *    comma-separated metadata "ptv.input_channels";
 *  - one float output, rank 4, [1, 2L - 1, H, W], L = number of "ss:sr" pairs in "ptv.levels"
 *    (first L channels are guides in [0, 1], then L - 1 blend weights);
 *  - metadata "ptv.format" = "guidenet-v1"; or "denoiser-v1": an image-to-image network (the
 *    U-Net baseline) with one output [1, 3, H, W], the denoised radiance, and no levels;
 *    optional "ptv.guide_scale" (default 255) and
 *    "ptv.demodulate" ("1" default: the grid denoises radiance / albedo; "0": radiance).
 *
 * No ONNX Runtime type appears here: the Ort:: objects live in the .cxx (PIMPL), so this header
 * may be included by code that does not see the ORT include folder.
 */
#ifndef ptvGuideNetSession_h
#define ptvGuideNetSession_h

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace ptv
{
class GuideNetSession
{
public:
  GuideNetSession();
  ~GuideNetSession();
  GuideNetSession(const GuideNetSession&) = delete;
  GuideNetSession& operator=(const GuideNetSession&) = delete;

  /// Intra-op threads for the next Load(); 0 = ONNX Runtime's default (one per physical core).
  void SetNumberOfThreads(int n) { this->NumberOfThreads = n < 0 ? 0 : n; }
  int GetNumberOfThreads() const { return this->NumberOfThreads; }

  /// Also try the CUDA execution provider when ORT lists it (default true).
  void SetAllowCuda(bool allow) { this->AllowCuda = allow; }

  /**
   * Open and validate @a path. On failure returns false, fills @a error with every problem found
   * (prefixed by the file name) and leaves the session unloaded.
   */
  bool Load(const std::string& path, std::string& error);

  /// Drop the loaded model.
  void Unload();

  bool IsLoaded() const;

  /**
   * Run on @a features (C x H x W, planar, row-major) into @a out (GetNumberOfOutputs() x H x W).
   * Both buffers belong to the caller; ORT reads/writes them in place (no copies). H and W are the
   * network's: the image's divided by GetGuideStride(), rounded up.
   */
  bool Run(const float* features, int height, int width, float* out, std::string& error);

  /// Writes rows [first, last) of the features (C planes of (last - first) x W) into planes.
  using BandInput = std::function<void(int first, int last, float* planes)>;
  /**
   * Run, with the features made a band of rows at a time by @a input (each band with the rows
   * its convolutions reach): they are never needed for the whole image. One band when
   * RunsInBands() is false.
   */
  bool Run(const BandInput& input, int height, int width, float* out, std::string& error);

  /// Whether Run goes in bands of rows for H x W network pixels (SetTilePixels).
  bool RunsInBands(int height, int width) const;

  /**
   * Above this many network pixels (default 2^17) Run goes in bands of rows, each with the
   * rows the network's convolutions reach (GetTileHalo), so that its activations need memory
   * for a band, not the image; the output is the whole image's.
   */
  void SetTilePixels(std::size_t pixels) { this->TilePixels = pixels; }
  /// Rows a band of Run reaches beyond itself: from "ptv.architecture" (kernel // 2 +
  /// kernel2 // 2); -1 (the image in one run) for a model without it or with a context branch.
  int GetTileHalo() const { return this->TileHalo; }

  int GetNumberOfInputChannels() const { return static_cast<int>(this->Channels.size()); }
  const std::vector<std::string>& GetInputChannels() const { return this->Channels; }
  int GetNumberOfLevels() const { return static_cast<int>(this->Levels.size()); }
  /// Output channels: 3 for an image model, else 2L - 1 (guides, blend weights) plus the padding
  /// channels that "ptv.outputs" names "pad..." (ignored: ONNX Runtime's fast kernels want
  /// channel counts that are multiples of 8).
  int GetNumberOfOutputs() const { return this->OutputChannels; }
  /// "ptv.guide_stride" (default 1): the network runs on s x s box-averaged features and its
  /// outputs are upsampled bilinearly (Training/ptv_training/guidenet.py).
  int GetGuideStride() const { return this->GuideStride; }
  /// True for a "denoiser-v1" model: its output is the denoised radiance, not grid guides.
  bool IsImageModel() const { return this->ImageOutput; }
  /// "ptv.default_levels": how many of the finest levels run when the caller asks for none in
  /// particular (the model's choice of speed and quality); every level when the model has none.
  int GetDefaultLevels() const
  {
    return this->DefaultLevels > 0 ? this->DefaultLevels : this->GetNumberOfLevels();
  }
  /// (spatial step ss, range step sr) per level, finest first.
  const std::vector<std::pair<int, int>>& GetLevels() const { return this->Levels; }
  double GetGuideScale() const { return this->GuideScale; }
  /// Whether the model was trained with albedo demodulation ("ptv.demodulate").
  bool GetDemodulate() const { return this->Demodulate; }
  /// "CPUExecutionProvider" or "CUDAExecutionProvider"; empty when nothing is loaded.
  const std::string& GetExecutionProvider() const { return this->Provider; }
  const std::string& GetPath() const { return this->Path; }
  /// "1.21.1" style version of the loaded ONNX Runtime library.
  static std::string GetRuntimeVersion();

private:
  /// Run's checks of the session and the sizes.
  bool CanRun(int height, int width, std::string& error) const;
  /// One ONNX Runtime run on @a height rows (Run's checks done).
  bool RunRows(const float* features, int height, int width, float* out, std::string& error);

  struct Internals;
  std::unique_ptr<Internals> Impl;
  int NumberOfThreads = 0;
  bool AllowCuda = true;
  std::string Path;
  std::string Provider;
  std::vector<std::string> Channels;
  std::vector<std::pair<int, int>> Levels;
  double GuideScale = 255.0;
  bool Demodulate = true;
  bool ImageOutput = false;
  int OutputChannels = 0;
  int GuideStride = 1;
  int DefaultLevels = 0;
  int TileHalo = -1;
  std::size_t TilePixels = std::size_t(1) << 17;
};
}

#endif
