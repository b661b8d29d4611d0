#include "ptvGuideUpsample.h"

#include "ptvThreads.h"

#include "vtkType.h"

#include <algorithm>
#include <cstddef>
#include <string>

namespace ptv
{
namespace
{
/// PyTorch's bilinear source indices and weights (align_corners=False, scale s) along one axis.
void Axis(int n, int reduced, int stride, std::vector<int>& i0, std::vector<int>& i1,
  std::vector<float>& lambda)
{
  i0.resize(static_cast<std::size_t>(n));
  i1.resize(static_cast<std::size_t>(n));
  lambda.resize(static_cast<std::size_t>(n));
  const float scale = 1.0f / static_cast<float>(stride);
  for (int x = 0; x < n; ++x)
  {
    float src = scale * (static_cast<float>(x) + 0.5f) - 0.5f;
    src = src < 0.f ? 0.f : src;
    const int a = std::min(static_cast<int>(src), reduced - 1);
    i0[x] = a;
    i1[x] = a < reduced - 1 ? a + 1 : a;
    lambda[x] = src - static_cast<float>(a);
  }
}
}

//------------------------------------------------------------------------------
void GuideUpsampler::Run(const float* net, int netWidth, int netHeight, int stride, int width,
  int height, int levels, int modelLevels, float scale, int threads, float* guides,
  float* weights)
{
  const std::size_t plane = static_cast<std::size_t>(netWidth) * netHeight;
  const int channels = 2 * levels - 1; // written: levels guides, levels - 1 weights
  if (stride > 1)
  {
    Axis(width, netWidth, stride, this->X0, this->X1, this->LX);
    Axis(height, netHeight, stride, this->Y0, this->Y1, this->LY);
  }
  ParallelFor(threads, 0, height, 16,
    [&](vtkIdType yBegin, vtkIdType yEnd)
    {
      for (vtkIdType y = yBegin; y < yEnd; ++y)
      {
        for (int c = 0; c < channels; ++c)
        {
          // Channel c: guide c, or weight c - levels (model plane modelLevels + c - levels).
          const bool guide = c < levels;
          const float* src = net + plane * (guide ? c : modelLevels + c - levels);
          float* dst = guide ? guides + c : weights + (c - levels);
          const int step = guide ? levels : levels - 1;
          const float factor = guide ? scale : 1.0f;
          float* out = dst + static_cast<std::size_t>(y) * width * step;
          if (stride == 1)
          {
            const float* row = src + static_cast<std::size_t>(y) * width;
            for (int x = 0; x < width; ++x)
            {
              out[static_cast<std::size_t>(x) * step] = row[x] * factor;
            }
            continue;
          }
          const float* r0 = src + static_cast<std::size_t>(this->Y0[y]) * netWidth;
          const float* r1 = src + static_cast<std::size_t>(this->Y1[y]) * netWidth;
          const float ly = this->LY[y];
          for (int x = 0; x < width; ++x)
          {
            const int a = this->X0[x];
            const int b = this->X1[x];
            const float lx = this->LX[x];
            const float top = (1.f - lx) * r0[a] + lx * r0[b];
            const float bottom = (1.f - lx) * r1[a] + lx * r1[b];
            out[static_cast<std::size_t>(x) * step] = ((1.f - ly) * top + ly * bottom) * factor;
          }
        }
      }
    });
}
}
