#include "ptvConvergence.h"

#include "ptvConvergenceBlend.h"
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

/// @a map (width x height pixels of @a channels interleaved floats) box-filtered in place over
/// size x size pixels, edges clamped: rows, then columns as running sums of whole rows (each
/// band of rows starts its own sum), both cache-friendly and in parallel.
void Box(std::vector<float>& map, std::vector<float>& scratch, int width, int height,
  int channels, int size, int threads)
{
  if (size <= 1)
  {
    return;
  }
  const int r = size / 2;
  const float norm = 1.0f / static_cast<float>(size);
  const std::size_t stride = static_cast<std::size_t>(width) * channels; // floats per row
  scratch.resize(map.size());
  const float* in = map.data();
  float* rows = scratch.data();
  ParallelFor(threads, 0, height, 8,
    [&](int y0, int y1)
    {
      for (int y = y0; y < y1; ++y)
      {
        for (int c = 0; c < channels; ++c)
        {
          const float* src = in + y * stride + c;
          float* dst = rows + y * stride + c;
          auto at = [&](int i)
          { return src[static_cast<std::size_t>(std::min(std::max(i, 0), width - 1)) * channels]; };
          double sum = 0.0;
          for (int i = -r; i <= r; ++i)
          {
            sum += at(i);
          }
          for (int x = 0; x < width; ++x)
          {
            dst[static_cast<std::size_t>(x) * channels] = static_cast<float>(sum) * norm;
            sum += at(x + r + 1) - at(x - r);
          }
        }
      }
    });
  float* out = map.data();
  ParallelFor(threads, 0, height, 16,
    [&](int y0, int y1)
    {
      std::vector<double> sum(stride, 0.0);
      auto row = [&](int y) { return rows + std::min(std::max(y, 0), height - 1) * stride; };
      for (int i = y0 - r; i <= y0 + r; ++i)
      {
        const float* src = row(i);
        for (std::size_t j = 0; j < stride; ++j)
        {
          sum[j] += src[j];
        }
      }
      for (int y = y0; y < y1; ++y)
      {
        float* dst = out + y * stride;
        const float* add = row(y + r + 1);
        const float* drop = row(y - r);
        for (std::size_t j = 0; j < stride; ++j)
        {
          dst[j] = static_cast<float>(sum[j]) * norm;
          sum[j] += static_cast<double>(add[j]) - drop[j];
        }
      }
    });
}

/// exp(x) for x <= 0 to about 2e-5 relative (the softmax's; std::exp four times a pixel was a
/// tenth of the blend): 2^(x log2 e), the fraction's power by its Taylor polynomial of degree 6.
/// Branch-free, so that loops over it vectorise.
inline float FastExp(float x)
{
  x = std::max(x, -80.0f);
  const float t = x * 1.44269504f;
  float whole = static_cast<float>(static_cast<int>(t)); // towards 0; for t < 0 one less:
  whole -= static_cast<float>(t < whole);                // floor
  const float f = t - whole;                             // [0, 1)
  const float high = 0.00961812911f + f * (0.00133335581f + f * 0.000154035304f);
  const float p = 1.0f + f * (0.693147181f + f * (0.240226507f + f * (0.0555041087f + f * high)));
  const std::uint32_t bits = __builtin_bit_cast(std::uint32_t, p) +
    (static_cast<std::uint32_t>(static_cast<int>(whole)) << 23);
  return __builtin_bit_cast(float, bits);
}

/// log(x) for x > 0 to about 1e-5 absolute: the exponent plus a series in the mantissa
/// (features only; std::log five times a pixel cost more than the rest of the blend).
inline float FastLog(float x)
{
  const std::uint32_t bits = __builtin_bit_cast(std::uint32_t, x);
  const int exponent = static_cast<int>((bits >> 23) & 0xFF) - 127;
  const float m = __builtin_bit_cast(float, (bits & 0x007FFFFFu) | 0x3F800000u); // [1, 2)
  // log(m) on [1, 2) via t = (m - 1) / (m + 1): log m = 2 (t + t^3/3 + t^5/5 + t^7/7 + t^9/9)
  const float t = (m - 1.0f) / (m + 1.0f);
  const float t2 = t * t;
  const float series =
    t * (2.0f + t2 * (2.0f / 3.0f + t2 * (2.0f / 5.0f + t2 * (2.0f / 7.0f + t2 * (2.0f / 9.0f)))));
  return static_cast<float>(exponent) * 0.69314718f + series;
}

