// The pieces of a distributed volume put back together (Rendering/Parallel/ptvPieces.h):
//
// 1. ViewOrder on ParaView-like block decompositions: 2 and 4 pieces (a 2 x 2 grid of boxes that
//    share faces) seen from eyes on every side and along parallel directions; the front piece is
//    the one the eye (or the rays' start) lies on the side of, for each separating plane;
//    empty boxes go last; boxes no plane separates fall back to centre distance.
// 2. CompositePieces on frames of known samples equals OverSample pixel by pixel (the pass
//    layout round trip), front piece first whatever the gather order, and misses of a piece
//    with another far distance are moved to the result's.
// 3. OverSample's cases: an event in front hides the back; no event in front lets the back's
//    event and depth through exactly; a first hit in front keeps its features.
// (Its statistics -- the composite of two pieces is the whole ray's estimator -- are checked
// against closed forms in TestPTVKernelSlab.)
#include "ptvPassBuffers.h"
#include "ptvPieces.h"
#include "ptvTestCheck.h"

#include <cmath>
#include <sstream>
#include <vector>

namespace
{
std::string Str(const std::vector<int>& v)
{
  std::ostringstream s;
  for (int i : v)
  {
    s << i << " ";
  }
  return s.str();
}

void OrderTests()
{
  // Two pieces split in y at 127 (ParaView's split of the head CT), then a 2 x 2 grid in x, y.
  const std::vector<ptv::PieceBox> two = { { { 0, 255, 0, 127, 0, 107 } },
    { { 0, 255, 127, 255, 0, 107 } } };
  const double front[3] = { 128, -500, 50 }, behind[3] = { 128, 900, 50 };
  const double none[3] = { 0, 0, 0 };
  Check(Str(ptv::ViewOrder(two, front, none, false)) == "0 1 ", "eye at y < 0: piece 0 first");
  Check(Str(ptv::ViewOrder(two, behind, none, false)) == "1 0 ", "eye at y > 255: piece 1 first");
  const double alongY[3] = { 0, 1, 0 }, againstY[3] = { 0.2, -1, 0.1 };
  Check(Str(ptv::ViewOrder(two, none, alongY, true)) == "0 1 ", "parallel along +y");
  Check(Str(ptv::ViewOrder(two, none, againstY, true)) == "1 0 ", "parallel along -y");

  const std::vector<ptv::PieceBox> grid = { { { 0, 50, 0, 50, 0, 9 } },
    { { 50, 100, 0, 50, 0, 9 } }, { { 0, 50, 50, 100, 0, 9 } }, { { 50, 100, 50, 100, 0, 9 } } };
  // An eye above piece 3's corner: piece 3 first, piece 0 (diagonally opposite) last.
  const double corner[3] = { 120, 130, 5 };
  const std::vector<int> order = ptv::ViewOrder(grid, corner, none, false);
  Check(order.front() == 3 && order.back() == 0, "2x2 grid from (120, 130): " + Str(order));
  // An eye inside piece 1's column: piece 1 before its neighbours 0 and 3.
  const double inside[3] = { 75, 25, 50 };
  const std::vector<int> in = ptv::ViewOrder(grid, inside, none, false);
  Check(in.front() == 1, "eye over piece 1: it comes first: " + Str(in));
  // Every pair that a ray can cross in both orders... is separated by x = 50 or y = 50: check
  // each pair's order against its separating plane for several eyes.
  const double eyes[4][3] = { { -10, -10, 0 }, { 200, -5, 3 }, { 20, 300, 1 }, { 60, 40, 50 } };
  for (const auto& eye : eyes)
  {
    const std::vector<int> o = ptv::ViewOrder(grid, eye, none, false);
    std::vector<int> rank(4);
    for (int k = 0; k < 4; ++k)
    {
      rank[o[k]] = k;
    }
    // Neighbours across x = 50: (0, 1), (2, 3); across y = 50: (0, 2), (1, 3).
    const int pairs[4][3] = { { 0, 1, 0 }, { 2, 3, 0 }, { 0, 2, 1 }, { 1, 3, 1 } };
    for (const auto& p : pairs)
    {
      const bool lowFirst = eye[p[2]] <= 50;
      Check((rank[p[0]] < rank[p[1]]) == lowFirst,
        "neighbours " + std::to_string(p[0]) + ", " + std::to_string(p[1]) + " from (" +
          std::to_string(eye[0]) + ", " + std::to_string(eye[1]) + "): " + Str(o));
    }
  }
  // Empty boxes last; overlapping boxes (no separating plane): nearest centre first.
  const std::vector<ptv::PieceBox> empty = { { { 0, -1, 0, -1, 0, -1 } },
    { { 0, 10, 0, 10, 0, 10 } } };
  Check(Str(ptv::ViewOrder(empty, front, none, false)) == "1 0 ", "empty box last");
  const std::vector<ptv::PieceBox> overlap = { { { 0, 10, 0, 10, 0, 10 } },
    { { 5, 15, 5, 15, 5, 15 } } };
  const double far[3] = { 40, 40, 40 };
  Check(Str(ptv::ViewOrder(overlap, far, none, false)) == "1 0 ", "overlap: nearest centre");
}

ptv::PixelSample Sample(float alpha, float depth1, float depth2, float value, float far)
{
  ptv::PixelSample s;
  s.Radiance = ptv::MakeVec3(value, 2 * value, 3 * value);
  s.Alpha = alpha;
  s.Albedo = depth1 < far ? ptv::MakeVec3(value, value, value) : ptv::MakeVec3(0, 0, 0);
  s.Depth1 = depth1;
  s.Position1 = depth1 < far ? ptv::MakeVec3(1, depth1, 0) : ptv::MakeVec3(0, 0, 0);
  s.Normal1 = depth1 < far ? ptv::MakeVec3(0, 0, 1) : ptv::MakeVec3(0, 0, 0);
  s.Depth2 = depth2;
  s.Position2 = alpha > 0 ? ptv::MakeVec3(2, depth2, 0) : ptv::MakeVec3(0, 0, 0);
  s.Normal2 = alpha > 0 ? ptv::MakeVec3(0, 1, 0) : ptv::MakeVec3(0, 0, 0);
  // The ray's opacity: whole where it has an event, partial where it only has a first hit.
  s.Coverage = alpha > 0 ? 0.8f + 0.2f * alpha : (depth1 < far ? 0.4f : 0.f);
  s.Footprint = depth1 < far ? 1.f : 0.f; // met opacity, or not (its corner ray missed too)
  if (alpha == 0)
  {
    s.Radiance = ptv::MakeVec3(0, 0, 0);
  }
  return s;
}

bool Same(const ptv::PixelSample& a, const ptv::PixelSample& b)
{
  const float v[2][23] = { { a.Radiance.x, a.Radiance.y, a.Radiance.z, a.Alpha, a.Albedo.x,
                             a.Albedo.y, a.Albedo.z, a.Depth1, a.Position1.x, a.Position1.y,
                             a.Position1.z, a.Normal1.x, a.Normal1.y, a.Normal1.z, a.Depth2,
                             a.Position2.x, a.Position2.y, a.Position2.z, a.Normal2.x,
                             a.Normal2.y, a.Normal2.z, a.Coverage, a.Footprint },
    { b.Radiance.x, b.Radiance.y, b.Radiance.z, b.Alpha, b.Albedo.x, b.Albedo.y, b.Albedo.z,
      b.Depth1, b.Position1.x, b.Position1.y, b.Position1.z, b.Normal1.x, b.Normal1.y,
      b.Normal1.z, b.Depth2, b.Position2.x, b.Position2.y, b.Position2.z, b.Normal2.x,
      b.Normal2.y, b.Normal2.z, b.Coverage, b.Footprint } };
  for (int i = 0; i < 23; ++i)
  {
    if (std::fabs(v[0][i] - v[1][i]) > 1e-4f * (1.f + std::fabs(v[1][i])))
    {
      return false;
    }
  }
  return true;
}

void OverTests()
{
  const float far = 1000.f;
  const ptv::PixelSample miss = Sample(0, far, far, 0, far);
  const ptv::PixelSample hitOnly = Sample(0, 10, far, 0.5f, far); // first hit, no event
  const ptv::PixelSample event = Sample(1, 12, 14, 0.25f, far);
  const ptv::PixelSample back = Sample(1, 40, 45, 0.75f, far);
  Check(Same(ptv::OverSample(event, back, far), event), "an event in front hides the back");
  Check(Same(ptv::OverSample(miss, back, far), back), "a miss in front shows the back exactly");
  const ptv::PixelSample mixed = ptv::OverSample(hitOnly, back, far);
  Check(mixed.Depth1 == 10 && mixed.Albedo.x == 0.5f && mixed.Alpha == 1 &&
      std::fabs(mixed.Depth2 - 45) < 1e-3f && mixed.Radiance.x == 0.75f,
    "a first hit without event: front's features, back's event");
  Check(std::fabs(mixed.Coverage - (0.4f + 1.f * 0.6f)) < 1e-6f,
    "coverage: the front's opacity over the back's");
  Check(ptv::OverSample(miss, back, far).Footprint == 1.f &&
      ptv::OverSample(back, miss, far).Footprint == 1.f,
    "footprint: met where either piece's rays met opacity");
  Check(Same(ptv::OverSample(miss, miss, far), miss), "two misses stay a miss");
}

void CompositeTests()
{
  // Three pieces, 2 x 1 pixels; gathered in the order 2, 0, 1 of depth (piece 1 in front).
  const int w = 2, h = 1;
  const float far = 500.f, otherFar = 800.f;
  std::vector<ptv::PassBuffers> frames(3);
  const ptv::PixelSample samples[3][2] = {
    { Sample(0, far, far, 0, far), Sample(1, 30, 31, 0.3f, far) },            // middle
    { Sample(0, 5, far, 0.1f, far), Sample(0, far, far, 0, far) },            // front
    { Sample(1, 60, 70, 0.9f, otherFar), Sample(0, otherFar, otherFar, 0, otherFar) }, // back
  };
  for (int k = 0; k < 3; ++k)
  {
    frames[k].Resize(w, h);
    for (int i = 0; i < 2; ++i)
    {
      frames[k].Store(i, samples[k][i]);
    }
  }
  // What Gather leaves: each pass of every piece, piece after piece.
  std::vector<std::vector<float>> passes(ptv::kTracedPassCount);
  std::vector<const float*> gathered(ptv::kTracedPassCount);
  for (int p = 0; p < ptv::kTracedPassCount; ++p)
  {
    const std::size_t n = static_cast<std::size_t>(w * h * ptv::GetPassInfo(p).Components);
    for (int k = 0; k < 3; ++k)
    {
      passes[p].insert(passes[p].end(), frames[k].Data(p), frames[k].Data(p) + n);
    }
    gathered[p] = passes[p].data();
  }
  ptv::PassBuffers out;
  out.Resize(w, h);
  ptv::CompositePieces(gathered, 2, { 1, 0, 2 }, { far, far, otherFar }, far, 1, out);
  const ptv::PixelSample backMoved = Sample(1, 60, 70, 0.9f, far);
  const ptv::PixelSample expected[2] = {
    ptv::OverSample(samples[1][0], ptv::OverSample(samples[0][0], backMoved, far), far),
    ptv::OverSample(samples[1][1], samples[0][1], far) };
  ptv::PassBuffers want;
  want.Resize(w, h);
  want.Store(0, expected[0]);
  want.Store(1, expected[1]);
  for (int p = 0; p < ptv::kTracedPassCount; ++p)
  {
    const std::size_t n = static_cast<std::size_t>(w * h * ptv::GetPassInfo(p).Components);
    for (std::size_t i = 0; i < n; ++i)
    {
      Check(std::fabs(out.Data(p)[i] - want.Data(p)[i]) <= 1e-4f,
        std::string("CompositePieces pass ") + ptv::GetPassInfo(p).Name + " value " +
          std::to_string(i) + ": " + std::to_string(out.Data(p)[i]) + " != " +
          std::to_string(want.Data(p)[i]));
    }
  }
  // Pixel 0: the front piece's first hit (depth 5) and the back piece's event (depth 70).
  Check(out.Data(ptv::PassDepth)[0] == 5.f && std::fabs(out.Data(ptv::PassScatterDepth)[0] - 70) < 1e-3f &&
      out.Data(ptv::PassAlpha)[0] == 1.f,
    "pixel 0: first hit in front, event at the back");
  // Pixel 1: the middle piece's event; the back's miss moved to the result's far distance.
  Check(out.Data(ptv::PassDepth)[1] == 30.f && out.Data(ptv::PassScatterDepth)[1] == 31.f,
    "pixel 1: the middle piece's hit and event");
}
}

int TestPTVPieces(int, char*[])
{
  OrderTests();
  OverTests();
  CompositeTests();
  std::cout << (failures == 0 ? "TestPTVPieces passed\n" : "TestPTVPieces FAILED\n");
  return TestResult();
}
