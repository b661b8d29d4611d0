#include "ptvCpuTracer.h"

#include "ptvPassBuffers.h"

#include "vtkSMPTools.h"

#include <algorithm>
#include <string>
#include <thread>

namespace ptv
{
namespace
{
void Add(PixelSample& acc, const PixelSample& s)
{
  acc.Radiance = acc.Radiance + s.Radiance;
  acc.Alpha += s.Alpha;
  acc.Albedo = acc.Albedo + s.Albedo;
  acc.Depth1 += s.Depth1;
  acc.Position1 = acc.Position1 + s.Position1;
  acc.Normal1 = acc.Normal1 + s.Normal1;
  acc.Depth2 += s.Depth2;
  acc.Position2 = acc.Position2 + s.Position2;
  acc.Normal2 = acc.Normal2 + s.Normal2;
}

void Scale(PixelSample& acc, float w)
{
  acc.Radiance = acc.Radiance * w;
  acc.Alpha *= w;
  acc.Albedo = acc.Albedo * w;
  acc.Depth1 *= w;
  acc.Position1 = acc.Position1 * w;
  acc.Normal1 = acc.Normal1 * w;
  acc.Depth2 *= w;
  acc.Position2 = acc.Position2 * w;
  acc.Normal2 = acc.Normal2 * w;
}
}

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
      TraceParams local = params; // only Frame changes per sample
      for (vtkIdType y = rowBegin; y < rowEnd; ++y)
      {
        for (int x = 0; x < width; ++x)
        {
          local.Frame = firstSample;
          PixelSample acc = TracePixel(local, x, static_cast<int>(y));
          for (int s = 1; s < samples; ++s)
          {
            local.Frame = firstSample + static_cast<unsigned int>(s);
            Add(acc, TracePixel(local, x, static_cast<int>(y)));
          }
          if (samples > 1)
          {
            Scale(acc, 1.0f / static_cast<float>(samples));
          }
          out.Store(static_cast<int>(y) * width + x, acc);
        }
      }
    }); });
}
}
