/**
 * @file ptvTestKernelCamera.h
 * @brief Shared by the kernel tests: an orthographic camera looking along +z, NDC x and y equal
 *        to world x and y (the image spans [-1, 1]^2), rays starting at z = -1, and a
 *        directional key light along +z (from behind the camera); and the step-corrected
 *        transfer tables as the mapper sets them.
 */
#ifndef ptvTestKernelCamera_h
#define ptvTestKernelCamera_h

#include "Kernels/ptvIntegrator.h"

/// Set @a p's camera (size x size pixels, far distance 100) and key-light direction.
inline void OrthographicAlongZ(ptv::TraceParams& p, int size)
{
  const float ndc[16] = { 1.f, 0.f, 0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 0.f, 1.5f, 0.5f, 0.f, 0.f,
    0.f, 1.f }; // NDC z = -1 -> world z = -1, z = +1 -> z = 2
  for (int i = 0; i < 16; ++i)
  {
    p.Camera.WorldFromNdc[i] = ndc[i];
  }
  p.Camera.Eye = ptv::MakeVec3(0.f, 0.f, -1.f);
  p.Camera.Parallel = 1;
  p.Camera.Width = size;
  p.Camera.Height = size;
  p.Camera.FarDistance = 100.f;
  p.KeyLight.Positional = 0;
  p.KeyLight.Direction = ptv::MakeVec3(0.f, 0.f, 1.f);
}

/// As the mapper's FrameInputs::SetStepTables: @a p's opacities corrected once per entry for
/// its camera and shadow steps into @a stepRGBA (4 x Transfer.Size) and @a shadowAlpha
/// (Transfer.Size), which @a p then reads.
inline void SetStepTables(ptv::TraceParams& p, float* stepRGBA, float* shadowAlpha)
{
  ptv::BuildStepTables(p.Transfer, ptv::StepOverUnit(p, p.StepWorld),
    ptv::StepOverUnit(p, ptv::ShadowStep(p)), stepRGBA, shadowAlpha);
  p.Transfer.StepRGBA = stepRGBA;
  p.Transfer.ShadowAlpha = shadowAlpha;
}

#endif
