// Built when PTV_ENABLE_CUDA is off: the CUDA path is not compiled in.
#include "ptvCudaDevice.h"

namespace ptv
{
const CudaDeviceQuery& QueryCudaDevices()
{
  static const CudaDeviceQuery query = []
  {
    CudaDeviceQuery q;
    q.Message = "built without CUDA (configure with -DPTV_ENABLE_CUDA=ON)";
    return q;
  }();
  return query;
}
}
