#include "ptvSceneToKernel.h"

#include "vtkCamera.h"
#include "vtkImageData.h"
#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkMath.h"
#include "vtkMatrix3x3.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkRenderer.h"
#include "vtkVolume.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

namespace ptv
{
namespace
{
Vec3 ToVec3(const double v[3])
{
  return Vec3{ static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2]) };
}
}

//------------------------------------------------------------------------------
std::string NonFiniteGeometry(vtkImageData* image)
{
  double spacing[3], origin[3];
  image->GetSpacing(spacing);
  image->GetOrigin(origin);
  for (const auto& v : { std::make_pair("spacing", spacing), std::make_pair("origin", origin) })
  {
    if (!std::isfinite(v.second[0]) || !std::isfinite(v.second[1]) || !std::isfinite(v.second[2]))
    {
      std::ostringstream msg;
      msg << "non-finite image " << v.first << " (" << v.second[0] << ", " << v.second[1] << ", "
          << v.second[2] << ")";
      return msg.str();
    }
  }
  return std::string();
}

//------------------------------------------------------------------------------
bool SetVolumeTransform(vtkImageData* image, vtkVolume* vol, VolumeGrid& g, double& step,
  FrameSignature& signature, std::string& error)
{
  // Index -> world: volume matrix * (origin + direction * diag(spacing) * (extent min + ijk)).
  error = NonFiniteGeometry(image);
  if (!error.empty())
  {
    return false;
  }
  double spacing[3], origin[3];
  image->GetSpacing(spacing);
  image->GetOrigin(origin);
  if (spacing[0] == 0.0 || spacing[1] == 0.0 || spacing[2] == 0.0)
  {
    std::ostringstream msg;
    msg << "zero image spacing (" << spacing[0] << ", " << spacing[1] << ", " << spacing[2]
        << ")";
    error = msg.str();
    return false;
  }
  const vtkMatrix3x3* dir = image->GetDirectionMatrix();
  vtkMatrix4x4* m = vol->GetMatrix();
  // Kernel index (0, 0, 0) is the image's first point, at structured index (extent minimum):
  // its physical position is origin + direction * diag(spacing) * extent minimum.
  int extent[6];
  image->GetExtent(extent);
  double first[3];
  for (int r = 0; r < 3; ++r)
  {
    first[r] = origin[r];
    for (int c = 0; c < 3; ++c)
    {
      first[r] += dir->GetElement(r, c) * spacing[c] * extent[2 * c];
    }
  }
  double a[3][3], t[3];
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 3; ++c)
    {
      double v = 0.0;
      for (int k = 0; k < 3; ++k)
      {
        v += m->GetElement(r, k) * dir->GetElement(k, c);
      }
      a[r][c] = v * spacing[c];
    }
    double o = m->GetElement(r, 3);
    for (int k = 0; k < 3; ++k)
    {
      o += m->GetElement(r, k) * first[k];
    }
    t[r] = o;
  }
  double inv[3][3];
  if (std::abs(vtkMath::Determinant3x3(a)) < 1e-300)
  {
    error = "the volume's index-to-world transform is singular (check the vtkVolume matrix)";
    return false;
  }
  vtkMath::Invert3x3(a, inv);
    for (int r = 0; r < 3; ++r)
  {
    double ti = 0.0;
    for (int c = 0; c < 3; ++c)
    {
      g.WorldToIndex[4 * r + c] = static_cast<float>(inv[r][c]);
      g.NormalToWorld[3 * r + c] = static_cast<float>(inv[c][r]);
      ti -= inv[r][c] * t[c];
    }
    g.WorldToIndex[4 * r + 3] = static_cast<float>(ti);
  }
  signature.AddApproximate(&a[0][0], 9);
  signature.AddApproximate(t, 3);
  step = std::numeric_limits<double>::max();
  for (int c = 0; c < 3; ++c)
  {
    step = std::min(step, std::sqrt(a[0][c] * a[0][c] + a[1][c] * a[1][c] + a[2][c] * a[2][c]));
  }
  return true;
}

