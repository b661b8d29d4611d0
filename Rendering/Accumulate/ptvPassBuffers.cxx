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
  { "Coverage", 1 },
  { "Footprint", 1 },
  { "Denoised", 3 },
  { "Guides", 3 },
  { "BlendWeights", 2 },
  { "Converged", 3 },
  { "HistoryLength", 1 },
  { "DenoisedAlpha", 1 },
  { "SampleRatio", 1 },
};
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
    this->Allocate(true); // passes handed away by TakeTracedPasses get storage again
    return;
  }
  this->Width = width;
  this->Height = height;
  this->Allocate(false);
}

//------------------------------------------------------------------------------
void PassBuffers::SetScatterPasses(bool keep)
{
  if (keep != this->Scatter)
  {
    this->Scatter = keep;
    this->Allocate(true);
  }
}

//------------------------------------------------------------------------------
void PassBuffers::Allocate(bool keepValues, int first)
{
  const std::size_t pixels =
    static_cast<std::size_t>(this->Width) * static_cast<std::size_t>(this->Height);
  const int kept = this->Set == PassSet::All ? PassCount : kTracedPassCount;
  for (int i = first; i < PassCount; ++i)
  {
    const bool keep = i < kept && !IsOnRequestPass(i) && (this->Scatter || !IsScatterPass(i));
    const bool allocated = this->Buffers[i].size() == pixels * kPasses[i].Components;
    if (keepValues && ((allocated && keep) || IsOnRequestPass(i)))
    {
      continue; // SetScatterPasses: the others' values stay
    }
    if (keep)
    {
      this->Buffers[i].assign(pixels * kPasses[i].Components, 0.0f);
    }
    else
    {
      std::vector<float>().swap(this->Buffers[i]); // not kept: no memory
    }
  }
}

//------------------------------------------------------------------------------
float* PassBuffers::Ensure(int pass)
{
  const std::size_t n = static_cast<std::size_t>(this->Width) *
    static_cast<std::size_t>(this->Height) * static_cast<std::size_t>(kPasses[pass].Components);
  if (this->Buffers[pass].size() != n)
  {
    this->Buffers[pass].assign(n, 0.0f);
  }
  return this->Buffers[pass].data();
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
TracedPassPlanes PassBuffers::Planes()
{
  TracedPassPlanes planes;
  for (int pass = 0; pass < kTracedPassCount; ++pass)
  {
    planes.Data[pass] = this->Buffers[pass].data();
  }
  return planes;
}

//------------------------------------------------------------------------------
void PassBuffers::Store(int pixel, const PixelSample& s)
{
  StoreSample(this->Planes(), static_cast<std::size_t>(pixel), s);
}

//------------------------------------------------------------------------------
void PassBuffers::TakeTracedPasses(PassBuffers& other)
{
  if (&other == this)
  {
    return;
  }
  for (int i = 0; i < kTracedPassCount; ++i)
  {
    std::vector<float>().swap(this->Buffers[i]); // released before the other's arrive
    this->Buffers[i].swap(other.Buffers[i]);
  }
  const bool sameSize = other.Width == this->Width && other.Height == this->Height;
  this->Width = other.Width;
  this->Height = other.Height;
  this->Allocate(sameSize, kTracedPassCount);
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
