// Unit tests of ptvFeatures and ptvGuideNetSession (issue #60).
// FeatureBuilder against the formulas of Training/ptv_training/features.py (its specification),
// written out here on a 5 x 3 image of random passes with misses:
//  - color: clip(max(0, r)^(1/2.2), 0, 1); alpha, albedo, coverage: clip(x, 0, 1); normal:
//    clip((n + 1) / 2, 0, 1); depth: (d - min) / (max - min) over hits (d < 0.999 x the
//    frame's largest depth), misses 1; position: per axis over the depth hits, misses 0;
//    history: 1 / max(frames, 1), 1 without the pass. Tolerance 1e-5 (float pow and division);
//  - stride 2: each output is the mean of its 2 x 2 block, edges replicated (the same formulas
//    box-averaged, 1e-5);
//  - 1 and 2 threads, and the portable row kernel, agree (1e-6);
//  - made a band of rows at a time (Prepare, then Rows), bit for bit Build's rows, at strides 1
//    and 2 (issue #62: the network's bands never need the whole image's features);
//  - an unknown channel and a missing pass are errors naming the channel.
// GuideNetSession on the shipped model: its metadata (known channels, 2L - 1 outputs or more,
// a stride >= 1) and one run on zero features: finite guides in [0, 1]; run in bands of rows
// (issue #62: a big image's activations), the same output as one run within 1e-6 (the bands
// reach 2 rows beyond themselves, the model's two 3 x 3 convolutions), also with each band's
// features made when the band runs (exactly the rows it asks for: the band and 2 rows either
// side, clipped to the image; bit for bit the bands run on the whole features); a missing file, a text
// file and a run without a model are errors naming the problem.
#include "ptvDataDirectory.h"
#include "ptvFeatures.h"
#include "ptvGuideNetSession.h"
#include "ptvPassBuffers.h"
#include "ptvTestCheck.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace
{
constexpr int W = 5, H = 3;

struct Passes
{
  std::vector<float> Data[ptv::PassCount];
  const float* Pointers[ptv::PassCount] = {};
};

Passes RandomPasses(std::mt19937& rng)
{
  std::uniform_real_distribution<float> u(-0.5f, 1.5f);
  Passes p;
  for (int pass = 0; pass < ptv::PassCount; ++pass)
  {
    p.Data[pass].resize(W * H * ptv::GetPassInfo(pass).Components);
    for (float& v : p.Data[pass])
    {
      v = u(rng);
    }
  }
  // Depth: hits in [2, 6], misses at the far distance 10 (pixels 1 and 7).
  std::uniform_real_distribution<float> depth(2.f, 6.f);
  for (int pass : { ptv::PassDepth, ptv::PassScatterDepth })
  {
    for (float& v : p.Data[pass])
    {
      v = depth(rng);
    }
    p.Data[pass][1] = p.Data[pass][7] = 10.f;
  }
  for (float& v : p.Data[ptv::PassHistoryLength])
  {
    v = std::floor(4.f * (u(rng) + 0.5f)); // 0 to 7 frames
  }
  for (int pass = 0; pass < ptv::PassCount; ++pass)
  {
    p.Pointers[pass] = p.Data[pass].data();
  }
  return p;
}

/// features.py's value of @a channel at pixel @a i (the specification, written out).
float Expected(const Passes& p, const std::string& channel, int i)
{
  auto component = [&](int pass, int c) { return p.Data[pass][3 * i + c]; };
  auto clip = [](float v) { return std::min(1.f, std::max(0.f, v)); };
  auto normalized = [&](int pass, int c, int comps, int maskPass, float miss)
  {
    const std::vector<float>& d = p.Data[maskPass];
    const float far = *std::max_element(d.begin(), d.end());
    float lo = 1e30f, hi = -1e30f;
    for (int k = 0; k < W * H; ++k)
    {
      if (d[k] < 0.999f * far)
      {
        lo = std::min(lo, p.Data[pass][comps * k + c]);
        hi = std::max(hi, p.Data[pass][comps * k + c]);
      }
    }
    if (!(d[i] < 0.999f * far))
    {
      return miss;
    }
    return hi > lo ? clip((p.Data[pass][comps * i + c] - lo) / (hi - lo)) : 0.f;
  };
  const std::size_t dot = channel.find('.');
  const std::string kind = channel.substr(0, dot);
  const int c = dot == std::string::npos ? 0 : static_cast<int>(std::string("xyzrgb").find(
                                                 channel[dot + 1]) % 3);
  if (kind == "color")
  {
    return clip(std::pow(std::max(0.f, component(ptv::PassRadiance, c)), 1.f / 2.2f));
  }
  if (kind == "albedo")
  {
    return clip(component(ptv::PassAlbedo, c));
  }
  if (kind == "normal")
  {
    return clip((component(ptv::PassNormal, c) + 1.f) * 0.5f);
  }
  if (kind == "scatter_normal")
  {
    return clip((component(ptv::PassScatterNormal, c) + 1.f) * 0.5f);
  }
  if (kind == "alpha")
  {
    return clip(p.Data[ptv::PassAlpha][i]);
  }
  if (kind == "coverage")
  {
    return clip(p.Data[ptv::PassCoverage][i]);
  }
  if (kind == "history")
  {
    return 1.f / std::max(p.Data[ptv::PassHistoryLength][i], 1.f);
  }
  if (kind == "depth")
  {
    return normalized(ptv::PassDepth, 0, 1, ptv::PassDepth, 1.f);
  }
  if (kind == "scatter_depth")
  {
    return normalized(ptv::PassScatterDepth, 0, 1, ptv::PassScatterDepth, 1.f);
  }
  if (kind == "position")
  {
    return normalized(ptv::PassPosition, c, 3, ptv::PassDepth, 0.f);
  }
  return normalized(ptv::PassScatterPosition, c, 3, ptv::PassScatterDepth, 0.f);
}

const std::vector<std::string> kChannels = { "color.r", "color.g", "color.b", "alpha",
  "albedo.r", "albedo.b", "normal.x", "normal.z", "depth", "position.x", "position.y",
  "scatter_normal.y", "scatter_depth", "scatter_position.z", "coverage", "history" };

void TestFeatureFormulas(std::mt19937& rng)
{
  const Passes p = RandomPasses(rng);
  ptv::FeatureBuilder builder;
  std::vector<float> out(kChannels.size() * W * H);
  std::string error;
  Check(builder.Build(p.Pointers, W, H, kChannels, 1, 1, false, out.data(), error),
    "Build with every kind of channel (" + error + ")");
  for (std::size_t ch = 0; ch < kChannels.size(); ++ch)
  {
    Check(ptv::IsFeatureChannel(kChannels[ch]), kChannels[ch] + " is a feature channel");
    double worst = 0.0;
    for (int i = 0; i < W * H; ++i)
    {
      worst = std::max(worst,
        static_cast<double>(std::abs(out[ch * W * H + i] - Expected(p, kChannels[ch], i))));
    }
    Check(worst <= 1e-5, kChannels[ch] + " follows features.py (worst " + std::to_string(worst) +
        ")");
  }

  // Stride 2: 3 x 2 planes, each value the mean of its 2 x 2 block (indices clamped).
  const int w2 = ptv::ReducedSize(W, 2), h2 = ptv::ReducedSize(H, 2);
  std::vector<float> coarse(kChannels.size() * w2 * h2);
  Check(builder.Build(p.Pointers, W, H, kChannels, 2, 2, false, coarse.data(), error),
    "Build with stride 2");
  double worstBox = 0.0;
  for (std::size_t ch = 0; ch < kChannels.size(); ++ch)
  {
    for (int y = 0; y < h2; ++y)
    {
      for (int x = 0; x < w2; ++x)
      {
        double mean = 0.0;
        for (int dy = 0; dy < 2; ++dy)
        {
          for (int dx = 0; dx < 2; ++dx)
          {
            const int sx = std::min(2 * x + dx, W - 1), sy = std::min(2 * y + dy, H - 1);
            mean += 0.25 * out[ch * W * H + sy * W + sx];
          }
        }
        worstBox = std::max(worstBox, std::abs(coarse[(ch * h2 + y) * w2 + x] - mean));
      }
    }
  }
  Check(worstBox <= 1e-5, "stride 2 box-averages the features (worst " +
      std::to_string(worstBox) + ")");

  std::vector<float> twoThreads(out.size()), portable(out.size());
  builder.Build(p.Pointers, W, H, kChannels, 1, 2, false, twoThreads.data(), error);
  builder.Build(p.Pointers, W, H, kChannels, 1, 1, true, portable.data(), error);
  double worstParity = 0.0;
  for (std::size_t i = 0; i < out.size(); ++i)
  {
    worstParity = std::max({ worstParity, static_cast<double>(std::abs(out[i] - twoThreads[i])),
      static_cast<double>(std::abs(out[i] - portable[i])) });
  }
  Check(worstParity <= 1e-6, "threads and the portable kernel agree");

  // A band of rows at a time: Build's rows, bit for bit.
  for (const int stride : { 1, 2 })
  {
    const int rows = ptv::ReducedSize(H, stride), cols = ptv::ReducedSize(W, stride);
    std::vector<float> whole(kChannels.size() * rows * cols);
    builder.Build(p.Pointers, W, H, kChannels, stride, 2, false, whole.data(), error);
    Check(builder.Prepare(p.Pointers, W, H, kChannels, stride, 2, error), "Prepare (" + error + ")");
    bool same = true;
    for (int first = 0; first < rows; ++first)
    {
      for (int last = first + 1; last <= rows; ++last)
      {
        const int n = last - first;
        std::vector<float> band(kChannels.size() * n * cols, -7.f);
        builder.Rows(first, last, 2, false, band.data());
        for (std::size_t ch = 0; ch < kChannels.size(); ++ch)
        {
          same = same && std::equal(band.begin() + ch * n * cols, band.begin() + (ch + 1) * n * cols,
                           whole.begin() + (ch * rows + first) * cols);
        }
      }
    }
    Check(same, "stride " + std::to_string(stride) + ": every band of rows is Build's rows");
  }

  const std::vector<std::string> unknown = { "color.r", "sparkle" };
  Check(!builder.Build(p.Pointers, W, H, unknown, 1, 1, false, out.data(), error) &&
      error.find("sparkle") != std::string::npos,
    "an unknown channel is an error naming it (" + error + ")");
  Passes missing = p;
  missing.Pointers[ptv::PassAlbedo] = nullptr;
  const std::vector<std::string> albedo = { "albedo.g" };
  error.clear();
  Check(!builder.Build(missing.Pointers, W, H, albedo, 1, 1, false, out.data(), error) &&
      error.find("albedo") != std::string::npos,
    "a missing pass is an error naming the channel (" + error + ")");
  Passes noHistory = p;
  noHistory.Pointers[ptv::PassHistoryLength] = nullptr;
  const std::vector<std::string> history = { "history" };
  std::vector<float> ones(W * H, 0.f);
  Check(builder.Build(noHistory.Pointers, W, H, history, 1, 1, false, ones.data(), error) &&
      std::all_of(ones.begin(), ones.end(), [](float v) { return v == 1.f; }),
    "history without the pass is one frame everywhere");
}

void TestGuideNetSession(const std::string& temp)
{
  ptv::GuideNetSession session;
  std::string error;
  session.SetNumberOfThreads(1);
  session.SetAllowCuda(false);
  const std::string model = ptv::DefaultModelFile();
  Check(session.Load(model, error) && session.IsLoaded(),
    "the shipped model loads (" + model + ": " + error + ")");
  if (!session.IsLoaded())
  {
    return;
  }
  bool known = session.GetNumberOfInputChannels() > 0;
  for (const std::string& c : session.GetInputChannels())
  {
    known = known && ptv::IsFeatureChannel(c);
  }
  const int levels = session.GetNumberOfLevels();
  Check(known && levels >= 1 && session.GetNumberOfOutputs() >= 2 * levels - 1 &&
      session.GetGuideStride() >= 1 && session.GetDefaultLevels() >= 1 &&
      session.GetDefaultLevels() <= levels && session.GetExecutionProvider() ==
      "CPUExecutionProvider",
    "the model's metadata: known channels, 2L - 1 outputs or more, a stride, the CPU");
  const int h = 6, w = 10;
  std::vector<float> features(session.GetNumberOfInputChannels() * h * w, 0.f);
  std::vector<float> out(session.GetNumberOfOutputs() * h * w, -1.f);
  Check(session.Run(features.data(), h, w, out.data(), error), "a run on zeros (" + error + ")");
  bool guides = true;
  for (int i = 0; i < levels * h * w; ++i)
  {
    guides = guides && std::isfinite(out[i]) && out[i] >= 0.f && out[i] <= 1.f;
  }
  Check(guides, "the guides are finite and in [0, 1]");

  // In bands of rows (what a big image does): the same output as one run.
  Check(session.GetTileHalo() == 2, "the shipped model's two 3x3 convolutions reach 2 rows");
  const int bh = 37, bw = 23;
  std::mt19937 rng(62);
  std::uniform_real_distribution<float> u(-1.f, 2.f);
  std::vector<float> noisy(session.GetNumberOfInputChannels() * bh * bw);
  for (float& f : noisy)
  {
    f = u(rng);
  }
  std::vector<float> whole(session.GetNumberOfOutputs() * bh * bw, -1.f);
  std::vector<float> banded(whole.size(), -2.f);
  const bool ran = session.Run(noisy.data(), bh, bw, whole.data(), error);
  session.SetTilePixels(5 * bw); // bands of 5 rows, the last of 2
  const bool ranBands = session.Run(noisy.data(), bh, bw, banded.data(), error);
  session.SetTilePixels(std::size_t(1) << 17);
  float worst = 0.f;
  for (std::size_t i = 0; i < whole.size(); ++i)
  {
    worst = std::max(worst, std::abs(whole[i] - banded[i]));
  }
  Check(ran && ranBands && worst <= 1e-6f,
    "bands of 5 rows give the whole run's output (largest difference " + std::to_string(worst) +
      ")");
  // The same bands with their features made when each runs: the rows asked for, and the output.
  const int c = session.GetNumberOfInputChannels();
  std::vector<std::pair<int, int>> asked;
  std::vector<float> made(whole.size(), -3.f);
  session.SetTilePixels(5 * bw);
  const bool ranMade = session.Run(
    [&](int first, int last, float* planes)
    {
      asked.emplace_back(first, last);
      const std::size_t band = static_cast<std::size_t>(last - first) * bw;
      for (int k = 0; k < c; ++k)
      {
        const float* from = noisy.data() + static_cast<std::size_t>(k) * bh * bw + first * bw;
        std::copy(from, from + band, planes + k * band);
      }
    },
    bh, bw, made.data(), error);
  session.SetTilePixels(std::size_t(1) << 17);
  bool rowsAsked = asked.size() == 8;
  for (std::size_t b = 0; b < asked.size(); ++b)
  {
    const int t0 = 5 * static_cast<int>(b);
    rowsAsked = rowsAsked && asked[b].first == std::max(t0 - 2, 0) &&
      asked[b].second == std::min(t0 + 5 + 2, bh);
  }
  Check(ranMade && rowsAsked && made == banded,
    "bands whose features are made as they run: 8 bands of the rows they reach, the banded "
    "run's output bit for bit");
  Check(session.RunsInBands(bh, 1 << 13) && !session.RunsInBands(bh, bw),
    "runs in bands above 2^17 network pixels only");

  ptv::GuideNetSession other;
  Check(!other.Load("/nonexistent/guidenet.onnx", error) && !other.IsLoaded() &&
      error.find("/nonexistent/guidenet.onnx") != std::string::npos,
    "a missing file is an error naming it (" + error + ")");
  const std::string text = temp + "/not_a_model.onnx";
  std::ofstream(text) << "not an ONNX model\n";
  Check(!other.Load(text, error) && error.find("not_a_model.onnx") != std::string::npos,
    "a text file is an error naming it");
  Check(!other.Run(features.data(), h, w, out.data(), error) && !error.empty(),
    "a run without a model is an error");
}
}

int TestPTVFeatures(int argc, char* argv[])
{
  std::mt19937 rng(60);
  TestFeatureFormulas(rng);
  TestGuideNetSession(TempDir(argc, argv));
  return TestResult();
}
