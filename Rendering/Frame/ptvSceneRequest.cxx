#include "ptvSceneRequest.h"


#include "Kernels/ptvTraceParams.h"
#include "ptvFrameSettings.h"

#include "vtkContourValues.h"
#include "vtkMath.h"
#include "vtkPlane.h"
#include "vtkPlaneCollection.h"
#include "vtkVolumeMapper.h"
#include "vtkVolumeProperty.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace ptv
{
// Clipping planes (world) and cropping into the frame settings; bad ones reported and skipped.
// A problem is reported when the set of problems differs from the last frame's (@a reported).
void GatherClipping(vtkVolumeMapper* self, ptv::FrameSettings& scene, std::string& reported)
{
  std::ostringstream problems;
  scene.ClipPlaneCount = 0;
  vtkPlaneCollection* planes = self->GetClippingPlanes();
  const int count = planes ? planes->GetNumberOfItems() : 0;
  for (int i = 0; i < count; ++i)
  {
    vtkPlane* plane = planes->GetItem(i);
    double n[3], o[3];
    plane->GetNormal(n);
    plane->GetOrigin(o);
    const bool finite = std::all_of(n, n + 3, [](double v) { return std::isfinite(v); }) &&
      std::all_of(o, o + 3, [](double v) { return std::isfinite(v); });
    std::ostringstream problem;
    if (!finite || (n[0] == 0.0 && n[1] == 0.0 && n[2] == 0.0))
    {
      problem << "clipping plane " << i << " has normal (" << n[0] << ", " << n[1] << ", " << n[2]
              << ") and origin (" << o[0] << ", " << o[1] << ", " << o[2]
              << "); it is ignored (a plane needs a finite, non-zero normal and a finite origin)";
    }
    else if (scene.ClipPlaneCount == 6)
    {
      problems << count << " clipping planes; only the first 6 are used (VTK's limit)\n";
      break;
    }
    if (!problem.str().empty())
    {
      problems << problem.str() << "\n";
      continue;
    }
    double* q = scene.ClipPlanes[scene.ClipPlaneCount++];
    std::copy(n, n + 3, q);
    q[3] = -vtkMath::Dot(n, o);
  }
  scene.Cropping = self->GetCropping() != 0;
  if (scene.Cropping)
  {
    const double* c = self->GetCroppingRegionPlanes();
    if (!std::all_of(c, c + 6, [](double v) { return std::isfinite(v); }))
    {
      std::ostringstream problem;
      problem << "cropping region planes (" << c[0] << ", " << c[1] << ", " << c[2] << ", "
              << c[3] << ", " << c[4] << ", " << c[5] << ") are not finite; cropping is off";
      problems << problem.str() << "\n";
      scene.Cropping = false;
    }
    else
    {
      std::copy(c, c + 6, scene.CroppingPlanes);
      scene.CroppingFlags = self->GetCroppingRegionFlags();
    }
  }
  if (problems.str() != reported)
  {
    reported = problems.str();
    std::istringstream lines(reported);
    for (std::string line; std::getline(lines, line);)
    {
      vtkErrorWithObjectMacro(self, << line);
    }
  }
}

// The blend mode: Composite is the path tracer; IsoSurface traces the property's iso values as
// surfaces (into scene.Iso); the intensity projections (maximum, minimum, average, additive) are
// ray cast (scene.Projection), except for a volume split across processes, whose pieces are
// composited front to back; Slice renders Composite. A problem (unsupported mode, no or too many
// or NaN iso values) is reported when it differs from the last one (@a reported).
static_assert(ptv::kProjectionMaximum == vtkVolumeMapper::MAXIMUM_INTENSITY_BLEND &&
    ptv::kProjectionMinimum == vtkVolumeMapper::MINIMUM_INTENSITY_BLEND &&
    ptv::kProjectionAverage == vtkVolumeMapper::AVERAGE_INTENSITY_BLEND &&
    ptv::kProjectionAdditive == vtkVolumeMapper::ADDITIVE_BLEND,
  "the kernel's projections use vtkVolumeMapper's blend-mode numbers");

void GatherBlendMode(vtkVolumeMapper* self, bool distributed, vtkVolumeProperty* property,
  ptv::FrameSettings& scene, std::string& reported)
{
  static const char* const names[] = { "Composite", "MaximumIntensity", "MinimumIntensity",
    "AverageIntensity", "Additive", "IsoSurface", "Slice" };
  const int mode = self->GetBlendMode();
  std::ostringstream problem;
  scene.Iso.Count = 0;
  scene.Projection = 0;
  const bool projection = mode >= vtkVolumeMapper::MAXIMUM_INTENSITY_BLEND &&
    mode <= vtkVolumeMapper::ADDITIVE_BLEND;
  if (projection && distributed)
  {
    problem << "BlendMode " << names[mode] << " (" << mode
            << ") is not supported for a volume split across processes (DistributedVolume); "
               "it renders Composite (path traced).";
  }
  else if (projection)
  {
    scene.Projection = mode; // ptv::kProjection* are vtkVolumeMapper's numbers
    self->GetAverageIPScalarRange(scene.AverageRange);
  }
  else if (mode == vtkVolumeMapper::ISOSURFACE_BLEND)
  {
    vtkContourValues* values = property ? property->GetIsoSurfaceValues() : nullptr;
    const int n = values ? values->GetNumberOfContours() : 0;
    std::vector<double> kept;
    for (int i = 0; i < n; ++i)
    {
      const double v = values->GetValue(i);
      if (!std::isfinite(v))
      {
        problem << "iso value " << i << " is " << v << "; it is ignored. ";
        continue;
      }
      kept.push_back(v);
    }
    std::sort(kept.begin(), kept.end());
    kept.erase(std::unique(kept.begin(), kept.end()), kept.end());
    if (kept.size() > static_cast<std::size_t>(ptv::kMaxIsoValues))
    {
      problem << kept.size() << " iso values; the lowest " << ptv::kMaxIsoValues
              << " are traced. ";
      kept.resize(ptv::kMaxIsoValues);
    }
    if (kept.empty())
    {
      problem << "BlendMode IsoSurface without iso values draws nothing; add them with "
                 "GetIsoSurfaceValues()->SetValue(i, value) on the volume property. ";
      scene.Iso.Count = 1;
      scene.Iso.Values[0] = std::numeric_limits<float>::infinity(); // crosses nothing
    }
    else
    {
      scene.Iso.Count = static_cast<int>(kept.size());
      std::copy(kept.begin(), kept.end(), scene.IsoValues); // stored as the voxels are
      std::transform(kept.begin(), kept.end(), scene.Iso.Values,
        [](double v) { return static_cast<float>(v); });
    }
  }
  else if (mode != vtkVolumeMapper::COMPOSITE_BLEND)
  {
    problem << "BlendMode " << (mode >= 0 && mode < 7 ? names[mode] : "unknown") << " (" << mode
            << ") is not supported by the path tracer; it renders Composite (path traced). "
               "Use vtkGPUVolumeRayCastMapper for slices.";
  }
  if (problem.str() != reported)
  {
    reported = problem.str();
    if (!reported.empty())
    {
      vtkWarningWithObjectMacro(self, << reported);
    }
  }
}
} // namespace ptv
