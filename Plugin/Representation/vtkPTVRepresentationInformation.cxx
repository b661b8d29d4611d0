#include "vtkPTVRepresentationInformation.h"

#include "vtkClientServerStream.h"
#include "vtkCompositeRepresentation.h"
#include "vtkObjectFactory.h"
#include "vtkPTVExpertOptions.h"
#include "vtkPTVRenderStatistics.h"
#include "vtkPTVVolumeRepresentation.h"
#include "vtkPathTracedVolumeMapper.h"

vtkStandardNewMacro(vtkPTVRepresentationInformation);

//------------------------------------------------------------------------------
vtkPTVRepresentationInformation::vtkPTVRepresentationInformation()
{
  this->RootOnly = 1;
}

//------------------------------------------------------------------------------
vtkPTVRepresentationInformation::~vtkPTVRepresentationInformation() = default;

//------------------------------------------------------------------------------
void vtkPTVRepresentationInformation::CopyFromObject(vtkObject* object)
{
  auto* repr = vtkPTVVolumeRepresentation::SafeDownCast(object);
  if (!repr)
  {
    if (auto* composite = vtkCompositeRepresentation::SafeDownCast(object))
    {
      repr = vtkPTVVolumeRepresentation::SafeDownCast(composite->GetActiveRepresentation());
    }
  }
  vtkPathTracedVolumeMapper* mapper = repr ? repr->GetPathTracedMapper() : nullptr;
  this->Found = mapper != nullptr;
  if (!mapper)
  {
    return;
  }
  this->AccumulatedFrames = mapper->GetAccumulatedFrames();
  this->MaximumAccumulatedFrames = mapper->GetExpertOptions()->GetMaximumAccumulatedFrames();
  this->LastRenderTraced = mapper->GetLastRenderTraced();
  this->NeedsRefinement = repr->GetNeedsRefinement();
  this->LastTraceTime = mapper->GetStatistics()->GetLastTraceTime();
  this->LastDenoiseTime = mapper->GetStatistics()->GetLastDenoiseTime();
  this->EstimatedQuality = mapper->GetEstimatedQuality();
  this->StillConverged = mapper->GetStillConverged();
  const char* backend = mapper->GetActiveBackend();
  this->ActiveBackend = backend ? backend : "none";
  const char* status = mapper->GetDenoiserStatus();
  this->DenoiserStatus = status ? status : "";
}

//------------------------------------------------------------------------------
void vtkPTVRepresentationInformation::AddInformation(vtkPVInformation* other)
{
  auto* info = vtkPTVRepresentationInformation::SafeDownCast(other);
  if (info && info->Found && !this->Found)
  {
    vtkClientServerStream stream;
    info->CopyToStream(&stream);
    this->CopyFromStream(&stream);
  }
}

//------------------------------------------------------------------------------
void vtkPTVRepresentationInformation::CopyToStream(vtkClientServerStream* stream)
{
  stream->Reset();
  *stream << vtkClientServerStream::Reply << this->Found << this->AccumulatedFrames
          << this->MaximumAccumulatedFrames << this->LastRenderTraced << this->NeedsRefinement
          << this->LastTraceTime << this->LastDenoiseTime << this->EstimatedQuality
          << this->StillConverged << this->ActiveBackend.c_str()
          << this->DenoiserStatus.c_str() << vtkClientServerStream::End;
}

//------------------------------------------------------------------------------
void vtkPTVRepresentationInformation::CopyFromStream(const vtkClientServerStream* stream)
{
  const char* backend = nullptr;
  const char* status = nullptr;
  if (!stream->GetArgument(0, 0, &this->Found) ||
    !stream->GetArgument(0, 1, &this->AccumulatedFrames) ||
    !stream->GetArgument(0, 2, &this->MaximumAccumulatedFrames) ||
    !stream->GetArgument(0, 3, &this->LastRenderTraced) ||
    !stream->GetArgument(0, 4, &this->NeedsRefinement) ||
    !stream->GetArgument(0, 5, &this->LastTraceTime) ||
    !stream->GetArgument(0, 6, &this->LastDenoiseTime) ||
    !stream->GetArgument(0, 7, &this->EstimatedQuality) ||
    !stream->GetArgument(0, 8, &this->StillConverged) || !stream->GetArgument(0, 9, &backend) ||
    !stream->GetArgument(0, 10, &status))
  {
    vtkErrorMacro(<< "Error parsing the Path Traced Volume information from the stream.");
    this->Found = false;
    return;
  }
  this->ActiveBackend = backend ? backend : "none";
  this->DenoiserStatus = status ? status : "";
}

//------------------------------------------------------------------------------
void vtkPTVRepresentationInformation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Found: " << this->Found << endl;
  os << indent << "AccumulatedFrames: " << this->AccumulatedFrames << endl;
  os << indent << "MaximumAccumulatedFrames: " << this->MaximumAccumulatedFrames << endl;
  os << indent << "LastRenderTraced: " << this->LastRenderTraced << endl;
  os << indent << "NeedsRefinement: " << this->NeedsRefinement << endl;
  os << indent << "LastTraceTime: " << this->LastTraceTime << endl;
  os << indent << "LastDenoiseTime: " << this->LastDenoiseTime << endl;
  os << indent << "EstimatedQuality: " << this->EstimatedQuality << endl;
  os << indent << "StillConverged: " << this->StillConverged << endl;
  os << indent << "ActiveBackend: " << this->ActiveBackend << endl;
  os << indent << "DenoiserStatus: " << this->DenoiserStatus << endl;
}
