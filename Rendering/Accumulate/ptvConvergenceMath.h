/**
 * @file ptvConvergenceMath.h
 * @brief Private: the arithmetic of ptvConvergence -- the tone map g and its slope, the box
 *        filter of its per-pixel statistics, the blend network's forward pass over blocks of
 *        pixels (weights in ptvConvergenceBlend.h), the hand-over past the trained counts and
 *        the PSNR of an MSE. Included by ptvConvergence.cxx only.
 */
#ifndef ptvConvergenceMath_h
#define ptvConvergenceMath_h

#include "ptvConvergenceBlend.h"
#include "ptvThreads.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace ptv
{
namespace convergence
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

inline const ToneTable& Tone()
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
inline int VarianceBox(int count)
{
  return count < 16 ? 7 : count < 32 ? 5 : count < 128 ? 3 : 1;
}

/// The horizontal box (size 2r + 1, edges clamped, @a norm = 1 / size) of one row of @a width
/// pixels of @a channels interleaved floats.
inline void BoxRow(const float* row, float* out, int width, int channels, int r, float norm)
{
  for (int c = 0; c < channels; ++c)
  {
    const float* src = row + c;
    float* dst = out + c;
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

/// The vertical box of rows [y0, y1) into @a out (row y at (y - y0) x @a stride) as running
/// sums (in @a sum, @a stride doubles) that start at y0, from the horizontally boxed rows:
/// @a row(y) is row y clamped to the image.
template <typename RowAt>
void BoxColumns(const RowAt& row, int y0, int y1, int r, float norm, std::size_t stride,
  float* out, double* sum)
{
  std::fill(sum, sum + stride, 0.0);
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
    float* dst = out + static_cast<std::size_t>(y - y0) * stride;
    const float* add = row(y + r + 1);
    const float* drop = row(y - r);
    for (std::size_t j = 0; j < stride; ++j)
    {
      dst[j] = static_cast<float>(sum[j]) * norm;
      sum[j] += static_cast<double>(add[j]) - drop[j];
    }
  }
}

/// Rows of the vertical pass that share one running sum: a box's value does not depend on how
/// the image is cut into threads' rows or bands (a multiple of it).
constexpr int kBoxRows = 16;

/// @a map (width x height pixels of @a channels interleaved floats) box-filtered in place over
/// size x size pixels, edges clamped: rows, then columns as running sums of whole rows (each
/// kBoxRows rows start their own sum), both cache-friendly and in parallel.
inline void Box(std::vector<float>& map, std::vector<float>& scratch, int width, int height,
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
        BoxRow(in + y * stride, rows + y * stride, width, channels, r, norm);
      }
    });
  float* out = map.data();
  ParallelFor(threads, 0, height, kBoxRows,
    [&](int y0, int y1)
    {
      std::vector<double> sum(stride);
      auto row = [&](int y) { return rows + std::min(std::max(y, 0), height - 1) * stride; };
      BoxColumns(row, y0, y1, r, norm, stride, out + y0 * stride, sum.data());
    });
}

/// Box() of the rows [y0, y1) of an image of @a height rows (y0 a multiple of kBoxRows; the
/// same values), from its rows [r0, r1) in @a in (which must hold the rows y0 - size / 2 to
/// y1 + size / 2 that are in the image), into @a out (row y0 first); @a rows and @a sum are
/// scratch.
inline void BoxBand(const float* in, int r0, int r1, int y0, int y1, int width, int height,
  int channels, int size, float* out, std::vector<float>& rows, std::vector<double>& sum)
{
  const std::size_t stride = static_cast<std::size_t>(width) * channels;
  if (size <= 1)
  {
    std::copy(in + (y0 - r0) * stride, in + (y1 - r0) * stride, out);
    return;
  }
  const int r = size / 2;
  const float norm = 1.0f / static_cast<float>(size);
  rows.resize(static_cast<std::size_t>(r1 - r0) * stride);
  sum.resize(stride);
  const int first = std::max(y0 - r, 0);
  const int last = std::min(y1 + r + 1, height); // the running sum reads one row further
  for (int y = first; y < last; ++y)
  {
    BoxRow(in + (y - r0) * stride, rows.data() + (y - r0) * stride, width, channels, r, norm);
  }
  auto row = [&](int y)
  { return rows.data() + (std::min(std::max(y, 0), height - 1) - r0) * stride; };
  for (int c = y0; c < y1; c += kBoxRows)
  {
    BoxColumns(row, c, std::min(c + kBoxRows, y1), r, norm, stride, out + (c - y0) * stride,
      sum.data());
  }
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
inline float HandOver(int k)
{
  return k <= kHandOverFrom
    ? 0.0f
    : std::min(1.0f, 0.5f * std::log2(static_cast<float>(k) / float(kHandOverFrom)));
}

/// PSNR in dB of a tone-mapped MSE; 0 ("not known") for 0: identical halves say nothing about
/// what the samples have not met yet (a 2 x 1 view of a faint volume).
inline double ToPsnr(double mse)
{
  return mse > 0.0 ? -10.0 * std::log10(mse) : 0.0;
}
}
}

#endif
