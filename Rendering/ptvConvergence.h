/**
 * @file ptvConvergence.h
 * @brief Private: how far the accumulation is from converged, and the image that converges --
 *        the denoised image faded into the raw running mean by their estimated errors.
 *
 * Kept per pixel while frames of one view accumulate: their mean M, the mean of the squared frame
 * radiance (the variance of M) and the mean of the odd-numbered frames (with the even ones: two
 * independent half-accumulations). M is the accumulated Radiance pass, bit for bit, until the
 * camera moves; after that the pass also holds reprojected history (ptvReprojection), whose
 * error these statistics cannot see, so the blend and the estimate use M, the view's own frames. Errors are measured where the project measures quality,
 * after the tone map g(x) = x^(1/2.2) (docs/measuring.md):
 *  - raw mean M, variance V = g'(M)^2 (E[f^2] - M^2) / (k - 1) (delta method), box-filtered
 *    with a radius that shrinks as frames add degrees of freedom;
 *  - denoised D, error E = box((g(D) - g(M))^2) - V (its squared distance from M, less the
 *    part that is M's own noise), over the variance's box (at least 3x3);
 *  - shown C = w M + (1 - w) D with w = E / (E + V) (the per-pixel blend of two estimates with
 *    the least squared error), from 8 frames on (fewer give too noisy a variance: measured in
 *    Testing/Benchmarks/convergence.py); below that, D.
 * The estimated error of C (for the stopping rule of still renders) uses the half
 * accumulations instead of the delta method, which misses the rare samples of dark pixels:
 * V_half = (g(A) - g(B))^2 n_A n_B / k^2, and MSE = mean(w^2 V_half + (1 - w)^2 box(...)).
 */
#ifndef ptvConvergence_h
#define ptvConvergence_h

#include <cstddef>
#include <vector>

namespace ptv
{
class Convergence
{
public:
  /// Frames before the raw mean is blended in (the variance needs this many samples).
  static constexpr int kMinimumBlendFrames = 8;

  /**
   * Add frame @a count (1 = first: restarts) of radiance @a frame (3 floats per pixel) for a
   * @a width x @a height image, on @a threads threads (<= 0: every core; the same result on
   * any count).
   */
  void AddFrame(const float* frame, int width, int height, int count, int threads = 0);

  /**
   * The image to show from the mean of the @a count frames added and @a denoised (nullptr:
   * Denoise off, the accumulation is shown) into @a shown (3 floats per pixel; may be nullptr
   * when @a denoised is). Returns the estimated PSNR in dB of the mean, or of what is shown with
   * a denoiser (tone-mapped, like docs/measuring.md); 0 when not known yet (fewer than 2 frames).
   */
  double Combine(const float* denoised, int count, float* shown, int threads);

  /**
   * The opacity to draw the last Combine's shown image with: per pixel the same blend of the
   * accumulated @a alpha and @a denoisedAlpha (the alpha through the denoiser's grid) as the
   * colour's, w alpha + (1 - w) denoisedAlpha, into @a shown (@a pixels floats each; below
   * kMinimumBlendFrames frames, or without statistics of this size, @a denoisedAlpha).
   */
  void BlendAlpha(
    const float* alpha, const float* denoisedAlpha, std::size_t pixels, float* shown) const;

private:
  int Width = 0;
  int Height = 0;
  int Count = 0;
  std::vector<float> Mean;         ///< mean of the frames, 3 per pixel
  std::vector<float> SecondMoment; ///< mean of frame^2, 3 per pixel
  std::vector<float> OddMean;      ///< mean of frames 1, 3, 5, ..., 3 per pixel
  std::vector<float> DenoiserError, Variance, HalfVariance, Scratch;
  std::vector<float> Blend; ///< the last Combine's w per pixel (0: the denoised image)
};
}

#endif
