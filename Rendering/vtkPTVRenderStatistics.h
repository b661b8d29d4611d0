/**
 * @class vtkPTVRenderStatistics
 * @brief What vtkPathTracedVolumeMapper's last render cost and did, for benchmarks and diagnostics
 *        (vtkPathTracedVolumeMapper::GetStatistics()).
 *
 * Read-only: the mapper fills it at the end of every render. The state a user acts on (frames
 * accumulated, estimated quality, still converged, denoiser and backend in use) stays on the
 * mapper.
 */
#ifndef vtkPTVRenderStatistics_h
#define vtkPTVRenderStatistics_h

#include "vtkObject.h"
#include "vtkPTVRenderingModule.h" // for export macro

class VTKPTVRENDERING_EXPORT vtkPTVRenderStatistics : public vtkObject
{
public:
  static vtkPTVRenderStatistics* New();
  vtkTypeMacro(vtkPTVRenderStatistics, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Frames traced by the last render (0, 1, or more for a still render).
  vtkGetMacro(LastRenderFrames, int);
  /// Milliseconds the last render spent tracing.
  vtkGetMacro(LastTraceTime, double);
  /// Milliseconds the last render spent denoising.
  vtkGetMacro(LastDenoiseTime, double);
  /// Milliseconds the last render spent reprojecting the history after a camera move.
  vtkGetMacro(LastReprojectionTime, double);
  /// Fraction of the volume's pixels that kept their history at the last camera move.
  vtkGetMacro(ReprojectionReuse, double);
  /// Fraction of the pixels that got edge samples in the last traced frame.
  vtkGetMacro(LastEdgeFraction, double);

  /// Set by the mapper after a render: every field at once.
  void Update(int renderFrames, double traceTime, double denoiseTime, double reprojectionTime,
    double reprojectionReuse, double edgeFraction);

protected:
  vtkPTVRenderStatistics() = default;
  ~vtkPTVRenderStatistics() override = default;

  int LastRenderFrames = 0;
  double LastTraceTime = 0.0;
  double LastDenoiseTime = 0.0;
  double LastReprojectionTime = 0.0;
  double ReprojectionReuse = 0.0;
  double LastEdgeFraction = 0.0;

private:
  vtkPTVRenderStatistics(const vtkPTVRenderStatistics&) = delete;
  void operator=(const vtkPTVRenderStatistics&) = delete;
};

#endif
