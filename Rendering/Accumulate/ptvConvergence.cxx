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
