#include "ptvPassBuffers.h"

#include <algorithm>
#include <cstring>

namespace ptv
{
namespace
{
const PassInfo kPasses[PassCount] = {
  { "Radiance", 3 },
  { "Alpha", 1 },
  { "Albedo", 3 },
  { "Depth", 1 },
  { "Position", 3 },
  { "Normal", 3 },
  { "ScatterDepth", 1 },
  { "ScatterPosition", 3 },
  { "ScatterNormal", 3 },
  { "Denoised", 3 },
  { "Guides", 3 },
  { "BlendWeights", 2 },
  { "Converged", 3 },
  { "HistoryLength", 1 },
  { "DenoisedAlpha", 1 },
};

void Put3(std::vector<float>& b, int pixel, const Vec3& v)
{
  b[3 * pixel + 0] = v.x;
  b[3 * pixel + 1] = v.y;
  b[3 * pixel + 2] = v.z;
}
}

//------------------------------------------------------------------------------
const PassInfo& GetPassInfo(int pass)
{
  return kPasses[pass];
}

//------------------------------------------------------------------------------
int FindPass(const char* name)
{
  if (!name)
  {
    return -1;
  }
  for (int i = 0; i < PassCount; ++i)
  {
    if (std::strcmp(kPasses[i].Name, name) == 0)
    {
      return i;
    }
  }
  return -1;
}

//------------------------------------------------------------------------------
void PassBuffers::Resize(int width, int height)
{
  if (width == this->Width && height == this->Height)
  {
    return;
  }
  this->Width = width;
  this->Height = height;
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  for (int i = 0; i < PassCount; ++i)
  {
    this->Buffers[i].assign(pixels * kPasses[i].Components, 0.0f);
  }
}

//------------------------------------------------------------------------------
void PassBuffers::Clear()
{
  for (auto& b : this->Buffers)
  {
    std::fill(b.begin(), b.end(), 0.0f);
  }
}

//------------------------------------------------------------------------------
void PassBuffers::Store(int pixel, const PixelSample& s)
{
  Put3(this->Buffers[PassRadiance], pixel, s.Radiance);
  this->Buffers[PassAlpha][pixel] = s.Alpha;
  Put3(this->Buffers[PassAlbedo], pixel, s.Albedo);
  this->Buffers[PassDepth][pixel] = s.Depth1;
  Put3(this->Buffers[PassPosition], pixel, s.Position1);
  Put3(this->Buffers[PassNormal], pixel, s.Normal1);
  this->Buffers[PassScatterDepth][pixel] = s.Depth2;
  Put3(this->Buffers[PassScatterPosition], pixel, s.Position2);
  Put3(this->Buffers[PassScatterNormal], pixel, s.Normal2);
}

//------------------------------------------------------------------------------
void PassBuffers::Accumulate(PassBuffers& frame, int count)
{
  const float w = 1.0f / static_cast<float>(count);
  for (int i = 0; i < kTracedPassCount; ++i)
  {
    if (count == 1)
    {
      this->Buffers[i].swap(frame.Buffers[i]); // the first frame is the mean: no copy
      continue;
    }
    float* acc = this->Buffers[i].data();
    const float* in = frame.Buffers[i].data();
    const std::size_t n = this->Buffers[i].size();
    for (std::size_t k = 0; k < n; ++k)
    {
      acc[k] += (in[k] - acc[k]) * w;
    }
  }
}
}
