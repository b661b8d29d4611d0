// Built when PTV_ENABLE_CUDA is off: the CUDA grid is not compiled in.
#include "ptvCudaBilateralGrid.h"

namespace ptv
{
struct CudaBilateralGrid::Internals
{
};

CudaBilateralGrid::CudaBilateralGrid() = default;
CudaBilateralGrid::~CudaBilateralGrid() = default;

bool CudaBilateralGrid::Apply(const BilateralGridSettings&, int, int, const float*,
  const float*, const float*, const float*, float*, std::string& error)
{
  error = "built without CUDA (configure with -DPTV_ENABLE_CUDA=ON)";
  return false;
}

void CudaBilateralGrid::Release() {}
}
