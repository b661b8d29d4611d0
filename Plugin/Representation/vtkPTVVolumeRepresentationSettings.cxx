// The representation's forwarded settings and progress getters: each one the path-traced
// mapper's (or its expert options') of the same name, so the panel and Python scripts set the
// mapper through the representation.
#include "vtkPTVVolumeRepresentation.h"

#include "vtkPTVExpertOptions.h"
#include "vtkPathTracedVolumeMapper.h"

#include <cstring>

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::SetSamplesPerFrame(int value)
{
  this->GetPathTracedMapper()->SetSamplesPerFrame(value);
}

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::SetTemporalReprojection(bool value)
{
  this->GetPathTracedMapper()->SetTemporalReprojection(value);
}

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::SetMaximumHistory(int value)
{
  this->GetPathTracedMapper()->GetExpertOptions()->SetMaximumHistory(value);
}

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::SetMaximumAccumulatedFrames(int value)
{
  this->GetPathTracedMapper()->GetExpertOptions()->SetMaximumAccumulatedFrames(value);
}

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::SetSeed(int value)
{
  this->GetPathTracedMapper()->SetSeed(static_cast<unsigned int>(value < 0 ? 0 : value));
}

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::SetScattering(bool value)
{
  this->GetPathTracedMapper()->SetScattering(value);
}

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::SetExpectedCoverage(bool value)
{
  this->GetPathTracedMapper()->GetExpertOptions()->SetExpectedCoverage(value);
}

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::SetAmbientOcclusion(bool value)
{
  this->GetPathTracedMapper()->SetAmbientOcclusion(value);
}

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::SetAmbientOcclusionReach(double value)
{
  this->GetPathTracedMapper()->GetExpertOptions()->SetAmbientOcclusionReach(value);
}

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::SetUseRendererLight(bool value)
{
  this->GetPathTracedMapper()->GetExpertOptions()->SetUseRendererLight(value);
}

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::SetLightIntensity(double value)
{
  this->GetPathTracedMapper()->SetLightIntensity(value);
}

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::SetEnvironmentIntensity(double value)
{
  this->GetPathTracedMapper()->SetEnvironmentIntensity(value);
}

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::SetEmptySpaceSkipping(bool value)
{
  this->GetPathTracedMapper()->GetExpertOptions()->SetEmptySpaceSkipping(value);
}

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::SetNumberOfThreads(int value)
{
  this->GetPathTracedMapper()->SetNumberOfThreads(value);
}

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::SetBackend(int value)
{
  this->GetPathTracedMapper()->SetBackend(value);
}

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::SetDenoise(bool value)
{
  this->GetPathTracedMapper()->SetDenoise(value);
}

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::SetDenoiserModelFile(const char* path)
{
  this->GetPathTracedMapper()->SetDenoiserModelFile(path && *path ? path : nullptr);
}

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::SetDenoiserUseNetwork(bool value)
{
  this->GetPathTracedMapper()->GetExpertOptions()->SetDenoiserUseNetwork(value);
}

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::SetEdgeSamples(int value)
{
  this->GetPathTracedMapper()->GetExpertOptions()->SetEdgeSamples(value);
}

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::SetDenoiserNumberOfLevels(int value)
{
  this->GetPathTracedMapper()->GetExpertOptions()->SetDenoiserNumberOfLevels(value);
}

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::SetDisplayPass(const char* name)
{
  const bool useDefault = !name || !*name || std::strcmp(name, "Default") == 0;
  this->GetPathTracedMapper()->SetDisplayPass(useDefault ? nullptr : name);
}

//------------------------------------------------------------------------------
const char* vtkPTVVolumeRepresentation::GetDisplayPass()
{
  const char* name = this->GetPathTracedMapper()->GetDisplayPass();
  return name && *name ? name : "Default";
}

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::SetProgressiveRefinement(bool value)
{
  // Not Modified(): that would re-execute the representation's pipeline for nothing.
  this->ProgressiveRefinement = value;
}

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::SetConvergeStillRenders(bool value)
{
  if (this->ConvergeStillRenders != value)
  {
    this->ConvergeStillRenders = value;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::SetStillQuality(double value)
{
  this->GetPathTracedMapper()->SetStillQuality(value);
}

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::SetMaximumStillFrames(int value)
{
  this->GetPathTracedMapper()->GetExpertOptions()->SetMaximumStillFrames(value);
}

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::SetStillTimeBudget(double value)
{
  this->GetPathTracedMapper()->SetStillTimeBudget(value);
}

//------------------------------------------------------------------------------
double vtkPTVVolumeRepresentation::GetEstimatedQuality()
{
  return this->GetPathTracedMapper()->GetEstimatedQuality();
}

//------------------------------------------------------------------------------
int vtkPTVVolumeRepresentation::GetAccumulatedFrames()
{
  return this->GetPathTracedMapper()->GetAccumulatedFrames();
}

//------------------------------------------------------------------------------
int vtkPTVVolumeRepresentation::GetLastRenderTraced()
{
  return this->GetPathTracedMapper()->GetLastRenderTraced() ? 1 : 0;
}

//------------------------------------------------------------------------------
const char* vtkPTVVolumeRepresentation::GetDenoiserStatus()
{
  return this->GetPathTracedMapper()->GetDenoiserStatus();
}

//------------------------------------------------------------------------------
const char* vtkPTVVolumeRepresentation::GetActiveBackend()
{
  return this->GetPathTracedMapper()->GetActiveBackend();
}
