#include "vtkPTVVolumeRepresentation.h"

#include "vtkCellData.h"
#include "vtkDataSetAttributes.h"
#include "vtkExtentTranslator.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPTVEXRPassWriter.h"
#include "vtkPTVExpertOptions.h"
#include "vtkPVSession.h"
#include "vtkPVLODVolume.h"
#include "vtkPVRenderView.h"
#include "vtkPathTracedVolumeMapper.h"
#include "vtkPVProgressHandler.h"
#include "vtkProcessModule.h"
#include "vtkRectilinearGrid.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStructuredData.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>

vtkStandardNewMacro(vtkPTVVolumeRepresentation);

namespace
{
/// Whether splitting @a whole into @a pieces blocks (ParaView's split) leaves a piece empty: a
/// rank without data would not render, and the others would wait for it in every collective.
bool SomePieceEmpty(const int whole[6], int pieces)
{
  vtkNew<vtkExtentTranslator> translator;
  int wholeExtent[6], piece[6];
  std::copy(whole, whole + 6, wholeExtent);
  for (int p = 0; p < pieces; ++p)
  {
    if (!translator->PieceToExtentThreadSafe(
          p, pieces, 0, wholeExtent, piece, vtkExtentTranslator::BLOCK_MODE, 0))
    {
      return true;
    }
  }
  return false;
}

/// The point extent of @a image's cells that are not ghosts (vtkGhostType without
/// DUPLICATECELL): the first and last such cell bound it. The whole extent without ghosts.
void OwnExtent(vtkImageData* image, int own[6])
{
  image->GetExtent(own);
  auto* ghosts = vtkUnsignedCharArray::SafeDownCast(
    image->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName()));
  if (!ghosts || ghosts->GetNumberOfTuples() == 0)
  {
    return;
  }
  int points[6];
  std::copy(own, own + 6, points);
  const vtkIdType n = ghosts->GetNumberOfTuples();
  auto owned = [&](vtkIdType c)
  { return (ghosts->GetValue(c) & vtkDataSetAttributes::DUPLICATECELL) == 0; };
  vtkIdType first = 0;
  while (first < n && !owned(first))
  {
    ++first;
  }
  vtkIdType last = n - 1;
  while (last >= 0 && !owned(last))
  {
    --last;
  }
  if (first >= n)
  {
    own[0] = own[2] = own[4] = 0; // every cell is a ghost: nothing of its own
    own[1] = own[3] = own[5] = -1;
    return;
  }
  int lo[3], hi[3];
  vtkStructuredData::ComputeCellStructuredCoordsForExtent(first, points, lo);
  vtkStructuredData::ComputeCellStructuredCoordsForExtent(last, points, hi);
  for (int a = 0; a < 3; ++a)
  {
    // Cells i..j span points i..j + 1; a flat axis (one point) keeps its point.
    own[2 * a] = lo[a];
    own[2 * a + 1] = points[2 * a] == points[2 * a + 1] ? hi[a] : hi[a] + 1;
  }
}

/// vtkPVView::GetInCaptureScreenshot() is protected; a member pointer taken through a subclass
/// reads it on any view (well-defined C++, no cast of the object).
struct CaptureFlag : vtkPVView
{
  static bool Get(vtkPVView* view) { return (view->*(&CaptureFlag::GetInCaptureScreenshot))(); }
};
}

//------------------------------------------------------------------------------
vtkPTVVolumeRepresentation::vtkPTVVolumeRepresentation()
{
  // The base class made a vtkMultiBlockVolumeMapper; UpdateMapperParameters() (called by the
  // base class on every render request) gives whatever VolumeMapper holds to the actor.
  this->VolumeMapper.TakeReference(vtkPathTracedVolumeMapper::New());
  // The environment light takes the view's Background property (REQUEST_RENDER below), not the
  // renderer's background: on a pvserver the compositing pass renders on another background.
  this->GetPathTracedMapper()->GetExpertOptions()->SetUseBackgroundAsEnvironment(false);
}

//------------------------------------------------------------------------------
vtkPTVVolumeRepresentation::~vtkPTVVolumeRepresentation()
{
  this->SetPassesFileName(nullptr);
}

//------------------------------------------------------------------------------
vtkPathTracedVolumeMapper* vtkPTVVolumeRepresentation::GetPathTracedMapper()
{
  return vtkPathTracedVolumeMapper::SafeDownCast(this->VolumeMapper);
}

