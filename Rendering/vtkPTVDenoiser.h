/**
 * @class vtkPTVDenoiser
 * @brief The denoiser: neural bilateral grid with named input images (the OIDN filter shape).
 *
 * Give it the passes of a frame by name -- the names of vtkPathTracedVolumeMapper's passes:
 * "Radiance" (required), "Albedo", and whatever the model's feature channels need ("Normal",
 * "Depth", "ScatterNormal", "ScatterDepth", ...; "HistoryLength", the frames in each pixel's
 * mean, for a model with the "history" channel: without it every pixel counts one frame) --
 * as 2D float images (W x H x 1, one
 * point-data array: the active scalars, or else the only array), call Execute() and read
 * GetOutput() (array "Denoised", 3 components; the Radiance image's origin and spacing).
 *
 * The stages: features -> GuideNet (ONNX Runtime; ModelFile, default GetDefaultModelFile())
 * predicts one guide per grid level and blend weights -> the radiance (divided by albedo + 0.01
 * when the model says so) is splatted into each level's bilateral grid, sliced with the level's
 * guide, blended and re-modulated (Rendering/Kernels/ptvBilateralGrid.h, which the torch
 * reference Training/ptv_training/bilateral_grid.py follows). GetGuides() and
 * GetBlendWeights() return what the network predicted. With a "SampleRatio" image (how many
 * times a plain pixel's samples each pixel's mean holds, as the mapper's pass of that name: its
 * edge pixels hold EdgeSamples times) every pixel of ratio r > 1 takes (r - 1) / (r - 1 + 4) of
 * its own mean (Radiance; Alpha for DenoisedAlpha) and the rest of its denoised value: the
 * denoised value counts as 4 samples (ratios <= 1, NaN or infinite, and pixels whose radiance
 * is not finite and non-negative keep it). With a "Footprint" image
 * (vtkPTVExpertOptions::FootprintRays) the pixels whose four corners it marks 0 --
 * empty space -- come out black (and transparent in the DenoiseAlpha opacity).
 *
 * Three more image names replace a stage, for tests and research:
 * - "Features": the network's input (channel last, in the model's channel order, at the
 *   model's resolution: ceil(W / s) x ceil(H / s) for guide stride s) instead of the features
 *   built from the passes.
 * - "Guides" (L components, [0, 255]) and "BlendWeights" (L - 1 components, [0, 1], needed when
 *   L > 1): the grid runs alone on them with SpatialStep/RangeStep, dividing by "Albedo" when it
 *   is given.
 *
 * Without a usable model (missing, corrupt, wrong shape, or UseNetwork off) it denoises with a
 * fixed guide built from albedo, depth and normal, warns once, and reports it in
 * GetNetworkActive()/GetStatus(): a model never fails a render. Invalid images are errors
 * (vtkErrorMacro naming the image and the offending value; Execute() returns false and the
 * output keeps the last result). The CPU work is bit-identical for any NumberOfThreads.
 * vtkPathTracedVolumeMapper runs the same code on its passes when its Denoise setting is on.
 */
#ifndef vtkPTVDenoiser_h
#define vtkPTVDenoiser_h

#include "vtkObject.h"
#include "vtkPTVRenderingModule.h" // for export macro

#include <memory> // for std::unique_ptr
#include <string> // for std::string

class vtkImageData;

