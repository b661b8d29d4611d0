/**
 * @file ptvDisplay.h
 * @brief Private: draws a float RGB image (premultiplied) and its opacity with per-pixel window
 *        depth into the renderer's viewport, so the volume and opaque geometry occlude each
 *        other correctly.
 *
 * The model is vtkOSPRayPass: float colour and depth textures on a full-screen quad that writes
 * gl_FragDepth; here textures of the rectangle the drawn pixels cover, made for each image.
 * OpenGL types stay in the .cxx.
 */
#ifndef ptvDisplay_h
#define ptvDisplay_h

#include <functional>
#include <memory>

class vtkRenderer;
class vtkWindow;

namespace ptv
{
class Display
{
public:
  Display();
  ~Display();

  /// Writes the window depth of columns [x0, x1) of rows [y0, y1), row after row.
  using DepthRows = std::function<void(int x0, int y0, int x1, int y1, float* out)>;

  /**
   * Blend @a rgb (width*height*3, premultiplied, bottom row first) with opacity @a alpha
   * (width*height) over the framebuffer (ONE, ONE_MINUS_SRC_ALPHA) where alpha > 0, and write
   * the window depth in [0,1] that @a depth gives (for the covered rectangle) where alpha > 0.5: later geometry, picking and other volumes see the volume where it mostly hides
   * what is behind it (a translucent volume drawn first would otherwise cut the rays of one
   * behind it). @a covered (ShownImage::GetCovered) holds every drawn pixel: only that
   * rectangle is drawn (nothing when it is empty).
   */
  void Draw(vtkRenderer* ren, int width, int height, const float* rgb, const float* alpha,
    const DepthRows& depth, const int covered[4]);

  /**
   * Read the depth buffer of the framebuffer being drawn (not whatever read buffer the window
   * left bound: after a window grab that is the displayed frame, which holds the volume's own
   * depth) for the renderer's viewport; a multisampled one is resolved into a single-sample
   * copy first. Returns false (and leaves @a depth alone) on failure.
   */
  bool ReadDepth(vtkRenderer* ren, int x0, int y0, int width, int height, float* depth);

  void ReleaseGraphicsResources(vtkWindow* window);

private:
  struct Internals;
  std::unique_ptr<Internals> Impl;
};
}

#endif