//------------------------------------------------------------------------------
int vtkPTVVolumeRepresentation::ProcessViewRequest(
  vtkInformationRequestKey* request_type, vtkInformation* inInfo, vtkInformation* outInfo)
{
  if (!this->Superclass::ProcessViewRequest(request_type, inInfo, outInfo))
  {
    return 0;
  }
  if (request_type == vtkPVView::REQUEST_UPDATE())
  {
    // After the base class has registered its pieces: only streamable representations are asked
    // for streamed pieces by vtkSMRenderViewProxy::StreamingUpdate(). Always streamable, so that
    // ProgressiveRefinement takes effect without a new update; it gates the pieces below.
    vtkPVRenderView::SetStreamable(inInfo, this, true);
  }
  else if (request_type == vtkPVView::REQUEST_RENDER() && !this->UnsupportedInput)
  {
    vtkPathTracedVolumeMapper* mapper = this->GetPathTracedMapper();
    auto* view = vtkPVRenderView::SafeDownCast(inInfo->Get(vtkPVView::VIEW()));
    if (view)
    {
      mapper->GetExpertOptions()->SetEnvironmentColor(view->GetBackground());
    }
    // Captures and script renders converge; the GUI's other still renders trace one frame.
    const bool capturing = view && CaptureFlag::Get(view);
    mapper->SetConvergeStillRenders(
      this->ConvergeStillRenders && (!this->InteractiveSession || capturing));
    if (!this->ProgressRegistered)
    {
      vtkPVSession* session = vtkPVSession::SafeDownCast(
        vtkProcessModule::GetProcessModule()->GetActiveSession());
      if (session && session->GetProgressHandler())
      {
        session->GetProgressHandler()->RegisterProgressEvent(mapper, 0);
        this->ProgressRegistered = true;
      }
    }
  }
  else if (request_type == vtkPVView::REQUEST_RENDER() && this->UnsupportedInput)
  {
    // The base class has just connected the delivered data to the mapper: undo that, so the
    // pipeline does not fail on every render.
    this->VolumeMapper->RemoveAllInputConnections(0);
    this->Actor->SetVisibility(false);
  }
  else if (request_type == vtkPVRenderView::REQUEST_STREAMING_UPDATE())
  {
    // A delivered piece makes StreamingUpdate(true) render the view once more, which traces the
    // next frame. The piece itself is empty and ignored in REQUEST_PROCESS_STREAMED_PIECE.
    if (this->ProgressiveRefinement && this->GetNeedsRefinement())
    {
      vtkPVRenderView::SetNextStreamedPiece(inInfo, this, this->RefinementToken);
    }
  }
  return 1;
}

//------------------------------------------------------------------------------
int vtkPTVVolumeRepresentation::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  this->UnsupportedInput = false;
  if (inputVector[0]->GetNumberOfInformationObjects() == 1 &&
    vtkRectilinearGrid::GetData(inputVector[0], 0))
  {
    this->UnsupportedInput = true;
    vtkErrorMacro(<< "Path Traced Volume renders vtkImageData only, not vtkRectilinearGrid; "
                  << "resample the data to an image (e.g. Resample To Image) first.");
  }
  if (!this->Superclass::RequestData(request, inputVector, outputVector))
  {
    return 0;
  }
  vtkPathTracedVolumeMapper* mapper = this->GetPathTracedMapper();
  vtkImageData* input = inputVector[0]->GetNumberOfInformationObjects() == 1
    ? vtkImageData::GetData(inputVector[0], 0)
    : nullptr;
  if (mapper->GetDistributedVolume() && input)
  {
    // The base class cropped the ghost layers away; the mapper needs them (and its own part).
    vtkSmartPointer<vtkImageData> piece;
    piece.TakeReference(input->NewInstance());
    piece->ShallowCopy(input);
    int own[6];
    OwnExtent(input, own);
    this->Cache = piece;
    mapper->SetPieceExtent(own);
    // The whole volume's grid and bounds: rank 0 draws all of it (IceT crops each rank's image
    // to its props' bounds).
    mapper->SetWholeExtent(this->WholeExtent);
  }
  return 1;
}

