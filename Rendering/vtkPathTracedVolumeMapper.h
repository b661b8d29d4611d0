/**
 * @class vtkPathTracedVolumeMapper
 * @brief Monte Carlo path-traced volume mapper with a learned denoiser, named render passes
 *        and progressive accumulation.
 *
 * Renders a scalar vtkImageData with the ordinary vtkVolumeProperty (colour, scalar and
 * gradient opacity, unit distance, shading, interpolation), the vtkVolume matrix, the
 * renderer's key light and a uniform environment light (the renderer's background). Each render
 * traces SamplesPerFrame samples per pixel; while the view stays unchanged the frames average,
 * a camera move reprojects them (TemporalReprojection), and the denoiser turns the accumulation
 * into the image shown (pass "Converged"). A still render (a script's Render(), a screenshot)
 * traces until the image reaches StillQuality. Clipping planes, cropping and the blend modes
 * Composite, IsoSurface, maximum/minimum/average intensity and additive are honoured.
 *
 * Passes (GetPassName, GetPass, GetPasses): Radiance, Alpha, Albedo, Depth, Position, Normal,
 * Coverage, Footprint, ScatterDepth, ScatterPosition and ScatterNormal (kept when asked for:
 * the expert option ScatterPasses, or DisplayPass), and with Denoise on Denoised, Guides,
 * BlendWeights, Converged, DenoisedAlpha; HistoryLength and SampleRatio.
 * docs/properties.md describes every property and pass; rarely needed settings are in
 * GetExpertOptions(). The frame itself runs in ptvFrameLoop (this class is its VTK face).
 */
#ifndef vtkPathTracedVolumeMapper_h
#define vtkPathTracedVolumeMapper_h

#include "vtkPTVRenderingModule.h" // for export macro
#include "vtkVolumeMapper.h"

#include <memory> // for std::unique_ptr

class vtkImageData;
class vtkMultiProcessController;
class vtkPTVExpertOptions;
class vtkPTVRenderStatistics;
class vtkWindow;

