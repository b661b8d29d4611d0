#include "ptvGuideNetMetadata.h"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <sstream>

namespace ptv
{
namespace
{
std::string Trim(const std::string& s)
{
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos)
  {
    return std::string();
  }
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

std::vector<std::string> Split(const std::string& s, char sep)
{
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(s);
  while (std::getline(in, part, sep))
  {
    parts.push_back(Trim(part));
  }
  if (!s.empty() && s.back() == sep)
  {
    parts.emplace_back(); // "a,b," has an empty last item
  }
  return parts;
}

/// Strictly parse a positive int; false on anything else.
bool ParsePositive(const std::string& s, int& value)
{
  if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos || s.size() > 9)
  {
    return false;
  }
  value = std::atoi(s.c_str());
  return value > 0;
}
}

//------------------------------------------------------------------------------
std::string Join(const std::vector<std::string>& items, const char* sep)
{
  std::string s;
  for (size_t i = 0; i < items.size(); ++i)
  {
    s += (i ? sep : "") + items[i];
  }
  return s;
}

//------------------------------------------------------------------------------
GuideNetMetadata ReadGuideNetMetadata(
  const MetadataLookup& lookup, std::vector<std::string>& problems)
{
  GuideNetMetadata meta;
  std::string value;
  if (!lookup(kFormatKey, value))
  {
    problems.push_back(std::string("metadata ") + kFormatKey + " is missing (expected \"" +
      kFormatValue + "\"; export with Training/ptv_training/export_onnx.py)");
  }
  else if (value == kImageFormatValue)
  {
    meta.Image = true;
  }
  else if (value != kFormatValue)
  {
    problems.push_back(std::string("metadata ") + kFormatKey + " is \"" + value +
      "\", expected \"" + kFormatValue + "\" (or \"" + kImageFormatValue + "\")");
  }
  if (!lookup(kChannelsKey, value))
  {
    problems.push_back(std::string("metadata ") + kChannelsKey + " is missing");
  }
  else
  {
    meta.Channels = Split(value, ',');
    meta.HaveChannels = !meta.Channels.empty() &&
      std::find(meta.Channels.begin(), meta.Channels.end(), std::string()) == meta.Channels.end();
    if (!meta.HaveChannels)
    {
      problems.push_back(std::string("metadata ") + kChannelsKey + " \"" + value +
        "\" is not a comma-separated list of non-empty channel names");
    }
  }
  if (meta.Image)
  {
    // Image-to-image models output the denoised radiance: no grid levels.
  }
  else if (!lookup(kLevelsKey, value))
  {
    problems.push_back(std::string("metadata ") + kLevelsKey + " is missing");
  }
  else
  {
    meta.HaveLevels = true;
    for (const auto& item : Split(value, ','))
    {
      const auto colon = item.find(':');
      int ss = 0;
      int sr = 0;
      if (colon == std::string::npos || !ParsePositive(Trim(item.substr(0, colon)), ss) ||
        !ParsePositive(Trim(item.substr(colon + 1)), sr))
      {
        meta.HaveLevels = false;
        break;
      }
      meta.Levels.emplace_back(ss, sr);
    }
    if (!meta.HaveLevels || meta.Levels.empty())
    {
      meta.HaveLevels = false;
      problems.push_back(std::string("metadata ") + kLevelsKey + " \"" + value +
        "\" is not a list like \"4:4,8:8,16:16\" (spatial step:range step per level)");
    }
  }
  if (lookup(kGuideScaleKey, value))
  {
    char* end = nullptr;
    errno = 0;
    meta.GuideScale = std::strtod(value.c_str(), &end);
    if (value.empty() || *end != '\0' || errno || !(meta.GuideScale > 0.0))
    {
      problems.push_back(std::string("metadata ") + kGuideScaleKey + " \"" + value +
        "\" is not a positive number");
    }
  }

  if (lookup(kGuideStrideKey, value))
  {
    if (!ParsePositive(Trim(value), meta.GuideStride) || meta.GuideStride > kMaxGuideStride)
    {
      problems.push_back(std::string("metadata ") + kGuideStrideKey + " \"" + value +
        "\" is not an integer from 1 to " + std::to_string(kMaxGuideStride));
      meta.GuideStride = 1;
    }
  }

  if (lookup(kDefaultLevelsKey, value))
  {
    // Checked against the level count once "ptv.levels" is known (below).
    if (meta.Image || !ParsePositive(Trim(value), meta.DefaultLevels))
    {
      problems.push_back(std::string("metadata ") + kDefaultLevelsKey + " \"" + value + "\" " +
        (meta.Image ? "is only for guidenet-v1 models" : "is not a positive integer"));
      meta.DefaultLevels = 0;
    }
  }

  if (meta.HaveLevels && meta.DefaultLevels > static_cast<int>(meta.Levels.size()))
  {
    problems.push_back(std::string("metadata ") + kDefaultLevelsKey + " \"" +
      std::to_string(meta.DefaultLevels) + "\" is above the model's " +
      std::to_string(meta.Levels.size()) + " levels");
    meta.DefaultLevels = 0;
  }

  if (meta.Image && meta.GuideStride != 1)
  {
    problems.push_back(std::string("metadata ") + kGuideStrideKey +
      " is only for guidenet-v1 models, an image model runs at full resolution");
  }

  if (lookup(kDemodulateKey, value))
  {
    if (value == "0" || value == "1")
    {
      meta.Demodulate = value == "1";
    }
    else
    {
      problems.push_back(std::string("metadata ") + kDemodulateKey + " \"" + value +
        "\" is not 0 or 1");
    }
  }
  if (lookup(kOutputsKey, value))
  {
    const std::vector<std::string> names = Split(value, ',');
    for (auto it = names.rbegin(); it != names.rend() && it->rfind("pad", 0) == 0; ++it)
    {
      ++meta.OutputPadding;
    }
  }
  return meta;
}
}
