/**
 * @class vtkPTVDenoiser
 * @brief Neural bilateral-grid denoiser with named input images (the OIDN filter shape).
 *
 * Give it the passes of a frame by name -- the names of vtkPathTracedVolumeMapper's passes:
 * "Radiance" and "Albedo" (required), and whatever the model's feature channels need ("Normal",
 * "Depth", "ScatterNormal", "ScatterDepth", ...) -- as 2D float images (W x H x 1, one
 * point-data array with 1 or 3 components), call Execute() and read GetOutput() (array
 * "Denoised", 3 components).
 *
 * GuideNet (ONNX Runtime; ModelFile, default the shipped Data/Models/guidenet.onnx) predicts
 * one guide per grid level and blend weights; the demodulated radiance (radiance / (albedo +
 * 0.01)) is splatted into each level's bilateral grid, sliced with the level's guide, blended
 * and re-modulated (Kernels/ptvBilateralGrid.h). Without a usable model (missing, corrupt,
 * wrong shape, or UseNetwork off) it denoises with a fixed guide built from albedo, depth and
 * normal, warns once, and reports it in GetNetworkActive()/GetStatus(): it never fails a render.
 * vtkPathTracedVolumeMapper runs the same code on its passes when its Denoise setting is on.
 */
#ifndef vtkPTVDenoiser_h
#define vtkPTVDenoiser_h

#include "vtkObject.h"
#include "vtkPTVRenderingModule.h" // for export macro

#include <memory> // for std::unique_ptr

class vtkImageData;

class VTKPTVRENDERING_EXPORT vtkPTVDenoiser : public vtkObject
{
public:
  static vtkPTVDenoiser* New();
  vtkTypeMacro(vtkPTVDenoiser, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * Set the input image called @a name (a pass name, see vtkPathTracedVolumeMapper::GetPassName);
   * nullptr removes it. Unknown names are an error.
   */
  void SetImage(const char* name, vtkImageData* image);
  vtkImageData* GetImage(const char* name);
  void RemoveAllImages();

  ///@{
  /**
   * The GuideNet .onnx model. Default: empty = vtkPTVGuideNet::GetDefaultModelFile().
   */
  vtkSetFilePathMacro(ModelFile);
  vtkGetFilePathMacro(ModelFile);
  ///@}

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
   * Grid levels: 0 (default) = the model's (3 with the fixed guide); 1..3 uses the finest ones.
   */
  vtkSetClampMacro(NumberOfLevels, int, 0, 3);
  vtkGetMacro(NumberOfLevels, int);
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

  /// The instruction set the grid's CPU kernels used in the last Execute() ("AVX3", "AVX2",
  /// "SSE4", "SCALAR", ...; "" before the first).
  const char* GetKernelTarget();

  /**
   * Denoise the current images. Returns false (with an error naming the problem) when Radiance
   * or Albedo is missing, sizes differ, arrays are not float or have the wrong component count,
   * or a pass the model needs is missing.
   */
  bool Execute();

  /// The last result (array "Denoised", 3 components); empty before the first Execute(). The
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

private:
  vtkPTVDenoiser(const vtkPTVDenoiser&) = delete;
  void operator=(const vtkPTVDenoiser&) = delete;

  struct vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
