// CUDA runtime query behind ptvCudaDevice.h. With no GPU or driver the runtime returns an error
// code (35: insufficient driver, 100: no device) that we report instead of failing.
#include "ptvCudaDevice.h"

#include <cuda_runtime.h>

#include <sstream>

namespace ptv
{
const CudaDeviceQuery& QueryCudaDevices()
{
  static const CudaDeviceQuery query = []
  {
    CudaDeviceQuery q;
    q.Compiled = true;
    int count = 0;
    const cudaError_t err = cudaGetDeviceCount(&count);
    q.RuntimeError = static_cast<int>(err);
    std::ostringstream msg;
    if (err != cudaSuccess)
    {
      cudaGetLastError(); // clear the sticky error state
      msg << "no usable CUDA device (error " << q.RuntimeError << ": " << cudaGetErrorString(err)
          << ")";
    }
    else if (count == 0)
    {
      msg << "CUDA runtime reports no device";
    }
    else
    {
      cudaDeviceProp prop{};
      if (cudaGetDeviceProperties(&prop, 0) == cudaSuccess)
      {
        q.DeviceName = prop.name;
      }
      q.DeviceCount = count;
      msg << count << " CUDA device(s); device 0: " << q.DeviceName << " (sm_" << prop.major
          << prop.minor << ")";
    }
    q.Message = msg.str();
    return q;
  }();
  return query;
}
}