//------------------------------------------------------------------------------
void SetClipping(const FrameSettings& settings, vtkImageData* image, const VolumeGrid& g,
  ClipRegion& clip, FrameSignature& signature)
{
  // World plane n.x + d >= 0 with x = M^-1 (i - t) for index i = M x + t (WorldToIndex):
  // (n^T M^-1) i + (d - n^T M^-1 t) >= 0.
  double m[3][3], mInv[3][3], t[3];
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 3; ++c)
    {
      m[r][c] = g.WorldToIndex[4 * r + c];
    }
    t[r] = g.WorldToIndex[4 * r + 3];
  }
  vtkMath::Invert3x3(m, mInv);
  clip.PlaneCount = std::min(settings.ClipPlaneCount, 6);
  for (int i = 0; i < clip.PlaneCount; ++i)
  {
    const double* n = settings.ClipPlanes[i];
    double ni[3] = { 0, 0, 0 }; // n^T M^-1
    for (int c = 0; c < 3; ++c)
    {
      for (int r = 0; r < 3; ++r)
      {
        ni[c] += n[r] * mInv[r][c];
      }
    }
    const double di = n[3] - (ni[0] * t[0] + ni[1] * t[1] + ni[2] * t[2]);
    for (int c = 0; c < 3; ++c)
    {
      clip.Planes[i][c] = static_cast<float>(ni[c]);
    }
    clip.Planes[i][3] = static_cast<float>(di);
    signature.AddApproximate(n, 4);
  }
  clip.Cropping = settings.Cropping ? 1 : 0;
  if (clip.Cropping)
  {
    // As vtkVolumeMapper: (plane - position of the first point) / spacing, per axis.
    double origin[3], spacing[3];
    int extent[6];
    image->GetOrigin(origin);
    image->GetSpacing(spacing);
    image->GetExtent(extent);
    for (int a = 0; a < 3; ++a)
    {
      const double first = origin[a] + spacing[a] * extent[2 * a];
      double lo = (settings.CroppingPlanes[2 * a] - first) / spacing[a];
      double hi = (settings.CroppingPlanes[2 * a + 1] - first) / spacing[a];
      if (lo > hi)
      {
        std::swap(lo, hi);
      }
      const double last = static_cast<double>(g.Dims[a] - 1);
      clip.CropPlanes[2 * a] = static_cast<float>(std::min(last, std::max(0.0, lo)));
      clip.CropPlanes[2 * a + 1] = static_cast<float>(std::min(last, std::max(0.0, hi)));
    }
    clip.CropFlags = settings.CroppingFlags;
    signature.AddApproximate(settings.CroppingPlanes, 6);
  }
  const double flags[3] = { static_cast<double>(clip.PlaneCount),
    static_cast<double>(clip.Cropping), static_cast<double>(clip.Cropping ? clip.CropFlags : 0) };
  signature.AddExact(flags, 3);
}

//------------------------------------------------------------------------------
void SetCamera(vtkRenderer* ren, int width, int height, CameraRays& camera,
  double worldFromNdc[16], FrameSignature& signature)
{
  vtkCamera* cam = ren->GetActiveCamera();
  const double aspect = static_cast<double>(width) / static_cast<double>(height);
  vtkNew<vtkMatrix4x4> inverse;
  inverse->DeepCopy(cam->GetCompositeProjectionTransformMatrix(aspect, -1, 1));
  inverse->Invert();
  for (int i = 0; i < 16; ++i)
  {
    worldFromNdc[i] = inverse->GetElement(i / 4, i % 4);
    camera.WorldFromNdc[i] = static_cast<float>(worldFromNdc[i]);
  }
  // Sign what moves rays, not the projection matrix: the renderer resets the clipping range on
  // every render (tiny changes of near/far would reset the accumulation), and rays do not depend
  // on it (vtkOSPRayRendererNode compares camera parameters for the same reason).
  const double cameraKey[14] = { cam->GetPosition()[0], cam->GetPosition()[1],
    cam->GetPosition()[2], cam->GetFocalPoint()[0], cam->GetFocalPoint()[1],
    cam->GetFocalPoint()[2], cam->GetViewUp()[0], cam->GetViewUp()[1], cam->GetViewUp()[2],
    cam->GetViewAngle(), cam->GetParallelScale(), cam->GetParallelProjection() ? 1.0 : 0.0,
    cam->GetWindowCenter()[0], cam->GetWindowCenter()[1] };
  signature.AddView(cameraKey, 14);
  camera.Eye = ToVec3(cam->GetPosition());
  camera.Parallel = cam->GetParallelProjection() ? 1 : 0;
  camera.Width = width;
  camera.Height = height;
  camera.FarDistance = static_cast<float>(cam->GetClippingRange()[1]);
  const double size[2] = { static_cast<double>(width), static_cast<double>(height) };
  signature.AddExact(size, 2);
}

