// The mapper's range-checked setters: a value outside a property's documented range is clamped
// into it (as vtkSetClampMacro does) and the user is told, once per call, what was set instead;
// a NaN keeps the current value.
#include "vtkPathTracedVolumeMapper.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <type_traits>

namespace
{
template <typename T>
T CheckedSetting(vtkObject* self, const char* name, T value, T current, T lo, T hi)
{
  if constexpr (std::is_floating_point<T>::value)
  {
    if (std::isnan(value))
    {
      vtkWarningWithObjectMacro(
        self, << "Set" << name << "(nan) ignored: not a number; it stays " << current << ".");
      return current;
    }
  }
  if (value >= lo && value <= hi)
  {
    return value;
  }
  const T clamped = value < lo ? lo : hi;
  vtkWarningWithObjectMacro(self, << "Set" << name << "(" << value << ") is outside [" << lo
                                  << ", " << hi << "]: " << name << " is set to " << clamped
                                  << ".");
  return clamped;
}
}

#define PTV_CLAMPED_SETTER(name, type, lo, hi)                                                    \
  void vtkPathTracedVolumeMapper::Set##name(type value)                                          \
  {                                                                                              \
    const type checked = CheckedSetting<type>(                                                   \
      this, #name, value, this->name, static_cast<type>(lo), static_cast<type>(hi));             \
    if (this->name != checked)                                                                   \
    {                                                                                            \
      this->name = checked;                                                                      \
      this->Modified();                                                                          \
    }                                                                                            \
  }

PTV_CLAMPED_SETTER(SamplesPerFrame, int, 1, 4096)
PTV_CLAMPED_SETTER(MaximumAccumulatedFrames, int, 1, 1000000)
PTV_CLAMPED_SETTER(MaximumHistory, int, 1, 1000000)
PTV_CLAMPED_SETTER(StillQuality, double, 10.0, 100.0)
PTV_CLAMPED_SETTER(MaximumStillFrames, int, 1, 1000000)
PTV_CLAMPED_SETTER(StillTimeBudget, double, 0.0, 1e6)
PTV_CLAMPED_SETTER(EdgeSamples, int, 1, 64)
PTV_CLAMPED_SETTER(AmbientOcclusionReach, double, 0.0, 1.0)
PTV_CLAMPED_SETTER(LightIntensity, double, 0.0, 1e6)
PTV_CLAMPED_SETTER(EnvironmentIntensity, double, 0.0, 1e6)
PTV_CLAMPED_SETTER(DenoiserNumberOfLevels, int, 0, 3)
PTV_CLAMPED_SETTER(NumberOfThreads, int, 0, 1024)
PTV_CLAMPED_SETTER(Backend, int, BACKEND_AUTO, BACKEND_CUDA)

void vtkPathTracedVolumeMapper::SetEnvironmentColor(double r, double g, double b)
{
  const double wanted[3] = { r, g, b };
  double checked[3];
  for (int k = 0; k < 3; ++k)
  {
    checked[k] = CheckedSetting<double>(
      this, "EnvironmentColor", wanted[k], this->EnvironmentColor[k], 0.0, 1.0);
  }
  if (!std::equal(checked, checked + 3, this->EnvironmentColor))
  {
    std::copy(checked, checked + 3, this->EnvironmentColor);
    this->Modified();
  }
}
