/**
 * @file ptvDenoiserImages.h
 * @brief Private: vtkPTVDenoiser's images by name -- the passes, and "Features", "Guides",
 *        "BlendWeights" that replace a stage -- checked and turned into what ptv::Denoiser runs
 *        on (pass pointers and ptv::DenoiserOverrides).
 */
#ifndef ptvDenoiserImages_h
#define ptvDenoiserImages_h

#include "ptvDenoiser.h"
#include "ptvPassBuffers.h"

#include "vtkImageData.h"
#include "vtkSmartPointer.h"

#include <string>

namespace ptv
{
class DenoiserImages
{
public:
  /// Sets (nullptr: removes) the image called @a name; false when the name is unknown.
  bool Set(const char* name, vtkImageData* image);
  vtkImageData* Get(const char* name) const;
  void Clear();

  /**
   * Checks every image (W x H x 1 with a float array: the active scalars, or else the only
   * one; component counts; equal sizes; Features at any size, checked against the model later)
   * and fills @a passes (indexed by PassId, nullptr where missing), the frame size and
   * @a given. Returns false with @a error naming the image and the offending value.
   */
  bool Resolve(const float* passes[PassCount], int& width, int& height, DenoiserOverrides& given,
    std::string& error) const;

  /// The names accepted besides the passes.
  static constexpr const char* kStageNames = "Features, Guides, BlendWeights";

private:
  enum Extra
  {
    ExtraFeatures,
    ExtraGuides,
    ExtraWeights,
    ExtraCount
  };
  static int FindExtra(const char* name);

  vtkSmartPointer<vtkImageData> Passes[PassCount];
  vtkSmartPointer<vtkImageData> Extras[ExtraCount];
};
}

#endif
