#include "ptvCpuTracer.h"

#include "ptvPassBuffers.h"
#include "ptvThreads.h"

#include <hwy/targets.h>

namespace ptv
{
namespace
{
/// The rows [y0, y1) of a frame. Every kernel function is inlined into it, so each build below
/// compiles the whole per-pixel estimator for its own instruction set.
inline void TraceRows(const TraceParams& params, unsigned int firstSample, int samples,
  vtkIdType y0, vtkIdType y1, PassBuffers& out)
{
  const int width = params.Camera.Width;
  for (vtkIdType y = y0; y < y1; ++y)
  {
    for (int x = 0; x < width; ++x)
    {
      out.Store(static_cast<int>(y) * width + x,
        TracePixelMean(params, firstSample, samples, x, static_cast<int>(y)));
    }
  }
}

#if defined(__GNUC__) && defined(__x86_64__)
#define PTV_TRACER_HAS_AVX2 1
// x86-64-v3 (AVX2, FMA, BMI1/2, F16C, LZCNT, MOVBE): the set Highway calls HWY_AVX2. The
// estimator is scalar code; this build gains from three-operand VEX forms, FMA contraction,
// roundss for floor/ceil and BMI address arithmetic (benchmark_tracer.py prints both builds).
__attribute__((target("avx2,fma,bmi,bmi2,f16c,lzcnt,movbe,popcnt"), flatten)) void
TraceRowsAvx2(const TraceParams& params, unsigned int firstSample, int samples, vtkIdType y0,
  vtkIdType y1, PassBuffers& out)
{
  TraceRows(params, firstSample, samples, y0, y1, out);
}
#endif

__attribute__((flatten)) void TraceRowsBaseline(const TraceParams& params,
  unsigned int firstSample, int samples, vtkIdType y0, vtkIdType y1, PassBuffers& out)
{
  TraceRows(params, firstSample, samples, y0, y1, out);
}

using RowsFunction = void (*)(
  const TraceParams&, unsigned int, int, vtkIdType, vtkIdType, PassBuffers&);

bool CpuHasAvx2()
{
#ifdef PTV_TRACER_HAS_AVX2
  return (hwy::SupportedTargets() & HWY_AVX2) != 0;
#else
  return false;
#endif
}

RowsFunction SelectRows(bool portable)
{
#ifdef PTV_TRACER_HAS_AVX2
  if (!portable && CpuHasAvx2())
  {
    return &TraceRowsAvx2;
  }
#endif
  (void)portable;
  return &TraceRowsBaseline;
}
}

//------------------------------------------------------------------------------
const char* TracerKernelTarget(bool portable)
{
  return SelectRows(portable) == &TraceRowsBaseline ? "baseline" : "AVX2";
}

//------------------------------------------------------------------------------
void TraceFrameCpu(const TraceParams& params, unsigned int firstSample, int samples, int threads,
  bool portable, PassBuffers& out)
{
  const RowsFunction rows = SelectRows(portable);
  WithThreads(threads,
    [&]()
    {
      vtkSMPTools::For(0, params.Camera.Height, 1,
        [&](vtkIdType y0, vtkIdType y1) { rows(params, firstSample, samples, y0, y1, out); });
    });
}
}
