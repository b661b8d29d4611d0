/**
 * @class vtkPathTracedVolumeMapper
 * @brief Monte Carlo path-traced volume mapper with named render passes and accumulation.
 *
 * Traces one sample per pixel per frame (SamplesPerFrame) through a scalar vtkImageData using the
 * ordinary vtkVolumeProperty (colour, scalar opacity and gradient opacity functions, scalar
 * opacity unit distance, shading coefficients, interpolation type), the vtkVolume matrix, the
 * image's spacing/origin/direction, and one key light: the renderer's first switched-on scene or
 * camera light, or, when the renderer has only its automatic headlight (or UseRendererLight is
 * off), a point light above the volume as in the seed paper. The environment is a uniform colour
 * (default: the renderer's background).
 *
 * One frame, top-down (ptvFrameLoop; this class is its VTK face): frame inputs (ptvFrameInputs)
 * -> the per-pixel estimator of Kernels/ptvIntegrator.h on the CPU or CUDA (ptvTracerRunner) ->
 * the running mean of named passes (ptvPassBuffers) -> the denoiser (ptvDenoiser) -> the shown
 * pass as colour and window depth (ptvShownImage) drawn into the window (ptvDisplay). While
 * camera, volume, transfer functions, light, viewport and opaque geometry stay unchanged,
 * frames accumulate as a running mean up to MaximumAccumulatedFrames. A change of the volume,
 * the transfer functions, a scene light, the settings or the viewport drops every sample; a
 * camera move alone (with the lights that follow the camera) reprojects them into the new view
 * (TemporalReprojection). Random numbers depend on (pixel, frame since the last drop, Seed)
 * only, so images are identical across runs and thread counts, and for a given camera path.
 *
 * Passes (GetPassName): "Radiance" (premultiplied HDR RGB), "Alpha", "Albedo", "Depth",
 * "Position", "Normal" (first non-transparent sample), "ScatterDepth", "ScatterPosition",
 * "ScatterNormal" (the scattering event), "Coverage" (the camera ray's opacity: see
 * ComputeCoverage; else Alpha), "Footprint" (0 where the pixel is empty space: see
 * ComputeFootprint; else 1). Depth is the world distance from the eye; misses have
 * depth = camera far distance, position 0, normal 0. With Denoise on, the denoiser (see
 * vtkPTVDenoiser) adds "Denoised" (shown by default), "Guides" and "BlendWeights", computed from
 * the accumulated passes after each traced frame, and "Converged" (the denoised image mixed with
 * the raw mean as samples accumulate). "HistoryLength" is the number of frames in each pixel's
 * accumulated mean (after a camera move: reprojected history, at most MaximumHistory, plus the
 * frames of the new view). "DenoisedAlpha" is the Alpha pass through the finest level of the
 * denoiser's grid (its guide, no clamp), and Denoised is 0 where it is 0 (vtkPTVDenoiser's
 * DenoiseAlpha): Denoised is drawn with it as its opacity, and
 * Converged with the same per-pixel blend of it and Alpha as its colour's (ptvConvergence); one
 * frame's Alpha is 0 or 1 per pixel, which would show the background through every pixel whose
 * ray met no event however much colour the denoiser gave it. "SampleRatio" is how many times a
 * plain pixel's samples each pixel's mean holds in the last frame: EdgeSamples on its edge
 * pixels, 1 elsewhere; with KeepEdgeMeans the denoiser leans those pixels towards their own
 * means by it (vtkPTVDenoiser, "SampleRatio").
 */
#ifndef vtkPathTracedVolumeMapper_h
#define vtkPathTracedVolumeMapper_h

#include "vtkPTVRenderingModule.h" // for export macro
#include "vtkVolumeMapper.h"

#include <memory> // for std::unique_ptr

class vtkMultiProcessController;

class vtkImageData;
class vtkWindow;

