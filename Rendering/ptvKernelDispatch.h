/**
 * @file ptvKernelDispatch.h
 * @brief Private: whether the CPU row kernels (ptvBilateralGridRows, ptvFeatureRows; Google
 *        Highway, dispatched per instruction set at run time) run their portable baseline build.
 */
#ifndef ptvKernelDispatch_h
#define ptvKernelDispatch_h

#include <cstdlib>
#include <cstring>

namespace ptv
{
/// The baseline build when @a requested (a property) or when PTV_PORTABLE_KERNELS=1.
inline bool UsePortableKernels(bool requested)
{
  const char* value = std::getenv("PTV_PORTABLE_KERNELS");
  return requested || (value && std::strcmp(value, "1") == 0);
}
}

#endif
