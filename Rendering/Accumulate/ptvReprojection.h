/**
 * @file ptvReprojection.h
 * @brief Private: temporal reuse -- the accumulated radiance of the previous view carried into a
 *        moved camera's view, and the per-pixel frame count of an accumulation that has it.
 *
 * Until the camera first moves, the accumulation is the plain running mean of PassBuffers
 * (every pixel has the same frame count, and nothing here runs: a still camera's images are
 * those of an accumulation without reprojection, bit for bit). When only the view changed
 * (FrameSignature::Compare), each pixel of the new frame looks up its history:
 *  1. the point it sees: its first event (Depth pass) on the ray through the pixel's centre;
 *     for a pixel whose new frame missed the volume, the nearest first event of its eight
 *     neighbours (it may partly cover that surface); a miss with no hit beside it is
 *     background and starts afresh (radiance and alpha 0, as its history would be);
 *  2. the point projected by the previous camera falls between four previous pixels. Each
 *     is read as a fraction c of the point's surface over the background: its mean depth is
 *     c d + (1 - c) far and its mean position c p (d: the point's distance from the previous
 *     camera; misses store far and 0), within Tolerance. A hit keeps the pixels with c >= 0.2
 *     whose mean albedo is within 0.25 per channel of c times the new frame's; a miss keeps
 *     those with c <= 0.9 (one that covered the surface fully is a disocclusion: background
 *     shows through it now). A pixel outside the image, behind the camera or at another
 *     depth or place (silhouettes, occlusion) is dropped; none kept: no history;
 *  3. Radiance, Alpha and the frame count n are read bilinearly from the kept pixels
 *     (renormalised weights), n capped at MaximumHistory times the fade of the view's turn:
 *     1 - turn / 8 degrees, 0 beyond (the turn: the angle of the rotation between the two
 *     views' frames, so an orbit turns by its step at any elevation and a roll counts too).
 *     What the history saw drifts as the view turns (lights that follow the camera,
 *     highlights, content behind the first event); a pan, a dolly or a zoom keeps the full cap;
 *  4. the new frame F joins the history H as the (n+1)-th frame: H + (F - H) / (n + 1), count
 *     n + 1. With n capped at M this is an exponential moving average of weight 1 / (M + 1).
 * The frame loop (ptvFrameLoop.cxx) gives this step the edge pixels' (ptvEdgeSamples.h) Depth
 * and Albedo of their frame sample, not the mean of their samples, and has them keep the new
 * frame alone (Reproject's fresh pixels): their new samples resolve the silhouette that the
 * history lags behind.
 * The other passes (the denoiser's auxiliary features and the tests' inputs) restart with the
 * view: one frame of them costs the denoiser ~0.3 dB against eight (measured on the head), and
 * carrying them too would cost more than the 5 % of a frame this step may take. Frames of an
 * unchanged view then join each pixel's Radiance/Alpha mean with its own count (no cap), and
 * the other passes' running mean.
 * Tolerance = 3 (StepWorld + pixel footprint at the point's distance) + 5 % of the distance:
 * the first event of a pixel varies by a step along the ray (the march's jitter) and a
 * footprint across it, and much more in a translucent medium, where it is a random point of a
 * thin haze.
 * Measured and left out (docs/temporal.md): a normal test (first-event normals in translucent
 * media are noise at one sample: it rejected good history), and a sharper Catmull-Rom read
 * (no better on the head's orbit: the error that history adds at edges comes from content
 * behind the first event, which moves with another parallax).
 */
#ifndef ptvReprojection_h
#define ptvReprojection_h

#include "ptvPassBuffers.h"

#include <cstdint>
#include <vector>

namespace ptv
{
class Reprojection
{
public:
  /// Forget the per-pixel counts: the accumulation is a plain running mean again.
  void Reset() { this->Counts.clear(); }

  /// Whether the accumulation has per-pixel counts (the camera moved since the last reset).
  bool HasHistory() const { return !this->Counts.empty(); }

  /**
   * Carry @a accumulated (seen by @a previous; @a previousFrames frames in every pixel unless
   * HasHistory()) into the view of @a current, and let @a frame (traced by @a current, same
   * size; its passes are taken, leaving it unspecified) join it as in the file comment. @a stepWorld is the march's step (for the tolerance).
   * The @a freshCount pixels @a freshPixels take the new frame alone (count 1).
   */
  void Reproject(const CameraRays& previous, const CameraRays& current, float stepWorld,
    int maximumHistory, int previousFrames, PassBuffers& accumulated, PassBuffers& frame,
    int threads, const std::uint32_t* freshPixels = nullptr, std::size_t freshCount = 0);

  /**
   * A frame of the same view joins the accumulation: Radiance and Alpha each pixel's mean,
   * acc += (frame - acc) / (n + 1), the other passes the running mean of the view's @a frames
   * frames (this one included).
   */
  void Accumulate(PassBuffers& accumulated, const PassBuffers& frame, int frames, int threads);

  /// Write each pixel's frame count into @a out (@a frames everywhere without history).
  void WriteCounts(float* out, int pixels, int frames) const;

  /// Fraction of the last Reproject()'s hit pixels (not misses) that kept a history (0..1).
  double GetReusedFraction() const { return this->Reused; }

private:
  std::vector<float> Counts;
  std::vector<float> NewCounts;
  std::vector<unsigned char> FreshMask; ///< Reproject's fresh pixels
  std::vector<int> HitBegin, HitEnd; ///< per row: the span of the new frame's hits
  double Reused = 0.0;
};
}

#endif
