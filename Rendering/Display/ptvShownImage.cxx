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
void Colorize(int pass, const PassBuffers& acc, const double* bounds, float far, float* rgba)
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
      rgba[4 * i + k] = std::min(1.0f, std::max(0.0f, c[k]));
    }
    rgba[4 * i + 3] = 1.0f;
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
  this->Color.resize(4 * pixels);
  this->Depth.resize(pixels);
  this->RowCover.resize(2 * static_cast<std::size_t>(std::max(height, 0)));
  const float far = camera.FarDistance;
  const bool radiance = pass == PassRadiance || pass == PassDenoised || pass == PassConverged;
  if (!radiance)
  {
    Colorize(pass, passes, bounds, far, this->Color.data());
  }

  // Window depth: only the last two rows of the projection matter (z and w).
  const double aspect = static_cast<double>(width) / static_cast<double>(height);
  vtkMatrix4x4* toNdc =
    ren->GetActiveCamera()->GetCompositeProjectionTransformMatrix(aspect, -1, 1);
  double zRow[4], wRow[4];
  for (int c = 0; c < 4; ++c)
  {
    zRow[c] = toNdc->GetElement(2, c);
    wRow[c] = toNdc->GetElement(3, c);
  }
  const float* rgb = passes.Data(radiance ? pass : PassRadiance);
  const float* alpha = shownAlpha ? shownAlpha : passes.Data(PassAlpha);
  const float* depth = passes.Data(PassDepth);
  float* color = this->Color.data();
  float* shown = this->Depth.data();
  int* rowCover = this->RowCover.data();
  ParallelFor(threads, 0, height, 16,
    [&](vtkIdType yBegin, vtkIdType yEnd)
    {
      for (vtkIdType y = yBegin; y < yEnd; ++y)
      {
        int first = width, last = -1; // the row's drawn pixels (alpha not <= 0, as the shader)
        for (int x = 0; x < width; ++x)
        {
          const std::size_t i = static_cast<std::size_t>(y) * width + x;
          if (radiance)
          {
            std::copy(rgb + 3 * i, rgb + 3 * i + 3, color + 4 * i);
            color[4 * i + 3] = alpha[i];
          }
          if (!(color[4 * i + 3] <= 0.0f))
          {
            first = std::min(first, x);
            last = x;
          }
          shown[i] = 1.0f;
          if (!IsHit(depth[i], far))
          {
            continue;
          }
          Vec3 o, d;
          GenerateRay(camera, x + 0.5f, static_cast<float>(y) + 0.5f, o, d);
          const Vec3 p = o + d * depth[i];
          const double z = zRow[0] * p.x + zRow[1] * p.y + zRow[2] * p.z + zRow[3];
          const double w = wRow[0] * p.x + wRow[1] * p.y + wRow[2] * p.z + wRow[3];
          if (w != 0.0)
          {
            shown[i] = static_cast<float>(std::min(1.0, std::max(0.0, 0.5 * (z / w) + 0.5)));
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
}
