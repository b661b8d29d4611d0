/**
 * @file ptvShownImage.h
 * @brief Private: what the window shows for a frame -- premultiplied colour, opacity and window
 *        depth made from the passes, ready for ptvDisplay to draw.
 *
 * Colour: the radiance (raw, denoised or converged) with its opacity, premultiplied, read in
 * the passes themselves (no copy); any other pass is colourised for inspection (opaque, in [0, 1], misses black: depths near = bright, normals
 * 0.5 n + 0.5, positions scaled to the volume's bounds). Depth: the window depth of the first
 * event along each pixel's centre ray (1 = no event: the depth buffer is left alone), so later
 * opaque geometry and picking see the volume. The rows are filled in parallel, with the
 * rectangle the drawn pixels cover.
 */
#ifndef ptvShownImage_h
#define ptvShownImage_h

#include "Kernels/ptvCamera.h"

#include <vector>

class vtkRenderer;

namespace ptv
{
class PassBuffers;

class ShownImage
{
public:
  /**
   * Show pass @a pass of @a passes, its depth from their Depth pass with the projection of
   * @a ren's active camera (WindowDepth); @a camera made the rays, @a bounds are the volume's
   * world bounds. Rows run on @a threads threads (<= 0: every core). A radiance-like pass
   * (Radiance, Denoised, Converged) is drawn premultiplied with opacity @a alpha (one float per
   * pixel), or with the Alpha pass when it is nullptr.
   */
  void Update(vtkRenderer* ren, const PassBuffers& passes, int pass, const CameraRays& camera,
    const double bounds[6], int threads, const float* alpha = nullptr);

  /// RGB per pixel (premultiplied) and its opacity; valid until the passes change or Release().
  const float* GetColor() const { return this->ShownColor; }
  const float* GetAlpha() const { return this->ShownAlpha; }

  /**
   * The window depth of columns [x0, x1) of rows [y0, y1) into @a out (row after row): the
   * first event along each pixel's centre ray, projected; 1 for no event. Made when asked for
   * (ptvDisplay asks for the covered rectangle), not kept.
   */
  void WindowDepth(int x0, int y0, int x1, int y1, float* out) const;

  /// Free what Update made (drawn: the next frame makes its own).
  void Release();

  /**
   * The smallest pixel rectangle holding every drawn pixel (alpha not <= 0): columns
   * [Covered[0], Covered[2]) and rows [Covered[1], Covered[3]); empty (all 0) when nothing is
   * drawn. ptvDisplay draws only there (the volume often covers a small part of the view).
   */
  const int* GetCovered() const { return this->Covered; }

private:
  std::vector<float> Color; ///< a colourised pass (RGB)
  std::vector<float> Alpha; ///< its opacity (1)
  const float* ShownColor = nullptr;
  const float* ShownAlpha = nullptr;
  const float* RayDepth = nullptr; ///< the Depth pass
  CameraRays Camera{};
  double ZRow[4] = {}, WRow[4] = {}; ///< the projection's rows for z and w
  int Width = 0, Threads = 0;
  std::vector<int> RowCover; ///< per row: first and last drawn column (last < first: none)
  int Covered[4] = { 0, 0, 0, 0 };
};
}

#endif
