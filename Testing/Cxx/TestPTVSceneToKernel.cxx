// Unit test of ptvSceneToKernel (issue #60): the pieces of a VTK scene that become kernel
// structs. Tolerances: float32 round trips of coordinates below 100, 1e-4 (a few ulps).
//  - SetVolumeTransform: index -> world -> index is the identity for an image with an origin,
//    anisotropic spacing, a rotated direction matrix, under a translated and scaled vtkVolume;
//    the step is the shortest voxel edge in world units; NormalToWorld maps an index-space
//    gradient to the world-space one; zero or non-finite spacing, a non-finite origin and a
//    singular volume matrix are errors naming the value (NonFiniteGeometry too);
//  - SetClipping: a world clipping plane keeps the same points in index space; cropping planes
//    in the image's coordinates move to index space (clamped to the index box, ordered);
//  - SetCamera: the centre pixel's ray of an odd-sized view leaves the camera position along
//    its direction of projection;
//  - SetGeometryLimits: a window depth at the view axis becomes the world distance of the point
//    it came from; depth 1 (nothing drawn) leaves no limit;
//  - SetLighting: the environment is the background times EnvironmentIntensity (or
//    EnvironmentColor when asked), and a non-finite background lights nothing.
#include "ptvSceneToKernel.h"
#include "ptvTestCheck.h"

