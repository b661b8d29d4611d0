// Regression image of VTK's stock CPU volume mapper on a synthetic volume, through the project's
// preset loader: guards the test harness itself (Xvfb, OpenGL, baselines, thresholds).
#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkFixedPointVolumeRayCastMapper.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkRTAnalyticSource.h"
#include "vtkRegressionTestImage.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

int TestPTVStockVolumeImage(int argc, char* argv[])
{
  vtkNew<vtkRTAnalyticSource> source; // smooth, deterministic 21^3 "wavelet", values ~37..277
  source->SetWholeExtent(-20, 20, -20, 20, -20, 20);

  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(40, 0.2, 0.2, 0.8);
  color->AddRGBPoint(160, 1.0, 1.0, 0.0);
  color->AddRGBPoint(280, 1.0, 1.0, 1.0);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(40, 0.0);
  opacity->AddPoint(150, 0.0);
  opacity->AddPoint(200, 0.3);
  opacity->AddPoint(280, 0.9);

  vtkNew<vtkVolumeProperty> property;
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  property->SetInterpolationTypeToLinear();
  property->ShadeOn();

  vtkNew<vtkFixedPointVolumeRayCastMapper> mapper;
  mapper->SetInputConnection(source->GetOutputPort());
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(property);

  vtkNew<vtkRenderer> renderer;
  renderer->AddVolume(volume);
  renderer->SetBackground(0.1, 0.1, 0.15);
  renderer->GetActiveCamera()->Azimuth(30);
  renderer->GetActiveCamera()->Elevation(20);
  renderer->ResetCamera();
  vtkNew<vtkRenderWindow> window;
  window->SetSize(256, 256);
  window->SetMultiSamples(0);
  window->AddRenderer(renderer);
  window->Render();

  // The fixed-point mapper is deterministic; the threshold only absorbs GL driver differences.
  const int result = vtkRegressionTestImageThreshold(window, 0.05);
  return result == vtkRegressionTester::PASSED ? EXIT_SUCCESS : EXIT_FAILURE;
}
