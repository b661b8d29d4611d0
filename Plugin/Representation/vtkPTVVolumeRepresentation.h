/**
 * @class vtkPTVVolumeRepresentation
 * @brief ParaView representation that volume-renders image data with vtkPathTracedVolumeMapper.
 *
 * A vtkImageVolumeRepresentation whose volume mapper is a vtkPathTracedVolumeMapper, in the way
 * ParaView's NVIDIA IndeX plugin replaces the mapper of the same base class. Everything the base
 * class does is kept: data delivery, the scalar array and scalar mode, the colour and scalar
 * opacity functions, the vtkVolumeProperty (shading coefficients, ScalarOpacityUnitDistance,
 * interpolation) and the outline used where the data is not present. The server-manager proxy is
 * "PathTracedVolumeRepresentation" (Plugin/PathTracedVolumeRepresentation.xml), offered as the
 * "Path Traced Volume" representation type of image data.
 *
 * The Set methods below forward one mapper setting each; see vtkPathTracedVolumeMapper for their
 * meaning, defaults and ranges. They do not re-execute the representation's pipeline: the mapper
 * decides whether a setting restarts its accumulation.
 *
 * Progressive refinement: ParaView renders only when something changes, so on its own the mapper
 * traces one frame per render. With ProgressiveRefinement on (default), the representation marks
 * itself streamable and, on each streaming pass (vtkPVRenderView::REQUEST_STREAMING_UPDATE), hands
 * the view an empty "piece" while the mapper is still accumulating. The view then renders again
 * (vtkSMRenderViewProxy::StreamingUpdate), which traces the next frame, until
 * MaximumAccumulatedFrames is reached. Scripts call StreamingUpdate themselves; the ParaView GUI
 * drives these passes only when streaming is enabled (Settings > General > Enable Streaming),
 * so the plugin's GUI component pqPTVProgressiveRefinement (Plugin/Qt) renders idle views with
 * a refining representation itself, with default settings.
 *
 * The environment light's colour is the view's Background property (set on the mapper before
 * each render, UseBackgroundAsEnvironment off), so that a pvserver, whose compositing renders on
 * another background, lights the volume as the builtin session does.
 *
 * Only vtkImageData is rendered. A vtkRectilinearGrid input (which ParaView's image-data
 * representation also takes) is reported as an error and shows nothing; resample it to an image
 * first. Partitioned datasets get the base class's warning.
 */
#ifndef vtkPTVVolumeRepresentation_h
#define vtkPTVVolumeRepresentation_h

#include "vtkImageVolumeRepresentation.h"
#include "vtkNew.h"                        // for vtkNew
#include "vtkPTVParaViewViewsModule.h"     // for export macro

class vtkImageData;
class vtkPathTracedVolumeMapper;