//------------------------------------------------------------------------------
void SetLighting(vtkRenderer* ren, const FrameSettings& settings, const double bounds[6],
  TraceParams& p, FrameSignature& signature)
{
  vtkCamera* cam = ren->GetActiveCamera();
  // Key light: first switched-on scene/camera light, else a point light above the volume.
  const double* b = bounds;
  const double center[3] = { (b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2 };
  const double diag = std::sqrt((b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) +
    (b[5] - b[4]) * (b[5] - b[4]));
  vtkLight* chosen = nullptr;
  if (settings.UseRendererLight)
  {
    vtkCollectionSimpleIterator it;
    ren->GetLights()->InitTraversal(it);
    while (vtkLight* light = ren->GetLights()->GetNextLight(it))
    {
      if (light->GetSwitch() && !light->LightTypeIsHeadlight())
      {
        chosen = light;
        break;
      }
    }
  }
  double lightPos[3], lightDir[3] = { 0, 0, -1 }, lightRad[3];
  int positional = 1;
  if (chosen)
  {
    double focal[3];
    chosen->GetTransformedPosition(lightPos);
    chosen->GetTransformedFocalPoint(focal);
    positional = chosen->GetPositional() ? 1 : 0;
    for (int k = 0; k < 3; ++k)
    {
      lightDir[k] = focal[k] - lightPos[k];
      lightRad[k] = chosen->GetDiffuseColor()[k] * chosen->GetIntensity() * settings.LightIntensity;
    }
    vtkMath::Normalize(lightDir);
  }
  else
  {
    double up[3], toEye[3];
    cam->GetViewUp(up);
    vtkMath::Normalize(up);
    const double* eye = cam->GetPosition();
    for (int k = 0; k < 3; ++k)
    {
      toEye[k] = eye[k] - center[k];
    }
    vtkMath::Normalize(toEye);
    for (int k = 0; k < 3; ++k)
    {
      lightPos[k] = center[k] + diag * (1.5 * up[k] + 0.5 * toEye[k]);
      lightRad[k] = settings.LightIntensity;
    }
  }
  p.KeyLight.Position = ToVec3(lightPos);
  p.KeyLight.Direction = ToVec3(lightDir);
  p.KeyLight.Positional = positional;
  p.KeyLight.Radiance = ToVec3(lightRad);
  // A light that follows the camera (VTK's camera lights, ParaView's light kit, the default
  // light) is part of the view: it moves when the camera does, and the history it lit fades
  // out (ptvReprojection); a scene light's change restarts the accumulation.
  if (!chosen || chosen->LightTypeIsCameraLight())
  {
    signature.AddView(lightPos, 3);
    signature.AddView(lightDir, 3);
  }
  else
  {
    signature.AddApproximate(lightPos, 3);
    signature.AddApproximate(lightDir, 3);
  }
  signature.AddExact(lightRad, 3);

  double env[3];
  const double* envSource =
    settings.UseBackgroundAsEnvironment ? ren->GetBackground() : settings.EnvironmentColor;
  for (int k = 0; k < 3; ++k)
  {
    // A renderer background is not range-checked by VTK: a non-finite one lights nothing.
    env[k] = std::isfinite(envSource[k]) ? envSource[k] * settings.EnvironmentIntensity : 0.0;
  }
  p.Environment = ToVec3(env);
  signature.AddExact(env, 3);
}

//------------------------------------------------------------------------------
bool SetGeometryLimits(const std::vector<float>& zbuffer, const CameraRays& camera,
  const double worldFromNdc[16], std::vector<float>& maxDistance, FrameSignature& signature)
{
  const int width = camera.Width;
  const int height = camera.Height;
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  bool anyGeometry = false;
  // Memory only when something is drawn (a depth below 1; NaN counts, as below).
  if (zbuffer.size() == pixels &&
    std::any_of(zbuffer.begin(), zbuffer.end(), [](float z) { return !(z >= 1.0f); }))
  {
    maxDistance.assign(pixels, std::numeric_limits<float>::infinity());
    double hash = 0.0;
    for (int y = 0; y < height; ++y)
    {
      for (int x = 0; x < width; ++x)
      {
        const std::size_t i = static_cast<std::size_t>(y) * width + x;
        const float z = zbuffer[i];
        if (z >= 1.0f)
        {
          continue;
        }
        anyGeometry = true;
        hash += (static_cast<double>(i % 9973) + 1.0) * z;
        const double ndc[4] = { 2.0 * (x + 0.5) / width - 1.0, 2.0 * (y + 0.5) / height - 1.0,
          2.0 * z - 1.0, 1.0 };
        double w[4];
        vtkMatrix4x4::MultiplyPoint(worldFromNdc, ndc, w);
        const Vec3 hit{ static_cast<float>(w[0] / w[3]), static_cast<float>(w[1] / w[3]),
          static_cast<float>(w[2] / w[3]) };
        Vec3 o, d;
        GenerateRay(camera, x + 0.5f, y + 0.5f, o, d);
        maxDistance[i] = std::max(0.0f, Dot(hit - o, d));
      }
    }
    signature.AddViewExact(&hash, 1); // moves with the camera
  }
  if (!anyGeometry)
  {
    std::vector<float>().swap(maxDistance);
  }
  return anyGeometry;
}
}
