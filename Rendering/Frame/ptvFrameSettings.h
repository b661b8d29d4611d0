/**
 * @file ptvFrameSettings.h
 * @brief Private: the mapper's settings that reach the kernel, as the mapper hands them to the
 *        frame loop each render (ptvFrameInputs turns them into TraceParams).
 */
#ifndef ptvFrameSettings_h
#define ptvFrameSettings_h

#include "Kernels/ptvIsosurface.h"

namespace ptv
{
/// The mapper settings that reach the kernel.
struct FrameSettings
{
  unsigned int Seed = 0;
  int SamplesPerFrame = 1;
  bool Scattering = true;
  bool AmbientOcclusion = true;
  double AmbientOcclusionReach = 1.0; ///< fraction of the volume's diagonal (>= 1: unlimited)
  bool UseRendererLight = true;
  double LightIntensity = 1.0;
  double EnvironmentColor[3] = { 1, 1, 1 };
  bool UseBackgroundAsEnvironment = true;
  double EnvironmentIntensity = 1.0;
  bool EmptySpaceSkipping = true;
  /// March each camera ray past its event for its opacity, the Coverage pass
  /// (TraceParams::CoverageMarch): asked for, or set by the frame loop when the denoiser's
  /// model reads it.
  bool CoverageMarch = false;
  /// Weight each camera ray's event by its opacity (TraceParams::ExpectedCoverage).
  bool ExpectedCoverage = false;
  /// Look for empty pixels with four fixed rays, the Footprint pass
  /// (TraceParams::FootprintRays): asked for, or set by the frame loop when it denoises.
  bool FootprintRays = false;
  /// Clipping planes in world space, kept where n.x + d >= 0: (n.x, n.y, n.z, d), at most 6.
  int ClipPlaneCount = 0;
  double ClipPlanes[6][4] = {};
  /// vtkVolumeMapper cropping: planes in the image's coordinates (origin and spacing applied).
  bool Cropping = false;
  double CroppingPlanes[6] = {};
  int CroppingFlags = 0;
  /// Isosurface blend mode: the property's iso values (sorted, at most 8); Count 0: composite.
  IsoSurfaces Iso;
  /// The same values in double (the data's units: FrameInputs stores them as its voxels).
  double IsoValues[kMaxIsoValues] = {};
  /// An intensity projection instead of the medium (TraceParams::Projection; 0: none), and the
  /// scalars an average counts (the data's units; vtkVolumeMapper::AverageIPScalarRange).
  int Projection = 0;
  double AverageRange[2] = { -1e300, 1e300 };
  /// A piece of a distributed volume: this process's own extent (structured point indices)
  /// inside the image's, which camera rays stay in (the rest is a ghost layer). Empty (x0 > x1,
  /// the default): the whole image.
  int PieceExtent[6] = { 0, -1, 0, -1, 0, -1 };
  /// The whole volume's extent (all pieces); empty: the union of the processes' pieces.
  int WholeExtent[6] = { 0, -1, 0, -1, 0, -1 };
};
}

#endif
