/**
 * @file ptvCudaDevice.h
 * @brief Private: ask the CUDA runtime whether a usable device exists (no CUDA types exposed).
 *
 * Built from Cuda/ptvCudaDevice.cu when PTV_ENABLE_CUDA is on, else from ptvCudaDeviceNone.cxx.
 * On a machine without a driver the runtime answers cudaErrorInsufficientDriver (35) or
 * cudaErrorNoDevice (100); both are reported as "no device", never as a crash.
 */
#ifndef ptvCudaDevice_h
#define ptvCudaDevice_h

#include <string>

namespace ptv
{
struct CudaDeviceQuery
{
  bool Compiled = false;    ///< the library was built with the CUDA path
  int DeviceCount = 0;      ///< usable devices (0 when none or no driver)
  int RuntimeError = 0;     ///< cudaError_t of cudaGetDeviceCount (0 = success)
  std::string Message;      ///< human-readable summary, e.g. "no CUDA driver (error 35 ...)"
  std::string DeviceName;   ///< name of device 0 when DeviceCount > 0
};

/// Query the CUDA runtime once; cheap to call again (the result is cached).
const CudaDeviceQuery& QueryCudaDevices();
}

#endif
