/**
 * @file ptvDisplay.h
 * @brief Private: draws a float RGBA image (premultiplied) with per-pixel window depth into the
 *        renderer's viewport, so the volume and opaque geometry occlude each other correctly.
 *
 * The model is vtkOSPRayPass: float colour and depth textures on a full-screen quad that writes
 * gl_FragDepth. OpenGL types stay in the .cxx.
 */
#ifndef ptvDisplay_h
#define ptvDisplay_h

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

  /**
   * Blend @a rgba (width*height*4, premultiplied, bottom row first) over the framebuffer
   * (ONE, ONE_MINUS_SRC_ALPHA) where alpha > 0, and write @a depth (window depth in [0,1]) where
   * alpha > 0.5: later geometry, picking and other volumes see the volume where it mostly hides
   * what is behind it (a translucent volume drawn first would otherwise cut the rays of one
   * behind it). @a covered (ShownImage::GetCovered) holds every drawn pixel: only that
   * rectangle is drawn (nothing when it is empty).
   */
  void Draw(vtkRenderer* ren, int width, int height, const float* rgba, const float* depth,
    const int covered[4]);

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
