#include "ptvGuideUpsample.h"

#include "Kernels/ptvBilateralGrid.h"
#include "ptvGuideUpsampleRows.h"
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
  int height, int levels, int modelLevels, float scale, int threads, bool portable, float* guides,
  float* weights)
{
  const std::size_t plane = static_cast<std::size_t>(netWidth) * netHeight;
  const int channels = 2 * levels - 1; // written: levels guides, levels - 1 weights
  if (stride > 1)
  {
    Axis(width, netWidth, stride, this->X0, this->X1, this->LX);
    Axis(height, netHeight, stride, this->Y0, this->Y1, this->LY);
  }
  // Fixed blocks of rows, one per thread, each with its scratch rows.
  const int blocks = std::max(1, std::min(ResolvedThreads(threads), height));
  const std::size_t rowFloats = static_cast<std::size_t>(width);
  this->Scratch.resize(static_cast<std::size_t>(blocks) * channels * rowFloats);
  ParallelFor(threads, 0, blocks, 1,
    [&](vtkIdType blockBegin, vtkIdType blockEnd)
    {
      for (vtkIdType b = blockBegin; b < blockEnd; ++b)
      {
        float* scratch = this->Scratch.data() + static_cast<std::size_t>(b) * channels * rowFloats;
        const float* rows[2 * kMaxGridLevels - 1] = {}; // levels <= kMaxGridLevels
        for (vtkIdType y = height * b / blocks; y < height * (b + 1) / blocks; ++y)
        {
          for (int c = 0; c < channels; ++c)
          {
            // Channel c: guide c, or weight c - levels (model plane modelLevels + c - levels).
            const bool guide = c < levels;
            const float* src = net + plane * (guide ? c : modelLevels + c - levels);
            float* row = scratch + static_cast<std::size_t>(c) * rowFloats;
            rows[c] = row;
            const float factor = guide ? scale : 1.0f;
            if (stride == 1)
            {
              const float* from = src + static_cast<std::size_t>(y) * width;
              for (int x = 0; x < width; ++x)
              {
                row[x] = from[x] * factor;
              }
              continue;
            }
            UpsampleRowInput in;
            in.R0 = src + static_cast<std::size_t>(this->Y0[y]) * netWidth;
            in.R1 = src + static_cast<std::size_t>(this->Y1[y]) * netWidth;
            in.LY = this->LY[y];
            in.X0 = this->X0.data();
            in.X1 = this->X1.data();
            in.LX = this->LX.data();
            in.Width = width;
            in.Factor = factor;
            in.Stride = stride;
            in.NetWidth = netWidth;
            UpsampleRow(in, row, portable);
          }
          const std::size_t pixel = static_cast<std::size_t>(y) * width;
          InterleaveRows(rows, levels, width, guides + pixel * levels, portable);
          if (levels > 1)
          {
            InterleaveRows(rows + levels, levels - 1, width, weights + pixel * (levels - 1),
              portable);
          }
        }
      }
    });
}
}
