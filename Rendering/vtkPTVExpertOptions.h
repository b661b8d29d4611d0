/**
 * @class vtkPTVExpertOptions
 * @brief Settings of vtkPathTracedVolumeMapper that benchmarks, tests and studies change and
 *        users rarely need (vtkPathTracedVolumeMapper::GetExpertOptions()).
 *
 * The defaults are the mapper's chosen behaviour (docs/decisions.md says why); ParaView shows
 * these behind the gear. Out-of-range values are clamped with one warning naming the value; NaN
 * keeps the current value. The mapper reads them at every render.
 */
#ifndef vtkPTVExpertOptions_h
#define vtkPTVExpertOptions_h

#include "vtkObject.h"
#include "vtkPTVRenderingModule.h" // for export macro

class VTKPTVRENDERING_EXPORT vtkPTVExpertOptions : public vtkObject
{
public:
  static vtkPTVExpertOptions* New();
  vtkTypeMacro(vtkPTVExpertOptions, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Most frames averaged while the view stays unchanged. Default 1024, range [1, 1e6].
  virtual void SetMaximumAccumulatedFrames(int value);
  vtkGetMacro(MaximumAccumulatedFrames, int);

  /// Most frames of reprojected history a pixel keeps when the camera moves (with
  /// TemporalReprojection). Default 1, range [1, 1e6].
  virtual void SetMaximumHistory(int value);
  vtkGetMacro(MaximumHistory, int);

  /// Most frames one still render accumulates. Default 256, range [1, 1e6].
  virtual void SetMaximumStillFrames(int value);
  vtkGetMacro(MaximumStillFrames, int);

  ///@{
  /// Trace the "Coverage" pass (each camera ray's opacity) even when the denoiser's model does
  /// not read it. Default off.
  vtkSetMacro(CoverageMarch, bool);
  vtkGetMacro(CoverageMarch, bool);
  vtkBooleanMacro(CoverageMarch, bool);
  ///@}

  ///@{
  /// Weight each camera ray's event by its opacity instead of a coin flip (less noise in
  /// translucent volumes, more trace time). Default off.
  vtkSetMacro(ExpectedCoverage, bool);
  vtkGetMacro(ExpectedCoverage, bool);
  vtkBooleanMacro(ExpectedCoverage, bool);
  ///@}

  ///@{
  /// Trace the "Footprint" pass (0 where a pixel sees only empty space) even without
  /// denoising. Default off.
  vtkSetMacro(FootprintRays, bool);
  vtkGetMacro(FootprintRays, bool);
  vtkBooleanMacro(FootprintRays, bool);
  ///@}

  ///@{
  /// Keep the ScatterDepth, ScatterPosition and ScatterNormal passes (GetPass, GetPasses)
  /// even when neither DisplayPass nor the denoiser's model reads them. Default off.
  vtkSetMacro(ScatterPasses, bool);
  vtkGetMacro(ScatterPasses, bool);
  vtkBooleanMacro(ScatterPasses, bool);
  ///@}

  /// Samples per frame on the volume's edge pixels of a denoised frame (1: none). Default 3,
  /// range [1, 64].
  virtual void SetEdgeSamples(int value);
  vtkGetMacro(EdgeSamples, int);

  ///@{
  /// Trace the edge samples in every frame, also without denoising. Default off.
  vtkSetMacro(ComputeEdgeSamples, bool);
  vtkGetMacro(ComputeEdgeSamples, bool);
  vtkBooleanMacro(ComputeEdgeSamples, bool);
  ///@}

  /// How far environment rays look for occluders, as a fraction of the volume's diagonal
  /// (0: unoccluded). Default 1, range [0, 1].
  virtual void SetAmbientOcclusionReach(double value);
  vtkGetMacro(AmbientOcclusionReach, double);

  ///@{
  /// Light with the renderer's first switched-on scene or camera light (on), or a point light
  /// above the volume (off; also when the renderer has only its automatic light). Default on.
  vtkSetMacro(UseRendererLight, bool);
  vtkGetMacro(UseRendererLight, bool);
  vtkBooleanMacro(UseRendererLight, bool);
  ///@}

  ///@{
  /// The environment light's colour: the renderer's background (UseBackgroundAsEnvironment
  /// on, default) or EnvironmentColor (default (1, 1, 1), each in [0, 1]).
  virtual void SetEnvironmentColor(double r, double g, double b);
  void SetEnvironmentColor(const double rgb[3])
  {
    this->SetEnvironmentColor(rgb[0], rgb[1], rgb[2]);
  }
  vtkGetVector3Macro(EnvironmentColor, double);
  vtkSetMacro(UseBackgroundAsEnvironment, bool);
  vtkGetMacro(UseBackgroundAsEnvironment, bool);
  vtkBooleanMacro(UseBackgroundAsEnvironment, bool);
  ///@}

  ///@{
  /// Skip empty bricks of the volume (the image is the same either way). Default on.
  vtkSetMacro(EmptySpaceSkipping, bool);
  vtkGetMacro(EmptySpaceSkipping, bool);
  vtkBooleanMacro(EmptySpaceSkipping, bool);
  ///@}

  ///@{
  /// The denoiser's guide from GuideNet (on) or its fixed guide (off). Default on.
  vtkSetMacro(DenoiserUseNetwork, bool);
  vtkGetMacro(DenoiserUseNetwork, bool);
  vtkBooleanMacro(DenoiserUseNetwork, bool);
  ///@}

  /// Bilateral-grid levels of the denoiser: 0 = the model's choice for the image size,
  /// 1..3 = the finest. Default 0, range [0, 3].
  virtual void SetDenoiserNumberOfLevels(int value);
  vtkGetMacro(DenoiserNumberOfLevels, int);

protected:
  vtkPTVExpertOptions();
  ~vtkPTVExpertOptions() override = default;

  // Defaults: ptv::FrameRequest's (the constructor copies them; one home for each).
  int MaximumAccumulatedFrames;
  int MaximumHistory;
  int MaximumStillFrames;
  bool CoverageMarch;
  bool ExpectedCoverage;
  bool FootprintRays;
  bool ScatterPasses;
  int EdgeSamples;
  bool ComputeEdgeSamples;
  double AmbientOcclusionReach;
  bool UseRendererLight;
  double EnvironmentColor[3];
  bool UseBackgroundAsEnvironment;
  bool EmptySpaceSkipping;
  bool DenoiserUseNetwork;
  int DenoiserNumberOfLevels;

private:
  vtkPTVExpertOptions(const vtkPTVExpertOptions&) = delete;
  void operator=(const vtkPTVExpertOptions&) = delete;
};

#endif
