#include "ptvFeatures.h"

#include "ptvPassBuffers.h"

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
}

//------------------------------------------------------------------------------
bool IsFeatureChannel(const std::string& name)
{
  Channel c;
  return Parse(name, c);
}

//------------------------------------------------------------------------------
bool BuildFeatures(const float* const* passes, int width, int height,
  const std::vector<std::string>& channels, float* out, std::string& error)
{
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  std::vector<Channel> parsed(channels.size());
  for (std::size_t i = 0; i < channels.size(); ++i)
  {
    if (!Parse(channels[i], parsed[i]))
    {
      error = "unknown feature channel '" + channels[i] + "'";
      return false;
    }
    const Channel& c = parsed[i];
    if (!passes[c.Pass] || (c.MaskPass >= 0 && !passes[c.MaskPass]))
    {
      error = "feature channel '" + channels[i] + "' needs pass '" +
        GetPassInfo(passes[c.Pass] ? c.MaskPass : c.Pass).Name + "', which is missing";
      return false;
    }
  }

  // Hit masks per depth pass: d < 0.999 * max(d) (features.py: hit_mask).
  std::vector<unsigned char> hits[PassCount];
  auto mask = [&](int depthPass) -> const std::vector<unsigned char>&
  {
    std::vector<unsigned char>& m = hits[depthPass];
    if (m.empty())
    {
      const float* d = passes[depthPass];
      const float far = n ? *std::max_element(d, d + n) : 0.0f;
      const float limit = 0.999f * far;
      m.resize(n);
      for (std::size_t k = 0; k < n; ++k)
      {
        m[k] = d[k] < limit ? 1 : 0;
      }
    }
    return m;
  };

  const float gamma = 1.0f / 2.2f;
  for (std::size_t ci = 0; ci < parsed.size(); ++ci)
  {
    const Channel& c = parsed[ci];
    const int comps = GetPassInfo(c.Pass).Components;
    const float* src = passes[c.Pass];
    float* plane = out + ci * n;
    auto value = [&](std::size_t k) { return src[k * comps + c.Component]; };
    switch (c.What)
    {
      case Kind::Color:
        for (std::size_t k = 0; k < n; ++k)
        {
          plane[k] = Clip01(std::pow(std::max(value(k), 0.0f), gamma));
        }
        break;
      case Kind::Alpha:
      case Kind::Albedo:
        for (std::size_t k = 0; k < n; ++k)
        {
          plane[k] = Clip01(value(k));
        }
        break;
      case Kind::Normal:
        for (std::size_t k = 0; k < n; ++k)
        {
          plane[k] = Clip01((value(k) + 1.0f) * 0.5f);
        }
        break;
      case Kind::Depth:
      case Kind::Position:
      {
        const std::vector<unsigned char>& m = mask(c.MaskPass);
        const float miss = c.What == Kind::Depth ? 1.0f : 0.0f;
        float lo = 0.0f, hi = 0.0f;
        bool any = false;
        for (std::size_t k = 0; k < n; ++k)
        {
          if (m[k])
          {
            const float v = value(k);
            lo = any ? std::min(lo, v) : v;
            hi = any ? std::max(hi, v) : v;
            any = true;
          }
        }
        const float range = hi - lo;
        for (std::size_t k = 0; k < n; ++k)
        {
          if (!m[k])
          {
            plane[k] = miss;
          }
          else
          {
            plane[k] = range > 0.0f ? Clip01((value(k) - lo) / range) : 0.0f;
          }
        }
        break;
      }
    }
  }
  return true;
}
}
