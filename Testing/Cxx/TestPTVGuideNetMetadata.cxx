// ptvGuideNetMetadata: a model's metadata read and checked without ONNX Runtime -- the shipped
// model's keys give its settings and no problem; each malformed or inconsistent key is one
// problem naming the key and its value, with the setting left at its default.
#include "ptvGuideNetMetadata.h"
#include "ptvTestCheck.h"

#include <map>
#include <string>
#include <vector>

namespace
{
using Keys = std::map<std::string, std::string>;

ptv::GuideNetMetadata Read(const Keys& keys, std::vector<std::string>& problems)
{
  problems.clear();
  return ptv::ReadGuideNetMetadata(
    [&keys](const char* key, std::string& value)
    {
      const auto it = keys.find(key);
      if (it == keys.end())
      {
        return false;
      }
      value = it->second;
      return true;
    },
    problems);
}

bool Mentions(const std::vector<std::string>& problems, const std::string& text)
{
  for (const auto& p : problems)
  {
    if (p.find(text) != std::string::npos)
    {
      return true;
    }
  }
  return false;
}

Keys Shipped()
{
  return { { "ptv.format", "guidenet-v1" }, { "ptv.input_channels", "albedo.r, albedo.g,depth" },
    { "ptv.levels", "4:4, 8:8,16:16" }, { "ptv.guide_scale", "255" },
    { "ptv.guide_stride", "2" }, { "ptv.default_levels", "1" }, { "ptv.demodulate", "0" },
    { "ptv.outputs", "g1,g2,g3,w1,w2,pad0,pad1,pad2" } };
}
}

int TestPTVGuideNetMetadata(int, char*[])
{
  std::vector<std::string> problems;

  const ptv::GuideNetMetadata ok = Read(Shipped(), problems);
  Check(problems.empty(), "the shipped model's keys give no problem");
  Check(!ok.Image && ok.HaveChannels && ok.HaveLevels, "a guidenet-v1 model with channels, levels");
  Check((ok.Channels == std::vector<std::string>{ "albedo.r", "albedo.g", "depth" }),
    "channels are split at commas and trimmed");
  Check((ok.Levels == std::vector<std::pair<int, int>>{ { 4, 4 }, { 8, 8 }, { 16, 16 } }),
    "levels are (spatial step, range step), finest first");
  Check(ok.GuideScale == 255.0 && ok.GuideStride == 2 && ok.DefaultLevels == 1 &&
      !ok.Demodulate,
    "guide scale, stride, default levels and demodulation are read");
  Check(ok.OutputPadding == 3, "the trailing pad outputs are counted");

  Keys image = { { "ptv.format", "denoiser-v1" }, { "ptv.input_channels", "radiance.r" } };
  const ptv::GuideNetMetadata im = Read(image, problems);
  Check(problems.empty() && im.Image && !im.HaveLevels, "an image model needs no levels");
  image["ptv.guide_stride"] = "2";
  image["ptv.default_levels"] = "1";
  Read(image, problems);
  Check(problems.size() == 2 && Mentions(problems, "only for guidenet-v1"),
    "an image model with a guide stride and default levels gives two problems");

  const struct
  {
    const char* key;
    const char* value;
    const char* says;
  } bad[] = { { "ptv.format", "guidenet-v9", "\"guidenet-v9\", expected \"guidenet-v1\"" },
    { "ptv.input_channels", "a,,b", "not a comma-separated list" },
    { "ptv.input_channels", "a,b,", "not a comma-separated list" },
    { "ptv.levels", "4:4,8", "\"4:4,8\" is not a list like" },
    { "ptv.levels", "4:0", "is not a list like" },
    { "ptv.guide_scale", "-1", "\"-1\" is not a positive number" },
    { "ptv.guide_scale", "1e999", "is not a positive number" },
    { "ptv.guide_stride", "17", "\"17\" is not an integer from 1 to 16" },
    { "ptv.default_levels", "4", "\"4\" is above the model's 3 levels" },
    { "ptv.default_levels", "x", "is not a positive integer" },
    { "ptv.demodulate", "yes", "\"yes\" is not 0 or 1" } };
  for (const auto& b : bad)
  {
    Keys keys = Shipped();
    keys[b.key] = b.value;
    const ptv::GuideNetMetadata m = Read(keys, problems);
    Check(problems.size() == 1 && Mentions(problems, b.key) && Mentions(problems, b.says),
      std::string(b.key) + " = \"" + b.value + "\" gives one problem saying " + b.says);
    Check(m.GuideStride == (std::string(b.key) == "ptv.guide_stride" ? 1 : 2) &&
        m.DefaultLevels == (std::string(b.key) == "ptv.default_levels" ? 0 : 1),
      std::string(b.key) + " = \"" + b.value + "\": a rejected stride or level count is reset");
  }

  for (const char* missing : { "ptv.format", "ptv.input_channels", "ptv.levels" })
  {
    Keys keys = Shipped();
    keys.erase(missing);
    Read(keys, problems);
    Check(problems.size() == 1 && Mentions(problems, std::string(missing) + " is missing"),
      std::string("a model without ") + missing + " names the missing key");
  }
  Check(ptv::Join({ "a", "b", "c" }, "; ") == "a; b; c" && ptv::Join({}, ",").empty(),
    "Join puts the separator between items only");
  return TestResult();
}
