// What the window is given to draw (ptvShownImage.h): premultiplied colour with the Alpha pass
// (the passes themselves, not a copy; the opacity given instead when there is one),
// window depth of the first event (1 for misses; a hit's point projected by the camera; made
// for any block of rows and columns, the same values as the whole image's), and
// the rectangle of drawn pixels that ptvDisplay draws under a scissor box. The rectangle must
// hold every pixel the shader would draw (alpha not <= 0, NaN included) and nothing more;
// empty when nothing is drawn; the whole image for the opaque inspection passes. Thread counts
// give the same result.
#include "ptvTestCheck.h"

#include "ptvPassBuffers.h"
#include "ptvSceneToKernel.h"
#include "ptvShownImage.h"

#include "vtkCamera.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkRenderer.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace
{
constexpr int kWidth = 40;
constexpr int kHeight = 30;
// Pixels with an event (x, y); the last one has alpha <= 0.
constexpr int kHit0[2] = { 5, 7 };
constexpr int kHit1[2] = { 30, 20 };
constexpr int kHit2[2] = { 12, 25 };
constexpr int kHit3[2] = { 38, 2 };

struct Frame
{
  vtkNew<vtkRenderer> Renderer;
  ptv::CameraRays Camera{};
  ptv::PassBuffers Passes;
  double Bounds[6] = { -1, 1, -1, 1, -1, 1 };

  Frame()
  {
    vtkCamera* cam = this->Renderer->GetActiveCamera();
    cam->SetPosition(0, 0, 10);
    cam->SetFocalPoint(0, 0, 0);
    cam->SetViewUp(0, 1, 0);
    cam->SetClippingRange(1, 100);
    double worldFromNdc[16];
    ptv::FrameSignature signature;
    ptv::SetCamera(this->Renderer, kWidth, kHeight, this->Camera, worldFromNdc, signature);
    this->Passes.Resize(kWidth, kHeight);
    float* depth = this->Passes.Data(ptv::PassDepth);
    float* rgb = this->Passes.Data(ptv::PassRadiance);
    for (int i = 0; i < kWidth * kHeight; ++i)
    {
      depth[i] = this->Camera.FarDistance; // a miss
      for (int c = 0; c < 3; ++c)
      {
        rgb[3 * i + c] = 0.01f * static_cast<float>((7 * i + c) % 97);
      }
    }
  }

  void Draw(int x, int y, float alpha, float distance)
  {
    this->Passes.Data(ptv::PassAlpha)[y * kWidth + x] = alpha;
    this->Passes.Data(ptv::PassDepth)[y * kWidth + x] = distance;
  }
};

std::string Rect(const int* r)
{
  return "[" + std::to_string(r[0]) + ", " + std::to_string(r[1]) + ", " +
    std::to_string(r[2]) + ", " + std::to_string(r[3]) + ")";
}

bool SameRect(const int* r, int x0, int y0, int x1, int y1)
{
  return r[0] == x0 && r[1] == y0 && r[2] == x1 && r[3] == y1;
}

void TestRadiance()
{
  Frame f;
  f.Draw(kHit0[0], kHit0[1], 0.5f, 9.0f);
  f.Draw(kHit1[0], kHit1[1], 1.0f, 9.5f);
  f.Draw(kHit2[0], kHit2[1], std::numeric_limits<float>::quiet_NaN(), 9.2f); // NaN: drawn
  f.Draw(kHit3[0], kHit3[1], -0.25f, 9.1f); // alpha <= 0: not drawn (its depth still counts)
  std::vector<float> depth1;
  for (int threads : { 1, 2, 3 })
  {
    ptv::ShownImage shown;
    shown.Update(f.Renderer, f.Passes, ptv::PassRadiance, f.Camera, f.Bounds, threads);
    const int* r = shown.GetCovered();
    Check(SameRect(r, 5, 7, 31, 26),
      "threads " + std::to_string(threads) + ": covered rectangle " + Rect(r) +
        ", expected [5, 7, 31, 26)");
    const float* color = shown.GetColor();
    std::vector<float> whole(static_cast<std::size_t>(kWidth * kHeight), -1.f);
    shown.WindowDepth(0, 0, kWidth, kHeight, whole.data());
    const float* depth = whole.data();
    // A block of rows and columns (what ptvDisplay asks a band at a time): the same values.
    std::vector<float> block(static_cast<std::size_t>(9 * 13), -1.f);
    shown.WindowDepth(4, 6, 17, 15, block.data());
    bool same = true;
    for (int y = 6; y < 15; ++y)
    {
      for (int x = 4; x < 17; ++x)
      {
        same = same && std::memcmp(&block[(y - 6) * 13 + (x - 4)], &depth[y * kWidth + x],
                         sizeof(float)) == 0;
      }
    }
    Check(same, "the window depth of a block is the whole image's there");
    const float* rgb = f.Passes.Data(ptv::PassRadiance);
    const float* alpha = f.Passes.Data(ptv::PassAlpha);
    Check(color == rgb && shown.GetAlpha() == alpha,
      "colour and opacity are the Radiance and Alpha passes themselves");
    bool misses = true;
    for (int i = 0; i < kWidth * kHeight; ++i)
    {
      bool hit = false;
      for (const int* px : { kHit0, kHit1, kHit2, kHit3 })
      {
        hit = hit || i == px[1] * kWidth + px[0];
      }
      misses = misses && (hit || depth[i] == 1.0f);
    }
    Check(misses, "misses have window depth 1");
    // Each hit's window depth: its point (the pixel's centre ray at the event distance)
    // through the camera's projection, 0.5 z/w + 0.5.
    vtkMatrix4x4* toNdc = f.Renderer->GetActiveCamera()->GetCompositeProjectionTransformMatrix(
      static_cast<double>(kWidth) / kHeight, -1, 1);
    for (const int* px : { kHit0, kHit1, kHit2, kHit3 })
    {
      const int i = px[1] * kWidth + px[0];
      ptv::Vec3 o, d;
      ptv::GenerateRay(f.Camera, px[0] + 0.5f, px[1] + 0.5f, o, d);
      const ptv::Vec3 q = o + d * f.Passes.Data(ptv::PassDepth)[i];
      const double in[4] = { q.x, q.y, q.z, 1.0 };
      double out[4];
      toNdc->MultiplyPoint(in, out);
      const double expected = 0.5 * out[2] / out[3] + 0.5;
      Check(std::abs(depth[i] - expected) < 1e-6 && expected > 0.0 && expected < 1.0,
        "pixel (" + std::to_string(px[0]) + ", " + std::to_string(px[1]) + "): window depth " +
          std::to_string(depth[i]) + ", expected " + std::to_string(expected));
    }
    if (threads == 1)
    {
      depth1.assign(depth, depth + kWidth * kHeight);
    }
    else
    {
      Check(std::memcmp(depth1.data(), depth, depth1.size() * sizeof(float)) == 0,
        "threads " + std::to_string(threads) + ": same depth as one thread");
    }
    // Given an opacity (the denoised one), that is drawn instead of the Alpha pass.
    std::vector<float> given(static_cast<std::size_t>(kWidth * kHeight), 0.0f);
    given[5] = 0.75f;
    shown.Update(f.Renderer, f.Passes, ptv::PassRadiance, f.Camera, f.Bounds, threads,
      given.data());
    Check(shown.GetAlpha() == given.data() && SameRect(shown.GetCovered(), 5, 0, 6, 1),
      "the given opacity is drawn: covered " + Rect(shown.GetCovered()) + ", expected [5, 0, 6, 1)");
    shown.Release();
    Check(!shown.GetColor() && !shown.GetAlpha(), "Release lets go of the image");
  }
}

void TestNothingDrawn()
{
  Frame f; // every alpha 0
  ptv::ShownImage shown;
  shown.Update(f.Renderer, f.Passes, ptv::PassDenoised, f.Camera, f.Bounds, 2);
  const int* r = shown.GetCovered();
  Check(SameRect(r, 0, 0, 0, 0), "nothing drawn: empty rectangle, got " + Rect(r));
  // One pixel in a corner, then a frame of another size: the rectangle follows.
  f.Draw(kWidth - 1, kHeight - 1, 1.0f, 9.0f);
  shown.Update(f.Renderer, f.Passes, ptv::PassRadiance, f.Camera, f.Bounds, 2);
  Check(SameRect(r, kWidth - 1, kHeight - 1, kWidth, kHeight),
    "one corner pixel: " + Rect(r));
}

void TestInspectionPass()
{
  Frame f;
  f.Draw(3, 4, 1.0f, 9.0f);
  ptv::ShownImage shown;
  shown.Update(f.Renderer, f.Passes, ptv::PassNormal, f.Camera, f.Bounds, 2);
  const int* r = shown.GetCovered();
  Check(SameRect(r, 0, 0, kWidth, kHeight),
    "an inspection pass is opaque: the whole image, got " + Rect(r));
  // Its own colour (0.5 n + 0.5, misses black) with opacity 1.
  float* normal = f.Passes.Data(ptv::PassNormal);
  normal[3 * (4 * kWidth + 3) + 2] = 1.0f; // the hit's normal: +z
  shown.Update(f.Renderer, f.Passes, ptv::PassNormal, f.Camera, f.Bounds, 2);
  const float* color = shown.GetColor();
  const float* alpha = shown.GetAlpha();
  bool opaque = color != normal;
  for (int i = 0; i < kWidth * kHeight; ++i)
  {
    opaque = opaque && alpha[i] == 1.0f;
  }
  const float* hit = color + 3 * (4 * kWidth + 3);
  Check(opaque && hit[0] == 0.5f && hit[1] == 0.5f && hit[2] == 1.0f && color[0] == 0.0f,
    "an inspection pass: its own RGB (0.5 n + 0.5; misses black), opacity 1");
}
}

int TestPTVShownImage(int, char*[])
{
  TestRadiance();
  TestNothingDrawn();
  TestInspectionPass();
  return TestResult();
}
