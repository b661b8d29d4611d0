/**
 * @file ptvCpuTracer.h
 * @brief Private: the CPU driver, a vtkSMPTools loop over Kernels/ptvIntegrator.h's TracePixel.
 *
 * Each pixel's random stream depends on (pixel, sample index, seed) only, so the frame is
 * bit-identical whatever the number of threads or the SMP backend.
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
 * width x height). @a threads <= 0 uses every core. The loop runs in a vtkSMPTools::LocalScope:
 * when the application's SMP backend is "Sequential" (the default of some VTK builds, e.g.
 * Debian's ParaView) it runs on "STDThread" for this frame only.
 */
void TraceFrameCpu(const TraceParams& params, unsigned int firstSample, int samples, int threads,
  PassBuffers& out);
}

#endif
