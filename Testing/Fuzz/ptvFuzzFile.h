// The readers' harnesses hand each input to a reader as a file: one per process in $TMPDIR
// (scripts/fuzz.sh points it into build-fuzz/), rewritten for every input.
#ifndef ptvFuzzFile_h
#define ptvFuzzFile_h

#include "vtkObject.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <unistd.h>

/// Writes @a data to this process's input file ending in @a extension; returns its name.
inline std::string WriteFuzzFile(const uint8_t* data, size_t size, const char* extension)
{
  static const std::string file = [extension] {
    vtkObject::GlobalWarningDisplayOff(); // errors are expected; they are not findings
    const char* dir = std::getenv("TMPDIR");
    return std::string(dir && *dir ? dir : "/tmp") + "/ptv_fuzz_" + std::to_string(getpid()) +
      extension;
  }();
  std::FILE* f = std::fopen(file.c_str(), "wb");
  if (!f)
  {
    std::abort();
  }
  if (size)
  {
    std::fwrite(data, 1, size, f);
  }
  std::fclose(f);
  return file;
}

#endif
