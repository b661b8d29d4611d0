#include "ptvCpuTracer.h"

#include "ptvPassBuffers.h"

#include "vtkSMPTools.h"

#include <algorithm>
#include <string>
#include <thread>

namespace ptv
{
//------------------------------------------------------------------------------
void TraceFrameCpu(
  const TraceParams& params, unsigned int firstSample, int samples, int threads, PassBuffers& out)
{
  const int width = params.Camera.Width;
  const int height = params.Camera.Height;
  std::string backend = vtkSMPTools::GetBackend() ? vtkSMPTools::GetBackend() : "Sequential";
  if (backend == "Sequential" && threads != 1)
  {
    backend = "STDThread";
  }
  if (threads <= 0)
  {
    threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  }
  vtkSMPTools::LocalScope(vtkSMPTools::Config{ threads, backend, false },
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