class VTKPTVRENDERING_EXPORT vtkPathTracedVolumeMapper : public vtkVolumeMapper
{
public:
  static vtkPathTracedVolumeMapper* New();
  vtkTypeMacro(vtkPathTracedVolumeMapper, vtkVolumeMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Samples traced per pixel in each rendered frame. Default 1, range [1, 4096].
  virtual void SetSamplesPerFrame(int value);
  vtkGetMacro(SamplesPerFrame, int);

  ///@{
  /// Carry the accumulated samples into the new view when only the camera moves (on), or start
  /// again at every camera change (off). Default on.
  vtkSetMacro(TemporalReprojection, bool);
  vtkGetMacro(TemporalReprojection, bool);
  vtkBooleanMacro(TemporalReprojection, bool);
  ///@}

  ///@{
  /// Whether a still render (the volume's allocated render time >= 1 s: a script's Render(), a
  /// screenshot) traces until StillQuality or StillTimeBudget; off: one frame. Default on.
  vtkSetMacro(ConvergeStillRenders, bool);
  vtkGetMacro(ConvergeStillRenders, bool);
  vtkBooleanMacro(ConvergeStillRenders, bool);
  ///@}

  /// Target of a still render: the estimated PSNR (dB, tone-mapped as in docs/measuring.md) of
  /// the shown image against the converged one. Default 40, range [10, 100].
  virtual void SetStillQuality(double value);
  vtkGetMacro(StillQuality, double);

  /// Seconds after which a still render stops short of StillQuality (0: no limit; a stop is
  /// reported once per budget). Default 30, range [0, 1e6].
  virtual void SetStillTimeBudget(double value);
  vtkGetMacro(StillTimeBudget, double);

  ///@{
  /// Seed mixed into every pixel's random numbers. Default 0.
  vtkSetMacro(Seed, unsigned int);
  vtkGetMacro(Seed, unsigned int);
  ///@}

  ///@{
  /// Light scatters inside the volume at a random opacity (on), or at the first non-transparent
  /// sample like a surface (off). Default on.
  vtkSetMacro(Scattering, bool);
  vtkGetMacro(Scattering, bool);
  vtkBooleanMacro(Scattering, bool);
  ///@}

  ///@{
  /// Shadow the environment light by the volume (ambient occlusion) or light unoccluded.
  /// Default on.
  vtkSetMacro(AmbientOcclusion, bool);
  vtkGetMacro(AmbientOcclusion, bool);
  vtkBooleanMacro(AmbientOcclusion, bool);
  ///@}

  /// Key-light intensity multiplier. Default 1, range [0, 1e6].
  virtual void SetLightIntensity(double value);
  vtkGetMacro(LightIntensity, double);

  /// Environment-light intensity multiplier. Default 1, range [0, 1e6].
  virtual void SetEnvironmentIntensity(double value);
  vtkGetMacro(EnvironmentIntensity, double);

  ///@{
  /// Denoise the accumulation and show it mixed with the raw mean (pass "Converged"). Without a
  /// usable model the denoiser uses a fixed guide and warns once. Default on.
  vtkSetMacro(Denoise, bool);
  vtkGetMacro(Denoise, bool);
  vtkBooleanMacro(Denoise, bool);
  ///@}

  ///@{
  /// The GuideNet model file. Default: empty, the shipped Data/Models/guidenet.onnx.
  vtkSetFilePathMacro(DenoiserModelFile);
  vtkGetFilePathMacro(DenoiserModelFile);
  ///@}

  /// Worker threads; 0 uses every core this process may run on. Images are the same for any
  /// value. Default 0, range [0, 1024].
  virtual void SetNumberOfThreads(int value);
  vtkGetMacro(NumberOfThreads, int);

  ///@{
  /// The pass shown in the window; empty (default) shows "Converged" with Denoise on, else
  /// "Radiance". An unknown name is reported once and the default is shown.
  vtkSetStringMacro(DisplayPass);
  vtkGetStringMacro(DisplayPass);
  ///@}

  ///@{
  /// Where frames are traced: BACKEND_AUTO (default: CUDA when built with it and a device is
  /// usable, else the CPU), BACKEND_CPU, BACKEND_CUDA (without a device: an error, the CPU).
  enum
  {
    BACKEND_AUTO = 0,
    BACKEND_CPU = 1,
    BACKEND_CUDA = 2
  };
  virtual void SetBackend(int value);
  vtkGetMacro(Backend, int);
  void SetBackendToAuto() { this->SetBackend(BACKEND_AUTO); }
  void SetBackendToCPU() { this->SetBackend(BACKEND_CPU); }
  void SetBackendToCUDA() { this->SetBackend(BACKEND_CUDA); }
  ///@}

  /// Rarely needed settings (limits, study switches, denoiser internals): see
  /// vtkPTVExpertOptions. Never null; owned by the mapper.
  vtkPTVExpertOptions* GetExpertOptions();

  ///@{
  /// Number and names of the render passes, in a stable order.
  static int GetNumberOfPasses();
  static const char* GetPassName(int index);
  ///@}

  /// Copy the named pass of the current accumulation into @a output (float point data on the
  /// viewport's pixels). False with an error for an unknown name, a pass not kept or when
  /// none is available.
  bool GetPass(const char* name, vtkImageData* output);

  /// Copy every kept pass into @a output, one array per pass, "Radiance" active (ready
  /// for vtkPTVEXRPassWriter). False with an error when none is available.
  bool GetPasses(vtkImageData* output);

  /// Drop the accumulation and its history; the next render starts again.
  void ResetAccumulation();

  /// @name Statistics of the last render (read-only)
  ///@{
  /// Frames in the current accumulation (0 before the first render).
  vtkGetMacro(AccumulatedFrames, int);
  /// Whether the last render traced (false once the accumulation is full).
  vtkGetMacro(LastRenderTraced, bool);
  /// Estimated PSNR (dB) of the image shown by the last still render; 0 when not known.
  vtkGetMacro(EstimatedQuality, double);
  /// Whether the last still render reached StillQuality.
  vtkGetMacro(StillConverged, bool);
  /// Frames traced, milliseconds per stage and the like of the last render (benchmarks and
  /// diagnostics): vtkPTVRenderStatistics. Never null; owned by the mapper.
  vtkPTVRenderStatistics* GetStatistics();
  /// What the last denoise used: "GuideNet <model> (...)" or "fixed guide: <why>".
  const char* GetDenoiserStatus();
  /// "CPU" or "CUDA": the backend of the last traced frame ("none" before the first).
  const char* GetActiveBackend();
  ///@}

  ///@{
  /// The CPU kernels' instruction set on this machine ("AVX2" or "baseline"); whether the CUDA
  /// path is built and a device usable, and a one-line report why.
  static const char* GetCpuKernelTarget();
  static bool GetCudaAvailable();
  static const char* GetCudaStatus();
  ///@}

  /// @name Parallel plumbing (set by ParaView's representation; docs/parallel.md)
  ///@{
  /// Processes (MPI ranks) that trace each frame together, each with the whole volume;
  /// nullptr (default): this process alone. Process 0 accumulates, denoises and draws.
  void SetController(vtkMultiProcessController* controller);
  vtkMultiProcessController* GetController();
  /// Each process holds its own piece (PieceExtent plus ghost layers) of the volume whose
  /// extent is WholeExtent; the processes composite the pieces into process 0's frame.
  /// Default off.
  vtkSetMacro(DistributedVolume, vtkTypeBool);
  vtkGetMacro(DistributedVolume, vtkTypeBool);
  vtkBooleanMacro(DistributedVolume, vtkTypeBool);
  vtkSetVector6Macro(PieceExtent, int);
  vtkGetVector6Macro(PieceExtent, int);
  vtkSetVector6Macro(WholeExtent, int);
  vtkGetVector6Macro(WholeExtent, int);
  ///@}

  void Render(vtkRenderer* ren, vtkVolume* vol) override;
  void ReleaseGraphicsResources(vtkWindow* window) override;

  /// The input's bounds (the whole volume's with DistributedVolume); non-finite ones are
  /// reported as an error naming the value.
  double* GetBounds() VTK_SIZEHINT(6) override;
  using vtkVolumeMapper::GetBounds;

protected:
  vtkPathTracedVolumeMapper();
  ~vtkPathTracedVolumeMapper() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;

  // Defaults: ptv::FrameRequest's (the constructor copies them; one home for each).
  int SamplesPerFrame;
  bool TemporalReprojection;
  bool ConvergeStillRenders;
  double StillQuality;
  double StillTimeBudget;
  unsigned int Seed;
  bool Scattering;
  bool AmbientOcclusion;
  double LightIntensity;
  double EnvironmentIntensity;
  bool Denoise;
  char* DenoiserModelFile = nullptr;
  int NumberOfThreads;
  char* DisplayPass = nullptr;
  int Backend;
  vtkTypeBool DistributedVolume;
  int PieceExtent[6];
  int WholeExtent[6];

  int AccumulatedFrames = 0;
  double EstimatedQuality = 0.0;
  bool StillConverged = false;
  bool LastRenderTraced = false;
  bool RenderFailed = false; ///< the last Render traced no frame (GetPass says so)
  const char* NoFrameReason() const;

private:
  vtkPathTracedVolumeMapper(const vtkPathTracedVolumeMapper&) = delete;
  void operator=(const vtkPathTracedVolumeMapper&) = delete;

  struct vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
