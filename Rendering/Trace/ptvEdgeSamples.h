/**
 * @file ptvEdgeSamples.h
 * @brief Private: more samples per frame where the camera rays pass from empty space onto the
 *        volume within a pixel's neighbourhood (silhouettes, thin structure), for the denoiser.
 *
 * With one sample a pixel on the volume's silhouette is all or nothing: its ray hits or
 * misses, so a pixel that the volume covers by half shows the full colour or none, and the
 * denoiser's guides keep those hits and misses in bins of their own. On 1-2 % of a frame's
 * pixels this edge holds a quarter to a half of the denoised frame's squared error
 * (docs/edge-samples.md). After a frame is traced:
 *  1. FindEdgePixels marks each pixel whose 3x3 neighbourhood holds a camera ray of opacity
 *     (the Coverage pass, which is Alpha without the coverage march) of at least kEdgeHigh and
 *     one below kEdgeLow: an edge between empty space and the volume. A fog, whose rays all
 *     have a low opacity, has none.
 *  2. TraceEdgeSamples traces EdgeSamples - 1 more samples there per sample of the frame and
 *     stores the pixel's mean of them all.
 * The extra samples draw from a stream of their own (the seed hashed with a constant; sample
 * indices 64 * frame sample + k), so every other pixel, every later frame and every other
 * pass of the frame is unchanged, and each pixel's mean stays an unbiased estimate of the same
 * image. The kernel is Kernels/ptvIntegrator.h's TracePixel, compiled twice (baseline and
 * x86-64-v3) like ptvCpuTracer; it runs on the CPU whichever backend traced the frame.
 */
#ifndef ptvEdgeSamples_h
#define ptvEdgeSamples_h

#include "Kernels/ptvIntegrator.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ptv
{
class PassBuffers;

/// EdgeSamples is at most this (the extra samples' indices are 64 * frame sample + k).
constexpr int kMaxEdgeSamples = 64;
/// A neighbourhood with a camera ray of at least this opacity ...
constexpr float kEdgeHigh = 0.5f;
/// ... and one below this is an edge.
constexpr float kEdgeLow = 0.05f;
/// The neighbourhood's half width: 3x3 pixels (docs/decisions.md).
constexpr int kEdgeRadius = 1;

/**
 * The pixels (indices y * width + x, increasing) whose 3x3 neighbourhood (clamped at the
 * image's border; 5x5 and wider with the study switch PTV_EDGE_RADIUS, docs/edge-samples.md)
 * has a @a coverage value >= kEdgeHigh and one < kEdgeLow (NaN counts as neither) into
 * @a edges.
 */
void FindEdgePixels(
  const float* coverage, int width, int height, int threads, std::vector<std::uint32_t>& edges);

/**
 * Trace (@a edgeSamples - 1) x @a samples more samples at each pixel of @a edges, whose frame
 * in @a frame holds the mean of @a samples samples from sample index @a firstSample, and store
 * the mean of all of them. @a edgeSamples in [2, kMaxEdgeSamples]; @a threads and @a portable
 * as TraceFrameCpu's.
 */
void TraceEdgeSamples(const TraceParams& params, unsigned int firstSample, int samples,
  int edgeSamples, const std::vector<std::uint32_t>& edges, int threads, bool portable,
  PassBuffers& frame);

/// Entries of TraceEdgeSampleList's list: @a edges x @a samples x (@a edgeSamples - 1), 0 when
/// @a samples < 1 or @a edgeSamples < 2.
std::size_t EdgeSampleListSize(std::size_t edges, int samples, int edgeSamples);

/**
 * For a volume split into pieces (ptvPieces.h), whose samples are composited one by one: the
 * extra samples TraceEdgeSamples would trace (the same rays, lattice and stream), each stored
 * alone in @a list, resized to EdgeSampleListSize() x 1 entries: entry (e x @a samples + s) x
 * (@a edgeSamples - 1) + k - 1 holds extra sample k (1 .. edgeSamples - 1) of frame sample s of
 * edge pixel e. Every process traces its piece's list; composited like a frame
 * (Ranks::GatherFrame), MergeEdgeSamples adds it to the composited frame.
 */
void TraceEdgeSampleList(const TraceParams& params, unsigned int firstSample, int samples,
  int edgeSamples, const std::vector<std::uint32_t>& edges, int threads, bool portable,
  PassBuffers& list);

/**
 * @a frame's pixels @a edges (the mean of @a samples samples) become the mean of those and the
 * extra samples in @a list (TraceEdgeSampleList's layout, for the same @a samples,
 * @a edgeSamples and @a edges; a list of another size changes nothing). Traced by one process,
 * list and merge give TraceEdgeSamples' frame up to float rounding.
 */
void MergeEdgeSamples(PassBuffers& list, int samples, int edgeSamples,
  const std::vector<std::uint32_t>& edges, int threads, PassBuffers& frame);
}

#endif
