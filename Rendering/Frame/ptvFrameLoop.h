/**
 * @file ptvFrameLoop.h
 * @brief Private: one frame of vtkPathTracedVolumeMapper from start to end, and the state kept
 *        between frames (kernel inputs, passes, accumulation signature, denoiser, display).
 *
 * A frame, in order (one file each):
 *  1. ptvFrameInputs -- the VTK scene (voxels, tables, camera, light, opaque geometry) becomes the
 *     kernel's plain structs and a signature of everything that changes the image;
 *  2. ptvTracerRunner -- the frame is traced on the CUDA device or the CPU (ptvCpuTracer runs
 *     Kernels/ptvIntegrator.h per pixel); ptvEdgeSamples -- a frame to be denoised gets more
 *     samples on the volume's edges (EdgeSamples);
 *  3. ptvPassBuffers -- the frame joins the running mean of the named passes (a changed scene
 *     restarts it); ptvReprojection -- when only the view moved, the mean of the previous view
 *     is carried into the new one first (per-pixel history, capped at MaximumHistory);
 *  4. ptvDenoiser -- with Denoise on, the accumulated passes are denoised;
 *     ptvConvergence -- the denoised image is mixed with the raw mean as the samples make it
 *     unnecessary, and the error of what is shown is estimated (a still render repeats 2.-4.
 *     until that estimate reaches the requested quality);
 *  5. ptvShownImage -- the pass to show: premultiplied colour, opacity and window depth;
 *  6. ptvDisplay -- which is drawn into the render window.
 * FrameLoop's own code follows the stages: ptvFrameLoop.cxx (Render: the order above),
 * ptvFrameLoopTrace.cxx (2.-3.), ptvFrameLoopDenoise.cxx (4.), ptvFrameLoopStill.cxx (the still
 * render's repetition).
 * The mapper (vtkPathTracedVolumeMapper) only turns its properties into a FrameRequest and the
 * loop's messages into vtkErrorMacro / vtkWarningMacro. With several processes (MPI ranks:
 * FrameRequest::Controller), each traces its own samples of every frame and 3. starts on
 * process 0 by averaging the frames over the processes (each with the whole volume) or by
 * compositing their pieces in view order (FrameRequest::Distributed; 1. then shares the whole
 * volume's scalar range and bounds) (ptvRanks); process 0 alone accumulates, denoises and draws;
 * its decisions (restart, trace, stop a still render) are everyone's, and a process whose
 * inputs fail stops every process's frame.
 */
#ifndef ptvFrameLoop_h
#define ptvFrameLoop_h

#include "ptvConvergence.h"
#include "ptvDenoiser.h"
#include "ptvDisplay.h"
#include "ptvFrameInputs.h"
#include "ptvPassBuffers.h"
#include "ptvRanks.h"
#include "ptvReprojection.h"
#include "ptvShownImage.h"
#include "ptvTracerRunner.h"

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

class vtkDataArray;
class vtkImageData;
class vtkMultiProcessController;
class vtkRenderer;
class vtkVolume;
class vtkWindow;

