#include "ptvShownImage.h"

#include "ptvPassBuffers.h"
#include "ptvThreads.h"

#include "vtkType.h"

#include "vtkCamera.h"
#include "vtkMatrix4x4.h"
#include "vtkRenderer.h"

#include <algorithm>
#include <limits>

namespace ptv
{
namespace
{
// Colour a pass for inspection: opaque, [0,1], misses black.
void Colorize(int pass, const PassBuffers& acc, const double* bounds, float far, float* rgb)
{
  const int n = acc.GetWidth() * acc.GetHeight();
  const int comps = GetPassInfo(pass).Components;
  const float* data = acc.Data(pass);
  float lo = std::numeric_limits<float>::max(), hi = -lo;
  if (pass == PassHistoryLength || pass == PassSampleRatio)
  {
    lo = 0.0f; // frames (samples) / the most: grey levels
    hi = std::max(1.0f, *std::max_element(data, data + n));
  }
  else if (comps == 1 && pass != PassAlpha && pass != PassDenoisedAlpha)
  {
    for (int i = 0; i < n; ++i)
    {
      if (IsHit(data[i], far))
      {
        lo = std::min(lo, data[i]);
        hi = std::max(hi, data[i]);
      }
    }
  }
  for (int i = 0; i < n; ++i)
  {
    float c[3] = { 0, 0, 0 };
    if (pass == PassAlpha || pass == PassDenoisedAlpha)
    {
      c[0] = c[1] = c[2] = data[i];
    }
    else if (pass == PassHistoryLength || pass == PassSampleRatio)
    {
      c[0] = c[1] = c[2] = data[i] / hi;
    }
    else if (comps == 1)
    {
      if (IsHit(data[i], far) && hi > lo)
      {
        c[0] = c[1] = c[2] = 1.0f - 0.9f * (data[i] - lo) / (hi - lo); // near = bright
      }
    }
    else if (pass == PassNormal || pass == PassScatterNormal)
    {
      const float* v = data + 3 * i;
      if (v[0] != 0.0f || v[1] != 0.0f || v[2] != 0.0f)
      {
        for (int k = 0; k < 3; ++k)
        {
          c[k] = 0.5f * v[k] + 0.5f;
        }
      }
    }
    else if (pass == PassPosition || pass == PassScatterPosition)
    {
      const float* v = data + 3 * i;
      const int depthPass = pass == PassPosition ? PassDepth : PassScatterDepth;
      if (IsHit(acc.Data(depthPass)[i], far)) // a miss stays black (its position 0 is a place)
      {
        for (int k = 0; k < 3; ++k)
        {
          const double extent = bounds[2 * k + 1] - bounds[2 * k];
          c[k] = extent > 0 ? static_cast<float>((v[k] - bounds[2 * k]) / extent) : 0.0f;
        }
      }
    }
    else
    {
      std::copy(data + 3 * i, data + 3 * i + 3, c);
    }
    for (int k = 0; k < 3; ++k)
    {
      rgb[3 * i + k] = std::min(1.0f, std::max(0.0f, c[k]));
    }
  }
}
}

//------------------------------------------------------------------------------
void ShownImage::Update(vtkRenderer* ren, const PassBuffers& passes, int pass,
  const CameraRays& camera, const double bounds[6], int threads, const float* shownAlpha)
{
  const int width = passes.GetWidth();
  const int height = passes.GetHeight();
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  this->RowCover.resize(2 * static_cast<std::size_t>(std::max(height, 0)));
  const bool radiance = pass == PassRadiance || pass == PassDenoised || pass == PassConverged;
  if (radiance)
  {
    std::vector<float>().swap(this->Color);
    std::vector<float>().swap(this->Alpha);
    this->ShownColor = passes.Data(pass);
    this->ShownAlpha = shownAlpha ? shownAlpha : passes.Data(PassAlpha);
  }
  else
  {
    this->Color.resize(3 * pixels);
    this->Alpha.assign(pixels, 1.0f);
    Colorize(pass, passes, bounds, camera.FarDistance, this->Color.data());
    this->ShownColor = this->Color.data();
    this->ShownAlpha = this->Alpha.data();
  }

  // Window depth: only the last two rows of the projection matter (z and w).
  const double aspect = static_cast<double>(width) / static_cast<double>(height);
  vtkMatrix4x4* toNdc =
    ren->GetActiveCamera()->GetCompositeProjectionTransformMatrix(aspect, -1, 1);
  for (int c = 0; c < 4; ++c)
  {
    this->ZRow[c] = toNdc->GetElement(2, c);
    this->WRow[c] = toNdc->GetElement(3, c);
  }
  this->RayDepth = passes.Data(PassDepth);
  this->Camera = camera;
  this->Width = width;
  this->Threads = threads;

  const float* alpha = this->ShownAlpha;
  int* rowCover = this->RowCover.data();
  ParallelFor(threads, 0, height, 16,
    [&](vtkIdType yBegin, vtkIdType yEnd)
    {
      for (vtkIdType y = yBegin; y < yEnd; ++y)
      {
        int first = width, last = -1; // the row's drawn pixels (alpha not <= 0, as the shader)
        const float* a = alpha + static_cast<std::size_t>(y) * width;
        for (int x = 0; x < width; ++x)
        {
          if (!(a[x] <= 0.0f))
          {
            first = std::min(first, x);
            last = x;
          }
        }
        rowCover[2 * y] = first;
        rowCover[2 * y + 1] = last;
      }
    });
  this->Covered[0] = width;
  this->Covered[1] = height;
  this->Covered[2] = this->Covered[3] = 0;
  for (int y = 0; y < height; ++y)
  {
    if (rowCover[2 * y + 1] >= rowCover[2 * y])
    {
      this->Covered[0] = std::min(this->Covered[0], rowCover[2 * y]);
      this->Covered[1] = std::min(this->Covered[1], y);
      this->Covered[2] = std::max(this->Covered[2], rowCover[2 * y + 1] + 1);
      this->Covered[3] = y + 1;
    }
  }
  if (this->Covered[2] <= this->Covered[0])
  {
    this->Covered[0] = this->Covered[1] = 0; // nothing drawn
  }
}

//------------------------------------------------------------------------------
void ShownImage::WindowDepth(int x0, int y0, int x1, int y1, float* out) const
{
  const int width = this->Width;
  const int columns = x1 - x0;
  if (!this->RayDepth || columns <= 0 || y1 <= y0)
  {
    return;
  }
  const float far = this->Camera.FarDistance;
  const float* depth = this->RayDepth;
  ParallelFor(this->Threads, y0, y1, 16,
    [&](vtkIdType yBegin, vtkIdType yEnd)
    {
      for (vtkIdType y = yBegin; y < yEnd; ++y)
      {
        float* shown = out + static_cast<std::size_t>(y - y0) * columns;
        for (int x = x0; x < x1; ++x)
        {
          const std::size_t i = static_cast<std::size_t>(y) * width + x;
          float& z = shown[x - x0];
          z = 1.0f;
          if (!IsHit(depth[i], far))
          {
            continue;
          }
          Vec3 o, d;
          GenerateRay(this->Camera, x + 0.5f, static_cast<float>(y) + 0.5f, o, d);
          const Vec3 p = o + d * depth[i];
          const double zc = this->ZRow[0] * p.x + this->ZRow[1] * p.y + this->ZRow[2] * p.z +
            this->ZRow[3];
          const double w = this->WRow[0] * p.x + this->WRow[1] * p.y + this->WRow[2] * p.z +
            this->WRow[3];
          if (w != 0.0)
          {
            z = static_cast<float>(std::min(1.0, std::max(0.0, 0.5 * (zc / w) + 0.5)));
          }
        }
      }
    });
}

//------------------------------------------------------------------------------
void ShownImage::Release()
{
  std::vector<float>().swap(this->Color);
  std::vector<float>().swap(this->Alpha);
  this->ShownColor = this->ShownAlpha = this->RayDepth = nullptr;
}
}
