/**
 * @file ptvTraceParams.h
 * @brief What one trace needs and returns: the key light, the frame's parameters (volume,
 *        tables, occupancy, clipping, isosurfaces, camera, shading) and one pixel sample.
 *
 * Plain structs of pointers and PODs, copied by value to the CUDA kernel. See ptvIntegrator.h
 * for how they are used.
 */
#ifndef ptvTraceParams_h
#define ptvTraceParams_h

#include "ptvCamera.h"
#include "ptvClipping.h"
#include "ptvIsosurface.h"
#include "ptvKernelCommon.h"
#include "ptvOccupancy.h"
#include "ptvTransferTable.h"
#include "ptvVolumeGrid.h"

namespace ptv
{
struct Light
{
  Vec3 Position;  ///< world position (positional lights)
  Vec3 Direction; ///< direction the light travels (directional lights)
  int Positional; ///< 1: point light at Position, 0: directional
  Vec3 Radiance;  ///< colour * intensity
};

struct TraceParams
{
  VolumeGrid Volume;
  TransferTable Transfer;
  OccupancyGrid Occupancy; ///< Occupancy.SkipDistance == nullptr: no skipping
  ClipRegion Clip;         ///< clipping planes and cropping (ptvClipping.h); default: none
  IsoSurfaces Iso;         ///< Iso.Count > 0: isosurfaces instead of the composite medium
  TransferTable ColorTable; ///< colours of Volume.ColorScalars (2-component data); else unused
  CameraRays Camera;
  Light KeyLight;
  Vec3 Environment;      ///< uniform environment radiance
  float StepWorld;       ///< camera-ray step in world units (typically one voxel)
  float ShadowStepScale; ///< shadow/environment step = StepWorld * ShadowStepScale (default 2)
  float UnitDistance;    ///< ScalarOpacityUnitDistance (world units)
  int Shade;
  float Ambient, Diffuse, Specular, SpecularPower;
  int Scattering;       ///< 1: event at a random opacity threshold, 0: first non-transparent sample
  int AmbientOcclusion; ///< 1: environment visibility traced, 0: unoccluded environment
  int Nearest;          ///< 1: nearest-voxel classification (VTK_NEAREST_INTERPOLATION)
  const float* MaxDistance; ///< per-pixel ray-length limit (world distance), nullptr = none
  uint32_t Seed;
  uint32_t Frame;
};

struct PixelSample
{
  Vec3 Radiance; ///< premultiplied radiance (0 without an event)
  float Alpha;   ///< 1 with an event, else 0
  Vec3 Albedo;   ///< colour at the first event
  float Depth1;  ///< first event: ray distance
  Vec3 Position1;
  Vec3 Normal1;
  float Depth2; ///< sampled (scattering) event: ray distance
  Vec3 Position2;
  Vec3 Normal2;
};

/// acc += s, field by field (averaging several samples of a pixel: CPU and CUDA drivers).
PTV_HD PTV_INLINE void AddSample(PixelSample& acc, const PixelSample& s)
{
  acc.Radiance = acc.Radiance + s.Radiance;
  acc.Alpha += s.Alpha;
  acc.Albedo = acc.Albedo + s.Albedo;
  acc.Depth1 += s.Depth1;
  acc.Position1 = acc.Position1 + s.Position1;
  acc.Normal1 = acc.Normal1 + s.Normal1;
  acc.Depth2 += s.Depth2;
  acc.Position2 = acc.Position2 + s.Position2;
  acc.Normal2 = acc.Normal2 + s.Normal2;
}

/// acc *= w, field by field.
PTV_HD PTV_INLINE void ScaleSample(PixelSample& acc, float w)
{
  acc.Radiance = acc.Radiance * w;
  acc.Alpha *= w;
  acc.Albedo = acc.Albedo * w;
  acc.Depth1 *= w;
  acc.Position1 = acc.Position1 * w;
  acc.Normal1 = acc.Normal1 * w;
  acc.Depth2 *= w;
  acc.Position2 = acc.Position2 * w;
  acc.Normal2 = acc.Normal2 * w;
}
}

#endif
