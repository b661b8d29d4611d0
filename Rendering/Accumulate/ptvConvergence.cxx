#include "ptvConvergence.h"

#include "ptvConvergenceMath.h"
#include "ptvThreads.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace ptv
{
using namespace convergence; // ptvConvergenceMath.h

//------------------------------------------------------------------------------
void Convergence::AddFrame(const float* frame, int width, int height, int count, int threads,
  bool shared, const float* previous)
{
  const std::size_t n = 3 * static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  const bool first = count <= 1 || width != this->Width || height != this->Height ||
    shared != this->Shared || (shared && !previous);
  if (first)
  {
    this->Width = width;
    this->Height = height;
    this->Shared = shared;
    if (shared)
    {
      std::vector<float>().swap(this->Mean);
    }
    else
    {
      this->Mean.resize(n);
    }
    // One frame needs only its mean: the others follow from it with the second frame.
    std::vector<float>().swap(this->OddMean);
    std::vector<float>().swap(this->SecondMoment);
    count = 1;
  }
  const bool second = !first && this->SecondMoment.size() != n; // made from the first frame
  if (second)
  {
    this->OddMean.resize(n);
    this->SecondMoment.resize(n);
  }
  const float w = 1.0f / static_cast<float>(count);
  const bool odd = count % 2 == 1;
  const float wOdd = 1.0f / static_cast<float>((count + 1) / 2);
  float* mean = this->Mean.data(); // not kept when shared
  const float* before = shared ? previous : mean;
  float* oddMean = this->OddMean.data();
  float* moment = this->SecondMoment.data();
  if (first && shared)
  {
    this->Count = count;
    return;
  }
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
          mean[i] = f;
          continue;
        }
        if (second)
        {
          oddMean[i] = before[i];
          moment[i] = before[i] * before[i];
        }
        if (!shared)
        {
          mean[i] += (f - mean[i]) * w; // as PassBuffers::Accumulate: same bits
        }
        moment[i] += (f * f - moment[i]) * w;
        if (odd)
        {
          oddMean[i] += (f - oddMean[i]) * wOdd;
        }
      }
    });
  this->Count = count;
}

namespace
{
/// Rows of a band of Blend (a multiple of kBoxRows and of kBlock: its boxes and blocks of
/// pixels are the whole image's).
constexpr int kBandRows = 64;
/// The most rows a band's boxes reach beyond it (the 7 x 7 box).
constexpr int kHalo = 3;
static_assert(kBandRows % kBoxRows == 0 && kBandRows % kBlock == 0, "band rows");
}

//------------------------------------------------------------------------------
double Convergence::Combine(const Images& images, int count, int threads, bool estimate)
{
  const std::size_t n = static_cast<std::size_t>(this->Width) * this->Height;
  const float* mean = this->MeanOf(images);
  if (count != this->Count || n == 0 || n != images.Pixels || !mean)
  {
    if (images.ShownAlpha && images.DenoisedAlpha) // no statistics of this size
    {
      std::copy(images.DenoisedAlpha, images.DenoisedAlpha + images.Pixels, images.ShownAlpha);
    }
    return 0.0; // statistics of another accumulation: nothing to say
  }
  const int k = count;
  const ToneTable& g = Tone();
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
  if (!images.Denoised)
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
  const bool error = k >= 2 && estimate;
  this->Blend(images, k, error, threads);
  if (!error)
  {
    return 0.0; // one frame: no estimate of the mean's error
  }
  // The shown image's error: C = sum w_j C_j leans on the mean's own noise by
  // rho = w_M + w_3 / 9 + w_7 / 49, so E[(C - M)^2] = MSE(C) + (1 - 2 rho) V (V: the mean's
  // variance); box((g(C) - g(M))^2) estimates the left side over the variance's box.
  const float* shown = images.Shown;
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
    const float rho = this->Rho[p];
    const float v = this->HalfVariance[p];
    sum += std::max(this->Error[p] - (1.0f - 2.0f * rho) * v, rho * rho * v);
  }
  return ToPsnr(sum / static_cast<double>(n));
}

//------------------------------------------------------------------------------
void Convergence::Blend(const Images& images, int k, bool rho, int threads)
{
  const int bands = (this->Height + kBandRows - 1) / kBandRows;
  const int slots = std::max(std::min(ResolvedThreads(threads), bands), 1);
  this->Bands.resize(static_cast<std::size_t>(slots));
  this->Rho.resize(rho ? static_cast<std::size_t>(this->Width) * this->Height : 0);
  // As many bands at once as threads, each with its own scratch.
  for (int first = 0; first < bands; first += slots)
  {
    ParallelFor(threads, first, std::min(first + slots, bands), 1,
      [&](int b0, int b1)
      {
        for (int b = b0; b < b1; ++b)
        {
          this->BlendBand(images, k, rho, b, this->Bands[static_cast<std::size_t>(b - first)]);
        }
      });
  }
}

