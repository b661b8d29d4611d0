/**
 * @file ptvGuideUpsample.h
 * @brief Private: GuideNet's planar outputs at the network's resolution -> the grid's interleaved
 *        full-resolution guides (times the guide scale) and blend weights.
 *
 * With guide stride s > 1 the network ran on ceil(H / s) x ceil(W / s) pixels; pixel (x, y) of the
 * image takes the bilinear interpolation of PyTorch's F.interpolate(scale_factor=s,
 * mode="bilinear", align_corners=False), cropped to W x H (Training/ptv_training/guidenet.py):
 * source coordinate sx = max((x + 0.5) / s - 0.5, 0), x0 = floor(sx), x1 = min(x0 + 1, w - 1),
 * lx = sx - x0 (likewise y), value = (1 - ly) ((1 - lx) o(y0, x0) + lx o(y0, x1))
 * + ly ((1 - lx) o(y1, x0) + lx o(y1, x1)). With s = 1 the values are copied. Threaded over
 * blocks of image rows; each channel's row is computed by the vectorised kernel
 * (ptvGuideUpsampleRows.h) into the block's scratch row, then interleaved into the output. The
 * coordinate tables and scratch rows are kept between frames.
 */
#ifndef ptvGuideUpsample_h
#define ptvGuideUpsample_h

#include <vector>

namespace ptv
{
class GuideUpsampler
{
public:
  /**
   * @a net holds the network's output planes (guides of the model's levels, then its blend
   * weights, then padding) of @a netWidth x @a netHeight pixels. Writes @a levels guides per
   * pixel, times @a scale, into @a guides (W * H * levels) and the first @a levels - 1 weights
   * into @a weights (W * H * (levels - 1)); @a modelLevels locates the weight planes.
   */
  void Run(const float* net, int netWidth, int netHeight, int stride, int width, int height,
    int levels, int modelLevels, float scale, int threads, bool portable, float* guides,
    float* weights);

private:
  std::vector<int> X0, X1, Y0, Y1;
  std::vector<float> LX, LY;
  std::vector<float> Scratch; // per block: one row per written channel
};
}

#endif