//------------------------------------------------------------------------------
int vtkPTVVolumeRepresentation::RequestUpdateExtent(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (!this->Superclass::RequestUpdateExtent(request, inputVector, outputVector))
  {
    return 0;
  }
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  const int ranks = controller ? controller->GetNumberOfProcesses() : 1;
  vtkInformation* in = inputVector[0]->GetNumberOfInformationObjects() > 0
    ? inputVector[0]->GetInformationObject(0)
    : nullptr;
  bool replicate = false;
  if (ranks > 1 && in && in->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
  {
    int whole[6];
    in->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), whole);
    double voxels = 1.0;
    for (int a = 0; a < 3; ++a)
    {
      voxels *= std::max(whole[2 * a + 1] - whole[2 * a] + 1, 0);
    }
    replicate = voxels > 0.0 &&
      (4.0 * voxels <= this->ReplicateVolumeLimit * 1048576.0 || SomePieceEmpty(whole, ranks));
  }
  const bool distribute = ranks > 1 && in && !replicate;
  if (replicate)
  {
    // The whole volume here: piece 0 of 1, no ghost cells (vtkPVDataRepresentation asked for
    // piece = rank of N).
    in->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), 0);
    in->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), 1);
    in->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
  }
  else if (distribute)
  {
    // This rank's piece (as asked by the base class) with the ghost layers its light rays cross.
    const int asked = in->Has(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS())
      ? in->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS())
      : 0;
    in->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(),
      std::max(asked, this->GhostLayers));
  }
  vtkPathTracedVolumeMapper* mapper = this->GetPathTracedMapper();
  mapper->SetController(replicate || distribute ? controller : nullptr);
  mapper->SetDistributedVolume(distribute);
  if (!distribute)
  {
    const int whole[6] = { 0, -1, 0, -1, 0, -1 };
    mapper->SetPieceExtent(whole);
    mapper->SetWholeExtent(whole);
  }
  return 1;
}

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::SetReplicateVolumeLimit(double megabytes)
{
  megabytes = std::max(megabytes, 0.0);
  if (this->ReplicateVolumeLimit != megabytes)
  {
    this->ReplicateVolumeLimit = megabytes;
    this->MarkModified(); // a new update decides again
  }
}

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::SetGhostLayers(int layers)
{
  layers = std::max(layers, 0);
  if (this->GhostLayers != layers)
  {
    this->GhostLayers = layers;
    this->MarkModified(); // a new update reads the new layers
  }
}

//------------------------------------------------------------------------------
int vtkPTVVolumeRepresentation::GetNumberOfSamplingRanks()
{
  vtkMultiProcessController* controller = this->GetPathTracedMapper()->GetController();
  return controller ? controller->GetNumberOfProcesses() : 1;
}

//------------------------------------------------------------------------------
bool vtkPTVVolumeRepresentation::GetNeedsRefinement()
{
  vtkPathTracedVolumeMapper* mapper = this->GetPathTracedMapper();
  return mapper && this->GetVisibility() && this->Actor->GetVisibility() &&
    mapper->GetLastRenderTraced() &&
    mapper->GetAccumulatedFrames() < mapper->GetExpertOptions()->GetMaximumAccumulatedFrames();
}

//------------------------------------------------------------------------------
bool vtkPTVVolumeRepresentation::WritePasses()
{
  // The client of a remote session does not render (remote rendering) or is not where the
  // command is meant to run: the server writes. Satellite ranks hold only their piece.
  vtkProcessModule* pm = vtkProcessModule::GetProcessModule();
  vtkPVSession* session = pm ? vtkPVSession::SafeDownCast(pm->GetActiveSession()) : nullptr;
  if (session && !session->HasProcessRole(vtkPVSession::RENDER_SERVER))
  {
    return true;
  }
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  if (controller && controller->GetLocalProcessId() > 0)
  {
    return true;
  }
  if (!this->PassesFileName || !*this->PassesFileName)
  {
    vtkErrorMacro(<< "WritePasses: PassesFileName is empty; set it to the .exr file to write.");
    return false;
  }
  vtkPathTracedVolumeMapper* mapper = this->GetPathTracedMapper();
  if (mapper->GetAccumulatedFrames() == 0)
  {
    const char* hint = (session && !session->HasProcessRole(vtkPVSession::CLIENT))
      ? " (in client/server mode the view may render on the client, local rendering: set its "
        "RemoteRenderThreshold to 0 to render on the server)."
      : ".";
    vtkErrorMacro(<< "WritePasses: no frame has been traced here yet, nothing to write to '"
                  << this->PassesFileName << "'. Render the view first" << hint);
    return false;
  }
  vtkNew<vtkImageData> passes;
  if (!mapper->GetPasses(passes))
  {
    return false;
  }
  vtkNew<vtkPTVEXRPassWriter> writer;
  writer->SetFileName(this->PassesFileName);
  writer->SetInputData(passes);
  return writer->Write() == 1;
}

//------------------------------------------------------------------------------
void vtkPTVVolumeRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ProgressiveRefinement: " << this->ProgressiveRefinement << endl;
  os << indent << "UnsupportedInput: " << this->UnsupportedInput << endl;
  os << indent << "DisplayPass: " << this->GetDisplayPass() << endl;
  os << indent << "ReplicateVolumeLimit: " << this->ReplicateVolumeLimit << " MB" << endl;
  os << indent << "GhostLayers: " << this->GhostLayers << endl;
  os << indent << "PassesFileName: " << (this->PassesFileName ? this->PassesFileName : "(none)")
     << endl;
  os << indent << "PathTracedMapper:" << endl;
  this->GetPathTracedMapper()->PrintSelf(os, indent.GetNextIndent());
}
