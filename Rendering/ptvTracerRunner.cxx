#include "ptvTracerRunner.h"

#include "ptvCpuTracer.h"
#include "ptvCudaDevice.h"
#include "vtkPathTracedVolumeMapper.h" // BACKEND_* (defined once, on the public class)

namespace ptv
{
//------------------------------------------------------------------------------
int ResolveBackend(
  int requested, bool cudaAvailable, const std::string& cudaStatus, std::string& message)
{
  message.clear();
  if (requested == vtkPathTracedVolumeMapper::BACKEND_CPU)
  {
    return vtkPathTracedVolumeMapper::BACKEND_CPU;
  }
  if (cudaAvailable)
  {
    return vtkPathTracedVolumeMapper::BACKEND_CUDA;
  }
  if (requested == vtkPathTracedVolumeMapper::BACKEND_CUDA)
  {
    message = "the CUDA backend was requested but " + cudaStatus + "; tracing on the CPU";
  }
  return vtkPathTracedVolumeMapper::BACKEND_CPU;
}

//------------------------------------------------------------------------------
void TracerRunner::Trace(const TraceParams& params, unsigned long long volumeVersion,
  unsigned int firstSample, int samples, int threads, bool portable, int requested,
  PassBuffers& out, std::string& problem)
{
  const CudaDeviceQuery& devices = QueryCudaDevices();
  int backend = ResolveBackend(requested, devices.DeviceCount > 0, devices.Message, problem);
  std::string cudaError;
  if (backend == vtkPathTracedVolumeMapper::BACKEND_CUDA &&
    !this->Cuda.Trace(params, volumeVersion, firstSample, samples, out, cudaError))
  {
    problem = "CUDA tracing failed (" + cudaError + "); tracing on the CPU";
    backend = vtkPathTracedVolumeMapper::BACKEND_CPU;
  }
  if (backend == vtkPathTracedVolumeMapper::BACKEND_CPU)
  {
    TraceFrameCpu(params, firstSample, samples, threads, portable, out);
  }
  this->LastBackend = backend == vtkPathTracedVolumeMapper::BACKEND_CUDA ? "CUDA" : "CPU";
}
}
