/**
 * @file ptvDataDirectory.h
 * @brief Private: where the shipped data (Models/guidenet.onnx, TransferFunctions/*.json) is.
 *
 * Found relative to the library that holds this code, so that an installed plugin folder (and
 * the build tree, which mirrors it) carries its own data: "<folder of libvtkPTVRendering.so>/Data".
 * $PTV_DATA_DIR, when set and not empty, takes precedence. No source-tree path is compiled in.
 */
#ifndef ptvDataDirectory_h
#define ptvDataDirectory_h

#include <string>

namespace ptv
{
/// The data folder (no trailing slash); "" when the library's own path cannot be found.
std::string DataDirectory();

/// The shipped GuideNet model: DataDirectory() + "/Models/guidenet.onnx".
inline std::string DefaultModelFile()
{
  return DataDirectory() + "/Models/guidenet.onnx";
}
}

#endif
