// The CUDA device query must answer, never crash: on a machine without a GPU/driver (CI) it
// reports zero devices with the runtime's error; with PTV_ENABLE_CUDA off it says so.
#include "ptvCudaDevice.h"
#include "vtkPathTracedVolumeMapper.h"

#include <cstdlib>
#include <iostream>

int TestPTVCudaDeviceQuery(int, char*[])
{
  const ptv::CudaDeviceQuery& q = ptv::QueryCudaDevices();
  std::cout << "compiled=" << q.Compiled << " devices=" << q.DeviceCount
            << " error=" << q.RuntimeError << " : " << q.Message << "\n";
  if (q.Message.empty())
  {
    std::cerr << "query gave no message\n";
    return EXIT_FAILURE;
  }
  if (!q.Compiled && (q.DeviceCount != 0 || q.RuntimeError != 0))
  {
    std::cerr << "a build without CUDA must report no device and no error\n";
    return EXIT_FAILURE;
  }
  if (q.Compiled && q.DeviceCount == 0 && q.RuntimeError == 0 &&
    q.Message.find("no device") == std::string::npos)
  {
    std::cerr << "zero devices must be explained\n";
    return EXIT_FAILURE;
  }
  if (q.DeviceCount > 0 && q.DeviceName.empty())
  {
    std::cerr << "a found device must have a name\n";
    return EXIT_FAILURE;
  }
  // The public face agrees with the private query.
  if (vtkPathTracedVolumeMapper::GetCudaAvailable() != (q.DeviceCount > 0) ||
    q.Message != vtkPathTracedVolumeMapper::GetCudaStatus())
  {
    std::cerr << "vtkPathTracedVolumeMapper::GetCudaStatus disagrees with the query\n";
    return EXIT_FAILURE;
  }
  // Cached: a second call returns the same object.
  if (&ptv::QueryCudaDevices() != &q)
  {
    std::cerr << "query is not cached\n";
    return EXIT_FAILURE;
  }
  return EXIT_SUCCESS;
}
