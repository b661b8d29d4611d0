/**
 * @file ptvTestMemory.h
 * @brief Test helper: this process's resident memory from /proc/self/status.
 */
#ifndef ptvTestMemory_h
#define ptvTestMemory_h

#include <fstream>
#include <string>

/// A /proc/self/status field (VmRSS, VmHWM) in bytes; 0 where it cannot be read.
inline double StatusBytes(const std::string& field)
{
  std::ifstream status("/proc/self/status");
  std::string key;
  double kib = 0.0;
  while (status >> key)
  {
    if (key == field + ":")
    {
      status >> kib;
      return 1024.0 * kib;
    }
    status.ignore(1 << 12, '\n');
  }
  return 0.0;
}

/// Reset this process's peak resident set (VmHWM) to its current one.
inline void ResetPeakMemory()
{
  std::ofstream("/proc/self/clear_refs") << "5";
}

#endif
