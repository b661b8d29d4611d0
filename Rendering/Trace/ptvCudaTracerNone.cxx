// Built when PTV_ENABLE_CUDA is off: the CUDA driver is not compiled in.
#include "ptvCudaTracer.h"

namespace ptv
{
struct CudaTracer::Internals
{
};

CudaTracer::CudaTracer() = default;
CudaTracer::~CudaTracer() = default;

bool CudaTracer::Trace(const TraceParams&, unsigned long long, unsigned int, int, PassBuffers&,
  std::string& error)
{
  error = "built without CUDA (configure with -DPTV_ENABLE_CUDA=ON)";
  return false;
}

void CudaTracer::Release() {}
}
