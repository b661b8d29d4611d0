/**
 * @file ptvCpuTracer.h
 * @brief Private: the CPU driver, a parallel loop (ptvThreads.h) over 16x16 pixel tiles running
 *        Kernels/ptvIntegrator.h's TracePixelMean.
 *
 * Each pixel's random stream depends on (pixel, sample index, seed) only, so the frame is
 * bit-identical whatever the number of threads.
 *
 * Instruction sets: the estimator is compiled twice, for the x86-64 baseline (SSE2) and for
 * x86-64-v3 (AVX2 + FMA; GCC/Clang function attributes), and the build is chosen at run time
 * with Highway's CPU detection, like the denoiser's row kernels. A frame is bit-identical for
 * any thread count on one machine; the two builds may differ in the last bits (FMA
 * contraction), as the CPU and CUDA paths do. PTV_PORTABLE_KERNELS=1 forces the baseline.
 */
#ifndef ptvCpuTracer_h
#define ptvCpuTracer_h

#include "Kernels/ptvIntegrator.h"

namespace ptv
{
class PassBuffers;

/**
 * Trace @a samples samples per pixel (sample indices firstSample .. firstSample+samples-1 become
 * TraceParams::Frame) and store their mean per pixel in @a out (already sized to the camera's
 * width x height). @a threads <= 0 uses every core. Tiles are handed to the plugin's persistent worker threads
 * (ptvThreads.h) in any order.
 */
void TraceFrameCpu(const TraceParams& params, unsigned int firstSample, int samples, int threads,
  bool portable, PassBuffers& out);

/// The build TraceFrameCpu() runs with @a portable: "AVX2" or "baseline".
const char* TracerKernelTarget(bool portable);
}

#endif
