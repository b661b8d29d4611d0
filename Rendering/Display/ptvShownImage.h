/**
 * @file ptvShownImage.h
 * @brief Private: what the window shows for a frame -- premultiplied RGBA and window depth made
 *        from the passes, ready for ptvDisplay to draw.
 *
 * Colour: the radiance (raw, denoised or converged) with the Alpha pass, premultiplied; any
 * other pass is
 * colourised for inspection (opaque, in [0, 1], misses black: depths near = bright, normals
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
   * Fill the colour from pass @a pass of @a passes and the depth from its Depth pass, with the
   * projection of @a ren's active camera; @a camera made the rays, @a bounds are the volume's
   * world bounds. Rows run on @a threads threads (<= 0: every core). A radiance-like pass
   * (Radiance, Denoised, Converged) is drawn premultiplied with opacity @a alpha (one float per
   * pixel), or with the Alpha pass when it is nullptr.
   */
  void Update(vtkRenderer* ren, const PassBuffers& passes, int pass, const CameraRays& camera,
    const double bounds[6], int threads, const float* alpha = nullptr);

  const float* GetColor() const { return this->Color.data(); }
  const float* GetDepth() const { return this->Depth.data(); }

  /**
   * The smallest pixel rectangle holding every drawn pixel (alpha not <= 0): columns
   * [Covered[0], Covered[2]) and rows [Covered[1], Covered[3]); empty (all 0) when nothing is
   * drawn. ptvDisplay draws only there (the volume often covers a small part of the view).
   */
  const int* GetCovered() const { return this->Covered; }

private:
  std::vector<float> Color;
  std::vector<float> Depth;
  std::vector<int> RowCover; ///< per row: first and last drawn column (last < first: none)
  int Covered[4] = { 0, 0, 0, 0 };
};
}

#endif
