// The CUDA driver behind ptvCudaTracer.h: one thread per pixel running TracePixelMean, the same
// kernel body the CPU driver runs (Kernels/ptvIntegrator.h), storing straight into device copies
// of the traced passes (StoreSample: PassBuffers' layout), each copied back into the frame's
// pass buffer with one cudaMemcpy (no per-pixel work on the host).
#include "ptvCudaTracer.h"
#include "ptvPassBuffers.h"
#include "ptvCudaBuffer.h"

#include <cuda_runtime.h>

#include <chrono>
#include <cstddef>

namespace ptv
{
namespace
{
double MillisecondsSince(std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
    .count();
}

__global__ void TraceKernel(TraceParams p, unsigned int firstSample, int samples,
  TracedPassPlanes out)
{
  const int x = static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
  const int y = static_cast<int>(blockIdx.y * blockDim.y + threadIdx.y);
  if (x >= p.Camera.Width || y >= p.Camera.Height)
  {
    return;
  }
  StoreSample(out, static_cast<std::size_t>(y) * p.Camera.Width + x,
    TracePixelMean(p, firstSample, samples, x, y));
}
}

struct CudaTracer::Internals
{
  DeviceBuffer Scalars, Table, Gradient, Bricks, MaxDistance;
  DeviceBuffer Passes; // the traced passes, one after the other (kTracedPassCount planes)
  DeviceBuffer StepTable, ShadowTable; // TransferTable::StepRGBA, ShadowAlpha
  DeviceBuffer OpaqueCounts;           // TransferTable::OpaqueBefore
  DeviceBuffer Colors, ColorScalars, ColorTable; // dependent colour data (VolumeGrid::Colors)
  cudaEvent_t KernelStart = nullptr, KernelEnd = nullptr; // created with the first trace
  unsigned long long VolumeVersion = ~0ull;
  const void* VolumeHost = nullptr;
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
         &in.Passes, &in.Colors, &in.ColorScalars, &in.ColorTable, &in.StepTable,
         &in.ShadowTable })
  {
    b->Free();
  }
  for (cudaEvent_t* e : { &in.KernelStart, &in.KernelEnd })
  {
    if (*e)
    {
      cudaEventDestroy(*e);
      *e = nullptr;
    }
  }
  in.VolumeVersion = ~0ull;
  in.VolumeHost = nullptr;
}

//------------------------------------------------------------------------------
bool CudaTracer::Trace(const TraceParams& params, unsigned long long volumeVersion,
  unsigned int firstSample, int samples, PassBuffers& out, std::string& error)
{
  Internals& in = *this->Impl;
  this->Timings = CudaTraceTimings{};
  auto start = std::chrono::steady_clock::now();
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
    // The voxels in their own type (VolumeGrid::Type): an 8- or 16-bit volume uploads 1 or 2
    // bytes a voxel.
    const std::size_t voxelBytes = static_cast<std::size_t>(ScalarTypeSize(params.Volume.Type));
    if (!upload(in.Scalars, params.Volume.Scalars, voxels * voxelBytes, "volume upload") ||
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
  d.Volume.Scalars = in.Scalars.Ptr;
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
  d.Transfer.OpaqueBefore = nullptr;
  if (params.Transfer.OpaqueBefore)
  {
    if (!upload(in.OpaqueCounts, params.Transfer.OpaqueBefore,
          sizeof(int) * (static_cast<std::size_t>(params.Transfer.Size) + 1),
          "opacity count table upload"))
    {
      return false;
    }
    d.Transfer.OpaqueBefore = static_cast<const int*>(in.OpaqueCounts.Ptr);
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
  // The passes @a out keeps (the scatter passes only when asked for; StoreSample skips them).
  auto kept = [&](int pass) { return out.GetScatterPasses() || !IsScatterPass(pass); };
  std::size_t floats = 0;
  for (int pass = 0; pass < kTracedPassCount; ++pass)
  {
    floats += kept(pass) ? pixels * static_cast<std::size_t>(GetPassInfo(pass).Components) : 0;
  }
  if (!ok(in.Passes.Fit(floats * sizeof(float)), "pass buffers"))
  {
    return false;
  }
  TracedPassPlanes planes;
  float* next = static_cast<float*>(in.Passes.Ptr);
  for (int pass = 0; pass < kTracedPassCount; ++pass)
  {
    planes.Data[pass] = kept(pass) ? next : nullptr;
    next += kept(pass) ? pixels * static_cast<std::size_t>(GetPassInfo(pass).Components) : 0;
  }
  if ((!in.KernelStart && !ok(cudaEventCreate(&in.KernelStart), "event")) ||
    (!in.KernelEnd && !ok(cudaEventCreate(&in.KernelEnd), "event")))
  {
    return false;
  }
  this->Timings.Upload = MillisecondsSince(start);
  const dim3 block(16, 8);
  const dim3 grid((w + block.x - 1) / block.x, (h + block.y - 1) / block.y);
  cudaEventRecord(in.KernelStart);
  TraceKernel<<<grid, block>>>(d, firstSample, samples, planes);
  if (!ok(cudaGetLastError(), "kernel launch") || !ok(cudaEventRecord(in.KernelEnd), "event") ||
    !ok(cudaEventSynchronize(in.KernelEnd), "kernel"))
  {
    return false;
  }
  float kernelMs = 0.f;
  cudaEventElapsedTime(&kernelMs, in.KernelStart, in.KernelEnd);
  this->Timings.Kernel = kernelMs;
  start = std::chrono::steady_clock::now();
  out.Resize(w, h);
  for (int pass = 0; pass < kTracedPassCount; ++pass)
  {
    if (!planes.Data[pass])
    {
      continue;
    }
    const std::size_t bytes =
      pixels * static_cast<std::size_t>(GetPassInfo(pass).Components) * sizeof(float);
    if (!ok(cudaMemcpy(out.Data(pass), planes.Data[pass], bytes, cudaMemcpyDeviceToHost),
          "pass download"))
    {
      return false;
    }
  }
  this->Timings.Download = MillisecondsSince(start);
  return true;
}
}