#include "vtkCamera.h"
#include "vtkImageData.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkVolume.h"

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace
{
constexpr double kTol = 1e-4;

bool Near(const ptv::Vec3& a, const double b[3], double tol = kTol)
{
  return std::abs(a.x - b[0]) <= tol && std::abs(a.y - b[1]) <= tol &&
    std::abs(a.z - b[2]) <= tol;
}

void TestVolumeTransform()
{
  vtkNew<vtkImageData> image;
  image->SetDimensions(5, 6, 7);
  image->SetOrigin(1.0, -2.0, 3.0);
  image->SetSpacing(0.5, 2.0, 1.5);
  const double c = std::cos(0.3), s = std::sin(0.3);
  const double direction[9] = { c, -s, 0, s, c, 0, 0, 0, 1 };
  image->SetDirectionMatrix(direction);
  vtkNew<vtkVolume> volume;
  volume->SetPosition(10.0, 0.0, -4.0);
  volume->SetScale(2.0);
  ptv::VolumeGrid g{};
  ptv::FrameSignature signature;
  double step = 0.0;
  std::string error;
  Check(ptv::SetVolumeTransform(image, volume, g, step, signature, error) && error.empty(),
    "SetVolumeTransform of a valid image (" + error + ")");
  Check(std::abs(step - 2.0 * 0.5) <= 1e-12, "the step is the shortest voxel edge in world units");
  bool identity = true;
  double worstNormal = 0.0;
  for (int i = 0; i < 5; ++i)
  {
    const int ijk[3] = { i, 5 - i, (2 * i) % 7 };
    double world[3];
    image->TransformIndexToPhysicalPoint(ijk, world);
    double placed[3];
    for (int k = 0; k < 3; ++k)
    {
      placed[k] = volume->GetMatrix()->GetElement(k, 0) * world[0] +
        volume->GetMatrix()->GetElement(k, 1) * world[1] +
        volume->GetMatrix()->GetElement(k, 2) * world[2] + volume->GetMatrix()->GetElement(k, 3);
    }
    const ptv::Vec3 back = ptv::TransformPoint(
      g.WorldToIndex, ptv::MakeVec3(static_cast<float>(placed[0]),
                        static_cast<float>(placed[1]), static_cast<float>(placed[2])));
    const double want[3] = { static_cast<double>(ijk[0]), static_cast<double>(ijk[1]),
      static_cast<double>(ijk[2]) };
    identity = identity && Near(back, want, 1e-3);
  }
  Check(identity, "index -> world -> index is the identity");
  // A linear field f(world) = a . world has the index gradient A^T a (A: index -> world); the
  // NormalToWorld matrix must give back a.
  const double a[3] = { 0.3, -1.2, 0.7 };
  double A[3][3];
  {
    const int o[3] = { 0, 0, 0 };
    double p0[3];
    image->TransformIndexToPhysicalPoint(o, p0);
    for (int axis = 0; axis < 3; ++axis)
    {
      int e[3] = { 0, 0, 0 };
      e[axis] = 1;
      double p1[3];
      image->TransformIndexToPhysicalPoint(e, p1);
      for (int k = 0; k < 3; ++k)
      {
        double v = 0.0;
        for (int m = 0; m < 3; ++m)
        {
          v += volume->GetMatrix()->GetElement(k, m) * (p1[m] - p0[m]);
        }
        A[k][axis] = v;
      }
    }
  }
  double gradIndex[3] = { 0, 0, 0 };
  for (int axis = 0; axis < 3; ++axis)
  {
    for (int k = 0; k < 3; ++k)
    {
      gradIndex[axis] += A[k][axis] * a[k];
    }
  }
  const ptv::Vec3 n = ptv::MultiplyMatrix3(g.NormalToWorld,
    ptv::MakeVec3(static_cast<float>(gradIndex[0]), static_cast<float>(gradIndex[1]),
      static_cast<float>(gradIndex[2])));
  worstNormal = std::max({ std::abs(n.x - a[0]), std::abs(n.y - a[1]), std::abs(n.z - a[2]) });
  Check(worstNormal <= 1e-4, "NormalToWorld maps the index gradient to the world gradient (" +
      std::to_string(worstNormal) + ")");

  struct Bad
  {
    double Spacing[3];
    double Origin[3];
    double Scale;
    const char* Words;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Bad bad[] = { { { 1, 0, 1 }, { 0, 0, 0 }, 1.0, "zero image spacing" },
    { { nan, 1, 1 }, { 0, 0, 0 }, 1.0, "non-finite image spacing" },
    { { 1, 1, 1 }, { 0, 0, nan }, 1.0, "origin" }, { { 1, 1, 1 }, { 0, 0, 0 }, 0.0, "singular" } };
  for (const Bad& b : bad)
  {
    vtkNew<vtkImageData> im;
    im->SetDimensions(3, 3, 3);
    im->SetSpacing(b.Spacing);
    im->SetOrigin(b.Origin);
    vtkNew<vtkVolume> vol;
    vol->SetScale(b.Scale);
    ptv::VolumeGrid bg{};
    std::string why;
    const bool ok = ptv::SetVolumeTransform(im, vol, bg, step, signature, why);
    Check(!ok && why.find(b.Words) != std::string::npos,
      std::string("error naming '") + b.Words + "' (got: " + why + ")");
  }
  vtkNew<vtkImageData> nonFinite;
  nonFinite->SetDimensions(2, 2, 2);
  nonFinite->SetSpacing(1, nan, 1);
  Check(ptv::NonFiniteGeometry(nonFinite).find("non-finite image spacing") == 0 &&
      ptv::NonFiniteGeometry(image).empty(),
    "NonFiniteGeometry names a NaN spacing and is empty for a valid image");
}

void TestClipping()
{
  vtkNew<vtkImageData> image;
  image->SetDimensions(11, 11, 11);
  image->SetOrigin(-5.0, 0.0, 2.0);
  image->SetSpacing(1.0, 0.5, 2.0);
  vtkNew<vtkVolume> volume;
  volume->SetPosition(1.0, 2.0, 3.0);
  ptv::VolumeGrid g{};
  ptv::FrameSignature signature;
  double step = 0.0;
  std::string error;
  ptv::SetVolumeTransform(image, volume, g, step, signature, error);
  image->GetDimensions(g.Dims); // as FrameInputs sets them: the crop box's clamp reads them

  ptv::FrameSettings settings;
  settings.ClipPlaneCount = 1;
  const double normal[3] = { 0.6, 0.0, 0.8 }; // kept where n.x + d >= 0
  settings.ClipPlanes[0][0] = normal[0];
  settings.ClipPlanes[0][1] = normal[1];
  settings.ClipPlanes[0][2] = normal[2];
  settings.ClipPlanes[0][3] = -4.0;
  settings.Cropping = true;
  const double crop[6] = { -2.0, 20.0, 1.0, 3.0, 14.0, 6.0 }; // x1 beyond the box, z reversed
  std::copy(crop, crop + 6, settings.CroppingPlanes);
  settings.CroppingFlags = 0x2000; // the centre region
  ptv::ClipRegion clip{};
  ptv::SetClipping(settings, image, g, clip, signature);
  Check(clip.PlaneCount == 1, "one clipping plane");
  bool same = true;
  for (int i = 0; i < 50; ++i)
  {
    const double w[3] = { -4.0 + 0.37 * i, 2.0 + 0.11 * i, 5.0 + 0.29 * (i % 17) };
    const double side = normal[0] * w[0] + normal[1] * w[1] + normal[2] * w[2] - 4.0;
    if (std::abs(side) < 1e-3)
    {
      continue;
    }
    const ptv::Vec3 p = ptv::TransformPoint(g.WorldToIndex,
      ptv::MakeVec3(static_cast<float>(w[0]), static_cast<float>(w[1]), static_cast<float>(w[2])));
    const float* P = clip.Planes[0];
    const bool keptIndex = P[0] * p.x + P[1] * p.y + P[2] * p.z + P[3] >= 0.f;
    same = same && keptIndex == (side >= 0.0);
  }
  Check(same, "the clipping plane keeps the same points in index space");
  // Cropping planes are in the image's coordinates (origin and spacing, not the volume's
  // position): index = (plane - origin) / spacing, clamped to [0, dims - 1], each pair ordered.
  const double want[6] = { 3.0, 10.0, 2.0, 6.0, 2.0, 6.0 };
  bool cropped = clip.Cropping != 0 && clip.CropFlags == 0x2000;
  for (int k = 0; k < 6; ++k)
  {
    cropped = cropped && std::abs(clip.CropPlanes[k] - want[k]) <= kTol;
  }
  Check(cropped, "cropping planes in index space, clamped and ordered");
}

void TestCameraAndGeometry()
{
  vtkNew<vtkRenderer> ren;
  vtkNew<vtkRenderWindow> window;
  window->AddRenderer(ren);
  window->SetSize(9, 7);
  vtkCamera* cam = ren->GetActiveCamera();
  cam->SetPosition(1.0, 2.0, 10.0);
  cam->SetFocalPoint(0.0, 0.5, 0.0);
  cam->SetViewUp(0.0, 1.0, 0.0);
  ren->ResetCameraClippingRange(-5, 5, -5, 5, -5, 5);
  ptv::CameraRays rays{};
  double worldFromNdc[16];
  ptv::FrameSignature signature;
  ptv::SetCamera(ren, 9, 7, rays, worldFromNdc, signature);
  ptv::Vec3 origin, dir;
  ptv::GenerateRay(rays, 4.5f, 3.5f, origin, dir);
  double dop[3];
  cam->GetDirectionOfProjection(dop);
  const double eye[3] = { 1.0, 2.0, 10.0 };
  Check(rays.Width == 9 && rays.Height == 7 && !rays.Parallel && Near(origin, eye) &&
      Near(dir, dop),
    "the centre ray leaves the eye along the direction of projection");

  // The focal point is on the view axis: its window depth is that of the centre pixel.
  double focal[4] = { 0.0, 0.5, 0.0, 1.0 };
  ren->SetWorldPoint(focal);
  ren->WorldToDisplay();
  double display[3];
  ren->GetDisplayPoint(display);
  std::vector<float> zbuffer(9 * 7, 1.0f);
  zbuffer[3 * 9 + 4] = static_cast<float>(display[2]);
  std::vector<float> limits;
  const bool any = ptv::SetGeometryLimits(zbuffer, rays, worldFromNdc, limits, signature);
  const double distance = std::sqrt(1.0 + 1.5 * 1.5 + 100.0);
  Check(any && limits.size() == zbuffer.size() &&
      std::abs(limits[3 * 9 + 4] - distance) <= 1e-3 * distance &&
      std::isinf(limits[0]),
    "a window depth becomes the world distance of its point (" +
      std::to_string(limits.empty() ? -1.0 : limits[3 * 9 + 4]) + " vs " +
      std::to_string(distance) + "); depth 1 is no limit");
  std::vector<float> empty(9 * 7, 1.0f);
  Check(!ptv::SetGeometryLimits(empty, rays, worldFromNdc, limits, signature) && limits.empty() &&
      limits.capacity() == 0,
    "no geometry: no limits, and no memory held for them");
}

void TestLighting()
{
  vtkNew<vtkRenderer> ren;
  ren->SetBackground(0.2, 0.4, 0.6);
  ptv::FrameSettings settings;
  settings.EnvironmentIntensity = 2.0;
  const double bounds[6] = { 0, 1, 0, 1, 0, 1 };
  ptv::TraceParams p{};
  ptv::FrameSignature signature;
  ptv::SetLighting(ren, settings, bounds, p, signature);
  const double fromBackground[3] = { 0.4, 0.8, 1.2 };
  Check(Near(p.Environment, fromBackground, 1e-6), "environment = background x intensity");
  settings.UseBackgroundAsEnvironment = false;
  settings.EnvironmentColor[0] = 1.0;
  settings.EnvironmentColor[1] = 0.5;
  settings.EnvironmentColor[2] = 0.0;
  ptv::SetLighting(ren, settings, bounds, p, signature);
  const double fromColour[3] = { 2.0, 1.0, 0.0 };
  Check(Near(p.Environment, fromColour, 1e-6), "environment = EnvironmentColor x intensity");
  settings.UseBackgroundAsEnvironment = true;
  ren->SetBackground(std::numeric_limits<double>::quiet_NaN(), 0.5, 0.5);
  ptv::SetLighting(ren, settings, bounds, p, signature);
  const double guarded[3] = { 0.0, 1.0, 1.0 };
  Check(Near(p.Environment, guarded, 1e-6), "a non-finite background component lights nothing");
}
}

int TestPTVSceneToKernel(int, char*[])
{
  TestVolumeTransform();
  TestClipping();
  TestCameraAndGeometry();
  TestLighting();
  return TestResult();
}