namespace ptv
{
/// The mapper's properties for one frame.
struct FrameRequest
{
  FrameSettings Scene;               ///< what reaches the kernel
  int MaximumAccumulatedFrames = 1024;
  /// When only the view changed, reproject the accumulation instead of dropping it.
  bool TemporalReprojection = true;
  int MaximumHistory = 1; ///< frames of reprojected history a pixel keeps at most
  int Threads = 0;                   ///< <= 0: every core
  int Backend = 0;                   ///< ptv::kBackend* (ptvBackend.h)
  bool Denoise = true;
  /// Samples per frame sample at the volume's edge pixels (ptvEdgeSamples.h; 1: none), traced
  /// when the frame is denoised or with ComputeEdgeSamples.
  int EdgeSamples = 3;
  bool ComputeEdgeSamples = false;
  DenoiserSettings Denoiser; ///< ModelFile, UseNetwork, Levels (Threads, UseCuda: here)
  std::string DisplayPass;           ///< "" shows the (converged) radiance
  /// Keep the ScatterDepth, ScatterPosition and ScatterNormal passes; also kept when
  /// DisplayPass shows one or the denoiser's model reads one.
  bool ScatterPasses = false;
  /// A still render: trace frames until the estimated quality of what is shown reaches
  /// StillQuality (dB), or MaximumStillFrames (also capped by MaximumAccumulatedFrames) are
  /// accumulated, or StillTimeBudget seconds (> 0) have passed (said once per budget).
  /// Otherwise one frame per render.
  bool Still = false;
  bool ConvergeStillRenders = true; ///< the mapper's default (Still is its per-render answer)
  double StillQuality = 40.0;
  int MaximumStillFrames = 256;
  double StillTimeBudget = 30.0;
  std::function<void(double)> Progress; ///< fraction done of a still render (may be empty)
  /// Asked between a still render's frames: true stops it (the render window's abort check).
  std::function<bool()> Abort;
  /// Processes that trace each frame together, each with the whole volume (ptvRanks.h);
  /// nullptr: this process alone.
  vtkMultiProcessController* Controller = nullptr;
  /// Each process holds its own piece (Scene.PieceExtent plus ghost layers) instead.
  bool Distributed = false;
};

/// What a frame asks the mapper to report, in order: (true = error, false = warning, text).
using FrameMessages = std::vector<std::pair<bool, std::string>>;

class FrameLoop
{
public:
  /**
   * Render one frame of @a vol into @a ren from @a image / @a scalars (@a cellScalars: the
   * chosen array is cell data, which is not supported). Problems go into @a messages, each only
   * when it differs from the last one reported (a problem that persists is reported once).
   */
  void Render(vtkRenderer* ren, vtkVolume* vol, vtkImageData* image, vtkDataArray* scalars,
    bool cellScalars, const FrameRequest& request, FrameMessages& messages);

  /// Drop the accumulation and its history; the next frame starts again from sample 0.
  void ResetAccumulation();

  /**
   * Report @a error only if it differs from the last error reported; false when it repeats it.
   * With an empty @a error, forget the last one if it starts with @a fixedPrefix (the problem
   * was fixed, so a later one is reported again).
   */
  bool ReportOnce(const std::string& error, const char* fixedPrefix = "");

  /// Frames traced since the view last changed (the still view's running mean).
  int GetAccumulatedFrames() const { return this->AccumulatedFrames; }
  /// Fraction of the volume's pixels that kept a history when the view last moved (0: none).
  double GetReprojectionReuse() const { return this->History.GetReusedFraction(); }
  /// Fraction of the pixels that got EdgeSamples in the last traced frame (0: none).
  double GetLastEdgeFraction() const { return this->LastEdgeFraction; }
  /// Milliseconds the last Render spent reprojecting (0 when the view did not move).
  double GetLastReprojectionTime() const { return this->LastReprojectionTime; }
  /// Frames traced by the last Render (0, 1, or more for a still render).
  int GetLastRenderFrames() const { return this->LastRenderFrames; }
  /// Estimated PSNR (dB, tone-mapped) of what is shown; 0 before 2 frames.
  double GetEstimatedQuality() const { return this->EstimatedQuality; }
  /// Whether a still render stopped because the estimate reached StillQuality.
  bool GetStillConverged() const { return this->StillConverged; }
  bool GetLastRenderTraced() const { return this->LastRenderTraced; }
  double GetLastTraceTime() const { return this->LastTraceTime; }
  double GetLastDenoiseTime() const { return this->LastDenoiseTime; }
  /// The accumulated passes, and the denoiser's when GetDenoisedValid().
  const PassBuffers& GetPasses()
  {
    this->FillGuidePasses();
    this->FillCountPasses();
    return this->Accumulated;
  }
  bool GetDenoisedValid() const { return this->DenoisedValid; }
  const std::string& GetActiveBackend() const { return this->Tracer.GetLastBackend(); }
  const std::string& GetDenoiserStatus() const { return this->Denoising.GetStatus(); }

