#include "vtkPTVExpertOptions.h"

#include "ptvCheckedSetting.h"
#include "ptvFrameLoop.h"

#include "vtkObjectFactory.h"

#include <algorithm>

vtkStandardNewMacro(vtkPTVExpertOptions);

//------------------------------------------------------------------------------
vtkPTVExpertOptions::vtkPTVExpertOptions()
{
  const ptv::FrameRequest defaults{};
  const ptv::FrameSettings& scene = defaults.Scene;
  this->MaximumAccumulatedFrames = defaults.MaximumAccumulatedFrames;
  this->MaximumHistory = defaults.MaximumHistory;
  this->MaximumStillFrames = defaults.MaximumStillFrames;
  this->CoverageMarch = scene.CoverageMarch;
  this->ExpectedCoverage = scene.ExpectedCoverage;
  this->FootprintRays = scene.FootprintRays;
  this->ScatterPasses = defaults.ScatterPasses;
  this->EdgeSamples = defaults.EdgeSamples;
  this->ComputeEdgeSamples = defaults.ComputeEdgeSamples;
  this->AmbientOcclusionReach = scene.AmbientOcclusionReach;
  this->UseRendererLight = scene.UseRendererLight;
  std::copy(scene.EnvironmentColor, scene.EnvironmentColor + 3, this->EnvironmentColor);
  this->UseBackgroundAsEnvironment = scene.UseBackgroundAsEnvironment;
  this->EmptySpaceSkipping = scene.EmptySpaceSkipping;
  this->DenoiserUseNetwork = defaults.Denoiser.UseNetwork;
  this->DenoiserNumberOfLevels = defaults.Denoiser.Levels;
}

PTV_CLAMPED_SETTER(vtkPTVExpertOptions, MaximumAccumulatedFrames, int, 1, 1000000)
PTV_CLAMPED_SETTER(vtkPTVExpertOptions, MaximumHistory, int, 1, 1000000)
PTV_CLAMPED_SETTER(vtkPTVExpertOptions, MaximumStillFrames, int, 1, 1000000)
PTV_CLAMPED_SETTER(vtkPTVExpertOptions, EdgeSamples, int, 1, 64)
PTV_CLAMPED_SETTER(vtkPTVExpertOptions, AmbientOcclusionReach, double, 0.0, 1.0)
PTV_CLAMPED_SETTER(vtkPTVExpertOptions, DenoiserNumberOfLevels, int, 0, 3)

//------------------------------------------------------------------------------
void vtkPTVExpertOptions::SetEnvironmentColor(double r, double g, double b)
{
  const double wanted[3] = { r, g, b };
  double checked[3];
  for (int k = 0; k < 3; ++k)
  {
    checked[k] = ptv::CheckedSetting<double>(
      this, "EnvironmentColor", wanted[k], this->EnvironmentColor[k], 0.0, 1.0);
  }
  if (!std::equal(checked, checked + 3, this->EnvironmentColor))
  {
    std::copy(checked, checked + 3, this->EnvironmentColor);
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkPTVExpertOptions::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "MaximumAccumulatedFrames: " << this->MaximumAccumulatedFrames << "\n";
  os << indent << "MaximumHistory: " << this->MaximumHistory << "\n";
  os << indent << "MaximumStillFrames: " << this->MaximumStillFrames << "\n";
  os << indent << "CoverageMarch: " << this->CoverageMarch << "\n";
  os << indent << "ExpectedCoverage: " << this->ExpectedCoverage << "\n";
  os << indent << "FootprintRays: " << this->FootprintRays << "\n";
  os << indent << "ScatterPasses: " << this->ScatterPasses << "\n";
  os << indent << "EdgeSamples: " << this->EdgeSamples << "\n";
  os << indent << "ComputeEdgeSamples: " << this->ComputeEdgeSamples << "\n";
  os << indent << "AmbientOcclusionReach: " << this->AmbientOcclusionReach << "\n";
  os << indent << "UseRendererLight: " << this->UseRendererLight << "\n";
  os << indent << "EnvironmentColor: " << this->EnvironmentColor[0] << ", "
     << this->EnvironmentColor[1] << ", " << this->EnvironmentColor[2] << "\n";
  os << indent << "UseBackgroundAsEnvironment: " << this->UseBackgroundAsEnvironment << "\n";
  os << indent << "EmptySpaceSkipping: " << this->EmptySpaceSkipping << "\n";
  os << indent << "DenoiserUseNetwork: " << this->DenoiserUseNetwork << "\n";
  os << indent << "DenoiserNumberOfLevels: " << this->DenoiserNumberOfLevels << "\n";
}
