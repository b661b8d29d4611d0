// Unit test of ptvPassBuffers (issue #60): the pass table, a sample's round trip through the
// passes, sizing, and the running mean of frames.
//  - pass names are unique and FindPass finds each (nullptr and unknown names: -1); the traced
//    passes come first and none of them is a denoiser pass;
//  - StoreSample then LoadSample gives back every field at its pixel, and writes nothing else;
//  - Resize zeroes every pass at the new size and keeps the contents when the size is the same;
//    Clear zeroes;
//  - Accumulate(frame, k) for k = 1..N leaves the arithmetic mean of the N frames in every
//    traced pass (float rounding: each update errs by at most ~2 eps for values in [-1, 1], so
//    within 2 N eps), swaps on the first frame, and leaves the derived passes alone;
//  - TakeTracedPasses moves the traced passes without a copy (the same storage, the same
//    values), releases the taker's own first and leaves the giver none until its Resize, which
//    allocates them again (zeros); the derived passes of the taker are sized to the giver.
#include "ptvPassBuffers.h"
#include "ptvTestCheck.h"

#include <cfloat>
#include <cmath>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace
{
ptv::PixelSample RandomSample(std::mt19937& rng)
{
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  auto v3 = [&]() { return ptv::MakeVec3(u(rng), u(rng), u(rng)); };
  ptv::PixelSample s;
  s.Radiance = v3();
  s.Alpha = u(rng);
  s.Albedo = v3();
  s.Depth1 = u(rng);
  s.Position1 = v3();
  s.Normal1 = v3();
  s.Depth2 = u(rng);
  s.Position2 = v3();
  s.Normal2 = v3();
  s.Coverage = u(rng);
  s.Footprint = u(rng);
  return s;
}

bool Same(const ptv::Vec3& a, const ptv::Vec3& b)
{
  return a.x == b.x && a.y == b.y && a.z == b.z;
}

bool Same(const ptv::PixelSample& a, const ptv::PixelSample& b)
{
  return Same(a.Radiance, b.Radiance) && a.Alpha == b.Alpha && Same(a.Albedo, b.Albedo) &&
    a.Depth1 == b.Depth1 && Same(a.Position1, b.Position1) && Same(a.Normal1, b.Normal1) &&
    a.Depth2 == b.Depth2 && Same(a.Position2, b.Position2) && Same(a.Normal2, b.Normal2) &&
    a.Coverage == b.Coverage && a.Footprint == b.Footprint;
}

std::size_t Values(const ptv::PassBuffers& b, int pass)
{
  return static_cast<std::size_t>(b.GetWidth()) * b.GetHeight() *
    ptv::GetPassInfo(pass).Components;
}

void TestPassTable()
{
  std::set<std::string> names;
  for (int pass = 0; pass < ptv::PassCount; ++pass)
  {
    const ptv::PassInfo& info = ptv::GetPassInfo(pass);
    names.insert(info.Name);
    Check(ptv::FindPass(info.Name) == pass, std::string("FindPass finds ") + info.Name);
    Check(info.Components >= 1 && info.Components <= 3,
      std::string(info.Name) + " has 1 to 3 components");
    Check(pass >= ptv::kTracedPassCount || !ptv::IsDenoiserPass(pass),
      std::string("traced pass ") + info.Name + " is not a denoiser pass");
  }
  Check(names.size() == static_cast<std::size_t>(ptv::PassCount), "pass names are unique");
  Check(ptv::FindPass(nullptr) == -1 && ptv::FindPass("Bogus") == -1 &&
      ptv::FindPass("radiance") == -1,
    "FindPass of nullptr, an unknown or a miscased name is -1");
}

void TestStoreLoad(std::mt19937& rng)
{
  ptv::PassBuffers b;
  b.Resize(5, 3);
  const ptv::TracedPassPlanes planes = b.Planes();
  const int pixel = 7;
  const ptv::PixelSample s = RandomSample(rng);
  ptv::StoreSample(planes, pixel, s);
  Check(Same(ptv::LoadSample(planes, pixel), s), "LoadSample returns what StoreSample wrote");
  bool othersZero = true;
  for (int p = 0; p < 15; ++p)
  {
    if (p != pixel)
    {
      const ptv::PixelSample o = ptv::LoadSample(planes, p);
      othersZero = othersZero && o.Alpha == 0.f && o.Radiance.x == 0.f && o.Depth2 == 0.f &&
        o.Normal2.z == 0.f && o.Footprint == 0.f;
    }
  }
  Check(othersZero, "StoreSample writes only its pixel");
  b.Store(3, s);
  Check(Same(ptv::LoadSample(b.Planes(), 3), s), "PassBuffers::Store is StoreSample");
}

void TestSizing(std::mt19937& rng)
{
  ptv::PassBuffers b;
  b.Resize(4, 2);
  bool sized = true;
  for (int pass = 0; pass < ptv::PassCount; ++pass)
  {
    const float* d = b.Data(pass);
    if (ptv::IsOnRequestPass(pass))
    {
      sized = sized && d == nullptr;
      continue;
    }
    for (std::size_t i = 0; i < Values(b, pass); ++i)
    {
      sized = sized && d[i] == 0.f;
    }
  }
  Check(sized && b.GetWidth() == 4 && b.GetHeight() == 2,
    "Resize allocates zeroed passes, the on-request ones not");
  b.Store(5, RandomSample(rng));
  const float kept = b.Data(ptv::PassAlpha)[5];
  b.Resize(4, 2);
  Check(b.Data(ptv::PassAlpha)[5] == kept && kept != 0.f, "Resize to the same size keeps");
  float* guides = b.Ensure(ptv::PassGuides);
  bool zeros = guides != nullptr;
  for (std::size_t i = 0; zeros && i < Values(b, ptv::PassGuides); ++i)
  {
    zeros = guides[i] == 0.f;
  }
  guides[23] = 1.f;
  Check(zeros && b.Ensure(ptv::PassGuides) == guides && guides[23] == 1.f,
    "Ensure allocates an on-request pass of the size, zeros, once");
  b.Resize(2, 4);
  Check(b.Data(ptv::PassAlpha)[5] == 0.f && b.Data(ptv::PassGuides) == nullptr,
    "Resize to another size clears, and drops the on-request passes");
  ptv::PassBuffers traced(ptv::PassSet::Traced);
  traced.Resize(4, 2);
  bool tracedOnly = true;
  for (int pass = 0; pass < ptv::PassCount; ++pass)
  {
    tracedOnly = tracedOnly && (traced.Data(pass) != nullptr) == (pass < ptv::kTracedPassCount);
  }
  Check(tracedOnly, "a PassSet::Traced buffer keeps the traced passes only");
  b.Store(1, RandomSample(rng));
  b.Data(ptv::PassConverged)[0] = 2.f;
  b.Clear();
  Check(b.Data(ptv::PassAlpha)[1] == 0.f && b.Data(ptv::PassConverged)[0] == 0.f,
    "Clear zeroes traced and derived passes");
}

void TestAccumulate(std::mt19937& rng)
{
  const int w = 3, h = 2, frames = 64;
  ptv::PassBuffers acc, frame;
  acc.Resize(w, h);
  frame.Resize(w, h);
  acc.Data(ptv::PassConverged)[0] = 5.f; // a derived pass: Accumulate must leave it
  std::vector<std::vector<double>> sum(ptv::kTracedPassCount);
  for (int pass = 0; pass < ptv::kTracedPassCount; ++pass)
  {
    sum[pass].assign(Values(acc, pass), 0.0);
  }
  bool swapped = false;
  for (int k = 1; k <= frames; ++k)
  {
    for (int p = 0; p < w * h; ++p)
    {
      frame.Store(p, RandomSample(rng));
    }
    for (int pass = 0; pass < ptv::kTracedPassCount; ++pass)
    {
      for (std::size_t i = 0; i < sum[pass].size(); ++i)
      {
        sum[pass][i] += frame.Data(pass)[i];
      }
    }
    const float* firstFrame = frame.Data(ptv::PassRadiance);
    acc.Accumulate(frame, k);
    if (k == 1)
    {
      swapped = acc.Data(ptv::PassRadiance) == firstFrame;
    }
  }
  Check(swapped, "the first frame is swapped in, not copied");
  double worst = 0.0;
  for (int pass = 0; pass < ptv::kTracedPassCount; ++pass)
  {
    for (std::size_t i = 0; i < sum[pass].size(); ++i)
    {
      worst = std::max(worst, std::abs(acc.Data(pass)[i] - sum[pass][i] / frames));
    }
  }
  const double bound = 2.0 * frames * FLT_EPSILON;
  Check(worst <= bound, "the running mean of 64 frames is their mean (worst error " +
      std::to_string(worst) + ")");
  Check(acc.Data(ptv::PassConverged)[0] == 5.f, "Accumulate leaves the derived passes");
}

void TestTakeTracedPasses(std::mt19937& rng)
{
  // A restart: the frame, traced at 4 x 3, becomes the mean of an accumulation of another size.
  ptv::PassBuffers mean, frame(ptv::PassSet::Traced);
  mean.Resize(2, 2);
  frame.Resize(4, 3);
  for (int p = 0; p < 12; ++p)
  {
    frame.Store(p, RandomSample(rng));
  }
  const ptv::PixelSample seventh = ptv::LoadSample(frame.Planes(), 7);
  const float* radiance = frame.Data(ptv::PassRadiance);
  mean.TakeTracedPasses(frame);
  bool derivedSized = true;
  for (int pass = ptv::kTracedPassCount; pass < ptv::PassCount; ++pass)
  {
    const float* d = mean.Data(pass);
    derivedSized = derivedSized &&
      (ptv::IsOnRequestPass(pass) ? d == nullptr : d != nullptr && d[Values(mean, pass) - 1] == 0.f);
  }
  Check(mean.GetWidth() == 4 && mean.GetHeight() == 3 && derivedSized,
    "the taker has the giver's size, its derived passes sized to it (zeros)");
  Check(mean.Data(ptv::PassRadiance) == radiance && Same(ptv::LoadSample(mean.Planes(), 7), seventh),
    "the traced passes are moved, not copied, values and all");
  bool none = true;
  for (int pass = 0; pass < ptv::PassCount; ++pass)
  {
    none = none && frame.Data(pass) == nullptr;
  }
  Check(none, "the giver keeps no traced pass (one set between the two)");

  // The next restart: the frame traces into the mean's storage, the mean keeps none of it.
  frame.TakeTracedPasses(mean);
  frame.Resize(4, 3);
  Check(frame.Data(ptv::PassRadiance) == radiance && mean.Data(ptv::PassRadiance) == nullptr,
    "the frame takes the mean's storage back; Resize of the same size keeps it");
  Check(frame.Data(ptv::PassConverged) == nullptr,
    "a PassSet::Traced taker keeps no derived pass");
  mean.Resize(4, 3);
  const float* alpha = mean.Data(ptv::PassAlpha);
  bool zeros = alpha != nullptr;
  for (std::size_t i = 0; zeros && i < Values(mean, ptv::PassAlpha); ++i)
  {
    zeros = alpha[i] == 0.f;
  }
  Check(zeros && mean.Data(ptv::PassNormal) != nullptr,
    "Resize of the same size allocates the passes given away, zeros");
  mean.SetScatterPasses(false);
  frame.SetScatterPasses(false);
  frame.TakeTracedPasses(mean);
  frame.Resize(4, 3);
  Check(frame.Data(ptv::PassAlpha) == alpha && frame.Data(ptv::PassScatterDepth) == nullptr,
    "without the scatter passes none is taken or allocated");
}
}

int TestPTVPassBuffers(int, char*[])
{
  std::mt19937 rng(60);
  TestPassTable();
  TestStoreLoad(rng);
  TestSizing(rng);
  TestAccumulate(rng);
  TestTakeTracedPasses(rng);
  return TestResult();
}
