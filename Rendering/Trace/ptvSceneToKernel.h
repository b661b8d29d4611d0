/**
 * @file ptvSceneToKernel.h
 * @brief Private: the pieces of a VTK scene that become kernel structs each frame -- volume
 *        transform, camera rays, key light and environment, opaque-geometry limits -- each
 *        adding the values that change the image to the frame's signature.
 *
 * ptvFrameInputs::Build() calls them in this order; they hold no state.
 */
#ifndef ptvSceneToKernel_h
#define ptvSceneToKernel_h

#include "Kernels/ptvIntegrator.h"
#include "ptvFrameSettings.h"
#include "ptvFrameSignature.h"

#include <string>
#include <vector>

class vtkImageData;
class vtkRenderer;
class vtkVolume;

namespace ptv
{
/// "non-finite image spacing (nan, 1, 1)" or "... origin (...)" for such an image, else "".
std::string NonFiniteGeometry(vtkImageData* image);

/**
 * Index -> world of @a image placed by @a vol (volume matrix * (origin + direction *
 * diag(spacing) * ijk)) into @a g's WorldToIndex and NormalToWorld; @a step receives the
 * shortest voxel edge in world units. False + @a error for a non-finite or zero spacing, a
 * non-finite origin or a singular transform.
 */
bool SetVolumeTransform(vtkImageData* image, vtkVolume* vol, VolumeGrid& g, double& step,
  FrameSignature& signature, std::string& error);

/**
 * The kept part of the volume (Kernels/ptvClipping.h): @a settings' world clipping planes moved
 * to index space with @a g's WorldToIndex, and its cropping planes to index space with the
 * image's origin and spacing (as vtkVolumeMapper converts them: clamped to the index box of
 * @a g's Dims, each pair in increasing order).
 */
void SetClipping(const FrameSettings& settings, vtkImageData* image, const VolumeGrid& g,
  ClipRegion& clip, FrameSignature& signature);

/**
 * Rays of @a ren's active camera for a @a width x @a height viewport; @a worldFromNdc receives
 * the inverse of its composite projection (row-major, double), for SetGeometryLimits().
 */
void SetCamera(vtkRenderer* ren, int width, int height, CameraRays& camera,
  double worldFromNdc[16], FrameSignature& signature);

/**
 * The key light (the renderer's first switched-on scene or camera light when
 * settings.UseRendererLight, else a point light above the volume with world bounds @a bounds)
 * and the uniform environment.
 */
void SetLighting(vtkRenderer* ren, const FrameSettings& settings, const double bounds[6],
  TraceParams& p, FrameSignature& signature);

/**
 * Opaque geometry: the world distance along each pixel's centre ray to the window depth in
 * @a zbuffer (values < 1), written into @a maxDistance (infinity elsewhere). Returns whether
 * any pixel has geometry (otherwise @a maxDistance is empty).
 */
bool SetGeometryLimits(const std::vector<float>& zbuffer, const CameraRays& camera,
  const double worldFromNdc[16], std::vector<float>& maxDistance, FrameSignature& signature);
}

#endif
