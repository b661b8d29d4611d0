/**
 * @file ptvKernelDispatch.h
 * @brief Private: whether the CPU row kernels (ptvBilateralGridRows, ptvFeatureRows; Google
 *        Highway, dispatched per instruction set at run time) run their portable baseline build,
 *        and whether the scalar loops compiled twice (ptvCpuTracer, ptvReprojection: baseline
 *        and x86-64-v3) may run their AVX2 build.
 */
#ifndef ptvKernelDispatch_h
#define ptvKernelDispatch_h

#include <hwy/targets.h>

#include <cstdlib>
#include <cstring>

#if defined(__GNUC__) && defined(__x86_64__)
/// GCC/Clang on x86-64: scalar loops are also compiled for x86-64-v3 (AVX2, FMA, BMI1/2, F16C,
/// LZCNT, MOVBE: the set Highway calls HWY_AVX2) with this attribute.
#define PTV_HAS_AVX2_BUILD 1
#define PTV_AVX2_TARGET __attribute__((target("avx2,fma,bmi,bmi2,f16c,lzcnt,movbe,popcnt")))
#endif

namespace ptv
{
/// The baseline build when @a requested (a property) or when PTV_PORTABLE_KERNELS=1.
inline bool UsePortableKernels(bool requested)
{
  const char* value = std::getenv("PTV_PORTABLE_KERNELS");
  return requested || (value && std::strcmp(value, "1") == 0);
}

/// Whether this CPU runs the x86-64-v3 builds (false without one).
inline bool CpuHasAvx2()
{
#ifdef PTV_HAS_AVX2_BUILD
  return (hwy::SupportedTargets() & HWY_AVX2) != 0;
#else
  return false;
#endif
}
}

#endif
