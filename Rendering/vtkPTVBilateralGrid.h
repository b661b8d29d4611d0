/**
 * @class vtkPTVBilateralGrid
 * @brief The bilateral-grid part of the Neural Bilateral Grid denoiser (Meng et al. 2020):
 *        demodulate by albedo, clamp outliers, splat into 1..3 guided grids, slice, blend,
 *        re-modulate.
 *
 * The exact semantics (sanitising of non-finite inputs, grid sizes, tent weights, empty cells,
 * blend formula) are defined once, in Rendering/Kernels/ptvBilateralGrid.h; the torch reference
 * Training/ptv_training/bilateral_grid.py implements the same. The guides and blend weights are
 * produced elsewhere (the GuideNet); this class only applies them.
 *
 * Apply() takes 2D images (dimensions W x H x 1, W, H >= 1) whose active point scalars are
 * vtkFloatArray with 3 (radiance), 3 (albedo), L (guides, range [0, 255]) and L - 1 (blend
 * weights, range [0, 1]) components, L = NumberOfLevels; with Demodulate off the albedo is
 * not used and may be nullptr. The output image gets the inputs'
 * geometry and a 3-component vtkFloatArray "Denoised" as active scalars (reused, not
 * reallocated, when the output already holds one of the right size). The CPU work runs on
 * the plugin's persistent worker threads (ptvThreads.h) and is bit-identical
 * for any NumberOfThreads. Invalid input is reported with vtkErrorMacro naming the offending
 * value, and Apply returns false without touching the output.
 */
#ifndef vtkPTVBilateralGrid_h
#define vtkPTVBilateralGrid_h

#include "vtkObject.h"
#include "vtkPTVRenderingModule.h" // for export macro

#include <memory> // for std::unique_ptr

class vtkImageData;

class VTKPTVRENDERING_EXPORT vtkPTVBilateralGrid : public vtkObject
{
public:
  static vtkPTVBilateralGrid* New();
  vtkTypeMacro(vtkPTVBilateralGrid, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Number of grid levels L, 1..3. Default: 3. The guides need L components, the blend weights
   * L - 1.
   */
  vtkSetClampMacro(NumberOfLevels, int, 1, 3);
  vtkGetMacro(NumberOfLevels, int);
  ///@}

  ///@{
  /**
   * Spatial cell size ss (pixels per cell along x and y) of level @a level (0..2), 1..256.
   * Defaults: 4, 8, 16. An invalid level is an error (and Get returns 0).
   */
  void SetSpatialStep(int level, int step);
  int GetSpatialStep(int level);
  ///@}

  ///@{
  /**
   * Range step sr (guide values per range bin, GD = ceil(256 / sr) bins) of level @a level
   * (0..2), 1..256. Defaults: 4, 8, 16. An invalid level is an error (and Get returns 0).
   */
  void SetRangeStep(int level, int step);
  int GetRangeStep(int level);
  ///@}

  ///@{
  /**
   * Outlier clamp: each channel of the demodulated radiance is clamped to at most
   * Clamp * (mean luminance of the lit pixels of the demodulated frame, those with a
   * luminance > 0). 0 disables it. Default: 8.
   */
  vtkSetClampMacro(Clamp, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(Clamp, double);
  ///@}

  ///@{
  /**
   * Denoise radiance / (albedo + 0.01) and multiply back (on), or the radiance itself (off).
   * At 1 spp a volume's albedo (colour at a random scattering event) is as noisy as the
   * radiance, so multiplying back by it restores that noise; models say which they were
   * trained with. Default: on.
   */
  vtkSetMacro(Demodulate, bool);
  vtkGetMacro(Demodulate, bool);
  vtkBooleanMacro(Demodulate, bool);
  ///@}

  ///@{
  /**
   * Run on the CUDA device (the same kernel body as the CPU; needs a build with
   * PTV_ENABLE_CUDA and a device). When it cannot run, Apply reports why with an error and
   * runs on the CPU. GetLastApplyOnCuda() tells where the last Apply ran. Default: off.
   */
  vtkSetMacro(UseCuda, bool);
  vtkGetMacro(UseCuda, bool);
  vtkBooleanMacro(UseCuda, bool);
  bool GetLastApplyOnCuda() const;
  ///@}

  ///@{
  /**
   * Number of CPU threads; 0 uses every core. The result does not depend on it. Default: 0.
   */
  vtkSetClampMacro(NumberOfThreads, int, 0, VTK_INT_MAX);
  vtkGetMacro(NumberOfThreads, int);
  ///@}

  /**
   * Denoise one frame (see the class description for the inputs). @a weights may be nullptr
   * when NumberOfLevels is 1 (it is ignored then). Returns false, reporting why, on invalid
   * input.
   */
  bool Apply(vtkImageData* radiance, vtkImageData* albedo, vtkImageData* guides,
    vtkImageData* weights, vtkImageData* output);

  ///@{
  /**
   * Wall-clock milliseconds of the phases of the last successful Apply: demodulate + outlier
   * clamp, splat (all levels), slice + blend + re-modulate.
   */
  double GetLastDemodulateTime() const;
  double GetLastSplatTime() const;
  double GetLastSliceTime() const;
  ///@}

protected:
  vtkPTVBilateralGrid();
  ~vtkPTVBilateralGrid() override;

  int NumberOfLevels = 3;
  double Clamp = 8.0;
  bool Demodulate = true;
  bool UseCuda = false;
  int NumberOfThreads = 0;

private:
  vtkPTVBilateralGrid(const vtkPTVBilateralGrid&) = delete;
  void operator=(const vtkPTVBilateralGrid&) = delete;

  struct vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
