#include "ptvFeatures.h"

#include "ptvFeatureRows.h"
#include "ptvPassBuffers.h"

#include "ptvThreads.h"

#include "vtkType.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

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
  Position,
  History
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
  else if (name == "coverage") // the camera ray's opacity: clipped like alpha
  {
    return (c = { Kind::Alpha, PassCoverage, -1, 0 }), true;
  }
  else if (name == "history")
  {
    return (c = { Kind::History, PassHistoryLength, -1, 0 }), true;
  }
  else
  {
    return false;
  }
  return c.Component >= 0;
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

/// The feature values of full-resolution row @a y of channel @a c into @a dst (W floats), by the
/// vectorised row kernel (ptvFeatureRows.cxx).
void TransformRow(const Channel& c, const ChannelRange& r, const float* const* passes, int y,
  int width, bool portable, float* dst)
{
  if (!passes[c.Pass]) // only History may lack its pass (Build): one frame everywhere
  {
    std::fill(dst, dst + width, 1.0f);
    return;
  }
  const int comps = GetPassInfo(c.Pass).Components;
  const std::size_t row = static_cast<std::size_t>(y) * static_cast<std::size_t>(width);
  FeatureRowInput in;
  in.Row = passes[c.Pass] + row * comps;
  in.Components = comps;
  in.Component = c.Component;
  in.Width = width;
  switch (c.What)
  {
    case Kind::Color:
      in.Transform = FeatureTransform::Gamma;
      break;
    case Kind::Alpha:
    case Kind::Albedo:
      in.Transform = FeatureTransform::Clip;
      break;
    case Kind::Normal:
      in.Transform = FeatureTransform::Normal;
      break;
    case Kind::History:
      in.Transform = FeatureTransform::Inverse;
      break;
    case Kind::Depth:
    case Kind::Position:
      in.Transform = FeatureTransform::Range;
      in.Mask = r.MaskDepth + row;
      in.HitLimit = r.HitLimit;
      in.Low = r.Low;
      in.Range = r.Range;
      in.Miss = r.Miss;
      break;
  }
  FeatureRow(in, dst, portable);
}

/**
 * out[j] (+)= line[s j] + ... + line[s j + s - 1] (indices clamped to the row), summed in that
 * order; @a first: out[j] starts from 0. Rows of a block added in order, then divided by s^2,
 * give the box average the network's input is defined with (guidenet.py).
 */
