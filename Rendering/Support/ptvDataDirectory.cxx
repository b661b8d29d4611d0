#include "ptvDataDirectory.h"

#include "vtksys/SystemTools.hxx"

#include <cstdlib>
#include <dlfcn.h>

namespace ptv
{
std::string DataDirectory()
{
  if (const char* env = std::getenv("PTV_DATA_DIR"))
  {
    if (*env)
    {
      return env;
    }
  }
  Dl_info info{};
  // Any function of this library names the library's file.
  if (!dladdr(reinterpret_cast<void*>(&DataDirectory), &info) || !info.dli_fname)
  {
    return {};
  }
  const std::string library = vtksys::SystemTools::GetRealPath(info.dli_fname);
  return vtksys::SystemTools::GetFilenamePath(library) + "/Data";
}
}
