/**
 * @file ptvTestScene.h
 * @brief Shared by the C++ tests: the small analytic scene (vtkRTAnalyticSource, 33^3, a
 *        two-point colour and opacity ramp, shading on) under vtkPathTracedVolumeMapper with the
 *        mapper's defaults, in a size x size window; Pass() reads a pass as floats.
 */
#ifndef ptvTestScene_h
#define ptvTestScene_h

#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPathTracedVolumeMapper.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkRTAnalyticSource.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <vector>

namespace
{
struct AnalyticScene
{
  vtkNew<vtkRTAnalyticSource> Source;
  vtkNew<vtkColorTransferFunction> Color;
  vtkNew<vtkPiecewiseFunction> Opacity;
  vtkNew<vtkVolumeProperty> Property;
  vtkNew<vtkPathTracedVolumeMapper> Mapper;
  vtkNew<vtkVolume> Volume;
  vtkNew<vtkRenderer> Renderer;
  vtkNew<vtkRenderWindow> Window;

  explicit AnalyticScene(int size = 64)
  {
    this->Source->SetWholeExtent(-16, 16, -16, 16, -16, 16);
    this->Color->AddRGBPoint(37, 0.2, 0.4, 1.0);
    this->Color->AddRGBPoint(277, 1.0, 0.9, 0.5);
    this->Opacity->AddPoint(37, 0.0);
    this->Opacity->AddPoint(150, 0.0);
    this->Opacity->AddPoint(277, 0.8);
    this->Property->SetColor(this->Color);
    this->Property->SetScalarOpacity(this->Opacity);
    this->Property->ShadeOn();
    this->Mapper->SetInputConnection(this->Source->GetOutputPort());
    this->Volume->SetMapper(this->Mapper);
    this->Volume->SetProperty(this->Property);
    this->Renderer->AddVolume(this->Volume);
    this->Renderer->SetBackground(0.4, 0.4, 0.4);
    this->Renderer->GetActiveCamera()->Azimuth(20);
    this->Renderer->ResetCamera();
    this->Window->SetSize(size, size);
    this->Window->AddRenderer(this->Renderer);
  }

  /// Pass @a name of the current accumulation (empty when the mapper cannot give it).
  std::vector<float> Pass(const char* name)
  {
    vtkNew<vtkImageData> image;
    if (!this->Mapper->GetPass(name, image))
    {
      return {};
    }
    vtkFloatArray* a = vtkFloatArray::SafeDownCast(image->GetPointData()->GetScalars());
    return std::vector<float>(a->GetPointer(0), a->GetPointer(0) + a->GetNumberOfValues());
  }
};
}

#endif