/// Added inside each log feature (converge_blend.py's EPS).
constexpr float kLogOffset = 1e-8f;

/// Pixels the blend's network runs on at once: feature-major blocks the compiler vectorises.
constexpr int kBlock = 64;

/// The blend's softmax weights of its four candidates for @a count (<= kBlock) pixels from their
/// features @a phi (kInputs rows of kBlock) into @a w (kCandidates rows of kBlock).
inline void BlendWeights(const float (*phi)[kBlock], int count, float (*w)[kBlock])
{
  float hidden[blend::kHidden][kBlock];
  for (int h = 0; h < blend::kHidden; ++h)
  {
    for (int b = 0; b < count; ++b)
    {
      hidden[h][b] = blend::kB1[h];
    }
    for (int i = 0; i < blend::kInputs; ++i)
    {
      const float weight = blend::kW1[h * blend::kInputs + i];
      for (int b = 0; b < count; ++b)
      {
        hidden[h][b] += weight * phi[i][b];
      }
    }
    for (int b = 0; b < count; ++b)
    {
      hidden[h][b] = std::max(hidden[h][b], 0.0f);
    }
  }
  for (int j = 0; j < blend::kCandidates; ++j)
  {
    for (int b = 0; b < count; ++b)
    {
      w[j][b] = blend::kB2[j];
    }
    for (int h = 0; h < blend::kHidden; ++h)
    {
      const float weight = blend::kW2[j * blend::kHidden + h];
      for (int b = 0; b < count; ++b)
      {
        w[j][b] += weight * hidden[h][b];
      }
    }
  }
  float top[kBlock], sum[kBlock];
  for (int b = 0; b < count; ++b)
  {
    top[b] = std::max(std::max(w[0][b], w[1][b]), std::max(w[2][b], w[3][b]));
  }
  for (int j = 0; j < blend::kCandidates; ++j)
  {
    float* row = w[j];
    for (int b = 0; b < count; ++b)
    {
      row[b] = FastExp(row[b] - top[b]);
    }
  }
  for (int b = 0; b < count; ++b)
  {
    sum[b] = 1.0f / (w[0][b] + w[1][b] + w[2][b] + w[3][b]);
  }
  for (int j = 0; j < blend::kCandidates; ++j)
  {
    float* row = w[j];
    for (int b = 0; b < count; ++b)
    {
      row[b] *= sum[b];
    }
  }
}

/// How far the shown image has moved to the raw mean after @a k frames: 0 up to
/// kHandOverFrom, then linearly in log2(k) to 1 at 4 kHandOverFrom (converge_blend.py's
/// hand_over: the blend is trained up to 512 frames, and the mean is unbiased).
constexpr int kHandOverFrom = 256;
float HandOver(int k)
{
  return k <= kHandOverFrom
    ? 0.0f
    : std::min(1.0f, 0.5f * std::log2(static_cast<float>(k) / float(kHandOverFrom)));
}

