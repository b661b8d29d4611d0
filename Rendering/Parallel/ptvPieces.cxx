#include "ptvPieces.h"

#include "ptvPassBuffers.h"
#include "ptvThreads.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace ptv
{
namespace
{
bool Empty(const PieceBox& b)
{
  return b[0] > b[1] || b[2] > b[3] || b[4] > b[5];
}

double CentreDistance(const PieceBox& b, const double eye[3])
{
  double d = 0.0;
  for (int a = 0; a < 3; ++a)
  {
    const double c = 0.5 * (b[2 * a] + b[2 * a + 1]) - eye[a];
    d += c * c;
  }
  return d;
}

/// Orders @a ids (front first) by recursive separating planes, see the file comment.
void OrderRange(const std::vector<PieceBox>& boxes, const double eye[3], const double dir[3],
  bool parallel, std::vector<int>& ids, std::size_t begin, std::size_t end)
{
  if (end - begin < 2)
  {
    return;
  }
  for (int a = 0; a < 3; ++a)
  {
    // Candidate planes: the upper faces; a plane separates when every box lies on one side.
    for (std::size_t i = begin; i < end; ++i)
    {
      const double plane = boxes[ids[i]][2 * a + 1];
      std::size_t below = 0;
      bool crossed = false;
      for (std::size_t j = begin; j < end && !crossed; ++j)
      {
        const PieceBox& b = boxes[ids[j]];
        if (b[2 * a + 1] <= plane)
        {
          ++below;
        }
        else if (b[2 * a] < plane)
        {
          crossed = true;
        }
      }
      if (crossed || below == 0 || below == end - begin)
      {
        continue;
      }
      const auto mid = std::stable_partition(ids.begin() + begin, ids.begin() + end,
        [&](int id) { return boxes[id][2 * a + 1] <= plane; });
      const std::size_t split = static_cast<std::size_t>(mid - ids.begin());
      const bool lowFirst = parallel ? dir[a] >= 0.0 : eye[a] <= plane;
      if (!lowFirst)
      {
        std::rotate(ids.begin() + begin, ids.begin() + split, ids.begin() + end);
      }
      const std::size_t firstEnd = lowFirst ? split : begin + (end - split);
      OrderRange(boxes, eye, dir, parallel, ids, begin, firstEnd);
      OrderRange(boxes, eye, dir, parallel, ids, firstEnd, end);
      return;
    }
  }
  // Not a block decomposition: nearest centre first (along dir for a parallel view).
  std::stable_sort(ids.begin() + begin, ids.begin() + end,
    [&](int x, int y)
    {
      if (parallel)
      {
        double px = 0.0, py = 0.0;
        for (int a = 0; a < 3; ++a)
        {
          px += dir[a] * 0.5 * (boxes[x][2 * a] + boxes[x][2 * a + 1]);
          py += dir[a] * 0.5 * (boxes[y][2 * a] + boxes[y][2 * a + 1]);
        }
        return px < py;
      }
      return CentreDistance(boxes[x], eye) < CentreDistance(boxes[y], eye);
    });
}

PixelSample Load(const std::vector<const float*>& passes, std::size_t piece, std::size_t pixels,
  std::size_t i, float pieceFar, float far)
{
  auto get3 = [&](int pass)
  {
    const float* v = passes[pass] + 3 * (piece * pixels + i);
    return MakeVec3(v[0], v[1], v[2]);
  };
  auto get1 = [&](int pass) { return passes[pass][piece * pixels + i]; };
  PixelSample s;
  s.Radiance = get3(PassRadiance);
  s.Alpha = get1(PassAlpha);
  s.Albedo = get3(PassAlbedo);
  s.Depth1 = get1(PassDepth);
  s.Position1 = get3(PassPosition);
  s.Normal1 = get3(PassNormal);
  if (passes[PassScatterDepth]) // kept
  {
    s.Depth2 = get1(PassScatterDepth);
    s.Position2 = get3(PassScatterPosition);
    s.Normal2 = get3(PassScatterNormal);
  }
  else
  {
    s.Depth2 = 0.0f;
    s.Position2 = s.Normal2 = MakeVec3(0.0f, 0.0f, 0.0f);
  }
  s.Coverage = get1(PassCoverage);
  s.Footprint = get1(PassFootprint);
  if (pieceFar != far) // another clipping range: its misses move to the result's far
  {
    s.Depth1 = IsHit(s.Depth1, pieceFar) ? s.Depth1 : far;
    s.Depth2 = IsHit(s.Depth2, pieceFar) ? s.Depth2 : far;
  }
  return s;
}
}

//------------------------------------------------------------------------------
std::vector<int> ViewOrder(
  const std::vector<PieceBox>& boxes, const double eye[3], const double dir[3], bool parallel)
{
  std::vector<int> ids(boxes.size());
  std::iota(ids.begin(), ids.end(), 0);
  const auto nonEmpty = std::stable_partition(
    ids.begin(), ids.end(), [&](int id) { return !Empty(boxes[id]); });
  OrderRange(boxes, eye, dir, parallel, ids, 0,
    static_cast<std::size_t>(nonEmpty - ids.begin()));
  return ids;
}

//------------------------------------------------------------------------------
void CompositePieces(const std::vector<const float*>& gathered, std::size_t pixels,
  const std::vector<int>& order, const std::vector<float>& fars, float far, int threads,
  PassBuffers& out)
{
  if (order.empty())
  {
    return;
  }
  ParallelFor(threads, std::size_t{ 0 }, pixels, std::size_t{ 4096 },
    [&](std::size_t begin, std::size_t end)
    {
      for (std::size_t i = begin; i < end; ++i)
      {
        // Back to front: each nearer piece goes over what lies behind it.
        auto load = [&](int piece)
        {
          return Load(gathered, static_cast<std::size_t>(piece), pixels, i, fars[piece], far);
        };
        PixelSample s = load(order.back());
        for (std::size_t k = order.size() - 1; k-- > 0;)
        {
          s = OverSample(load(order[k]), s, far);
        }
        out.Store(static_cast<int>(i), s);
      }
    });
}
}
