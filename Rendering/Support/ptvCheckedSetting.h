/**
 * @file ptvCheckedSetting.h
 * @brief Private: range-checked setters of the public classes. A value outside a property's
 *        documented range is clamped into it (as vtkSetClampMacro does) and the user is told,
 *        once per call, what was set instead; a NaN keeps the current value.
 */
#ifndef ptvCheckedSetting_h
#define ptvCheckedSetting_h

#include "vtkObject.h"

#include <cmath>
#include <type_traits>

namespace ptv
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

/// Defines cls::Set<name>(type) with CheckedSetting over [lo, hi].
#define PTV_CLAMPED_SETTER(cls, name, type, lo, hi)                                               \
  void cls::Set##name(type value)                                                                \
  {                                                                                              \
    const type checked = ptv::CheckedSetting<type>(                                              \
      this, #name, value, this->name, static_cast<type>(lo), static_cast<type>(hi));             \
    if (this->name != checked)                                                                   \
    {                                                                                            \
      this->name = checked;                                                                      \
      this->Modified();                                                                          \
    }                                                                                            \
  }

#endif