  void ReleaseGraphicsResources(vtkWindow* window);

private:
  /// Trace one frame (this process's block of samples) and, where it is kept, accumulate it.
  void Trace(const FrameRequest& request, FrameMessages& messages);
  /// The frame's edge samples (ptvEdgeSamples.h) for @a edgeSamples > 1, on process 0's whole
  /// frame (@a keep); distributed pieces trace them together (collective).
  void TraceEdges(const FrameRequest& request, unsigned int firstSample, int edgeSamples,
    bool keep, const PieceView& piece);
  /// The traced frame joins the accumulation (reprojected history, running mean, counts).
  void AccumulateFrame(const FrameRequest& request);
  /// A moved view: the accumulation reprojected into the traced frame (ptvReprojection), the
  /// edge pixels (ptvEdgeSamples) tested with their frame sample's first hit and kept fresh.
  void ReprojectFrame(const FrameRequest& request);
  /// @a save: keep the edge pixels' Depth and Albedo of the frame sample in @a frame (before
  /// its edge samples); else exchange the kept ones with @a frame's (twice: back as they were).
  void SwapEdgeFirstHits(PassBuffers& frame, bool save);
  /// Denoise the accumulation if it changed since the last denoise; false on failure.
  /// The denoiser's settings for @a request (its threads; the grid on the tracer's device).
  DenoiserSettings SettingsOf(const FrameRequest& request) const;
  bool DenoiseFrame(const FrameRequest& request, FrameMessages& messages);
  /// Copy the last denoise's guides and weights into their passes (once per denoise).
  void FillGuidePasses();
  /// Write the HistoryLength and SampleRatio passes (once per accumulated frame).
  void FillCountPasses();
  /// Denoise (when on) and combine; updates EstimatedQuality.
  void Combine(const FrameRequest& request, FrameMessages& messages);
  /// The still render's loop (after the render's first frame).
  void Refine(const FrameRequest& request, FrameMessages& messages);
  int ShownPass(const FrameRequest& request, FrameMessages& messages);
  /// Whether this frame keeps the scatter passes (FrameRequest::ScatterPasses); process 0
  /// decides for everyone.
  bool KeepsScatterPasses(const FrameRequest& request);

  FrameInputs Inputs;
  Ranks Parallel; ///< the processes tracing each frame together (none: this one alone)
  TraceParams Params{};
  FrameSignature Signature; ///< of the frame that started the accumulation (or the view)
  TracerRunner Tracer;
  PassBuffers Frame{ PassSet::Traced };
  /// Distributed pieces, SamplesPerFrame > 1: one sample at a time.
  PassBuffers Sample{ PassSet::Traced };
  /// Distributed pieces: every extra edge sample on its own.
  PassBuffers EdgeList{ PassSet::Traced };
  PassBuffers Accumulated;
  Reprojection History;
  CameraRays AccumulatedCamera{}; ///< the camera of the accumulated passes
  bool ViewMoved = false;         ///< reproject the accumulation into the next traced frame
  /// The frame being traced starts the accumulation without history: it becomes the mean
  /// (PassBuffers::TakeTracedPasses), traced into the old mean's storage.
  bool FrameIsMean = false;
  Denoiser Denoising;
  Convergence Converging;
  ShownImage Shown;
  Display Drawing;
  std::vector<float> ZBuffer; ///< the window depth, read for the frame's rays (Render)
  std::vector<std::uint32_t> EdgePixels; ///< the last frame's (ptvEdgeSamples.h)
  std::vector<float> EdgeFirstHits;      ///< their frame sample's Depth and Albedo
  int EdgeSampleCount = 1;               ///< the EdgeSamples they got (1: none)
  std::vector<float> ConvergedAlpha; ///< the opacity the Converged pass is drawn with

  int AccumulatedFrames = 0;
  unsigned int SampleFrames = 0; ///< frames since the last reset: the sample index
  int LastViewFrames = 0;        ///< AccumulatedFrames after the last trace
  double LastReprojectionTime = 0.0;
  double LastEdgeFraction = 0.0;
  int LastRenderFrames = 0;
  double EstimatedQuality = 0.0;
  bool StillConverged = false;
  double ReportedBudget = -1.0; ///< the StillTimeBudget whose stop was last reported
  bool CombinedValid = false; ///< PassConverged and EstimatedQuality match the passes
  bool CombinedWithDenoiser = false;
  bool CombinedWithEstimate = false; ///< the last Combine estimated its error (still renders)
  bool LastRenderTraced = false;
  double LastTraceTime = 0.0;
  double LastDenoiseTime = 0.0;
  bool DenoisedValid = false;          ///< Denoised/Guides/BlendWeights match the passes
  bool CountPassesValid = false;       ///< HistoryLength/SampleRatio hold the last frame's
  bool GuidePassesValid = false;       ///< Guides/BlendWeights hold the last denoise's
  std::vector<std::string> DenoiseKey; ///< settings of the last denoise
  std::string LastError;
  std::string DisplayProblem; ///< the last DisplayPass problem reported (ShownPass)
  std::string BackendProblem; ///< the last backend problem reported
  vtkIdType LastNonFinite = 0;
};
}

#endif
