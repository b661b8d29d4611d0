/**
 * @file ptvCoverage.h
 * @brief Private: the Coverage pass -- which pixels provably show no volume at all, so the
 *        denoiser can leave them exactly empty instead of smearing colour into them.
 *
 * A pixel is *empty* (Coverage 0) when no ray through any point of its footprint can meet a
 * brick of the occupancy grid that may hold a visible sample (ptvOccupancy.h); its radiance and
 * alpha are then exactly 0 in every frame and in the converged image (premultiplied: the
 * background is composited outside). Every other pixel has Coverage 1. The test, per pixel:
 *  1. the occupancy grid is read dilated by one brick (the 26 neighbours; the signed distances
 *     of the brick one step back on every axis, minus 2: no second grid), so that one ray can
 *     stand for the rays near it: any point less than BrickSize voxels (on every axis, index
 *     space) from a point of a dilated-empty brick lies in an empty brick;
 *  2. the ray through the pixel's centre walks that dilated grid over the volume's box widened
 *     by BrickSize voxels on every side, jumping over empty cubes of bricks (RegionExitT, as
 *     the tracer does); meeting a dilated-occupied brick makes the pixel covered;
 *  3. a pixel whose walk met none is empty only if every ray of its footprint stays less than
 *     BrickSize voxels from the centre ray up to the walk's exit parameter: the offset of a ray
 *     half a pixel away, in index space, is bounded by a0 + a1 t (measured from rays one pixel
 *     apart at the image's centre and corners, times 1.25 for the change across the image).
 *     Far away, or with a volume of more voxels than pixels, the bound fails and pixels stay
 *     covered: the pass is conservative, never wrong, only less useful.
 * The pass ignores clipping, cropping and opaque geometry (they only remove samples). It is all
 * ones (nothing known empty) without empty-space skipping (no occupancy grid) and for a
 * distributed piece (CameraBoxed: this process sees part of the volume only). It depends on the
 * camera, the volume and the transfer function, not on the samples: computed once per view.
 */
#ifndef ptvCoverage_h
#define ptvCoverage_h

#include "Kernels/ptvTraceParams.h"

#include <cstdint>

namespace ptv
{
/**
 * Write the Coverage of every pixel of @a p's camera into @a out (Width * Height floats, 0 or 1,
 * row-major, bottom row first). Returns the number of empty pixels (0 when the pass does not
 * apply: @a out all ones).
 */
std::int64_t ComputeCoverage(const TraceParams& p, float* out, int threads);
}

#endif
