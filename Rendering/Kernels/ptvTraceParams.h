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
  OccupancyGrid Occupancy; ///< Occupancy.Distance == nullptr: no skipping
  ClipRegion Clip;         ///< clipping planes and cropping (ptvClipping.h); default: none
  IsoSurfaces Iso;         ///< Iso.Count > 0: isosurfaces instead of the composite medium
  /// VTK's intensity projections instead of the medium (kProjection*; 0: none; ptvIntegrator.h,
  /// "Projections"); AverageLo/Hi: the scalars an average counts (stored units).
  int Projection;
  float AverageLo, AverageHi;
  TransferTable ColorTable; ///< colours of Volume.ColorScalars (2-component data); else unused
  CameraRays Camera;
  Light KeyLight;
  Vec3 Environment;      ///< uniform environment radiance
  float StepWorld;       ///< camera-ray step in world units (typically one voxel)
  float ShadowStepScale; ///< shadow/environment step = StepWorld * ShadowStepScale (default 2)
  /// Transmittance rays play Russian roulette while T is below this (<= 0: kRouletteThreshold)
  float RouletteThreshold;
  float UnitDistance;    ///< ScalarOpacityUnitDistance (world units)
  int Shade;
  float Ambient, Diffuse, Specular, SpecularPower;
  int Scattering;       ///< 1: event at a random opacity threshold, 0: first non-transparent sample
  /// vtkPathTracedVolumeMapper::ExpectedCoverage (or PTV_EXPECTED_COVERAGE=1), with
  /// Scattering and a composite medium: 1 marches each camera ray to its end (until its
  /// transmittance is below kCoverageCutoff), stores the ray's opacity as Alpha and draws the
  /// event among its samples in proportion to their share of it (ptvIntegrator.h, step 4b);
  /// 0 (default): the event decides Alpha, 0 or 1. Ignored with CameraBoxed.
  int ExpectedCoverage;
  /// 1: every camera ray's march goes on past its event (until its transmittance is below
  /// kCoverageMarchCutoff or the ray ends) for the ray's opacity, the Coverage field
  /// (ptvIntegrator.h, step 4c); every other field is unchanged. Set when the denoiser's model
  /// reads the "coverage" channel. 0: Coverage is the sample's Alpha. Ignored without
  /// Scattering and with isosurfaces (Coverage = Alpha).
  int CoverageMarch;
  /// 1: where a camera ray meets no opacity but comes near it, a ray through its pixel's corner
  /// looks for opacity: the Footprint field (ptvIntegrator.h, step 4d), 0 where the pixel is
  /// taken for empty space. Set when the frame is denoised. 0: Footprint is 1 (nothing is known
  /// to be empty). Draws no random numbers: every other field is unchanged.
  int FootprintRays;
  int AmbientOcclusion; ///< 1: environment visibility traced, 0: unoccluded environment
  /// With AmbientOcclusion: the farthest an environment ray looks for occluders (world
  /// distance; what lies beyond does not occlude); <= 0: to the volume's exit.
  float EnvironmentReach;
  int Nearest;          ///< 1: nearest-voxel classification (VTK_NEAREST_INTERPOLATION)
  const float* MaxDistance; ///< per-pixel ray-length limit (world distance), nullptr = none
  /// A piece of a distributed volume (vtkPathTracedVolumeMapper::DistributedVolume): camera rays
  /// stay inside this index-space box (x0, x1, y0, y1, z0, z1), this process's own piece; the
  /// rest of the grid is a ghost layer that only shadow and environment rays see.
  /// CameraBoxed == 0: camera rays cross the whole grid.
  int CameraBoxed;
  float CameraBox[6];
  float WholeBox[6]; ///< with CameraBoxed: the whole volume's box (all pieces), index space
  /// A piece's own random numbers: 0 (default) draws a sample from MakeRng(pixel, sample,
  /// Seed) alone; k > 0 keeps that stream for the pixel jitter only (every piece traces the same
  /// camera ray) and draws the rest from a stream of its own (independent pieces).
  uint32_t PieceStream;
  uint32_t Seed;
  uint32_t Frame;
};