//------------------------------------------------------------------------------
void Convergence::BlendBand(const Images& images, int k, bool rho, int band, Band& s)
{
  const int width = this->Width;
  const int height = this->Height;
  const int y0 = band * kBandRows;
  const int y1 = std::min(y0 + kBandRows, height);
  const int r0 = std::max(y0 - kHalo, 0);
  const int r1 = std::min(y1 + kHalo + 1, height); // BoxBand reads one row further
  const std::size_t w = static_cast<std::size_t>(width);
  const std::size_t q0 = static_cast<std::size_t>(r0) * w; // the band's rows with their halo
  const std::size_t local = static_cast<std::size_t>(r1 - r0) * w;
  const std::size_t p0 = static_cast<std::size_t>(y0) * w; // the band's own rows
  const std::size_t own = static_cast<std::size_t>(y1 - y0) * w;
  const ToneTable& g = Tone();
  const float* mean = this->MeanOf(images);
  const float* denoised = images.Denoised;
  const bool alpha = images.Alpha && images.DenoisedAlpha && images.ShownAlpha;
  // Per pixel: the mean's variance (delta method; 0 on the first frame) and the squared
  // distance of the denoised image from the mean, tone-mapped; the residual M - D.
  s.Variance.resize(local);
  s.Distance.resize(local);
  s.ToneMean.resize(local);
  s.ToneDenoised.resize(local);
  s.Residual.resize(3 * local);
  for (std::size_t q = 0; q < local; ++q)
  {
    const std::size_t p = q0 + q;
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
      s.Residual[3 * q + c] = m - denoised[i];
    }
    s.Variance[q] = v / 3.0f;
    s.Distance[q] = e / 3.0f;
    s.ToneMean[q] = tm / 3.0f;
    s.ToneDenoised[q] = td / 3.0f;
  }
  auto box = [&](const std::vector<float>& in, int channels, int size, std::vector<float>& out)
  {
    out.resize(own * static_cast<std::size_t>(channels));
    BoxBand(in.data(), r0, r1, y0, y1, width, height, channels, size, out.data(), s.Rows,
      s.Sums);
  };
  box(s.Variance, 1, VarianceBox(k), s.VarianceBoxed);
  box(s.Distance, 1, 3, s.Distance3);
  box(s.Distance, 1, 7, s.Distance7);
  box(s.Residual, 3, 3, s.Residual3);
  box(s.Residual, 3, 7, s.Residual7);
  if (alpha)
  {
    s.AlphaResidual.resize(local);
    for (std::size_t q = 0; q < local; ++q)
    {
      s.AlphaResidual[q] = images.Alpha[q0 + q] - images.DenoisedAlpha[q0 + q];
    }
    box(s.AlphaResidual, 1, 3, s.Alpha3);
    box(s.AlphaResidual, 1, 7, s.Alpha7);
  }

  const float logK = std::log(static_cast<float>(k));
  const float handOver = HandOver(k);
  const float first = k == 1 ? 1.0f : 0.0f;
  const std::size_t halo = p0 - q0; // the own rows' offset in the halo-wide features
  const float* features[5] = { s.VarianceBoxed.data(), s.Variance.data() + halo,
    s.Distance.data() + halo, s.Distance3.data(), s.Distance7.data() };
  float phi[blend::kInputs][kBlock];
  float wb[blend::kCandidates][kBlock];
  for (std::size_t b0 = 0; b0 < own; b0 += kBlock) // blocks aligned as the whole image's
  {
    const int count = static_cast<int>(std::min<std::size_t>(kBlock, own - b0));
    for (int f = 0; f < 5; ++f) // logs of the variances and distances
    {
      const float* src = features[f] + b0;
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
      phi[7][b] = s.ToneMean[halo + b0 + b];
      phi[8][b] = s.ToneDenoised[halo + b0 + b];
    }
    BlendWeights(phi, count, wb);
    for (int b = 0; b < count; ++b)
    {
      const std::size_t o = b0 + b; // in the band
      const std::size_t p = p0 + o; // in the image
      float out[blend::kCandidates];
      for (int j = 0; j < blend::kCandidates; ++j)
      {
        // Beyond the trained counts the weights move towards the raw mean.
        out[j] = j < 3 ? wb[j][b] * (1.0f - handOver) : wb[3][b] + handOver * (1.0f - wb[3][b]);
      }
      for (int c = 0; c < 3; ++c)
      {
        const std::size_t i = 3 * p + c;
        images.Shown[i] = std::max(denoised[i] + out[1] * s.Residual3[3 * o + c] +
            out[2] * s.Residual7[3 * o + c] + out[3] * (mean[i] - denoised[i]),
          0.0f); // the residual boxes can undershoot next to a dark pixel
      }
      if (alpha)
      {
        const float d = images.DenoisedAlpha[p];
        const float a =
          d + out[1] * s.Alpha3[o] + out[2] * s.Alpha7[o] + out[3] * (images.Alpha[p] - d);
        images.ShownAlpha[p] = std::min(std::max(a, 0.0f), 1.0f);
      }
      if (rho)
      {
        this->Rho[p] = out[3] + out[1] / 9.0f + out[2] / 49.0f;
      }
    }
  }
}
}
