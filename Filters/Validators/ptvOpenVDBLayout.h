/**
 * @file ptvOpenVDBLayout.h
 * @brief Checks an OpenVDB file's layout before OpenVDB reads it (private).
 *
 * OpenVDB trusts the sizes and offsets stored in a file: a corrupt string length, metadata size
 * or delayed-load count makes it allocate gigabytes, and a truncated file fails only half-way
 * through a grid. CheckOpenVDBLayout walks the header (format >= 222, OpenVDB 3.0 and later;
 * older formats are refused), the file metadata and each grid descriptor, and checks that every
 * declared size fits its section, that each grid's [grid, block, end) offsets are ordered and
 * inside the file, that the grid's metadata (the contents of its delayed-load metadata included)
 * and its transform's type name fit before its data block. The topology and voxel blocks are
 * walked separately, before OpenVDB reads them (ptvOpenVDBTree.h).
 */
#ifndef ptvOpenVDBLayout_h
#define ptvOpenVDBLayout_h

#include "vtkPTVFiltersModule.h" // for export macro

#include <string> // for std::string

namespace ptv
{

/// True if @a file passes the check; otherwise false with @a error naming the file and what is
/// wrong ("... is not a valid OpenVDB file (truncated or corrupt: ...)").
VTKPTVFILTERS_EXPORT bool CheckOpenVDBLayout(const std::string& file, std::string& error);

} // namespace ptv

#endif
