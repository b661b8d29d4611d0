/**
 * @class vtkPTVGuideNet
 * @brief Runs the denoiser's GuideNet (an ONNX model) with ONNX Runtime on a feature image.
 *
 * GuideNet maps per-pixel features (tone-mapped noisy colour, albedo, normal, depth, ...; see
 * Training/ptv_training/features.py) to the bilateral grid's guides and blend weights. The model
 * file is written by Training/ptv_training/export_onnx.py ("guidenet-v1") and names its inputs,
 * levels and guide scale in its metadata; Load() checks all of it and reports every mismatch.
 *
 * Run() takes a W x H x 1 vtkImageData whose point data holds one float array with C components
 * (channel-last per point, in the order of GetInputChannelName()): its active scalars, or else its
 * only array. The output image gets the same geometry and a float array "GuidesWeights" (active
 * scalars) with 2L - 1 components: guides 0..L-1 in [0, 1] (multiply by GetGuideScale() for grid
 * bins), then blend weights 0..L-2. Row j of the network's tensor is image row j (VTK order).
 *
 * ONNX Runtime runs on the CPU, or with the CUDA execution provider when the runtime lists it
 * (GetExecutionProvider()). Errors (missing/corrupt file, metadata, shapes, wrong component count)
 * are reported with vtkErrorMacro and the methods return false.
 */
#ifndef vtkPTVGuideNet_h
#define vtkPTVGuideNet_h

#include "vtkObject.h"
#include "vtkPTVRenderingModule.h" // for export macro

#include <memory> // for std::unique_ptr
#include <string> // for std::string

class vtkImageData;

class VTKPTVRENDERING_EXPORT vtkPTVGuideNet : public vtkObject
{
public:
  static vtkPTVGuideNet* New();
  vtkTypeMacro(vtkPTVGuideNet, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The .onnx model to load. Default: none (see GetDefaultModelFile()).
   */
  vtkSetFilePathMacro(ModelFile);
  vtkGetFilePathMacro(ModelFile);
  ///@}

  ///@{
  /**
   * ONNX Runtime intra-op threads. Default 0: ONNX Runtime's choice (one per physical core).
   * Takes effect at the next Load() (Run() reloads when it changed). Idle threads sleep rather
   * than spin, so they do not compete with the path tracer between runs.
   */
  vtkSetClampMacro(NumberOfThreads, int, 0, 1024);
  vtkGetMacro(NumberOfThreads, int);
  ///@}

  /**
   * Load and validate ModelFile. Returns false (and reports why) when the file is missing or not
   * a valid "guidenet-v1" model; nothing stays loaded in that case.
   */
  bool Load();

  /// Whether a model is loaded.
  bool IsLoaded() const;

  /// Input channels of the loaded model (0 when none is loaded).
  int GetNumberOfInputChannels() const;

  /// Name of input channel @a index (e.g. "color.r"), or nullptr when out of range.
  const char* GetInputChannelName(int index) const;

  /// Bilateral grid levels L of the loaded model (0 when none is loaded).
  int GetNumberOfLevels() const;

  /// Output components, 2L - 1 (0 when none is loaded).
  int GetNumberOfOutputs() const;

  /// Spatial cell size (pixels) of @a level, or 0 when out of range.
  int GetSpatialStep(int level) const;

  /// Range step of @a level (the grid has 256 / step bins), or 0 when out of range.
  int GetRangeStep(int level) const;

  /// Factor from guide values in [0, 1] to grid range units (metadata ptv.guide_scale, 255).
  double GetGuideScale() const;

  /// "CPUExecutionProvider" or "CUDAExecutionProvider"; nullptr when no model is loaded.
  const char* GetExecutionProvider() const;

  /// Version of the ONNX Runtime library in use (e.g. "1.21.1").
  static std::string GetRuntimeVersion();

  /**
   * Run the network on @a features into @a output (see the class description). Loads the model
   * first when nothing is loaded or ModelFile/NumberOfThreads changed. Buffers are reused between
   * calls of the same size.
   */
  bool Run(vtkImageData* features, vtkImageData* output);

  /// Wall time of the last successful Run() in milliseconds (layout conversions included).
  vtkGetMacro(LastRunTime, double);

  /**
   * The shipped model: $PTV_DATA_DIR/Models/guidenet.onnx when PTV_DATA_DIR is set, else
   * Data/Models/guidenet.onnx in the plugin folder (beside libvtkPTVRendering.so: the build tree
   * and an install alike).
   */
  static std::string GetDefaultModelFile();

protected:
  vtkPTVGuideNet();
  ~vtkPTVGuideNet() override;

  char* ModelFile = nullptr;
  int NumberOfThreads = 0;
  double LastRunTime = 0.0;

private:
  vtkPTVGuideNet(const vtkPTVGuideNet&) = delete;
  void operator=(const vtkPTVGuideNet&) = delete;

  struct vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
