/**
 * @class vtkPTVOpenVDBWriter
 * @brief Writes a scalar point-data array of a vtkImageData as one grid of an OpenVDB file.
 *
 * The input must be a vtkImageData with identity direction matrix and uniform spacing (OpenVDB
 * voxels are cubes), carrying a 1-component float or double point-data array (ArrayName, or the
 * active scalars when ArrayName is empty). Each VTK point becomes the voxel of the same
 * structured index (i, j, k); its centre lies at the point's position. Float arrays give an
 * OpenVDB FloatGrid, double arrays a DoubleGrid, of class fog volume, named GridName.
 *
 * Values exactly equal to Background (tolerance 0) become inactive background voxels, all other
 * values active voxels; vtkPTVOpenVDBReader therefore returns the bounding box of the voxels that
 * differ from the background. NaN never equals the background: NaN, +-Inf and -0 voxels are
 * stored as active voxels with their exact bits (-0 equals a background of 0, though). A volume
 * that holds only the background value gives a grid with no active voxels, which the reader
 * rejects as empty.
 *
 * The file is written to a temporary file beside FileName and renamed into place, so a failed
 * write never leaves a partial file. Errors (no input, no or unsuitable scalars, non-uniform
 * spacing, non-identity direction, unwritable path) are reported with vtkErrorMacro naming the
 * offending value, set the error code and make Write() return 0.
 *
 * @sa vtkPTVOpenVDBReader
 */
#ifndef vtkPTVOpenVDBWriter_h
#define vtkPTVOpenVDBWriter_h

#include "vtkPTVFiltersModule.h" // for export macro
#include "vtkWriter.h"

class vtkImageData;

class VTKPTVFILTERS_EXPORT vtkPTVOpenVDBWriter : public vtkWriter
{
public:
  static vtkPTVOpenVDBWriter* New();
  vtkTypeMacro(vtkPTVOpenVDBWriter, vtkWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The .vdb file to write (replaced if it exists). Default: none.
   */
  vtkSetFilePathMacro(FileName);
  vtkGetFilePathMacro(FileName);
  ///@}

  ///@{
  /**
   * Name of the grid written to the file. Default: "density".
   */
  vtkSetStringMacro(GridName);
  vtkGetStringMacro(GridName);
  ///@}

  ///@{
  /**
   * Point-data array to write. Default: empty, meaning the active point scalars.
   */
  vtkSetStringMacro(ArrayName);
  vtkGetStringMacro(ArrayName);
  ///@}

  ///@{
  /**
   * Background value of the grid: voxels equal to it are stored as inactive background.
   * Default: 0.
   */
  vtkSetMacro(Background, double);
  vtkGetMacro(Background, double);
  ///@}

  ///@{
  /**
   * The input image (port 0).
   */
  vtkImageData* GetInput();
  vtkImageData* GetInput(int port);
  ///@}

  /// ".vdb"
  const char* GetFileExtensions() { return ".vdb"; }

  /// "OpenVDB volume"
  const char* GetDescriptiveName() { return "OpenVDB volume"; }

protected:
  vtkPTVOpenVDBWriter();
  ~vtkPTVOpenVDBWriter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  void WriteData() override;

  char* FileName = nullptr;
  char* GridName = nullptr;
  char* ArrayName = nullptr;
  double Background = 0.0;

private:
  vtkPTVOpenVDBWriter(const vtkPTVOpenVDBWriter&) = delete;
  void operator=(const vtkPTVOpenVDBWriter&) = delete;
};

#endif
