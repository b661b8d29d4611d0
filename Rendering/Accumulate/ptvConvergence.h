/**
 * @file ptvConvergence.h
 * @brief Private: what the accumulation shows -- the denoised image and the raw running mean
 *        mixed per pixel by a learned blend that leans on the mean as samples accumulate -- and
 *        how far that image is from converged.
 *
 * Kept per pixel while frames of one view accumulate: their mean M, the mean of the squared frame
 * radiance (the variance of M) and the mean of the odd-numbered frames (with the even ones: two
 * independent half-accumulations). M is the accumulated Radiance pass, bit for bit, until the
 * camera moves, and is then read there; after that the pass also holds reprojected history
 * (ptvReprojection), whose error these statistics cannot see, so the blend and the estimate use
 * their own M, the view's own frames.
 *
 * The shown image mixes four candidates, from the most smoothed to the least: the denoised D,
 * D + box3(M - D), D + box7(M - D) and M, with softmax weights of a small MLP
 * (ptvConvergenceBlend.h, trained by Training/ptv_training/converge_blend.py) on nine features
 * per pixel: M's variance (tone-mapped by the delta method, alone and box-filtered), D's squared
 * distance from M (alone, over 3x3 and 7x7 pixels), log k, whether k is 1, and the tone-mapped
 * luminance of M and D. Errors are measured after the tone map g(x) = x^(1/2.2)
 * (docs/measuring.md). The estimated error of what is shown (for the stopping rule of still
 * renders) uses the half accumulations, which do not miss the rare samples of dark pixels as
 * the delta method does: V = (g(A) - g(B))^2 n_A n_B / k^2 over a box, and with
 * rho = w_M + w_3 / 9 + w_7 / 49 (how much of M's own noise the mix keeps)
 * MSE = mean(max(box((g(C) - g(M))^2) - (1 - 2 rho) V, rho^2 V)).
 *
 * The features and candidates are made a band of rows at a time (with the rows their boxes
 * reach), so that only the running statistics are kept per pixel.
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
  /// Samples per pixel a still render traces at least before it trusts the estimate.
  static constexpr int kMinimumStillSamples = 8;

  /**
   * Add frame @a count (1 = first: restarts) of radiance @a frame (3 floats per pixel) for a
   * @a width x @a height image, on @a threads threads (<= 0: every core; the same result on
   * any count). With @a shared the caller keeps M itself (the accumulated Radiance pass of an
   * accumulation without history: the same bits) and gives it to Combine (Images::Mean);
   * @a previous is then M before this frame (read by the second frame; nullptr for the first).
   */
  void AddFrame(const float* frame, int width, int height, int count, int threads = 0,
    bool shared = false, const float* previous = nullptr);

  /// The images Combine mixes and writes.
  struct Images
  {
    const float* Mean = nullptr; ///< M, 3 floats per pixel, when AddFrame was told it is shared
    const float* Denoised = nullptr;      ///< D, 3 floats per pixel (nullptr: Denoise off)
    const float* Alpha = nullptr;         ///< the accumulated opacity (optional)
    const float* DenoisedAlpha = nullptr; ///< the opacity through the denoiser's grid
    float* Shown = nullptr;               ///< the mix, 3 floats per pixel (with Denoised)
    float* ShownAlpha = nullptr; ///< its opacity: the same mix of the two alphas, in [0, 1]
    std::size_t Pixels = 0;      ///< pixels of each image
  };

  /**
   * The image to show from the mean of the @a count frames added and @a images.Denoised
   * (nullptr: Denoise off, the accumulation is shown) into @a images.Shown, and with the
   * alphas its opacity into ShownAlpha (without statistics of this size: DenoisedAlpha).
   * Returns the estimated PSNR in dB of the mean, or of what is shown with a denoiser
   * (tone-mapped, like docs/measuring.md); 0 when not known (fewer than 2 frames, or halves
   * that agree exactly: nothing met yet says how much is still to meet) or not asked for
   * (@a estimate off: the image alone, a third cheaper).
   */
  double Combine(const Images& images, int count, int threads, bool estimate = true);

private:
  /// Per band of rows: its features and candidates (kept between frames: no allocation).
  struct Band
  {
    std::vector<float> Variance, Distance, ToneMean, ToneDenoised, Residual, AlphaResidual;
    std::vector<float> VarianceBoxed, Distance3, Distance7, Residual3, Residual7, Alpha3, Alpha7;
    std::vector<float> Rows;
    std::vector<double> Sums;
  };

  /// M: the caller's (Images::Mean) when shared, else the one kept here.
  const float* MeanOf(const Images& images) const
  {
    return this->Shared ? images.Mean : this->Mean.data();
  }
  /// The learned mix of the images after @a k frames (and rho per pixel when @a rho).
  void Blend(const Images& images, int k, bool rho, int threads);
  /// Blend's band @a band of kBandRows rows.
  void BlendBand(const Images& images, int k, bool rho, int band, Band& scratch);

  int Width = 0;
  int Height = 0;
  int Count = 0;
  bool Shared = false;             ///< M is the caller's (AddFrame), Mean stays empty
  std::vector<float> Mean;         ///< mean of the frames, 3 per pixel
  std::vector<float> SecondMoment; ///< mean of frame^2, 3 per pixel (from the second frame)
  std::vector<float> OddMean;      ///< mean of frames 1, 3, 5, ..., 3 per pixel (likewise)
  std::vector<Band> Bands;         ///< one per band made at once
  std::vector<float> HalfVariance, Error, Scratch; ///< the estimate's
  std::vector<float> Rho; ///< how much of M's noise the last mix keeps (the estimate's)
};
}

#endif
