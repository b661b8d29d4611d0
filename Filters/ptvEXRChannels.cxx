#include "ptvEXRChannels.h"

#include <algorithm>
#include <cstdlib>
#include <map>
#include <set>
#include <tuple>

namespace ptv
{
namespace
{

struct KnownPass
{
  const char* Name;
  std::vector<std::string> Channels;
};

// The conventional channels of the mapper's passes (see the header).
const std::vector<KnownPass>& KnownPasses()
{
  static const std::vector<KnownPass> known = {
    { "Radiance", { "R", "G", "B" } },
    { "Alpha", { "A" } },
    { "Albedo", { "albedo.R", "albedo.G", "albedo.B" } },
    { "Depth", { "Z" } },
    { "Position", { "P.X", "P.Y", "P.Z" } },
    { "Normal", { "N.X", "N.Y", "N.Z" } },
    { "ScatterDepth", { "scatter.Z" } },
    { "ScatterPosition", { "scatter.P.X", "scatter.P.Y", "scatter.P.Z" } },
    { "ScatterNormal", { "scatter.N.X", "scatter.N.Y", "scatter.N.Z" } },
    { "Coverage", { "coverage.A" } },
    { "Footprint", { "footprint.A" } },
    { "Denoised", { "denoised.R", "denoised.G", "denoised.B" } },
  };
  return known;
}

std::vector<std::string> Split(const std::string& text, char separator)
{
  std::vector<std::string> parts;
  std::string::size_type start = 0;
  while (true)
  {
    const std::string::size_type end = text.find(separator, start);
    parts.push_back(text.substr(start, end == std::string::npos ? std::string::npos : end - start));
    if (end == std::string::npos)
    {
      return parts;
    }
    start = end + 1;
  }
}

// Sort key of a channel suffix: colour/axis letters, then numbers, then anything else.
std::tuple<int, long, std::string> SuffixKey(const std::string& suffix)
{
  static const std::string letters = "RGBA";
  static const std::string axes = "XYZ";
  if (suffix.size() == 1 && letters.find(suffix[0]) != std::string::npos)
  {
    return std::make_tuple(0, static_cast<long>(letters.find(suffix[0])), suffix);
  }
  if (suffix.size() == 1 && axes.find(suffix[0]) != std::string::npos)
  {
    return std::make_tuple(0, static_cast<long>(axes.find(suffix[0])), suffix);
  }
  if (!suffix.empty() && suffix.size() < 10 &&
    std::all_of(suffix.begin(), suffix.end(), [](char c) { return c >= '0' && c <= '9'; }))
  {
    return std::make_tuple(1, std::strtol(suffix.c_str(), nullptr, 10), suffix);
  }
  return std::make_tuple(2, 0L, suffix);
}

} // namespace

//------------------------------------------------------------------------------
std::vector<std::string> EXRChannelsForPass(const std::string& name, int components)
{
  for (const KnownPass& known : KnownPasses())
  {
    if (name == known.Name && static_cast<int>(known.Channels.size()) == components)
    {
      return known.Channels;
    }
  }
  std::vector<std::string> channels;
  if (components == 1)
  {
    channels.push_back(name + ".Y");
  }
  else if (components == 3 || components == 4)
  {
    for (int c = 0; c < components; ++c)
    {
      channels.push_back(name + "." + "RGBA"[c]);
    }
  }
  else
  {
    for (int c = 0; c < components; ++c)
    {
      channels.push_back(name + "." + std::to_string(c));
    }
  }
  return channels;
}

//------------------------------------------------------------------------------
std::string FormatEXRPassLayout(const std::vector<EXRPassLayout>& passes)
{
  std::string text;
  for (const EXRPassLayout& pass : passes)
  {
    if (!text.empty())
    {
      text += ';';
    }
    text += pass.Name + '=';
    for (size_t c = 0; c < pass.Channels.size(); ++c)
    {
      text += (c ? "," : "") + pass.Channels[c];
    }
  }
  return text;
}

//------------------------------------------------------------------------------
bool ParseEXRPassLayout(const std::string& text, const std::vector<std::string>& available,
  std::vector<EXRPassLayout>& passes)
{
  passes.clear();
  const std::set<std::string> have(available.begin(), available.end());
  std::set<std::string> used;
  for (const std::string& entry : Split(text, ';'))
  {
    const std::string::size_type eq = entry.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 >= entry.size())
    {
      passes.clear();
      return false;
    }
    EXRPassLayout pass;
    pass.Name = entry.substr(0, eq);
    pass.Channels = Split(entry.substr(eq + 1), ',');
    for (const std::string& channel : pass.Channels)
    {
      if (!have.count(channel) || !used.insert(channel).second)
      {
        passes.clear();
        return false;
      }
    }
    passes.push_back(pass);
  }
  return !passes.empty();
}

//------------------------------------------------------------------------------
std::vector<EXRPassLayout> GroupEXRChannels(const std::vector<std::string>& channels)
{
  std::set<std::string> left(channels.begin(), channels.end());
  std::vector<EXRPassLayout> passes;
  auto take = [&left](const std::vector<std::string>& wanted) {
    for (const std::string& c : wanted)
    {
      if (!left.count(c))
      {
        return false;
      }
    }
    for (const std::string& c : wanted)
    {
      left.erase(c);
    }
    return true;
  };
  for (const KnownPass& known : KnownPasses())
  {
    if (take(known.Channels))
    {
      passes.push_back({ known.Name, known.Channels });
    }
    else if (std::string(known.Name) == "Alpha" && take({ "alpha.A" }))
    {
      passes.push_back({ known.Name, { "alpha.A" } });
    }
  }
  // The rest by prefix; a channel without '.' is a pass of its own.
  std::map<std::string, std::vector<std::string>> groups;
  for (const std::string& c : left)
  {
    const std::string::size_type dot = c.rfind('.');
    groups[dot == std::string::npos ? c : c.substr(0, dot)].push_back(c);
  }
  for (auto& group : groups)
  {
    std::vector<std::string>& members = group.second;
    std::sort(members.begin(), members.end(), [](const std::string& a, const std::string& b) {
      const std::string::size_type da = a.rfind('.');
      const std::string::size_type db = b.rfind('.');
      return SuffixKey(da == std::string::npos ? a : a.substr(da + 1)) <
        SuffixKey(db == std::string::npos ? b : b.substr(db + 1));
    });
    passes.push_back({ group.first, members });
  }
  return passes;
}

} // namespace ptv
