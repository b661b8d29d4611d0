#include "ptvFeatures.h"

#include "ptvFeatureRows.h"
#include "ptvPassBuffers.h"

#include "ptvThreads.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace ptv
{
namespace
{
enum class Kind
{
  Color,
  Alpha,
  Albedo,
  Normal,
  Depth,
  Position
};

struct Channel
{
  Kind What;
  int Pass;     // source pass
  int MaskPass; // depth pass whose hits matter (-1: none)
  int Component;
};

bool Parse(const std::string& name, Channel& c)
{
  const std::size_t dot = name.find('.');
  const std::string group = name.substr(0, dot);
  const std::string suffix = dot == std::string::npos ? "" : name.substr(dot + 1);
  auto component = [&](const char* letters) -> int
  {
    if (suffix.size() != 1)
    {
      return -1;
    }
    for (int i = 0; i < 3; ++i)
    {
      if (suffix[0] == letters[i])
      {
        return i;
      }
    }
    return -1;
  };
  if (group == "color")
  {
    c = { Kind::Color, PassRadiance, -1, component("rgb") };
  }
  else if (group == "albedo")
  {
    c = { Kind::Albedo, PassAlbedo, -1, component("rgb") };
  }
  else if (group == "normal")
  {
    c = { Kind::Normal, PassNormal, -1, component("xyz") };
  }
  else if (group == "scatter_normal")
  {
    c = { Kind::Normal, PassScatterNormal, -1, component("xyz") };
  }
  else if (group == "position")
  {
    c = { Kind::Position, PassPosition, PassDepth, component("xyz") };
  }
  else if (group == "scatter_position")
  {
    c = { Kind::Position, PassScatterPosition, PassScatterDepth, component("xyz") };
  }
  else if (name == "depth")
  {
    return (c = { Kind::Depth, PassDepth, PassDepth, 0 }), true;
  }
  else if (name == "scatter_depth")
  {
    return (c = { Kind::Depth, PassScatterDepth, PassScatterDepth, 0 }), true;
  }
  else if (name == "alpha")
  {
    return (c = { Kind::Alpha, PassAlpha, -1, 0 }), true;
  }
  else
  {
    return false;
  }
  return c.Component >= 0;
}

float Clip01(float v)
{
  return std::min(1.0f, std::max(0.0f, v));
}

/// What one channel needs besides its pass: the hit test and normalisation of depth/position.
struct ChannelRange
{
  const float* MaskDepth = nullptr; ///< depth pass of the hit test (nullptr: no test)
  float HitLimit = 0.f;             ///< hit: depth < 0.999 * far
  float Low = 0.f;                  ///< min over hits
  float Range = 0.f;                ///< max - min over hits
  float Miss = 0.f;                 ///< value of a miss
};

/**
 * out[j] for j < ceil(W / s): the mean of f over the s x s block of low-resolution pixel (i, j),
 * pixel indices clamped to the image (s = 1: out[j] = f(i W + j)).
 */
template <class F>
void PoolRow(const F& f, int i, int s, int width, int height, float* out)
{
  const std::size_t w = static_cast<std::size_t>(width);
  if (s == 1)
  {
    const std::size_t row = static_cast<std::size_t>(i) * w;
    for (std::size_t j = 0; j < w; ++j)
    {
      out[j] = f(row + j);
    }
    return;
  }
  const int reduced = ReducedSize(width, s);
  const float area = static_cast<float>(s * s);
  for (int j = 0; j < reduced; ++j)
  {
    float sum = 0.f;
    for (int dy = 0; dy < s; ++dy)
    {
      const std::size_t row = static_cast<std::size_t>(std::min(s * i + dy, height - 1)) * w;
      for (int dx = 0; dx < s; ++dx)
      {
        sum += f(row + static_cast<std::size_t>(std::min(s * j + dx, width - 1)));
      }
    }
    out[j] = sum / area;
  }
}

/**
 * The pooled colour feature of low-resolution row @a i: each full-resolution row of its block is
 * copied to @a scratch (W floats), put through the power law at once, and summed in the order of
 * PoolRow (rows, then columns of each block), then divided by the block's area.
 */
void GammaPooledRow(const float* src, int comps, int i, int s, int width, int height,
  bool portable, float* scratch, float* out)
{
  const int reduced = ReducedSize(width, s);
  const std::size_t w = static_cast<std::size_t>(width);
  for (int dy = 0; dy < s; ++dy)
  {
    const float* line = src + static_cast<std::size_t>(std::min(s * i + dy, height - 1)) * w * comps;
    for (std::size_t x = 0; x < w; ++x)
    {
      scratch[x] = line[x * comps];
    }
    GammaInPlace(scratch, w, portable);
    if (s == 1)
    {
      std::copy(scratch, scratch + w, out);
      return;
    }
    for (int j = 0; j < reduced; ++j)
    {
      float sum = dy == 0 ? 0.f : out[j];
      for (int dx = 0; dx < s; ++dx)
      {
        sum += scratch[std::min(s * j + dx, width - 1)];
      }
      out[j] = sum;
    }
  }
  const float area = static_cast<float>(s * s);
  for (int j = 0; j < reduced; ++j)
  {
    out[j] = out[j] / area;
  }
}
}

//------------------------------------------------------------------------------
bool IsFeatureChannel(const std::string& name)
{
  Channel c;
  return Parse(name, c);
}

//------------------------------------------------------------------------------
struct FeatureBuilder::Plan
{
  Channel Source;
  ChannelRange Range;
};

FeatureBuilder::FeatureBuilder() = default;
FeatureBuilder::~FeatureBuilder() = default;

//------------------------------------------------------------------------------
bool FeatureBuilder::Build(const float* const* passes, int width, int height,
  const std::vector<std::string>& channels, int stride, int threads, bool portable, float* out,
  std::string& error)
{
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  const int s = stride < 1 ? 1 : stride;
  this->Plans.resize(channels.size()); // kept between frames: no allocation
  for (std::size_t i = 0; i < channels.size(); ++i)
  {
    this->Plans[i] = Plan{};
    if (!Parse(channels[i], this->Plans[i].Source))
    {
      error = "unknown feature channel '" + channels[i] + "'";
      return false;
    }
    const Channel& c = this->Plans[i].Source;
    if (!passes[c.Pass] || (c.MaskPass >= 0 && !passes[c.MaskPass]))
    {
      error = "feature channel '" + channels[i] + "' needs pass '" +
        GetPassInfo(passes[c.Pass] ? c.MaskPass : c.Pass).Name + "', which is missing";
      return false;
    }
  }
  if (n == 0)
  {
    return true;
  }
  this->RowLow.resize(static_cast<std::size_t>(height));
  this->RowHigh.resize(static_cast<std::size_t>(height));
  this->RowFar.resize(static_cast<std::size_t>(height));
  this->RowAny.resize(static_cast<std::size_t>(height));
  const int blocks = ResolvedThreads(threads);
  this->Scratch.resize(static_cast<std::size_t>(blocks) * static_cast<std::size_t>(width));

  // Per channel: the hit limit of its depth pass (d < 0.999 max d, features.py: hit_mask) and
  // the min / max of its values over the hits; per-row reductions, then rows in order.
  const int reducedW = ReducedSize(width, s);
  const int reducedH = ReducedSize(height, s);
  const std::size_t plane = static_cast<std::size_t>(reducedW) * reducedH;
  WithThreads(threads,
    [&]()
    {
      for (Plan& plan : this->Plans)
      {
        const Channel& c = plan.Source;
        if (c.What != Kind::Depth && c.What != Kind::Position)
        {
          continue;
        }
        ChannelRange& r = plan.Range;
        r.Miss = c.What == Kind::Depth ? 1.0f : 0.0f;
        r.MaskDepth = passes[c.MaskPass];
        const float* depth = r.MaskDepth;
        vtkSMPTools::For(0, height, 32,
          [&](vtkIdType y0, vtkIdType y1)
          {
            for (vtkIdType y = y0; y < y1; ++y)
            {
              const float* d = depth + static_cast<std::size_t>(y) * width;
              this->RowFar[y] = *std::max_element(d, d + width);
            }
          });
        const float far = *std::max_element(this->RowFar.begin(), this->RowFar.end());
        r.HitLimit = 0.999f * far;
        const int comps = GetPassInfo(c.Pass).Components;
        const float* src = passes[c.Pass];
        vtkSMPTools::For(0, height, 32,
          [&](vtkIdType y0, vtkIdType y1)
          {
            for (vtkIdType y = y0; y < y1; ++y)
            {
              float lo = 0.f, hi = 0.f;
              bool any = false;
              for (std::size_t k = static_cast<std::size_t>(y) * width,
                               end = k + static_cast<std::size_t>(width);
                   k < end; ++k)
              {
                if (depth[k] < r.HitLimit)
                {
                  const float v = src[k * comps + c.Component];
                  lo = any ? std::min(lo, v) : v;
                  hi = any ? std::max(hi, v) : v;
                  any = true;
                }
              }
              this->RowLow[y] = lo;
              this->RowHigh[y] = hi;
              this->RowAny[y] = any ? 1 : 0;
            }
          });
        bool any = false;
        float lo = 0.f, hi = 0.f;
        for (int y = 0; y < height; ++y)
        {
          if (this->RowAny[y])
          {
            lo = any ? std::min(lo, this->RowLow[y]) : this->RowLow[y];
            hi = any ? std::max(hi, this->RowHigh[y]) : this->RowHigh[y];
            any = true;
          }
        }
        r.Low = lo;
        r.Range = hi - lo;
      }

      // The features, pooled to the network's resolution; fixed blocks of its rows, each with
      // a scratch row for the colour's power law (vectorised, ptvFeatureRows.cxx).
      vtkSMPTools::For(0, blocks, 1,
        [&](vtkIdType b0, vtkIdType b1)
        {
          for (vtkIdType b = b0; b < b1; ++b)
          {
            float* scratch = this->Scratch.data() + static_cast<std::size_t>(b) * width;
            const vtkIdType first = reducedH * b / blocks;
            const vtkIdType last = reducedH * (b + 1) / blocks;
            for (vtkIdType i = first; i < last; ++i)
            {
              for (std::size_t ci = 0; ci < this->Plans.size(); ++ci)
              {
                const Channel& c = this->Plans[ci].Source;
                const int comps = GetPassInfo(c.Pass).Components;
                const float* src = passes[c.Pass] + c.Component;
                float* row = out + ci * plane + static_cast<std::size_t>(i) * reducedW;
                const int ii = static_cast<int>(i);
                switch (c.What)
                {
                  case Kind::Color:
                    GammaPooledRow(src, comps, ii, s, width, height, portable, scratch, row);
                    break;
                  case Kind::Alpha:
                  case Kind::Albedo:
                    PoolRow([&](std::size_t k) { return Clip01(src[k * comps]); }, ii, s, width,
                      height, row);
                    break;
                  case Kind::Normal:
                    PoolRow([&](std::size_t k) { return Clip01((src[k * comps] + 1.0f) * 0.5f); },
                      ii, s, width, height, row);
                    break;
                  case Kind::Depth:
                  case Kind::Position:
                  {
                    const ChannelRange& r = this->Plans[ci].Range;
                    PoolRow(
                      [&](std::size_t k)
                      {
                        if (!(r.MaskDepth[k] < r.HitLimit))
                        {
                          return r.Miss;
                        }
                        return r.Range > 0.0f ? Clip01((src[k * comps] - r.Low) / r.Range) : 0.0f;
                      },
                      ii, s, width, height, row);
                    break;
                  }
                }
              }
            }
          }
        });
    });
  return true;
}
}
