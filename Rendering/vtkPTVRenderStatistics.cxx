#include "vtkPTVRenderStatistics.h"

#include "vtkObjectFactory.h"

vtkStandardNewMacro(vtkPTVRenderStatistics);

//------------------------------------------------------------------------------
void vtkPTVRenderStatistics::Update(int renderFrames, double traceTime, double denoiseTime,
  double reprojectionTime, double reprojectionReuse, double edgeFraction)
{
  this->LastRenderFrames = renderFrames;
  this->LastTraceTime = traceTime;
  this->LastDenoiseTime = denoiseTime;
  this->LastReprojectionTime = reprojectionTime;
  this->ReprojectionReuse = reprojectionReuse;
  this->LastEdgeFraction = edgeFraction;
  this->Modified();
}

//------------------------------------------------------------------------------
void vtkPTVRenderStatistics::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "LastRenderFrames: " << this->LastRenderFrames << "\n";
  os << indent << "LastTraceTime: " << this->LastTraceTime << " ms\n";
  os << indent << "LastDenoiseTime: " << this->LastDenoiseTime << " ms\n";
  os << indent << "LastReprojectionTime: " << this->LastReprojectionTime << " ms\n";
  os << indent << "ReprojectionReuse: " << this->ReprojectionReuse << "\n";
  os << indent << "LastEdgeFraction: " << this->LastEdgeFraction << "\n";
}
