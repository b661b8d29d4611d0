#include "ptvCpuTracer.h"

#include "ptvPassBuffers.h"
#include "ptvThreads.h"

#include "vtkType.h"

#include "ptvKernelDispatch.h"

namespace ptv
{
namespace
{
/// Square tiles of pixels are traced together: neighbouring rays read neighbouring voxels, and
/// a tile's rays (camera, shadow and environment) share far more cache lines than a row's.
constexpr int kTile = 16;

int TilesAcross(const TraceParams& params)
{
  return (params.Camera.Width + kTile - 1) / kTile;
}

/// The tiles [t0, t1) of a frame (row-major over tiles). Every kernel function is inlined into
/// it, so each build below compiles the whole per-pixel estimator for its own instruction set.
inline void TraceTiles(const TraceParams& params, unsigned int firstSample, int samples,
  vtkIdType t0, vtkIdType t1, PassBuffers& out)
{
  const int width = params.Camera.Width;
  const int height = params.Camera.Height;
  const int across = TilesAcross(params);
  const TracedPassPlanes planes = out.Planes();
  for (vtkIdType t = t0; t < t1; ++t)
  {
    const int x0 = static_cast<int>(t % across) * kTile;
    const int y0 = static_cast<int>(t / across) * kTile;
    const int x1 = x0 + kTile < width ? x0 + kTile : width;
    const int y1 = y0 + kTile < height ? y0 + kTile : height;
    for (int y = y0; y < y1; ++y)
    {
      for (int x = x0; x < x1; ++x)
      {
        StoreSample(planes, static_cast<std::size_t>(y) * width + x,
          TracePixelMean(params, firstSample, samples, x, y));
      }
    }
  }
}

#ifdef PTV_HAS_AVX2_BUILD
// The estimator is scalar code; the x86-64-v3 build gains from three-operand VEX forms, FMA
// contraction, roundss for floor/ceil and BMI address arithmetic (benchmark_tracer.py prints
// both builds).
PTV_AVX2_TARGET __attribute__((flatten)) void
TraceTilesAvx2(const TraceParams& params, unsigned int firstSample, int samples, vtkIdType t0,
  vtkIdType t1, PassBuffers& out)
{
  TraceTiles(params, firstSample, samples, t0, t1, out);
}
#endif

__attribute__((flatten)) void TraceTilesBaseline(const TraceParams& params,
  unsigned int firstSample, int samples, vtkIdType t0, vtkIdType t1, PassBuffers& out)
{
  TraceTiles(params, firstSample, samples, t0, t1, out);
}

using TilesFunction = void (*)(
  const TraceParams&, unsigned int, int, vtkIdType, vtkIdType, PassBuffers&);

TilesFunction SelectTiles(bool portable)
{
#ifdef PTV_HAS_AVX2_BUILD
  if (!portable && CpuHasAvx2())
  {
    return &TraceTilesAvx2;
  }
#endif
  (void)portable;
  return &TraceTilesBaseline;
}
}

//------------------------------------------------------------------------------
const char* TracerKernelTarget(bool portable)
{
  return SelectTiles(portable) == &TraceTilesBaseline ? "baseline" : "AVX2";
}

//------------------------------------------------------------------------------
void TraceFrameCpu(const TraceParams& params, unsigned int firstSample, int samples, int threads,
  bool portable, PassBuffers& out)
{
  const TilesFunction trace = SelectTiles(portable);
  const vtkIdType tiles =
    static_cast<vtkIdType>(TilesAcross(params)) * ((params.Camera.Height + kTile - 1) / kTile);
  ParallelFor(threads, vtkIdType(0), tiles, vtkIdType(1),
    [&](vtkIdType t0, vtkIdType t1) { trace(params, firstSample, samples, t0, t1, out); });
}
}
