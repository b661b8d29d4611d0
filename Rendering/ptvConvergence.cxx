#include "ptvConvergence.h"

#include "ptvThreads.h"


#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace ptv
{
namespace
{
constexpr float kInvGamma = 1.0f / 2.2f;
constexpr float kDarkest = 1e-3f; ///< g' is taken at no less than this (g'(0) is infinite)

/// g(x) = x^(1/2.2) (0 for x <= 0) from a table over the float's exponent and top 7 mantissa
/// bits, linearly interpolated (relative error < 1e-4), instead of std::pow four times per
/// pixel and channel. Only error estimates use it, never a shown value.
class ToneTable
{
public:
  ToneTable()
  {
    for (std::uint32_t i = 0; i < kEntries; ++i)
    {
      this->Values[i] = std::pow(FromBits(i << 16), kInvGamma);
    }
  }
  float operator()(float x) const
  {
    if (!(x > 0.0f))
    {
      return 0.0f; // also NaN
    }
    if (x >= kLargest)
    {
      return std::pow(x, kInvGamma);
    }
    std::uint32_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    const std::uint32_t i = bits >> 16;
    const float t = static_cast<float>(bits & 0xFFFFu) * (1.0f / 65536.0f);
    return this->Values[i] + t * (this->Values[i + 1] - this->Values[i]);
  }

private:
  static float FromBits(std::uint32_t bits)
  {
    float x;
    std::memcpy(&x, &bits, sizeof x);
    return x;
  }
  static constexpr std::uint32_t kEntries = 0x7F80u + 1; ///< up to +infinity's upper bits
  static constexpr float kLargest = 1e30f;
  float Values[kEntries];
};

const ToneTable& Tone()
{
  static const ToneTable table;
  return table;
}

/// g'(x), taken at no less than kDarkest.
inline float ToneSlope(const ToneTable& g, float x)
{
  x = std::max(x, kDarkest);
  return kInvGamma * g(x) / x;
}

/// Width of the box that smooths the variance after @a count frames: each frame adds a degree
/// of freedom per pixel, so fewer neighbours are needed (a fixed box blurs thin structures'
/// variance into their background: measured on the stent).
int VarianceBox(int count)
{
  return count < 16 ? 7 : count < 32 ? 5 : count < 128 ? 3 : 1;
}

/// @a map (width x height) box-filtered in place over size x size pixels, edges clamped.
void Box(std::vector<float>& map, std::vector<float>& scratch, int width, int height, int size,
  int threads)
{
  if (size <= 1)
  {
    return;
  }
  const int r = size / 2;
  const float norm = 1.0f / static_cast<float>(size);
  scratch.resize(map.size());
  auto pass = [&](const float* in, float* out, int lines, int length, std::ptrdiff_t along,
                std::ptrdiff_t across)
  {
    ParallelFor(threads, 0, lines, 0,
      [&](int begin, int end)
      {
        for (int line = begin; line < end; ++line)
        {
          const float* src = in + line * across;
          float* dst = out + line * across;
          auto at = [&](int i) { return src[std::min(std::max(i, 0), length - 1) * along]; };
          double sum = 0.0;
          for (int i = -r; i <= r; ++i)
          {
            sum += at(i);
          }
          for (int i = 0; i < length; ++i)
          {
            dst[i * along] = std::max(static_cast<float>(sum) * norm, 0.0f); // no -0 rounding
            sum += at(i + r + 1) - at(i - r);
          }
        }
      });
  };
  pass(map.data(), scratch.data(), height, width, 1, width);   // rows
  pass(scratch.data(), map.data(), width, height, width, 1);   // columns
}
}

//------------------------------------------------------------------------------
void Convergence::AddFrame(const float* frame, int width, int height, int count, int threads)
{
  const std::size_t n = 3 * static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  const bool first = count <= 1 || width != this->Width || height != this->Height;
  if (first)
  {
    this->Width = width;
    this->Height = height;
    this->Mean.resize(n);
    this->OddMean.resize(n);
    this->SecondMoment.resize(n);
    count = 1;
  }
  const float w = 1.0f / static_cast<float>(count);
  const bool odd = count % 2 == 1;
  const float wOdd = 1.0f / static_cast<float>((count + 1) / 2);
  float* mean = this->Mean.data();
  float* oddMean = this->OddMean.data();
  float* second = this->SecondMoment.data();
  // Element-wise, in parallel blocks (the same bits on any thread count): at 1024² these are
  // three 12 MB arrays per frame, which would otherwise run on one core inside the trace time.
  ParallelFor(threads, std::size_t(0), n, std::size_t(1) << 14,
    [&](std::size_t i0, std::size_t i1)
    {
      for (std::size_t i = i0; i < i1; ++i)
      {
        const float f = frame[i];
        if (first)
        {
          mean[i] = oddMean[i] = f;
          second[i] = f * f;
          continue;
        }
        mean[i] += (f - mean[i]) * w; // as PassBuffers::Accumulate: same bits
        second[i] += (f * f - second[i]) * w;
        if (odd)
        {
          oddMean[i] += (f - oddMean[i]) * wOdd;
        }
      }
    });
  this->Count = count;
}

//------------------------------------------------------------------------------
double Convergence::Combine(const float* denoised, int count, float* shown, int threads)
{
  const float* mean = this->Mean.data();
  const std::size_t n = static_cast<std::size_t>(this->Width) * this->Height;
  this->Blend.clear(); // BlendAlpha: the denoised alpha unless set below
  if (count != this->Count || n == 0)
  {
    return 0.0; // statistics of another accumulation: nothing to say
  }
  if (count < 2)
  {
    if (denoised)
    {
      std::copy(denoised, denoised + 3 * n, shown); // one frame: no variance, the denoised image
    }
    return 0.0;
  }
  // Every pixel is written below; the denoiser's maps only exist with a denoised image.
  this->HalfVariance.resize(n);
  this->DenoiserError.resize(denoised ? n : 0);
  this->Variance.resize(denoised ? n : 0);
  const int k = count;
  const int odd = (k + 1) / 2;
  const int even = k - odd;
  const float halfScale = float(odd) * float(even) / (float(k) * float(k));
  const ToneTable& g = Tone();
  ParallelFor(threads, std::size_t(0), n, std::size_t(0),
    [&](std::size_t begin, std::size_t end)
    {
      for (std::size_t p = begin; p < end; ++p)
      {
        float e = 0.0f, v = 0.0f, h = 0.0f;
        for (int c = 0; c < 3; ++c)
        {
          const std::size_t i = 3 * p + c;
          const float m = mean[i];
          const float other = (float(k) * m - float(odd) * this->OddMean[i]) / float(even);
          const float half = g(this->OddMean[i]) - g(other);
          h += half * half * halfScale;
          if (denoised)
          {
            const float diff = g(denoised[i]) - g(m);
            e += diff * diff;
            const float slope = ToneSlope(g, m);
            v += std::max(this->SecondMoment[i] - m * m, 0.0f) / float(k - 1) * slope * slope;
          }
        }
        this->HalfVariance[p] = h / 3.0f;
        if (denoised)
        {
          this->DenoiserError[p] = e / 3.0f;
          this->Variance[p] = v / 3.0f;
        }
      }
    });
  const int box = VarianceBox(k);
  Box(this->HalfVariance, this->Scratch, this->Width, this->Height, std::max(box, 3), threads);
  if (denoised)
  {
    // The denoiser's error over the same box as the variance it is corrected by: over 3x3 pixels
    // its estimate was too noisy at 8-15 frames and gave noisy raw pixels weight (the head at
    // 512² showed 0.9 dB less at 8 spp than the denoised image alone; test_converged_real.py).
    Box(this->DenoiserError, this->Scratch, this->Width, this->Height, std::max(box, 3), threads);
    Box(this->Variance, this->Scratch, this->Width, this->Height, box, threads);
  }

  this->Blend.assign(n, 1.0f); // Denoise off: the raw mean
  double sum = 0.0;
  for (std::size_t p = 0; p < n; ++p)
  {
    if (!denoised)
    {
      sum += this->HalfVariance[p]; // Denoise off: the raw mean is shown (w = 1)
      continue;
    }
    const float v = this->Variance[p];
    const float e = std::max(this->DenoiserError[p] - v, 0.0f);
    const bool blend = k >= kMinimumBlendFrames && e + v > 0.0f;
    const float w = blend ? std::min(e / (e + v), 1.0f) : 0.0f;
    this->Blend[p] = w;
    for (int c = 0; c < 3; ++c)
    {
      const std::size_t i = 3 * p + c;
      shown[i] = w * mean[i] + (1.0f - w) * denoised[i];
    }
    sum += double(w) * w * this->HalfVariance[p] +
      double(1.0f - w) * (1.0f - w) * this->DenoiserError[p];
  }
  const double mse = sum / static_cast<double>(n);
  return mse > 0.0 ? -10.0 * std::log10(mse) : 100.0; // identical halves: an empty view
}

//------------------------------------------------------------------------------
void Convergence::BlendAlpha(
  const float* alpha, const float* denoisedAlpha, std::size_t pixels, float* shown) const
{
  if (this->Blend.size() != pixels) // one frame (or no statistics): the denoised image's alpha
  {
    std::copy(denoisedAlpha, denoisedAlpha + pixels, shown);
    return;
  }
  for (std::size_t p = 0; p < pixels; ++p)
  {
    const float w = this->Blend[p];
    shown[p] = w * alpha[p] + (1.0f - w) * denoisedAlpha[p];
  }
}
}