class VTKPTVRENDERING_EXPORT vtkPathTracedVolumeMapper : public vtkVolumeMapper
{
public:
  static vtkPathTracedVolumeMapper* New();
  vtkTypeMacro(vtkPathTracedVolumeMapper, vtkVolumeMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Samples traced per pixel in each rendered frame. Default 1, range [1, 4096].
   */
  virtual void SetSamplesPerFrame(int value); ///< clamped to [1, 4096] with a warning
  vtkGetMacro(SamplesPerFrame, int);
  ///@}

  ///@{
  /**
   * Most frames averaged while the view stays unchanged; once reached, further renders redraw
   * the converged image without tracing. Default 1024, range [1, 1000000].
   */
  virtual void SetMaximumAccumulatedFrames(int value); ///< clamped to [1, 1000000] with a warning
  vtkGetMacro(MaximumAccumulatedFrames, int);
  ///@}

  ///@{
  /**
   * Temporal reuse while the camera moves. On (default), a change of the camera alone (and of
   * the lights that follow it: camera lights, the default light) carries the accumulated passes
   * into the new view instead of dropping them: each pixel finds what it sees in the previous
   * image through its first event's world position, keeps only neighbours that saw the same
   * surface (depth, normal and albedo agree; disocclusions and silhouettes start afresh), and
   * its Radiance and Alpha (the other passes restart with the view) join that history as
   * an exponential moving average of at most
   * MaximumHistory frames (default 1, range [1, 1000000]): more history is less noisy, but
   * lags behind what changes with the view (lights that follow the camera, highlights, content
   * behind the first event, which moves with another parallax); on 2-degree-per-frame orbits
   * of the head and the stent, 1 and 2 are equally close to the converged views and 2 is
   * steadier (tPSNR +0.1 dB), but after a transfer-function change 2 left frames up to 0.12 dB
   * below the same samples without history, 1 at most 0.02 (docs/temporal.md).
   * The cap shrinks as the view turns between frames (orbit or roll) and reaches 0 at a turn of
   * 8 degrees (a fast orbit starts afresh each frame; a pan or zoom keeps it). A still camera
   * accumulates exactly as with it off. Off: every camera change starts again from one frame.
   */
  vtkSetMacro(TemporalReprojection, bool);
  vtkGetMacro(TemporalReprojection, bool);
  vtkBooleanMacro(TemporalReprojection, bool);
  virtual void SetMaximumHistory(int value); ///< clamped to [1, 1000000] with a warning
  vtkGetMacro(MaximumHistory, int);
  ///@}

  /// Fraction of the pixels showing the volume that kept their history at the last camera
  /// move (0 before one).
  vtkGetMacro(ReprojectionReuse, double);

  /// Milliseconds the last render spent reprojecting (0 when the camera did not move).
  vtkGetMacro(LastReprojectionTime, double);

  ///@{
  /**
   * Whether a still render converges. A render is a still render when the volume's allocated
   * render time is at least 1 s (VTK's convention, as in vtkFixedPointVolumeRayCastMapper: the
   * render window's desired update rate is below 1, e.g. a script's Render() or the
   * interactor's still render; ParaView's still renders and screenshots). A still render traces
   * frames until the estimated quality of the shown image reaches StillQuality, or
   * MaximumStillFrames (and MaximumAccumulatedFrames) frames are accumulated, or StillTimeBudget
   * seconds have passed; an interactive render (or any render with this off) traces one frame.
   * A still render that finds the accumulation converged traces nothing. Default on.
   */
  vtkSetMacro(ConvergeStillRenders, bool);
  vtkGetMacro(ConvergeStillRenders, bool);
  vtkBooleanMacro(ConvergeStillRenders, bool);
  ///@}

  ///@{
  /**
   * Target of a still render: the estimated PSNR in dB of the shown image against the converged
   * one, after the tone map x^(1/2.2) (docs/measuring.md). Default 40, range [10, 100].
   */
  virtual void SetStillQuality(double value); ///< clamped to [10.0, 100.0] with a warning
  vtkGetMacro(StillQuality, double);
  ///@}

  ///@{
  /**
   * Most frames a still render accumulates. Default 256, range [1, 1000000].
   */
  virtual void SetMaximumStillFrames(int value); ///< clamped to [1, 1000000] with a warning
  vtkGetMacro(MaximumStillFrames, int);
  ///@}

  ///@{
  /**
   * Seconds after which a still render stops tracing even if StillQuality is not reached
   * (0 = no limit; a stop before the target is reported once). Default 30, range [0, 1e6].
   */
  virtual void SetStillTimeBudget(double value); ///< clamped to [0.0, 1e6] with a warning
  vtkGetMacro(StillTimeBudget, double);
  ///@}

  /**
   * Estimated PSNR in dB (tone-mapped) of the image shown by the last render against the
   * converged image, estimated by still renders; 0 after an interactive render, before 2 frames,
   * or while every sample so far agrees (not known). With
   * Denoise on it rates the shown image (the denoised image mixed with the raw mean: pass
   * "Converged").
   */
  vtkGetMacro(EstimatedQuality, double);

  /// Frames traced by the last render (0, 1, or more for a still render).
  vtkGetMacro(LastRenderFrames, int);

  /// Whether the last still render stopped because its estimate reached StillQuality.
  vtkGetMacro(StillConverged, bool);

  ///@{
  /**
   * User seed mixed into every pixel's random stream. Default 0.
   */
  vtkSetMacro(Seed, unsigned int);
  vtkGetMacro(Seed, unsigned int);
  ///@}

  ///@{
  /**
   * Single scattering at a random opacity threshold (on) or a surface-like event at the first
   * non-transparent sample (off). Default on.
   */
  vtkSetMacro(Scattering, bool);
  vtkGetMacro(Scattering, bool);
  vtkBooleanMacro(Scattering, bool);
  ///@}

  ///@{
  /**
   * Trace the "Coverage" pass, each camera ray's opacity (its expected Alpha, without the
   * noise of the event's coin flip), by marching the ray on past its event until its
   * transmittance is below 0.01. The denoiser turns this on by itself when its model reads the
   * "coverage" channel (the shipped one does); set it to get the pass without denoising (the
   * training data does). It costs trace time in translucent volumes and changes no other pass.
   * Without it the Coverage pass is Alpha, whose expectation is the same opacity, so turning
   * it on or off keeps the accumulation. Only with Scattering on (off: Coverage is Alpha).
   * Default off.
   */
  vtkSetMacro(ComputeCoverage, bool);
  vtkGetMacro(ComputeCoverage, bool);
  vtkBooleanMacro(ComputeCoverage, bool);
  ///@}

  ///@{
  /**
   * Give every camera ray that meets opacity its event, weighted by the ray's opacity, instead
   * of deciding by a coin flip with that probability whether it has one. Each camera ray is
   * marched to its end (until its transmittance is below 1e-4), its opacity is stored as Alpha
   * (and Coverage), and its event is drawn among the samples in proportion to their share of
   * that opacity: the same expected image without the flip's noise, which dominates in
   * translucent transfer functions and thin shells and is nothing on opaque surfaces. Measured
   * at 256² on translucent ramps the 1-spp frame goes from 16.4 to 26.7 dB and its denoised
   * image from 34.0 to 36.1 dB, for 1.4x the trace time; on the datasets' presets the denoised
   * image gains 0.05-0.09 dB for 1.2-1.3x (research/results/coverage_frames.md). Ignored without
   * Scattering, with isosurfaces and for a DistributedVolume split across processes. Changing
   * it restarts the accumulation. Default off.
   */
  vtkSetMacro(ExpectedCoverage, bool);
  vtkGetMacro(ExpectedCoverage, bool);
  vtkBooleanMacro(ExpectedCoverage, bool);
  ///@}

  ///@{
  /**
   * Trace the "Footprint" pass: where a camera ray meets no opacity but comes near it, the ray
   * through its pixel's corner looks for opacity anywhere along it; the pass is 1 where the
   * camera ray met opacity, else that corner ray's answer, 0 where the camera ray only crossed
   * empty space. The denoiser keeps a pixel whose four corners are 0 black (vtkPTVDenoiser):
   * at one sample it cannot otherwise tell such a pixel from the fringe of a thin structure that
   * its one ray missed. The frame loop traces it by itself when it denoises with
   * DenoiserFootprint on (the default); set this to get the pass without denoising. It costs
   * trace time where rays pass near the volume and changes no other pass. Without it the pass
   * is 1. Default off.
   */
  vtkSetMacro(ComputeFootprint, bool);
  vtkGetMacro(ComputeFootprint, bool);
  vtkBooleanMacro(ComputeFootprint, bool);
  ///@}

  ///@{
  /**
   * Samples per frame at the volume's edge pixels (EdgeSamples, default 3; 1: none), traced
   * when the frame is denoised, or in every frame with ComputeEdgeSamples on (default off; for
   * benchmarks that denoise the passes themselves). With one sample a pixel on the volume's
   * silhouette or on thin structure shows all of its colour or none, and the denoiser cannot
   * average the two. After each frame, the pixels whose 3x3 neighbourhood holds a camera ray of
   * opacity (the Coverage pass, or Alpha without its march) of at least 0.5 and one below 0.05
   * get EdgeSamples - 1 more samples per frame sample: the frame sample's jitter completes a
   * lattice over the pixel (2: the opposite point), and every other random number comes from a
   * stream of their own, so every other pixel and pass is unchanged and each pixel's mean still
   * converges to the same image. On the evaluation's views 1-3 % of the pixels are edges
   * (stent 5-11 %); 2 samples there add 0.6-1.2 dB to the denoised frame for 4-18 % of the
   * trace time (stent 0.3-0.7 dB for 27-40 %), the third another 0.1-0.4 dB for 2-6 % (stent
   * 0.1-0.2 dB for 13-18 %), as much as 4 give (docs/edge-samples.md). When the camera moves
   * (TemporalReprojection), edge pixels start again from the new frame: their history lags
   * behind the silhouette. Edge samples are traced on the CPU, also when the CUDA backend
   * traced the frame; with several processes holding the whole volume by process 0 for all of
   * them; for a DistributedVolume split across processes by every process through its piece,
   * composited sample by sample like the frame's own samples.
   */
  virtual void SetEdgeSamples(int value); ///< clamped to [1, 64] with a warning
  vtkGetMacro(EdgeSamples, int);
  vtkSetMacro(ComputeEdgeSamples, bool);
  vtkGetMacro(ComputeEdgeSamples, bool);
  vtkBooleanMacro(ComputeEdgeSamples, bool);
  ///@}

  ///@{
  /**
   * Keep part of each edge pixel's own mean in the denoised image (default off): the denoiser
   * gets the SampleRatio pass (EdgeSamples on the last frame's edge pixels, 1 elsewhere) and
   * gives a pixel of ratio r the weight (r - 1) / (r - 1 + 4) of its own mean (vtkPTVDenoiser,
   * "SampleRatio"), while fewer than 8 frames have accumulated (then the Converged pass weighs
   * every pixel's mean against the denoised value). The grid averages an edge pixel with its
   * one-sample neighbours; on vessels narrower than a pixel (angiography) that loses more than
   * the extra samples' noise, and this step gains: the stent +0.66 dB at 256² with 3 edge
   * samples, +0.33 at 512². Where the edges are most of what is lit (thin shells: narrow
   * transfer-function bands) the neighbours are edge pixels too, the denoised value is worth
   * more than 4 samples, and the step loses (-1.10 dB on held-out narrow bands): hence off by
   * default (docs/edge-samples.md).
   */
  vtkSetMacro(KeepEdgeMeans, bool);
  vtkGetMacro(KeepEdgeMeans, bool);
  vtkBooleanMacro(KeepEdgeMeans, bool);
  ///@}

  /// Fraction of the pixels that got EdgeSamples in the last traced frame (0: none).
  vtkGetMacro(LastEdgeFraction, double);

  ///@{
  /**
   * Trace the visibility of the environment light (ambient occlusion) or light unoccluded.
   * Default on.
   */
  vtkSetMacro(AmbientOcclusion, bool);
  vtkGetMacro(AmbientOcclusion, bool);
  vtkBooleanMacro(AmbientOcclusion, bool);
  ///@}

  ///@{
  /**
   * How far environment rays look for occluders, as a fraction of the volume's diagonal: what
   * lies farther from an event does not darken it (local occlusion, like VTK's
   * GlobalIlluminationReach for its shadows). 1 (default) traces them to the volume's exit;
   * 0 leaves the environment unoccluded. Cheaper below 1: environment rays stop early.
   */
  virtual void SetAmbientOcclusionReach(double value); ///< clamped to [0.0, 1.0] with a warning
  vtkGetMacro(AmbientOcclusionReach, double);
  ///@}

  ///@{
  /**
   * Use the renderer's first switched-on scene or camera light as key light. When off, or when
   * the renderer has only its automatic headlight, a point light is placed above the volume
   * (along the camera's view-up, 1.5 bounding-box diagonals from the centre). Default on.
   */
  vtkSetMacro(UseRendererLight, bool);
  vtkGetMacro(UseRendererLight, bool);
  vtkBooleanMacro(UseRendererLight, bool);
  ///@}

  ///@{
  /**
   * Key-light intensity multiplier. Default 1, range [0, 1e6].
   */
  virtual void SetLightIntensity(double value); ///< clamped to [0.0, 1e6] with a warning
  vtkGetMacro(LightIntensity, double);
  ///@}

  ///@{
  /**
   * Uniform environment radiance. When UseBackgroundAsEnvironment is on (default) the renderer's
   * background colour is used instead of EnvironmentColor (default (1,1,1), each in [0, 1]).
   * EnvironmentIntensity scales either. Default 1, range [0, 1e6].
   */
  virtual void SetEnvironmentColor(double r, double g, double b); ///< clamped, with a warning
  void SetEnvironmentColor(const double rgb[3])
  {
    this->SetEnvironmentColor(rgb[0], rgb[1], rgb[2]);
  }
  vtkGetVector3Macro(EnvironmentColor, double);
  vtkSetMacro(UseBackgroundAsEnvironment, bool);
  vtkGetMacro(UseBackgroundAsEnvironment, bool);
  vtkBooleanMacro(UseBackgroundAsEnvironment, bool);
  virtual void SetEnvironmentIntensity(double value); ///< clamped to [0.0, 1e6] with a warning
  vtkGetMacro(EnvironmentIntensity, double);
  ///@}

  ///@{
  /**
   * Empty-space skipping over a brick grid rebuilt when volume or transfer function change.
   * Does not change the image (the sample positions are the same). Default on.
   */
  vtkSetMacro(EmptySpaceSkipping, bool);
  vtkGetMacro(EmptySpaceSkipping, bool);
  vtkBooleanMacro(EmptySpaceSkipping, bool);
  ///@}

  ///@{
  /**
   * Denoise the accumulated image with the neural bilateral grid and show the result (mixed
   * with the raw mean as samples accumulate: pass "Converged"). Default on. Without a usable model the denoiser uses a fixed guide and warns once.
   */
  vtkSetMacro(Denoise, bool);
  vtkGetMacro(Denoise, bool);
  vtkBooleanMacro(Denoise, bool);
  ///@}

  ///@{
  /**
   * The GuideNet model. Default: empty = the shipped Data/Models/guidenet.onnx.
   */
  vtkSetFilePathMacro(DenoiserModelFile);
  vtkGetFilePathMacro(DenoiserModelFile);
  ///@}

  ///@{
  /**
   * Use GuideNet (on, default) or always the denoiser's fixed guide (off, no network).
   */
  vtkSetMacro(DenoiserUseNetwork, bool);
  vtkGetMacro(DenoiserUseNetwork, bool);
  vtkBooleanMacro(DenoiserUseNetwork, bool);
  ///@}

  ///@{
  /**
   * With Denoise, trace the "Footprint" pass (see ComputeFootprint) and keep the pixels it
   * marks empty space black (on, default), or do neither (off). At one sample the denoiser
   * otherwise spreads the colour of thin structures into the empty pixels around them; on the
   * evaluation's views the pass adds 0.1-0.7 dB for 6-28 % of the trace time
   * (Testing/Benchmarks/results/footprint.md).
   */
  vtkSetMacro(DenoiserFootprint, bool);
  vtkGetMacro(DenoiserFootprint, bool);
  vtkBooleanMacro(DenoiserFootprint, bool);
  ///@}

  ///@{
  /**
   * Bilateral-grid levels used by the denoiser: 0 (default) = automatic (the model's default
   * above 256 x 256 pixels, the shipped model: 1 of its 3; every level at or below), less those
   * too coarse for a small image
   * (vtkPTVDenoiser::SetNumberOfLevels); 1..3 = the finest, up to the model's.
   */
  virtual void SetDenoiserNumberOfLevels(int value); ///< clamped to [0, 3] with a warning
  vtkGetMacro(DenoiserNumberOfLevels, int);
  ///@}

  /// What the last denoise used: "GuideNet <model> (...)" or "fixed guide: <why>".
  const char* GetDenoiserStatus();

  /// Milliseconds spent denoising in the last render (0 if it did not denoise).
  vtkGetMacro(LastDenoiseTime, double);

  ///@{
  /**
   * Threads used to trace a frame; 0 (default) uses every core this process may run on (its
   * CPU affinity; with a Controller, the host's cores shared by its ranks). Frames are
   * bit-identical for any value. The tracer, the denoiser and the display share one persistent pool of worker
   * threads of the plugin's own (VTK 9.2's SMP backends are either sequential or start new
   * threads for every loop); the application's vtkSMPTools backend is left alone.
   */
  virtual void SetNumberOfThreads(int value); ///< clamped to [0, 1024] with a warning
  vtkGetMacro(NumberOfThreads, int);
  ///@}

  ///@{
  /**
   * Processes (MPI ranks) that trace each frame together; nullptr (default): this process
   * alone. Every process must hold the whole volume and render every frame. Process r traces
   * the samples of frame f that one process would trace as block f * N + r with N times the
   * SamplesPerFrame, and process 0 accumulates the frames' mean over the N processes: the image
   * one process would accumulate, N times faster. Process 0 alone accumulates, denoises and
   * draws (the others draw nothing, so that compositing keeps process 0's image; their passes
   * are not kept), and its decisions (restart, trace, when a still render stops) are everyone's. With NumberOfThreads 0
   * the processes on one host share its cores. ParaView's "Path Traced Volume" representation
   * sets it in parallel runs when the volume fits (ReplicateVolumeLimit).
   */
  void SetController(vtkMultiProcessController* controller);
  vtkMultiProcessController* GetController();
  ///@}

  ///@{
  /**
   * A volume too large for one process (off by default: every process holds the whole volume,
   * above). On, each process's input is its own piece, PieceExtent, plus ghost layers around
   * it: camera rays cross only the piece, shadow and environment rays the ghost layers as well
   * (nothing beyond them). Each process traces its piece with its own random numbers (block
   * f * N + r as above, SamplesPerFrame samples per frame in all), and process 0 composites the
   * pieces' traced passes in view order -- the premultiplied "over" of their events, the first
   * hit of the nearest piece that has one -- into the frame of the whole volume, which it
   * accumulates, denoises and draws as above. The processes share the whole volume's scalar
   * range (the transfer function's table spans it) and bounds (the default light). Without a
   * Controller the one process traces its piece alone.
   */
  vtkSetMacro(DistributedVolume, vtkTypeBool);
  vtkGetMacro(DistributedVolume, vtkTypeBool);
  vtkBooleanMacro(DistributedVolume, vtkTypeBool);
  ///@}

  ///@{
  /**
   * With DistributedVolume: the part of the input's extent (structured point indices) that this
   * process owns; the rest of the input is its ghost layer. Must lie inside the input's extent
   * (else an error names both and nothing is rendered). Pieces that share a face share its
   * points (as ParaView's do). Default (0, -1, 0, -1, 0, -1): the whole input, no ghost layer.
   */
  vtkSetVector6Macro(PieceExtent, int);
  vtkGetVector6Macro(PieceExtent, int);
  ///@}

  ///@{
  /**
   * With DistributedVolume: the extent of the whole volume, all pieces together (structured
   * point indices, the pipeline's WHOLE_EXTENT). Camera rays sample on its grid, and GetBounds
   * reports its bounds, since process 0 draws the whole composited volume (a compositor that
   * crops each process's image to its prop bounds, such as ParaView's IceT pass, then keeps
   * all of it). Default (0, -1, 0, -1, 0, -1): the union of the processes' PieceExtents, learnt
   * at each render, and the input's own bounds.
   */
  vtkSetVector6Macro(WholeExtent, int);
  vtkGetVector6Macro(WholeExtent, int);
  ///@}

  ///@{
  /**
   * Pass shown in the render window; empty (default) shows "Converged" (the denoised image mixed
   * with the raw mean) when Denoise is on, else "Radiance". Normals are shown as (n+1)/2, positions normalised to the volume's bounds,
   * depths to the range of hits (near = bright).
   */
  vtkSetStringMacro(DisplayPass);
  vtkGetStringMacro(DisplayPass);
  ///@}

  ///@{
  /// Number and names of the render passes, in a stable order.
  static int GetNumberOfPasses();
  static const char* GetPassName(int index);
  ///@}

  /**
   * Copy the named pass of the current accumulation into @a output as a float vtkImageData
   * (extent = the viewport's pixels, one point-data array named after the pass, 1 or 3
   * components). Returns false with an error for an unknown name or before the first render.
   */
  bool GetPass(const char* name, vtkImageData* output);

  /**
   * Copy every available pass of the current accumulation into @a output: one float point-data
   * array per pass, named after it, on the viewport's pixels (as GetPass()), "Radiance" the
   * active scalars. The denoiser's passes (Denoised, Guides, BlendWeights, Converged) are included when
   * the last frame was denoised. Ready for vtkPTVEXRPassWriter. Returns false with an error
   * before the first render.
   */
  bool GetPasses(vtkImageData* output);

  ///@{
  /**
   * Where frames are traced: BACKEND_AUTO (default: CUDA when this build has it and a usable
   * device exists, else the CPU), BACKEND_CPU, or BACKEND_CUDA (without a usable device: an
   * error naming why, then the CPU). Both run the same kernel; GetActiveBackend() tells which
   * traced the last frame.
   */
  enum
  {
    BACKEND_AUTO = 0,
    BACKEND_CPU = 1,
    BACKEND_CUDA = 2
  };
  virtual void SetBackend(int value); ///< clamped to [BACKEND_AUTO, BACKEND_CUDA] with a warning
  vtkGetMacro(Backend, int);
  void SetBackendToAuto() { this->SetBackend(BACKEND_AUTO); }
  void SetBackendToCPU() { this->SetBackend(BACKEND_CPU); }
  void SetBackendToCUDA() { this->SetBackend(BACKEND_CUDA); }
  /// "CPU" or "CUDA": the backend of the last traced frame ("none" before the first).
  const char* GetActiveBackend();
  ///@}

  /**
   * The instruction set the CPU tracer runs with on this machine: "AVX2" (x86-64-v3, chosen at
   * run time when the CPU has it) or "baseline" (SSE2; also forced by the environment variable
   * PTV_PORTABLE_KERNELS=1). Both builds trace the same estimator; they may differ in the last
   * bits (FMA contraction).
   */
  static const char* GetCpuKernelTarget();

  ///@{
  /**
   * Whether this build has the CUDA path and the machine has a usable CUDA device, and a
   * one-line report (e.g. "built without CUDA ..." or "no usable CUDA device (error 35 ...)").
   * Backend Auto traces on CUDA when this is true and on the CPU otherwise (see Backend).
   */
  static bool GetCudaAvailable();
  static const char* GetCudaStatus();
  ///@}

  /// Frames averaged so far in the current view (0 before the first render); after a camera
  /// move the passes also hold reprojected history (see the HistoryLength pass).
  vtkGetMacro(AccumulatedFrames, int);

  /// Drop the accumulation and its history; the next render starts again from frame 0.
  void ResetAccumulation();

  /// Whether the last render traced a new frame (false once MaximumAccumulatedFrames is reached).
  vtkGetMacro(LastRenderTraced, bool);

  /// Milliseconds spent tracing in the last render, all its frames (0 if it did not trace).
  vtkGetMacro(LastTraceTime, double);

  void Render(vtkRenderer* ren, vtkVolume* vol) override;
  void ReleaseGraphicsResources(vtkWindow* window) override;

  /**
   * The input's bounds. Non-finite ones (NaN/Inf image spacing or origin) are reported here as an
   * error naming the value: VTK's culler drops such a volume before Render() could say why.
   */
  double* GetBounds() VTK_SIZEHINT(6) override;
  using vtkVolumeMapper::GetBounds;

protected:
  vtkPathTracedVolumeMapper();
  ~vtkPathTracedVolumeMapper() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;

  // The properties the frame loop reads start at ptv::FrameRequest's defaults (set by the
  // constructor, so that each default has one home); the documented values above are those.
  int SamplesPerFrame;
  int MaximumAccumulatedFrames;
  bool TemporalReprojection;
  int MaximumHistory;
  bool ConvergeStillRenders = true;
  double StillQuality;
  int MaximumStillFrames;
  double StillTimeBudget;
  unsigned int Seed;
  bool Scattering;
  bool ComputeCoverage;
  bool ExpectedCoverage;
  bool ComputeFootprint;
  int EdgeSamples;
  bool ComputeEdgeSamples;
  bool KeepEdgeMeans;
  bool AmbientOcclusion;
  double AmbientOcclusionReach;
  bool UseRendererLight;
  double LightIntensity;
  double EnvironmentColor[3];
  bool UseBackgroundAsEnvironment;
  double EnvironmentIntensity;
  bool EmptySpaceSkipping;
  int NumberOfThreads;
  vtkTypeBool DistributedVolume;
  int PieceExtent[6];
  int WholeExtent[6];
  int Backend;
  bool Denoise;
  char* DenoiserModelFile = nullptr;
  bool DenoiserUseNetwork;
  bool DenoiserFootprint;
  int DenoiserNumberOfLevels;
  char* DisplayPass = nullptr;

  int AccumulatedFrames = 0;
  int LastRenderFrames = 0;
  double EstimatedQuality = 0.0;
  bool StillConverged = false;
  bool LastRenderTraced = false;
  double LastTraceTime = 0.0;
  bool RenderFailed = false; ///< the last Render traced no frame (GetPass says so)
  const char* NoFrameReason() const;
  double LastDenoiseTime = 0.0;
  double ReprojectionReuse = 0.0;
  double LastReprojectionTime = 0.0;
  double LastEdgeFraction = 0.0;

private:
  vtkPathTracedVolumeMapper(const vtkPathTracedVolumeMapper&) = delete;
  void operator=(const vtkPathTracedVolumeMapper&) = delete;

  struct vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
