/**
 * @file ptvFrameSignature.h
 * @brief Private: what a frame's image depends on, compared between renders to keep, reproject
 *        or restart the accumulation.
 */
#ifndef ptvFrameSignature_h
#define ptvFrameSignature_h

#include <vector>

namespace ptv
{
/**
 * Everything that changes the image, in two parts: the scene (volume, transfer function, fixed
 * lights, settings, size), whose change drops every sample, and the view (the camera, the lights
 * that move with it, the opaque geometry's depths), whose change alone lets the accumulation be
 * reprojected (ptvReprojection). Exact values (modification times, sizes, settings, the
 * geometry's hash) must match exactly; geometric values (camera, light) within a relative 1e-6,
 * far below a pixel: VTK itself nudges them by rounding (vtkWindowToImageFilter changes the view
 * angle by ~1e-8 and back), which must not restart the accumulation.
 */
struct FrameSignature
{
  enum class Change
  {
    None,  ///< the same image
    View,  ///< only the view moved: the scene's samples can be reprojected
    Scene, ///< the scene changed (or the view's exact part without the camera): start again
  };

  std::vector<double> Exact;
  std::vector<double> Approximate;
  std::vector<double> View;      ///< approximate
  std::vector<double> ViewExact; ///< exact, and expected to change when the camera moves

  /// What changed from @a other to this.
  Change Compare(const FrameSignature& other) const;
  void AddExact(const double* v, int n) { this->Exact.insert(this->Exact.end(), v, v + n); }
  void AddApproximate(const double* v, int n)
  {
    this->Approximate.insert(this->Approximate.end(), v, v + n);
  }
  void AddView(const double* v, int n) { this->View.insert(this->View.end(), v, v + n); }
  void AddViewExact(const double* v, int n)
  {
    this->ViewExact.insert(this->ViewExact.end(), v, v + n);
  }
  void Clear()
  {
    this->Exact.clear();
    this->Approximate.clear();
    this->View.clear();
    this->ViewExact.clear();
  }
};
}

#endif
