/**
 * @file ptvOpenVDBGrid.h
 * @brief Plain-C++ bridge between dense VTK-ordered volumes and OpenVDB files (private).
 *
 * This header is the whole interface of ptvOpenVDBGrid.cxx, which with ptvOpenVDBLayout.cxx
 * (the file check run before every read) is the only code of the project that includes OpenVDB
 * headers (they are slow to compile and must not leak into the public, wrapped headers). vtkPTVOpenVDBReader and vtkPTVOpenVDBWriter use it, and so do the
 * white-box C++ tests (hence the exported symbols).
 *
 * Conventions shared by all functions:
 * - Every function catches OpenVDB and standard exceptions; a failure returns false and puts a
 *   human-readable message naming the file (and grid, where one is involved) in @c error.
 * - A dense volume is stored with x varying fastest, then y, then z (VTK point order).
 *   Sample (i, j, k) of a DenseVolume is OpenVDB voxel IndexMin + (i, j, k), whose centre lies at
 *   world position Origin + (i, j, k) * Spacing.
 * - Only scalar `float` and `double` grids with a uniform-scale linear transform (voxel size
 *   equal along x, y and z, no rotation or shear, any translation) can be read or written.
 */
#ifndef ptvOpenVDBGrid_h
#define ptvOpenVDBGrid_h

#include "vtkPTVFiltersModule.h" // for export macro

#include <cstddef> // for std::size_t
#include <string>  // for std::string
#include <utility> // for std::pair
#include <vector>  // for std::vector

namespace ptv
{

/// One grid of an OpenVDB file, as described by the file's metadata (no voxels are read).
struct VTKPTVFILTERS_EXPORT GridInfo
{
  /// The grid's name ("density", ...); may be empty for unnamed grids.
  std::string Name;
  /// OpenVDB value type name: "float", "double", "vec3s", "int32", "bool", "ptdataidx32", ...
  std::string ValueType;
  /// OpenVDB grid class: "fog volume", "level set", "staggered" or "unknown".
  std::string GridClass;
  /// Number of active voxels, or -1 when the file carries no statistics metadata.
  long long ActiveVoxelCount = -1;
  /// Whether BBoxMin/BBoxMax (inclusive index-space active voxel bounds) come from the file.
  bool HasBBox = false;
  int BBoxMin[3] = { 0, 0, 0 };
  int BBoxMax[3] = { -1, -1, -1 };

  /// True for the value types this project reads and writes ("float" and "double").
  bool IsScalar() const { return this->ValueType == "float" || this->ValueType == "double"; }
};

/// Geometry (and optionally the values) of an axis-aligned block of voxels.
struct VTKPTVFILTERS_EXPORT DenseVolume
{
  /// Number of samples along x, y and z.
  int Dims[3] = { 0, 0, 0 };
  /// OpenVDB index coordinate of sample (0, 0, 0).
  int IndexMin[3] = { 0, 0, 0 };
  /// World position of sample (0, 0, 0).
  double Origin[3] = { 0.0, 0.0, 0.0 };
  /// Distance between samples (the OpenVDB voxel size); all three are equal for OpenVDB data.
  double Spacing[3] = { 1.0, 1.0, 1.0 };
  /// Value type: double when true, float when false.
  bool IsDouble = false;
  /**
   * Dims[0] * Dims[1] * Dims[2] values, x fastest, of type double (IsDouble) or float.
   * Not owned. Read: the caller provides the buffer to fill; write: the values to store.
   */
  void* Data = nullptr;

  /// Dims[0] * Dims[1] * Dims[2] (0 when any dimension is not positive).
  std::size_t GetNumberOfValues() const;
};

/**
 * Whether OpenVDB can open @a file (it exists, is readable and starts with a valid VDB header and
 * grid table). Never throws.
 */
VTKPTVFILTERS_EXPORT bool CanOpenFile(const std::string& file);

/**
 * List the grids of @a file from metadata only, in the order OpenVDB's io::File reports them:
 * sorted by grid name (io::File keeps its grid table in a name-keyed map and offers no access to
 * the order in which the grids are stored).
 */
VTKPTVFILTERS_EXPORT bool ListGrids(
  const std::string& file, std::vector<GridInfo>& grids, std::string& error);

/// "'density' (float), 'v' (vec3s)" for messages; "(none)" for an empty list.
VTKPTVFILTERS_EXPORT std::string DescribeGrids(const std::vector<GridInfo>& grids);

/**
 * Geometry of grid @a gridName of @a file: Dims/IndexMin span the grid's active voxel bounding box
 * (from the file's statistics metadata when present, else by reading the grid), Spacing is the
 * voxel size, Origin the world position of the bounding box's minimum corner voxel, IsDouble the
 * value type. @a volume.Data is left untouched.
 * Fails for a missing grid (the message lists the grids of the file), a non-scalar grid, a grid
 * with no active voxels and a transform that is not a uniform scale plus translation.
 */
VTKPTVFILTERS_EXPORT bool ReadScalarGridInfo(
  const std::string& file, const std::string& gridName, DenseVolume& volume, std::string& error);

/**
 * Copy the voxels of grid @a gridName of @a file inside the index box given by @a volume.IndexMin
 * and @a volume.Dims (usually as returned by ReadScalarGridInfo, or a sub-box of it) into
 * @a volume.Data, which must hold GetNumberOfValues() values of the grid's type (IsDouble must
 * match it). Voxels of the box that are not active get their stored (inactive) value, which is
 * the grid's background for files written by WriteScalarGrid. Origin and Spacing are updated from
 * the grid's transform.
 */
VTKPTVFILTERS_EXPORT bool ReadScalarGrid(
  const std::string& file, const std::string& gridName, DenseVolume& volume, std::string& error);

/**
 * Write one scalar grid (see WriteScalarGrids).
 */
VTKPTVFILTERS_EXPORT bool WriteScalarGrid(const std::string& file, const std::string& gridName,
  const DenseVolume& volume, double background, std::string& error);

/**
 * Write @a grids (name, volume) to @a file, replacing it. Each volume becomes a FloatGrid or
 * DoubleGrid (per IsDouble) of class fog volume with the given background value and a transform
 * that maps voxel IndexMin + (i, j, k) to Origin + (i, j, k) * Spacing. Values equal to
 * @a background (tolerance 0: exactly equal) become inactive background voxels; all others are
 * active, each with its exact bits (NaN and infinities included: NaN is never == background;
 * OpenVDB's copyFromDense, which treats NaN as equal to anything, is used only for volumes without
 * NaN or -0). A volume whose values all equal the background gives a grid with no active voxels
 * (ReadScalarGridInfo rejects such grids).
 * Spacing must be positive and equal along x, y and z (relative tolerance 1e-6).
 * The file is written to "<file>.tmp-<pid>" and renamed into place, so a failure never leaves a
 * partial file behind; the OS error is reported when the temporary file cannot be created or
 * renamed.
 */
VTKPTVFILTERS_EXPORT bool WriteScalarGrids(const std::string& file,
  const std::vector<std::pair<std::string, const DenseVolume*>>& grids, double background,
  std::string& error);

} // namespace ptv

#endif // ptvOpenVDBGrid_h