class VTKPTVPARAVIEWVIEWS_EXPORT vtkPTVVolumeRepresentation : public vtkImageVolumeRepresentation
{
public:
  static vtkPTVVolumeRepresentation* New();
  vtkTypeMacro(vtkPTVVolumeRepresentation, vtkImageVolumeRepresentation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * Adds the streaming hooks used for progressive refinement to the base class's handling of
   * the view requests.
   */
  int ProcessViewRequest(vtkInformationRequestKey* request_type, vtkInformation* inInfo,
    vtkInformation* outInfo) override;

  ///@{
  /**
   * Forwarded to vtkPathTracedVolumeMapper (same names; see there for defaults and ranges).
   * Seed is clamped to be non-negative; an empty DenoiserModelFile means the shipped model.
   */
  void SetSamplesPerFrame(int value);
  void SetMaximumAccumulatedFrames(int value);
  void SetTemporalReprojection(bool value);
  void SetMaximumHistory(int value);
  void SetSeed(int value);
  void SetScattering(bool value);
  void SetExpectedCoverage(bool value);
  void SetAmbientOcclusion(bool value);
  void SetAmbientOcclusionReach(double value);
  void SetUseRendererLight(bool value);
  void SetLightIntensity(double value);
  void SetEnvironmentIntensity(double value);
  void SetEmptySpaceSkipping(bool value);
  void SetNumberOfThreads(int value);
  void SetBackend(int value);
  void SetDenoise(bool value);
  void SetDenoiserModelFile(const char* path);
  void SetDenoiserUseNetwork(bool value);
  void SetEdgeSamples(int value);
  void SetDenoiserNumberOfLevels(int value);
  ///@}

  ///@{
  /**
   * Pass shown in the view: a name from vtkPathTracedVolumeMapper::GetPassName(), or "Default"
   * (or empty / nullptr) for the mapper's default (Converged when Denoise is on, else Radiance).
   */
  void SetDisplayPass(const char* name);
  const char* GetDisplayPass();
  ///@}

  ///@{
  /**
   * Keep asking the view for renders, through its streaming passes, until the mapper has
   * accumulated MaximumAccumulatedFrames frames. Default on. In the GUI (streaming off by
   * default) pqPTVProgressiveRefinement reads it and renders idle views itself.
   */
  void SetProgressiveRefinement(bool value);
  vtkGetMacro(ProgressiveRefinement, bool);
  vtkBooleanMacro(ProgressiveRefinement, bool);
  ///@}

  ///@{
  /**
   * Still renders (vtkPathTracedVolumeMapper::ConvergeStillRenders and its StillQuality,
   * MaximumStillFrames, StillTimeBudget): screenshots, animation frames and script renders
   * converge. With InteractiveSession on (set by the GUI's pqPTVProgressiveRefinement) a still
   * render converges only while the view captures an image (vtkPVView::PrepareForScreenshot to
   * CleanupAfterScreenshot); other still renders trace one frame and the idle refinement
   * continues, so the window never freezes. Defaults: on, 40, 256, 30, off.
   */
  void SetConvergeStillRenders(bool value);
  vtkGetMacro(ConvergeStillRenders, bool);
  void SetStillQuality(double value);
  void SetMaximumStillFrames(int value);
  void SetStillTimeBudget(double value);
  vtkSetMacro(InteractiveSession, bool);
  vtkGetMacro(InteractiveSession, bool);
  ///@}

  /// Estimated PSNR (dB, tone-mapped) of the shown image; 0 before 2 frames.
  double GetEstimatedQuality();

  ///@{
  /**
   * Progress of the mapper, for information-only properties: frames averaged so far, whether the
   * last render traced a frame (0 once converged), and what the denoiser last used.
   */
  int GetAccumulatedFrames();
  int GetLastRenderTraced();
  const char* GetDenoiserStatus();
  ///@}

  /// "CPU" or "CUDA": where the last frame was traced ("none" before the first).
  const char* GetActiveBackend();

  ///@{
  /**
   * Where WritePasses() writes: an .exr file (on the server in client/server mode). Default: none.
   */
  vtkSetStringMacro(PassesFileName);
  vtkGetStringMacro(PassesFileName);
  ///@}

  /**
   * Write every kept render pass of the current frame (vtkPathTracedVolumeMapper::GetPasses():
   * the Scatter* passes only with the mapper's expert option ScatterPasses) to
   * PassesFileName as one multi-channel float EXR (vtkPTVEXRPassWriter: atomic, conventional
   * channel names). Errors (no file name, nothing rendered yet, unwritable path) are reported
   * with vtkErrorMacro and return false.
   *
   * ParaView sends the command to every process that holds the representation. It is done by
   * the processes that render: the server when connected to one (only its first rank; the
   * client of a remote session does nothing and returns true), the single process otherwise.
   * With client/server local rendering (data under the remote-render threshold) the server has
   * not traced a frame: its error says so (set the view's RemoteRenderThreshold to 0).
   */
  bool WritePasses();

  /**
   * Whether another streaming pass would trace a new frame: the volume is shown, the last render
   * traced a frame and fewer than MaximumAccumulatedFrames have been accumulated.
   */
  bool GetNeedsRefinement();

  ///@{
  /**
   * Parallel runs (pvbatch or pvserver under MPI with N > 1 ranks): a volume of at most this
   * many megabytes (voxels x 4 bytes) is read whole on every rank, and the ranks trace each
   * frame together (vtkPathTracedVolumeMapper::SetController: N times the samples per second,
   * the same image as one rank with no seam between pieces). A larger one, or 0, keeps
   * ParaView's split into one piece per rank, with GhostLayers around each piece
   * (vtkPathTracedVolumeMapper::DistributedVolume): each rank traces camera rays through its
   * piece, shadow and environment rays through the ghost layers as well, the ranks composite
   * the pieces in view order, each a share of the pixels, and rank 0 denoises and draws the
   * whole frame. A volume too small to give
   * every rank a piece is replicated whatever the limit. Default: 4096 MB.
   */
  void SetReplicateVolumeLimit(double megabytes);
  vtkGetMacro(ReplicateVolumeLimit, double);
  ///@}

  ///@{
  /**
   * A volume split across ranks (above ReplicateVolumeLimit): layers of voxels each rank reads
   * around its piece, which its shadow and environment rays cross (what lies beyond them casts
   * no shadow into the piece). Memory per rank grows by about (1 + 2 g / d)^3 for pieces of d
   * voxels a side. 0: shadows stop at the piece. Default: 16 (chosen by the ablation in
   * docs/parallel.md).
   */
  void SetGhostLayers(int layers);
  vtkGetMacro(GhostLayers, int);
  ///@}

  /// The ranks that trace this volume's frames together (1: this rank alone).
  int GetNumberOfSamplingRanks();

  /// The mapper this representation renders with (owned by the representation).
  vtkPathTracedVolumeMapper* GetPathTracedMapper();

protected:
  vtkPTVVolumeRepresentation();
  ~vtkPTVVolumeRepresentation() override;

  /**
   * Notes whether the input is a vtkImageData; the base class also accepts vtkRectilinearGrid,
   * which the path tracer cannot render (one error per update, and the volume is hidden). A
   * piece of a split volume is rendered with its ghost layers (the base class would crop them),
   * and the mapper learns which part is the rank's own (the cells that are not ghosts).
   */
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  /**
   * In parallel runs, asks for the whole volume on every rank when it fits under
   * ReplicateVolumeLimit, else for this rank's piece as the base class does, with GhostLayers;
   * either way the mapper gets the ranks to trace with.
   */
  int RequestUpdateExtent(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  bool ProgressiveRefinement = true;
  bool ConvergeStillRenders = true;
  bool InteractiveSession = false;
  bool ProgressRegistered = false; ///< the mapper's progress reaches ParaView's progress bar
  bool UnsupportedInput = false;
  char* PassesFileName = nullptr;
  double ReplicateVolumeLimit = 4096.0;
  int GhostLayers = 16;

  /// Empty image handed to the view as the "next streamed piece" while refinement goes on.
  vtkNew<vtkImageData> RefinementToken;

private:
  vtkPTVVolumeRepresentation(const vtkPTVVolumeRepresentation&) = delete;
  void operator=(const vtkPTVVolumeRepresentation&) = delete;
};

#endif