void AccumulateRow(const float* line, int s, int width, bool first, bool portable, float* out)
{
  const int reduced = ReducedSize(width, s);
  int j = 0;
  if (s == 2) // the shipped model's stride: pairs without index clamps (vectorised)
  {
    j = width / 2;
    AccumulatePairs(line, static_cast<std::size_t>(j), first, out, portable);
  }
  for (; j < reduced; ++j)
  {
    float sum = first ? 0.f : out[j];
    for (int dx = 0; dx < s; ++dx)
    {
      sum += line[std::min(s * j + dx, width - 1)];
    }
    out[j] = sum;
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
  if (!this->Prepare(passes, width, height, channels, stride, threads, error))
  {
    return false;
  }
  this->Rows(0, ReducedSize(height, this->Stride), threads, portable, out);
  return true;
}

//------------------------------------------------------------------------------
bool FeatureBuilder::Prepare(const float* const* passes, int width, int height,
  const std::vector<std::string>& channels, int stride, int threads, std::string& error)
{
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  const int s = stride < 1 ? 1 : stride;
  this->Width = width;
  this->Height = height;
  this->Stride = s;
  this->Passes.assign(passes, passes + PassCount);
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
    if (c.What == Kind::History && !passes[c.Pass])
    {
      continue; // no HistoryLength: every pixel's mean is one frame (the feature's value 1)
    }
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

  // Per channel: the hit limit of its depth pass (d < 0.999 max d, features.py: hit_mask) and
  // the min / max of its values over the hits; per-row reductions, then rows in order.
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
    ParallelFor(threads, 0, height, 32,
      [&](vtkIdType y0, vtkIdType y1)
      {
        for (vtkIdType y = y0; y < y1; ++y)
        {
          const float* d = depth + static_cast<std::size_t>(y) * width;
          float far = d[0];
          for (int x = 1; x < width; ++x) // branch-free: vectorisable
          {
            far = d[x] > far ? d[x] : far;
          }
          this->RowFar[y] = far;
        }
      });
    const float far = *std::max_element(this->RowFar.begin(), this->RowFar.end());
    r.HitLimit = kHitFraction * far; // IsHit(d, far), evaluated once
    const int comps = GetPassInfo(c.Pass).Components;
    const float* src = passes[c.Pass];
    ParallelFor(threads, 0, height, 32,
      [&](vtkIdType y0, vtkIdType y1)
      {
        for (vtkIdType y = y0; y < y1; ++y)
        {
          // min / max over the row's hits, branch-free (no hit: lo > hi)
          float lo = std::numeric_limits<float>::infinity();
          float hi = -std::numeric_limits<float>::infinity();
          for (std::size_t k = static_cast<std::size_t>(y) * width,
                           end = k + static_cast<std::size_t>(width);
               k < end; ++k)
          {
            const float v = src[k * comps + c.Component];
            const bool hit = depth[k] < r.HitLimit;
            lo = hit && v < lo ? v : lo;
            hi = hit && v > hi ? v : hi;
          }
          this->RowLow[y] = lo;
          this->RowHigh[y] = hi;
          this->RowAny[y] = lo <= hi ? 1 : 0;
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
  return true;
}

//------------------------------------------------------------------------------
void FeatureBuilder::Rows(int first, int last, int threads, bool portable, float* out)
{
  const int width = this->Width;
  const int height = this->Height;
  const int s = this->Stride;
  const float* const* passes = this->Passes.data();
  const int reducedW = ReducedSize(width, s);
  const int rows = last - first;
  if (rows <= 0 || width <= 0 || height <= 0)
  {
    return;
  }
  const std::size_t plane = static_cast<std::size_t>(reducedW) * static_cast<std::size_t>(rows);
  const int blocks = std::min(ResolvedThreads(threads), rows);
  this->Scratch.resize(static_cast<std::size_t>(blocks) * static_cast<std::size_t>(width));

  // The features, pooled to the network's resolution; fixed blocks of its rows, each with
  // a scratch row: each channel's full-resolution rows are transformed there (the colour's
  // power law vectorised, ptvFeatureRows.cxx), then pooled.
  ParallelFor(threads, 0, blocks, 1,
    [&](vtkIdType b0, vtkIdType b1)
    {
      for (vtkIdType b = b0; b < b1; ++b)
      {
        float* scratch = this->Scratch.data() + static_cast<std::size_t>(b) * width;
        const vtkIdType begin = first + static_cast<vtkIdType>(rows) * b / blocks;
        const vtkIdType end = first + static_cast<vtkIdType>(rows) * (b + 1) / blocks;
        for (vtkIdType i = begin; i < end; ++i)
        {
          const int ii = static_cast<int>(i);
          for (std::size_t ci = 0; ci < this->Plans.size(); ++ci)
          {
            const Plan& plan = this->Plans[ci];
            float* row = out + ci * plane + static_cast<std::size_t>(i - first) * reducedW;
            if (s == 1)
            {
              TransformRow(plan.Source, plan.Range, passes, ii, width, portable, row);
              continue;
            }
            for (int dy = 0; dy < s; ++dy)
            {
              TransformRow(plan.Source, plan.Range, passes, std::min(s * ii + dy, height - 1),
                width, portable, scratch);
              AccumulateRow(scratch, s, width, dy == 0, portable, row);
            }
            const float area = static_cast<float>(s * s);
            if ((s & (s - 1)) == 0) // a power of two: its reciprocal's product is the division
            {
              const float inverseArea = 1.0f / area;
              for (int j = 0; j < reducedW; ++j)
              {
                row[j] = row[j] * inverseArea;
              }
            }
            else
            {
              for (int j = 0; j < reducedW; ++j)
              {
                row[j] = row[j] / area;
              }
            }
          }
        }
      }
    });
}
}