/// TraceParams::Projection: VTK's blend modes MaximumIntensity, MinimumIntensity,
/// AverageIntensity and Additive (vtkVolumeMapper::*_BLEND 1-4).
constexpr int kProjectionMaximum = 1;
constexpr int kProjectionMinimum = 2;
constexpr int kProjectionAverage = 3;
constexpr int kProjectionAdditive = 4;

/// A depth below this fraction of the far distance is a hit (features.py: HIT_FRACTION); misses
/// are stored at the far distance itself.
constexpr float kHitFraction = 0.999f;

/// ExpectedCoverage: a camera ray stops once its transmittance is below this; what lies behind
/// would add less than this to its opacity (and its share of the radiance).
constexpr float kCoverageCutoff = 1e-4f;

/// CoverageMarch: a camera ray stops once its transmittance is below this after its event. The
/// Coverage it stores is then above 0.99, which the denoiser reads as opaque.
constexpr float kCoverageMarchCutoff = 1e-2f;

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
  /// The camera ray's opacity 1 - T over its whole march, the expectation of Alpha (noise-free:
  /// it depends on the pixel's jitter only), with TraceParams::CoverageMarch; else Alpha.
  float Coverage;
  /// With TraceParams::FootprintRays: 1 where the camera ray met opacity, else whether the ray
  /// through the pixel's corner (x, y) does (0 when the camera ray only crossed empty bricks);
  /// 1 without FootprintRays (ptvIntegrator.h, step 4d).
  float Footprint;
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
  acc.Coverage += s.Coverage;
  acc.Footprint += s.Footprint;
}

/**
 * One sample of a pixel through two pieces of a volume, @a front first along the ray, from one
 * sample of each along the same camera ray (same jitter and march offset, independent events:
 * TraceParams::PieceStream): the sample of the ray through both. An event in the back piece
 * counts only where the front one has none (Alpha 0), and the event's fields (Radiance, Alpha,
 * Depth2, Position2, Normal2) come from the piece that holds it; the first-hit fields (Albedo,
 * Depth1, Position1, Normal1) from the nearest piece with a first hit; Coverage is the front's
 * opacity over the back's (exact for the expected opacities of one camera ray); Footprint is
 * 1 where either piece's rays met opacity. Misses store
 * @a far as their depths (Camera.FarDistance). Single samples only: for means of several samples the
 * product of the front's coverage and the back's radiance is not the mean of the products.
 */
PTV_HD PTV_INLINE PixelSample OverSample(const PixelSample& front, const PixelSample& back,
  float far)
{
  PixelSample o;
  const float keep = 1.f - front.Alpha; // no event in front: the back piece's event counts
  o.Radiance = front.Radiance + back.Radiance * keep;
  o.Alpha = front.Alpha + back.Alpha * keep;
  o.Depth2 = front.Depth2 + (back.Depth2 - far) * keep; // a miss stores far: remove it
  o.Position2 = front.Position2 + back.Position2 * keep;
  o.Normal2 = front.Normal2 + back.Normal2 * keep;
  const float keep1 = front.Depth1 < kHitFraction * far ? 0.f : 1.f;
  o.Albedo = front.Albedo + back.Albedo * keep1;
  o.Depth1 = front.Depth1 + (back.Depth1 - far) * keep1;
  o.Position1 = front.Position1 + back.Position1 * keep1;
  o.Normal1 = front.Normal1 + back.Normal1 * keep1;
  o.Coverage = front.Coverage + back.Coverage * (1.f - front.Coverage); // the opacities' over
  o.Footprint = Max(front.Footprint, back.Footprint);
  return o;
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
  acc.Coverage *= w;
  acc.Footprint *= w;
}
}

#endif
