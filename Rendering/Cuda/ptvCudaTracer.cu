// The CUDA driver behind ptvCudaTracer.h: one thread per pixel running TracePixelMean, the same
// kernel body the CPU driver runs (Kernels/ptvIntegrator.h).
#include "../ptvCudaTracer.h"
#include "../ptvPassBuffers.h"
#include "ptvCudaBuffer.h"

#include <cuda_runtime.h>

#include <cstddef>
#include <vector>

namespace ptv
{
namespace
{
__global__ void TraceKernel(TraceParams p, unsigned int firstSample, int samples,
  PixelSample* out)
{
  const int x = static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
  const int y = static_cast<int>(blockIdx.y * blockDim.y + threadIdx.y);
  if (x >= p.Camera.Width || y >= p.Camera.Height)
  {
    return;
  }
  out[static_cast<std::size_t>(y) * p.Camera.Width + x] =
    TracePixelMean(p, firstSample, samples, x, y);
}
}

struct CudaTracer::Internals
{
  DeviceBuffer Scalars, Table, Gradient, Bricks, MaxDistance, Samples;
  DeviceBuffer StepTable, ShadowTable; // TransferTable::StepRGBA, ShadowAlpha
  DeviceBuffer Colors, ColorScalars, ColorTable; // dependent colour data (VolumeGrid::Colors)
  unsigned long long VolumeVersion = ~0ull;
  const float* VolumeHost = nullptr;
  std::vector<PixelSample> Host;
};

//------------------------------------------------------------------------------
CudaTracer::CudaTracer()
  : Impl(new Internals)
{
}

//------------------------------------------------------------------------------
CudaTracer::~CudaTracer()
{
  this->Release();
}

//------------------------------------------------------------------------------
void CudaTracer::Release()
{
  Internals& in = *this->Impl;
  for (DeviceBuffer* b : { &in.Scalars, &in.Table, &in.Gradient, &in.Bricks, &in.MaxDistance,
         &in.Samples, &in.Colors, &in.ColorScalars, &in.ColorTable, &in.StepTable,
         &in.ShadowTable })
  {
    b->Free();
  }
  in.VolumeVersion = ~0ull;
  in.VolumeHost = nullptr;
}

//------------------------------------------------------------------------------
bool CudaTracer::Trace(const TraceParams& params, unsigned long long volumeVersion,
  unsigned int firstSample, int samples, PassBuffers& out, std::string& error)
{
  Internals& in = *this->Impl;
  auto ok = [&error](cudaError_t e, const char* what) { return CudaOk(e, what, error); };
  auto upload = [&ok](DeviceBuffer& b, const void* host, std::size_t bytes, const char* what)
  { return ok(b.Upload(host, bytes), what); };

  TraceParams d = params;
  const int* dims = params.Volume.Dims;
  const std::size_t voxels =
    static_cast<std::size_t>(dims[0]) * static_cast<std::size_t>(dims[1]) * dims[2];
  // The voxels and any colour data change together (FrameInputs' volume version).
  if (volumeVersion != in.VolumeVersion || params.Volume.Scalars != in.VolumeHost)
  {
    if (!upload(in.Scalars, params.Volume.Scalars, voxels * sizeof(float), "volume upload") ||
      (params.Volume.Colors &&
        !upload(in.Colors, params.Volume.Colors, 3 * voxels * sizeof(float), "colour upload")) ||
      (params.Volume.ColorScalars &&
        !upload(in.ColorScalars, params.Volume.ColorScalars, voxels * sizeof(float),
          "colour channel upload")))
    {
      in.VolumeVersion = ~0ull;
      return false;
    }
    in.VolumeVersion = volumeVersion;
    in.VolumeHost = params.Volume.Scalars;
  }
  d.Volume.Scalars = static_cast<const float*>(in.Scalars.Ptr);
  d.Volume.Colors = params.Volume.Colors ? static_cast<const float*>(in.Colors.Ptr) : nullptr;
  if (params.Volume.ColorScalars)
  {
    // The colour table follows the transfer function: small, uploaded with every frame as the
    // scalar table is.
    if (!upload(in.ColorTable, params.ColorTable.RGBA, 4 * sizeof(float) * params.ColorTable.Size,
          "colour table upload"))
    {
      return false;
    }
    d.Volume.ColorScalars = static_cast<const float*>(in.ColorScalars.Ptr);
    d.ColorTable.RGBA = static_cast<const float*>(in.ColorTable.Ptr);
  }
  if (!upload(in.Table, params.Transfer.RGBA, 4 * sizeof(float) * params.Transfer.Size,
        "transfer table upload"))
  {
    return false;
  }
  d.Transfer.RGBA = static_cast<const float*>(in.Table.Ptr);
  if (params.Transfer.GradientOpacity)
  {
    if (!upload(in.Gradient, params.Transfer.GradientOpacity,
          sizeof(float) * params.Transfer.GradientSize, "gradient table upload"))
    {
      return false;
    }
    d.Transfer.GradientOpacity = static_cast<const float*>(in.Gradient.Ptr);
  }
  if (params.Transfer.StepRGBA && params.Transfer.ShadowAlpha)
  {
    const std::size_t entries = static_cast<std::size_t>(params.Transfer.Size);
    if (!upload(in.StepTable, params.Transfer.StepRGBA, 4 * sizeof(float) * entries,
          "step table upload") ||
      !upload(in.ShadowTable, params.Transfer.ShadowAlpha, sizeof(float) * entries,
        "shadow step table upload"))
    {
      return false;
    }
    d.Transfer.StepRGBA = static_cast<const float*>(in.StepTable.Ptr);
    d.Transfer.ShadowAlpha = static_cast<const float*>(in.ShadowTable.Ptr);
  }
  else
  {
    d.Transfer.StepRGBA = nullptr; // corrected per sample, as on the CPU
    d.Transfer.ShadowAlpha = nullptr;
  }
  if (params.Occupancy.Distance)
  {
    const int* b = params.Occupancy.Bricks;
    const std::size_t bricks = static_cast<std::size_t>(b[0]) * b[1] * b[2];
    if (!upload(in.Bricks, params.Occupancy.Distance, 8 * bricks, "occupancy upload"))
    {
      return false;
    }
    d.Occupancy.Distance = static_cast<const int8_t*>(in.Bricks.Ptr);
  }
  const int w = params.Camera.Width, h = params.Camera.Height;
  const std::size_t pixels = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  if (params.MaxDistance)
  {
    if (!upload(in.MaxDistance, params.MaxDistance, pixels * sizeof(float), "depth upload"))
    {
      return false;
    }
    d.MaxDistance = static_cast<const float*>(in.MaxDistance.Ptr);
  }
  if (!ok(in.Samples.Fit(pixels * sizeof(PixelSample)), "sample buffer"))
  {
    return false;
  }
  const dim3 block(16, 8);
  const dim3 grid((w + block.x - 1) / block.x, (h + block.y - 1) / block.y);
  TraceKernel<<<grid, block>>>(
    d, firstSample, samples, static_cast<PixelSample*>(in.Samples.Ptr));
  if (!ok(cudaGetLastError(), "kernel launch"))
  {
    return false;
  }
  in.Host.resize(pixels);
  if (!ok(cudaMemcpy(in.Host.data(), in.Samples.Ptr, pixels * sizeof(PixelSample),
            cudaMemcpyDeviceToHost),
        "sample download"))
  {
    return false;
  }
  for (std::size_t i = 0; i < pixels; ++i)
  {
    out.Store(static_cast<int>(i), in.Host[i]);
  }
  return true;
}
}