/// PSNR in dB of a tone-mapped MSE; 0 ("not known") for 0: identical halves say nothing about
/// what the samples have not met yet (a 2 x 1 view of a faint volume).
double ToPsnr(double mse)
{
  return mse > 0.0 ? -10.0 * std::log10(mse) : 0.0;
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
double Convergence::Combine(
  const float* denoised, int count, float* shown, int threads, bool estimate)
{
  const std::size_t n = static_cast<std::size_t>(this->Width) * this->Height;
  this->Weights.clear(); // BlendAlpha: the denoised alpha unless set below
  if (count != this->Count || n == 0)
  {
    return 0.0; // statistics of another accumulation: nothing to say
  }
  const int k = count;
  const ToneTable& g = Tone();
  const float* mean = this->Mean.data();
  if (k >= 2 && estimate)
  {
    // The raw mean's error from the two half accumulations (the still render's estimate).
    this->HalfVariance.resize(n);
    const int odd = (k + 1) / 2;
    const int even = k - odd;
    const float halfScale = float(odd) * float(even) / (float(k) * float(k));
    ParallelFor(threads, std::size_t(0), n, std::size_t(0),
      [&](std::size_t begin, std::size_t end)
      {
        for (std::size_t p = begin; p < end; ++p)
        {
          float h = 0.0f;
          for (int c = 0; c < 3; ++c)
          {
            const std::size_t i = 3 * p + c;
            const float other =
              (float(k) * mean[i] - float(odd) * this->OddMean[i]) / float(even);
            const float half = g(this->OddMean[i]) - g(other);
            h += half * half * halfScale;
          }
          this->HalfVariance[p] = h / 3.0f;
        }
      });
    Box(this->HalfVariance, this->Scratch, this->Width, this->Height, 1,
      std::max(VarianceBox(k), 3), threads);
  }
  if (!denoised)
  {
    if (k < 2 || !estimate)
    {
      return 0.0;
    }
    double sum = 0.0; // Denoise off: the raw mean is shown
    for (std::size_t p = 0; p < n; ++p)
    {
      sum += this->HalfVariance[p];
    }
    return ToPsnr(sum / static_cast<double>(n));
  }
  this->Blend(denoised, k, shown, threads);
  if (k < 2 || !estimate)
  {
    return 0.0; // one frame: no estimate of the mean's error
  }
  // The shown image's error: C = sum w_j C_j leans on the mean's own noise by
  // rho = w_M + w_3 / 9 + w_7 / 49, so E[(C - M)^2] = MSE(C) + (1 - 2 rho) V (V: the mean's
  // variance); box((g(C) - g(M))^2) estimates the left side over the variance's box.
  this->Error.resize(n);
  ParallelFor(threads, std::size_t(0), n, std::size_t(0),
    [&](std::size_t begin, std::size_t end)
    {
      for (std::size_t p = begin; p < end; ++p)
      {
        float e = 0.0f;
        for (int c = 0; c < 3; ++c)
        {
          const float diff = g(shown[3 * p + c]) - g(mean[3 * p + c]);
          e += diff * diff;
        }
        this->Error[p] = e / 3.0f;
      }
    });
  Box(this->Error, this->Scratch, this->Width, this->Height, 1, std::max(VarianceBox(k), 3),
    threads);
  double sum = 0.0;
  for (std::size_t p = 0; p < n; ++p)
  {
    const float* w = &this->Weights[blend::kCandidates * p];
    const float rho = w[3] + w[1] / 9.0f + w[2] / 49.0f;
    const float v = this->HalfVariance[p];
    sum += std::max(this->Error[p] - (1.0f - 2.0f * rho) * v, rho * rho * v);
  }
  return ToPsnr(sum / static_cast<double>(n));
}

//------------------------------------------------------------------------------
void Convergence::Blend(const float* denoised, int k, float* shown, int threads)
{
  const std::size_t n = static_cast<std::size_t>(this->Width) * this->Height;
  const ToneTable& g = Tone();
  const float* mean = this->Mean.data();
  // Per pixel: the mean's variance (delta method; 0 on the first frame) and the squared
  // distance of the denoised image from the mean, tone-mapped; the residual M - D.
  this->Variance.resize(n);
  this->Distance.resize(n);
  this->ToneMean.resize(n);
  this->ToneDenoised.resize(n);
  this->Residual3.resize(3 * n);
  ParallelFor(threads, std::size_t(0), n, std::size_t(0),
    [&](std::size_t begin, std::size_t end)
    {
      for (std::size_t p = begin; p < end; ++p)
      {
        float v = 0.0f, e = 0.0f, tm = 0.0f, td = 0.0f;
        for (int c = 0; c < 3; ++c)
        {
          const std::size_t i = 3 * p + c;
          const float m = mean[i];
          const float gm = g(m), gd = g(denoised[i]);
          const float diff = gd - gm;
          e += diff * diff;
          tm += std::min(gm, 1.0f);
          td += std::min(gd, 1.0f);
          if (k >= 2)
          {
            const float slope = ToneSlope(g, m);
            v += std::max(this->SecondMoment[i] - m * m, 0.0f) / float(k - 1) * slope * slope;
          }
          this->Residual3[i] = m - denoised[i];
        }
        this->Variance[p] = v / 3.0f;
        this->Distance[p] = e / 3.0f;
        this->ToneMean[p] = tm / 3.0f;
        this->ToneDenoised[p] = td / 3.0f;
      }
    });
  this->VarianceBoxed = this->Variance;
  Box(this->VarianceBoxed, this->Scratch, this->Width, this->Height, 1, VarianceBox(k), threads);
  this->Distance3 = this->Distance;
  Box(this->Distance3, this->Scratch, this->Width, this->Height, 1, 3, threads);
  this->Distance7 = this->Distance;
  Box(this->Distance7, this->Scratch, this->Width, this->Height, 1, 7, threads);
  this->Residual7 = this->Residual3;
  Box(this->Residual3, this->Scratch, this->Width, this->Height, 3, 3, threads);
  Box(this->Residual7, this->Scratch, this->Width, this->Height, 3, 7, threads);

  this->Weights.resize(blend::kCandidates * n);
  const float logK = std::log(static_cast<float>(k));
  const float handOver = HandOver(k);
  const float first = k == 1 ? 1.0f : 0.0f;
  const float* features[5] = { this->VarianceBoxed.data(), this->Variance.data(),
    this->Distance.data(), this->Distance3.data(), this->Distance7.data() };
  ParallelFor(threads, std::size_t(0), n, std::size_t(kBlock),
    [&](std::size_t begin, std::size_t end)
    {
      float phi[blend::kInputs][kBlock];
      float w[blend::kCandidates][kBlock];
      for (std::size_t p0 = begin; p0 < end; p0 += kBlock)
      {
        const int count = static_cast<int>(std::min<std::size_t>(kBlock, end - p0));
        for (int f = 0; f < 5; ++f) // logs of the variances and distances
        {
          const float* src = features[f] + p0;
          float* dst = phi[f];
          for (int b = 0; b < count; ++b)
          {
            const float x = src[b];
            dst[b] = FastLog((x > 0.0f ? x : 0.0f) + kLogOffset);
          }
        }
        for (int b = 0; b < count; ++b)
        {
          phi[5][b] = logK;
          phi[6][b] = first;
          phi[7][b] = this->ToneMean[p0 + b];
          phi[8][b] = this->ToneDenoised[p0 + b];
        }
        BlendWeights(phi, count, w);
        for (int b = 0; b < count; ++b)
        {
          const std::size_t p = p0 + b;
          float* out = &this->Weights[blend::kCandidates * p];
          for (int j = 0; j < blend::kCandidates; ++j)
          {
            // Beyond the trained counts the weights move towards the raw mean.
            out[j] = j < 3 ? w[j][b] * (1.0f - handOver) : w[3][b] + handOver * (1.0f - w[3][b]);
          }
          for (int c = 0; c < 3; ++c)
          {
            const std::size_t i = 3 * p + c;
            shown[i] = std::max(denoised[i] + out[1] * this->Residual3[i] +
                out[2] * this->Residual7[i] + out[3] * (mean[i] - denoised[i]),
              0.0f); // the residual boxes can undershoot next to a dark pixel
          }
        }
      }
    });
}

//------------------------------------------------------------------------------
void Convergence::BlendAlpha(const float* alpha, const float* denoisedAlpha, std::size_t pixels,
  float* shown, int threads)
{
  if (this->Weights.size() != blend::kCandidates * pixels) // no statistics of this size
  {
    std::copy(denoisedAlpha, denoisedAlpha + pixels, shown);
    return;
  }
  this->Residual3.resize(pixels);
  for (std::size_t p = 0; p < pixels; ++p)
  {
    this->Residual3[p] = alpha[p] - denoisedAlpha[p];
  }
  this->Residual7 = this->Residual3;
  Box(this->Residual3, this->Scratch, this->Width, this->Height, 1, 3, threads);
  Box(this->Residual7, this->Scratch, this->Width, this->Height, 1, 7, threads);
  for (std::size_t p = 0; p < pixels; ++p)
  {
    const float* w = &this->Weights[blend::kCandidates * p];
    const float a = denoisedAlpha[p] + w[1] * this->Residual3[p] + w[2] * this->Residual7[p] +
      w[3] * (alpha[p] - denoisedAlpha[p]);
    shown[p] = std::min(std::max(a, 0.0f), 1.0f);
  }
}
}
