// Temporal reuse while the camera moves (vtkPathTracedVolumeMapper, ptvReprojection):
//  - a still camera accumulates bit for bit as with TemporalReprojection off;
//  - a pure translation by whole pixels (parallel projection: every pixel's footprint lands on
//    a new pixel's) carries 32 frames of history over: away from the entering columns the
//    result is as close to a 1024-spp reference as a 33-frame accumulation of the new view
//    (its error within 1.5x plus 1e-5), the entering columns start at one frame, every other
//    pixel of the volume keeps its history;
//  - a translation by 2.5 pixels: error within 1.5x that of 33 frames plus twice the error of
//    bilinearly shifting the converged image itself (the interpolation error);
//  - MaximumHistory caps the history; frames of a still view after a move add to each pixel;
//  - a turn of the view shrinks the cap: by 1 - sin(1 deg) / sin(4 deg) for 2 degrees (the
//    chords of 2 and 8 degrees), to nothing for 9 degrees;
//  - the history is dropped when the transfer function or a scene light changes (the frame is
//    bit-identical to a fresh mapper's first frame), not when a camera light moves with the
//    camera;
//  - with background around the volume, pixels with no hit beside them start afresh and the
//    misses on the edge of the neighbouring rows' hits keep their history;
//  - the same camera path and seed give the same frames, with 1 or 2 threads.
#include "ptvTestCheck.h"
#include "ptvTestMetrics.h"
#include "ptvTestScene.h"
#include "vtkCamera.h"
#include "vtkLight.h"
#include "vtkMath.h"
#include "vtkPTVExpertOptions.h"
#include "vtkPTVRenderStatistics.h"
#include "vtkPiecewiseFunction.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace
{
constexpr int kSize = 64;

struct Scene : AnalyticScene
{
  Scene()
    : AnalyticScene(kSize)
  {
    this->Mapper->ConvergeStillRendersOff();
    this->Mapper->DenoiseOff();
    this->Mapper->GetExpertOptions()->SetMaximumHistory(1000);
    vtkCamera* camera = this->Renderer->GetActiveCamera();
    camera->ParallelProjectionOn();
    this->Renderer->ResetCamera();
    camera->Zoom(2.0); // the volume fills the image: columns enter at its edges
  }

  /// Move the camera by @a pixels along its right vector (parallel projection: an image shift).
  void Pan(double pixels)
  {
    vtkCamera* camera = this->Renderer->GetActiveCamera();
    double up[3], forward[3], right[3];
    camera->GetViewUp(up);
    camera->GetDirectionOfProjection(forward);
    vtkMath::Cross(forward, up, right);
    vtkMath::Normalize(right);
    const double step = pixels * 2.0 * camera->GetParallelScale() / kSize;
    double position[3], focal[3];
    camera->GetPosition(position);
    camera->GetFocalPoint(focal);
    for (int k = 0; k < 3; ++k)
    {
      position[k] += step * right[k];
      focal[k] += step * right[k];
    }
    camera->SetPosition(position);
    camera->SetFocalPoint(focal);
  }

  void Frames(int n)
  {
    for (int i = 0; i < n; ++i)
    {
      this->Window->Render();
    }
  }

  /// A fresh accumulation of @a frames frames with @a seed (history dropped first).
  std::vector<float> Accumulate(int frames, unsigned int seed)
  {
    this->Mapper->SetSeed(seed);
    this->Mapper->ResetAccumulation();
    this->Frames(frames);
    return this->Pass("Radiance");
  }
};

/// @a image (kSize^2 x 3) sampled at x + shift (bilinear, edge clamped).
std::vector<float> ShiftX(const std::vector<float>& image, double shift)
{
  std::vector<float> out(image.size());
  for (int y = 0; y < kSize; ++y)
  {
    for (int x = 0; x < kSize; ++x)
    {
      const double u = std::min(std::max(x + shift, 0.0), kSize - 1.0);
      const int x0 = std::min(static_cast<int>(u), kSize - 2);
      const float t = static_cast<float>(u - x0);
      for (int c = 0; c < 3; ++c)
      {
        const float a = image[3 * (y * kSize + x0) + c];
        const float b = image[3 * (y * kSize + x0 + 1) + c];
        out[3 * (y * kSize + x) + c] = a + (b - a) * t;
      }
    }
  }
  return out;
}

std::string Num(double v)
{
  std::ostringstream s;
  s << v;
  return s.str();
}

void TestStillCameraUnchanged()
{
  Scene on, off;
  off.Mapper->TemporalReprojectionOff();
  on.Frames(8);
  off.Frames(8);
  Check(on.Pass("Radiance") == off.Pass("Radiance") && on.Pass("Depth") == off.Pass("Depth"),
    "a still camera's 8 frames are bit-identical with TemporalReprojection on and off");
  const std::vector<float> history = on.Pass("HistoryLength");
  Check(!history.empty() && history.front() == 8.0f && history.back() == 8.0f,
    "HistoryLength of a still view is its frame count");
}

/// Translate by @a pixels after 32 still frames; compare with 33 frames of the new view.
void TestTranslation(double pixels)
{
  const std::string what = "translation by " + Num(pixels) + " px: ";
  Scene s;
  vtkNew<vtkLight> light; // fixed in the scene: only the camera moves (the default light
  light->SetLightTypeToSceneLight(); // follows the camera)
  light->SetPosition(20, -30, 60);
  light->SetFocalPoint(0, 0, 0);
  s.Renderer->AddLight(light);
  const std::vector<float> refA = s.Accumulate(1024, 7);
  s.Pan(pixels);
  const std::vector<float> refB = s.Accumulate(1024, 7);
  const std::vector<float> still = s.Accumulate(33, 3);
  s.Pan(-pixels);
  s.Accumulate(32, 3);
  s.Pan(pixels);
  s.Frames(1);
  const std::vector<float> moved = s.Pass("Radiance");
  const std::vector<float> history = s.Pass("HistoryLength");
  const std::vector<float> alpha = s.Pass("Alpha");
  Check(s.Mapper->GetAccumulatedFrames() == 1, what + "the moved view has 1 frame of its own");
  Check(s.Mapper->GetStatistics()->GetLastReprojectionTime() > 0.0, what + "the move was reprojected");
  Check(s.Mapper->GetStatistics()->GetReprojectionReuse() > 0.9,
    what + "most pixels keep their history: " + Num(s.Mapper->GetStatistics()->GetReprojectionReuse()));

  // Pixels away from the entering columns (the camera moves right: the image moves left).
  const int entering = static_cast<int>(std::ceil(pixels)) + 1;
  std::vector<bool> inner(kSize * kSize, false);
  int kept = 0, volume = 0, fresh = 0;
  for (int y = 0; y < kSize; ++y)
  {
    for (int x = 0; x < kSize; ++x)
    {
      const int p = y * kSize + x;
      inner[p] = x < kSize - entering;
      if (x >= kSize - static_cast<int>(std::floor(pixels)) && alpha[p] > 0.0f)
      {
        fresh += history[p] == 1.0f ? 1 : 0; // seen for the first time
        continue;
      }
      if (inner[p] && refB[3 * p] + refB[3 * p + 1] + refB[3 * p + 2] > 0.0f && alpha[p] > 0.5f)
      {
        ++volume;
        kept += history[p] > 30.0f ? 1 : 0;
      }
    }
  }
  Check(volume > 100 && kept >= volume * 95 / 100,
    what + "volume pixels with history: " + Num(kept) + " of " + Num(volume));
  Check(fresh > 0, what + "the entering columns start afresh");
  const double mseMoved = ToneMse(moved, refB, inner);
  const double mseStill = ToneMse(still, refB, inner);
  double bound = 1.5 * mseStill + 1e-5;
  if (pixels != std::floor(pixels))
  {
    bound += 2.0 * ToneMse(ShiftX(refA, pixels), refB, inner); // the interpolation error
  }
  Check(mseMoved <= bound,
    what + "error " + Num(mseMoved) + " vs 33 still frames' " + Num(mseStill) + " (bound " +
      Num(bound) + ")");
}

/// The volume in the middle of the image: a pixel with no hit in its 3 x 3 neighbourhood
/// starts afresh (history 1, alpha 0). The step looks only at the pixels within the hull of
/// the neighbouring rows' hits widened by one pixel; the misses on that hull's edge (beside a
/// hit diagonally) are looked at, so some of them keep their history.
void TestBackgroundAroundTheVolume()
{
  Scene s;
  s.Renderer->GetActiveCamera()->Zoom(0.4); // undo the 2x zoom: background all around
  s.Frames(8);
  s.Pan(1.0);
  s.Frames(1);
  const std::vector<float> depth = s.Pass("Depth");
  const std::vector<float> history = s.Pass("HistoryLength");
  const std::vector<float> alpha = s.Pass("Alpha");
  const float far = *std::max_element(depth.begin(), depth.end()); // what misses store
  auto hit = [&](int x, int y)
  { return x >= 0 && y >= 0 && x < kSize && y < kSize && depth[y * kSize + x] < 0.999f * far; };
  std::vector<int> first(kSize, kSize), last(kSize, -1); // each row's outermost hits
  for (int y = 0; y < kSize; ++y)
  {
    for (int x = 0; x < kSize; ++x)
    {
      first[y] = hit(x, y) ? std::min(first[y], x) : first[y];
      last[y] = hit(x, y) ? std::max(last[y], x) : last[y];
    }
  }
  int background = 0, fresh = 0, edge = 0, kept = 0;
  for (int y = 0; y < kSize; ++y)
  {
    int lo = kSize, hi = -1; // the hull of rows y - 1 .. y + 1
    for (int py = std::max(y - 1, 0); py <= std::min(y + 1, kSize - 1); ++py)
    {
      lo = std::min(lo, first[py]);
      hi = std::max(hi, last[py]);
    }
    for (int x = 0; x < kSize; ++x)
    {
      bool near = false;
      for (int d = 0; d < 9; ++d)
      {
        near = near || hit(x + d % 3 - 1, y + d / 3 - 1);
      }
      const int p = y * kSize + x;
      if (!near)
      {
        ++background;
        fresh += history[p] == 1.0f && alpha[p] == 0.0f ? 1 : 0;
      }
      else if (hi >= 0 && (x == lo - 1 || x == hi + 1))
      {
        ++edge;
        kept += history[p] > 1.0f ? 1 : 0;
      }
    }
  }
  Check(background > 200 && fresh == background,
    "background pixels start afresh: " + Num(fresh) + " of " + Num(background));
  Check(edge > 20 && 2 * kept >= edge, // measured: 64 of 64 (0 without the widening)
    "misses on the edge of the hits' hull are reprojected: " + Num(kept) + " of " + Num(edge) +
      " kept a history");
}

void TestHistoryCapAndStillAfterMove()
{
  Scene s;
  s.Mapper->GetExpertOptions()->SetMaximumHistory(4);
  s.Frames(16);
  s.Pan(1.0);
  s.Frames(1);
  std::vector<float> history = s.Pass("HistoryLength");
  const float most = *std::max_element(history.begin(), history.end());
  Check(most == 5.0f, "MaximumHistory 4 caps the history at 4 (+1 new frame): " + Num(most));
  s.Frames(3);
  history = s.Pass("HistoryLength");
  Check(*std::max_element(history.begin(), history.end()) == 8.0f,
    "a still view after the move adds its frames to each pixel's history");
  Check(s.Mapper->GetAccumulatedFrames() == 4, "the still view counts its own frames");
}

void TestTurnFade()
{
  Scene s;
  s.Mapper->GetExpertOptions()->SetMaximumHistory(4);
  s.Frames(8);
  s.Renderer->GetActiveCamera()->Azimuth(2.0);
  s.Frames(1);
  std::vector<float> history = s.Pass("HistoryLength");
  const double expected = 1.0 + 4.0 * (1.0 - 2.0 / 8.0);
  const float most = *std::max_element(history.begin(), history.end());
  Check(std::fabs(most - expected) < 1e-3,
    "a 2-degree turn caps the history at 4 x its fade (+1): " + Num(most) + " vs " +
      Num(expected));
  Check(s.Mapper->GetStatistics()->GetReprojectionReuse() > 0.5, "the 2-degree turn kept most histories");
  s.Frames(4);
  s.Renderer->GetActiveCamera()->Azimuth(9.0);
  s.Frames(1);
  history = s.Pass("HistoryLength");
  Check(*std::max_element(history.begin(), history.end()) == 1.0f &&
      s.Mapper->GetStatistics()->GetReprojectionReuse() == 0.0,
    "a 9-degree turn keeps no history");

  // The fade counts the view's rotation, not the central ray's: seen from 40 degrees above, a
  // 7.5-degree orbit turns the central ray by only ~5.7 degrees, but the view by 7.5.
  s.Renderer->GetActiveCamera()->Elevation(40.0);
  s.Frames(4);
  s.Renderer->GetActiveCamera()->Azimuth(7.5);
  s.Frames(1);
  history = s.Pass("HistoryLength");
  const double orbit = 1.0 + 4.0 * (1.0 - 7.5 / 8.0);
  const float orbitMost = *std::max_element(history.begin(), history.end());
  Check(std::fabs(orbitMost - orbit) < 1e-3,
    "a 7.5-degree orbit at 40 degrees of elevation fades the history by its own 7.5 degrees: " +
      Num(orbitMost) + " vs " + Num(orbit));

  // A roll leaves the central ray where it was but turns everything around it (and the lights
  // that follow the camera).
  s.Frames(4);
  s.Renderer->GetActiveCamera()->Roll(9.0);
  s.Frames(1);
  history = s.Pass("HistoryLength");
  Check(*std::max_element(history.begin(), history.end()) == 1.0f,
    "a 9-degree roll keeps no history");
}

void TestHistoryDropped()
{
  Scene s, fresh;
  s.Frames(8);
  s.Pan(1.0);
  s.Frames(1);
  Check(s.Mapper->GetStatistics()->GetReprojectionReuse() > 0.9, "the camera move kept the history");
  // A transfer-function change, in both scenes.
  for (Scene* scene : { &s, &fresh })
  {
    scene->Opacity->AddPoint(200, 0.3);
  }
  fresh.Pan(1.0);
  s.Frames(1);
  fresh.Frames(1);
  std::vector<float> history = s.Pass("HistoryLength");
  Check(*std::max_element(history.begin(), history.end()) == 1.0f,
    "a transfer-function change drops the history");
  Check(s.Pass("Radiance") == fresh.Pass("Radiance"),
    "after a transfer-function change the frame is a fresh mapper's first frame, bit for bit");

  // A scene light that moves drops it; a camera light moving with the camera does not.
  vtkNew<vtkLight> light;
  light->SetLightTypeToSceneLight();
  light->SetPosition(0, 0, 100);
  light->SetFocalPoint(0, 0, 0);
  s.Renderer->AddLight(light);
  s.Frames(4);
  light->SetPosition(10, 0, 100);
  s.Frames(1);
  history = s.Pass("HistoryLength");
  Check(*std::max_element(history.begin(), history.end()) == 1.0f,
    "a scene light's change drops the history");
  light->SetLightTypeToCameraLight();
  light->SetPosition(0, 0, 1);
  light->SetFocalPoint(0, 0, 0);
  s.Frames(4);
  s.Pan(1.0);
  s.Frames(1);
  history = s.Pass("HistoryLength");
  Check(*std::max_element(history.begin(), history.end()) > 4.0f,
    "a camera light moving with the camera keeps the history");
}

void TestDeterministic()
{
  Scene a, b;
  b.Mapper->SetNumberOfThreads(1);
  a.Mapper->SetNumberOfThreads(2);
  bool same = true;
  for (int step = 0; step < 6; ++step)
  {
    for (Scene* s : { &a, &b })
    {
      if (step % 3 != 0)
      {
        s->Pan(0.7);
        s->Renderer->GetActiveCamera()->Azimuth(1.5);
      }
      s->Frames(1 + step % 2);
    }
    same = same && a.Pass("Radiance") == b.Pass("Radiance") &&
      a.Pass("HistoryLength") == b.Pass("HistoryLength");
  }
  Check(same, "the same camera path and seed give the same frames (1 and 2 threads)");
}
}

int TestPTVTemporalReprojection(int, char*[])
{
  TestStillCameraUnchanged();
  TestTranslation(3.0);
  TestTranslation(2.5);
  TestBackgroundAroundTheVolume();
  TestHistoryCapAndStillAfterMove();
  TestTurnFade();
  TestHistoryDropped();
  TestDeterministic();
  return TestResult();
}
