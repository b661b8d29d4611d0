/**
 * @class vtkPTVOpenVDBReader
 * @brief Reads one scalar grid of an OpenVDB (.vdb) file into a vtkImageData.
 *
 * The reader produces the dense block of voxels spanned by the grid's active voxel bounding box:
 * the output extent starts at 0 and the origin is the world position of the box's minimum
 * corner voxel (OpenVDB stores values at voxel centres; they become VTK points), the spacing is
 * the OpenVDB voxel size. Voxels of the box that are not active get the grid's background value
 * (more precisely: the value stored for them, which is the background for files written by
 * vtkPTVOpenVDBWriter). The values land in a 1-component point-data array named after the grid
 * (vtkFloatArray for float grids, vtkDoubleArray for double grids), set as the active scalars.
 *
 * Only scalar `float` and `double` grids with a uniform-scale linear transform are supported.
 * GetNumberOfGrids(), GetGridName() and GetGridType() list all grids of the file (including the
 * ones that cannot be read) once UpdateInformation() has run.
 *
 * Errors (no file name, missing, unreadable, corrupt or truncated file, unknown grid name,
 * non-scalar grid, empty grid, unsupported transform) are reported with vtkErrorMacro naming the
 * offending value; the output is then an empty vtkImageData and the pipeline request fails.
 *
 * @sa vtkPTVOpenVDBWriter
 */
#ifndef vtkPTVOpenVDBReader_h
#define vtkPTVOpenVDBReader_h

#include "vtkImageAlgorithm.h"
#include "vtkPTVFiltersModule.h" // for export macro

class vtkStringArray;

class VTKPTVFILTERS_EXPORT vtkPTVOpenVDBReader : public vtkImageAlgorithm
{
public:
  static vtkPTVOpenVDBReader* New();
  vtkTypeMacro(vtkPTVOpenVDBReader, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The .vdb file to read. Default: none.
   */
  vtkSetFilePathMacro(FileName);
  vtkGetFilePathMacro(FileName);
  ///@}

  ///@{
  /**
   * Name of the grid to read. Default: empty, meaning the first scalar (float or double) grid
   * of the file in the listing order of GetGridName() (sorted by name). A name that is not in
   * the file is an error listing the available grids.
   */
  vtkSetStringMacro(GridName);
  vtkGetStringMacro(GridName);
  ///@}

  ///@{
  /**
   * Largest number of voxels one read may produce: the requested extent, by default the dense
   * bounding box of the grid's active voxels (4 bytes per voxel for float grids, 8 for double).
   * A sparse grid whose few active voxels lie far apart spans a huge box; a read of more voxels
   * than this is refused with an error giving the box, instead of allocating it. Request a
   * smaller update extent, or raise the limit, to read such a grid.
   * Default: 2^31 - 1 = 2147483647 voxels (8 GiB as float; the largest default a ParaView
   * IdTypeVectorProperty can declare).
   */
  vtkSetClampMacro(MaximumNumberOfVoxels, vtkIdType, 1, VTK_ID_MAX);
  vtkGetMacro(MaximumNumberOfVoxels, vtkIdType);
  ///@}

  /**
   * Name of the grid that the last successful UpdateInformation() selected (GridName, or the
   * first scalar grid when GridName is empty); nullptr when there is none.
   */
  const char* GetActiveGridName();

  ///@{
  /**
   * The grids of the file, valid after UpdateInformation(), sorted by name (the order in which
   * OpenVDB lists them; the storage order in the file is not available). GetGridType() returns
   * the OpenVDB value type ("float", "double", "vec3s", "int32", ...). Out-of-range indices give
   * nullptr.
   */
  int GetNumberOfGrids();
  const char* GetGridName(int index);
  const char* GetGridType(int index);
  ///@}

  /**
   * Names of the grids that this reader can read (scalar float/double grids), valid after
   * UpdateInformation(). The array belongs to the reader. Used by the ParaView proxy to offer a
   * list of grid names.
   */
  vtkStringArray* GetScalarGridNames();

  /**
   * 1 when OpenVDB can open @a filename (it exists and has a valid VDB header), else 0.
   * Never throws or crashes on bad input.
   */
  static int CanReadFile(VTK_FILEPATH const char* filename);

  /// ".vdb"
  const char* GetFileExtensions() { return ".vdb"; }

  /// "OpenVDB volume"
  const char* GetDescriptiveName() { return "OpenVDB volume"; }

protected:
  vtkPTVOpenVDBReader();
  ~vtkPTVOpenVDBReader() override;

  int RequestInformation(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  char* FileName = nullptr;
  char* GridName = nullptr;
  vtkIdType MaximumNumberOfVoxels = 2147483647;

private:
  vtkPTVOpenVDBReader(const vtkPTVOpenVDBReader&) = delete;
  void operator=(const vtkPTVOpenVDBReader&) = delete;

  class vtkInternals;
  vtkInternals* Internals;
};

#endif
