/**
 * @file ptvSceneRequest.h
 * @brief Private: the parts of the VTK scene a frame reads beside the volume -- the mapper's
 *        clipping planes, cropping and blend mode -- checked and copied into the frame settings.
 *
 * A problem (a bad plane, an unsupported blend mode, missing iso values) is reported on the
 * mapper when it differs from the last one reported (@a reported), not on every frame.
 */
#ifndef ptvSceneRequest_h
#define ptvSceneRequest_h

#include <string>

class vtkVolumeMapper;
class vtkVolumeProperty;

namespace ptv
{
struct FrameSettings;

/// Clipping planes (world) and cropping into @a scene; bad ones are reported and skipped.
void GatherClipping(vtkVolumeMapper* self, FrameSettings& scene, std::string& reported);

/**
 * The blend mode into @a scene: Composite is the path tracer; IsoSurface traces the property's
 * iso values as surfaces (scene.Iso); the intensity projections are ray cast
 * (scene.Projection), except for a volume split across processes (@a distributed), which
 * renders Composite; Slice renders Composite.
 */
void GatherBlendMode(vtkVolumeMapper* self, bool distributed, vtkVolumeProperty* property,
  FrameSettings& scene, std::string& reported);
}

#endif