class VTKPTVRENDERING_EXPORT vtkPTVDenoiser : public vtkObject
{
public:
  static vtkPTVDenoiser* New();
  vtkTypeMacro(vtkPTVDenoiser, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * Set the input image called @a name (a pass name, see vtkPathTracedVolumeMapper::GetPassName,
   * or "Features", "Guides", "BlendWeights"); nullptr removes it. Unknown names are an error.
   */
  void SetImage(const char* name, vtkImageData* image);
  vtkImageData* GetImage(const char* name);
  void RemoveAllImages();

  ///@{
  /**
   * The GuideNet .onnx model. Default: empty = GetDefaultModelFile().
   */
  vtkSetFilePathMacro(ModelFile);
  vtkGetFilePathMacro(ModelFile);
  ///@}

  /**
   * The shipped model: $PTV_DATA_DIR/Models/guidenet.onnx when PTV_DATA_DIR is set, else
   * Data/Models/guidenet.onnx in the plugin folder (beside libvtkPTVRendering.so: the build tree
   * and an install alike).
   */
  static std::string GetDefaultModelFile();

  /// Version of the ONNX Runtime library in use (e.g. "1.21.1").
  static std::string GetRuntimeVersion();

  ///@{
  /**
   * Use the network (on, default) or always the fixed guide (off).
   */
  vtkSetMacro(UseNetwork, bool);
  vtkGetMacro(UseNetwork, bool);
  vtkBooleanMacro(UseNetwork, bool);
  ///@}

  ///@{
  /**
   * Grid levels: 0 (default) = automatic: on an image above 256 x 256 pixels the model's
   * default ("ptv.default_levels", else all its levels; the shipped model: 1 of its 3), at or
   * below that every level of the model; 3 with the fixed guide; the component count of given
   * "Guides"; 1..3 uses the model's finest ones, up to all it has (given guides must have as
   * many components).
   * With 0 and the network, a small image drops the model's coarser levels whose grid would
   * have fewer than 16 cells over it (the finest stays): there they only blur (e.g. an 8 x 8
   * image uses the 4-pixel level alone).
   */
  vtkSetClampMacro(NumberOfLevels, int, 0, 3);
  vtkGetMacro(NumberOfLevels, int);
  ///@}

  ///@{
  /**
   * Spatial cell size (pixels per cell along x and y) and range step (guide values per bin,
   * ceil(256 / step) bins) of grid level @a level (0..2), each clamped to 1..256, for the fixed
   * guide and given "Guides"; a model's own steps (its metadata) take precedence when the
   * network runs. Defaults: 4, 8, 16 for both. An invalid level is an error (Get returns 0).
   */
  void SetSpatialStep(int level, int step);
  int GetSpatialStep(int level);
  void SetRangeStep(int level, int step);
  int GetRangeStep(int level);
  ///@}

  ///@{
  /**
   * Outlier clamp before splatting: each channel of the demodulated radiance is limited to
   * Clamp x its mean luminance (fireflies). Default 8; 0 turns it off. Range [0, 1e6].
   */
  vtkSetClampMacro(Clamp, double, 0.0, 1e6);
  vtkGetMacro(Clamp, double);
  ///@}

  ///@{
  /**
   * Threads for the grid and the network; 0 (default) = every core.
   */
  vtkSetClampMacro(NumberOfThreads, int, 0, 1024);
  vtkGetMacro(NumberOfThreads, int);
  ///@}

  ///@{
  /**
   * Run the bilateral grid's CPU kernels in their portable (baseline) build instead of the best
   * instruction set of this CPU (AVX-512, AVX2, SSE4, chosen at run time). Default off; the
   * environment variable PTV_PORTABLE_KERNELS=1 forces it too. Results agree within rounding.
   */
  vtkSetMacro(PortableKernels, bool);
  vtkGetMacro(PortableKernels, bool);
  vtkBooleanMacro(PortableKernels, bool);
  ///@}

  ///@{
  /**
   * Run the bilateral grid on the CUDA device (the same kernel body as the CPU; needs a build
   * with PTV_ENABLE_CUDA and a device). When it cannot run, Execute() warns why and runs it on
   * the CPU; GetLastGridOnCuda() tells where the last one ran. Default: off.
   */
  vtkSetMacro(UseCuda, bool);
  vtkGetMacro(UseCuda, bool);
  vtkBooleanMacro(UseCuda, bool);
  bool GetLastGridOnCuda();
  ///@}

  ///@{
  /**
   * Also denoise the opacity: the "Alpha" image (then required) through the finest level of the
   * same grid, into the output's "DenoisedAlpha" array (1 component, [0, 1]): the opacity to
   * draw the premultiplied "Denoised" colour with over a background (one frame's alpha is 0 or 1
   * per pixel). Where it is 0 no nearby pixel in that level's space has an event, and the colour
   * the coarser levels spread there is set to 0 too (with one level it is 0 already).
   * vtkPathTracedVolumeMapper always does this. Default: off (the colour alone, like OIDN).
   */
  vtkSetMacro(DenoiseAlpha, bool);
  vtkGetMacro(DenoiseAlpha, bool);
  vtkBooleanMacro(DenoiseAlpha, bool);
  ///@}

  /// The instruction set the grid's CPU kernels used in the last Execute() ("AVX3", "AVX2",
  /// "SSE4", "SCALAR", ...; "" before the first).
  const char* GetKernelTarget();

  /**
   * Denoise the current images. Returns false (with an error naming the problem) when Radiance
   * is missing, sizes differ, arrays are not float or have the wrong component count, a pass
   * the features or the demodulation need is missing, or given Features/Guides do not fit.
   */
  bool Execute();

  /// The last result (array "Denoised", 3 components, and with DenoiseAlpha "DenoisedAlpha");
  /// empty before the first Execute(). The
  /// array is reused (overwritten) by the next Execute() of the same size: copy it to keep it.
  vtkImageData* GetOutput();

  /// Guides (array "Guides", one component per level, [0, 255]) of the last Execute().
  void GetGuides(vtkImageData* output);
  /// Blend weights (array "BlendWeights", levels - 1 components) of the last Execute().
  void GetBlendWeights(vtkImageData* output);

  /// Whether the last Execute() used GuideNet; GetStatus() says which model or why not.
  bool GetNetworkActive();
  const char* GetStatus();

  ///@{
  /// Milliseconds of the last Execute(): features, GuideNet, splat (incl. demodulation), slice.
  double GetLastFeatureTime();
  double GetLastGuideNetTime();
  double GetLastSplatTime();
  double GetLastSliceTime();
  /// The opacity with DenoiseAlpha on (0 otherwise): on the CPU grid only its last step
  /// (clamp, colour set to 0), as the opacity rides in the colour's splat and slice there; on
  /// the CUDA grid its own grid pass.
  double GetLastAlphaTime();
  ///@}

protected:
  vtkPTVDenoiser();
  ~vtkPTVDenoiser() override;

  char* ModelFile = nullptr;
  bool UseNetwork = true;
  int NumberOfLevels = 0;
  double Clamp = 8.0;
  int NumberOfThreads = 0;
  bool PortableKernels = false;
  bool UseCuda = false;
  bool DenoiseAlpha = false;

private:
  vtkPTVDenoiser(const vtkPTVDenoiser&) = delete;
  void operator=(const vtkPTVDenoiser&) = delete;

  void SetStep(int level, int step, int* steps, const char* what);
  int GetStep(int level, const int* steps, const char* what);

  struct vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
