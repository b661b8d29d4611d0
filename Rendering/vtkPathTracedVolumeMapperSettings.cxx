// The mapper's range-checked setters (ptvCheckedSetting.h): clamped with one warning naming the
// value; a NaN keeps the current value.
#include "vtkPathTracedVolumeMapper.h"

#include "ptvCheckedSetting.h"

PTV_CLAMPED_SETTER(vtkPathTracedVolumeMapper, SamplesPerFrame, int, 1, 4096)
PTV_CLAMPED_SETTER(vtkPathTracedVolumeMapper, StillQuality, double, 10.0, 100.0)
PTV_CLAMPED_SETTER(vtkPathTracedVolumeMapper, StillTimeBudget, double, 0.0, 1e6)
PTV_CLAMPED_SETTER(vtkPathTracedVolumeMapper, LightIntensity, double, 0.0, 1e6)
PTV_CLAMPED_SETTER(vtkPathTracedVolumeMapper, EnvironmentIntensity, double, 0.0, 1e6)
PTV_CLAMPED_SETTER(vtkPathTracedVolumeMapper, NumberOfThreads, int, 0, 1024)
PTV_CLAMPED_SETTER(vtkPathTracedVolumeMapper, Backend, int, BACKEND_AUTO, BACKEND_CUDA)
