#include "ptvCpuTracer.h"

#include "ptvPassBuffers.h"

#include "ptvThreads.h"

#include <algorithm>
#include <string>

namespace ptv
{
//------------------------------------------------------------------------------
void TraceFrameCpu(
  const TraceParams& params, unsigned int firstSample, int samples, int threads, PassBuffers& out)
{
  const int width = params.Camera.Width;
  const int height = params.Camera.Height;
  WithThreads(threads,
    [&]() { vtkSMPTools::For(0, height, 1,
    [&](vtkIdType rowBegin, vtkIdType rowEnd)
    {
      for (vtkIdType y = rowBegin; y < rowEnd; ++y)
      {
        for (int x = 0; x < width; ++x)
        {
          out.Store(static_cast<int>(y) * width + x,
            TracePixelMean(params, firstSample, samples, x, static_cast<int>(y)));
        }
      }
    }); });
}
}
