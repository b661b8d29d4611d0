#include "ptvTracerRunner.h"

#include "ptvCpuTracer.h"
#include "ptvCudaDevice.h"
#include "ptvBackend.h"

namespace ptv
{
//------------------------------------------------------------------------------
int ResolveBackend(
  int requested, bool cudaAvailable, const std::string& cudaStatus, std::string& message)
{
  message.clear();
  if (requested == kBackendCpu)
  {
    return kBackendCpu;
  }
  if (cudaAvailable)
  {
    return kBackendCuda;
  }
  if (requested == kBackendCuda)
  {
    message = "the CUDA backend was requested but " + cudaStatus + "; tracing on the CPU";
  }
  return kBackendCpu;
}

//------------------------------------------------------------------------------
void TracerRunner::Trace(const TraceParams& params, unsigned long long volumeVersion,
  unsigned int firstSample, int samples, int threads, bool portable, int requested,
  PassBuffers& out, std::string& problem)
{
  const CudaDeviceQuery& devices = QueryCudaDevices();
  int backend = ResolveBackend(requested, devices.DeviceCount > 0, devices.Message, problem);
  std::string cudaError;
  if (backend == kBackendCuda &&
    !this->Cuda.Trace(params, volumeVersion, firstSample, samples, out, cudaError))
  {
    problem = "CUDA tracing failed (" + cudaError + "); tracing on the CPU";
    backend = kBackendCpu;
  }
  if (backend == kBackendCpu)
  {
    TraceFrameCpu(params, firstSample, samples, threads, portable, out);
  }
  this->LastBackend = backend == kBackendCuda ? "CUDA" : "CPU";
}
}
