/**
 * @class vtkPTVEXRPassReader
 * @brief Reads a multi-channel OpenEXR file (render passes) into a 2D float vtkImageData.
 *
 * The counterpart of vtkPTVEXRPassWriter: the output has extent (0, width-1, 0, height-1, 0, 0),
 * spacing 1, origin 0, and one float point-data array per pass, bottom row first (VTK order;
 * the file holds the top row first). Files written by vtkPTVEXRPassWriter carry the
 * "ptv.passes" attribute and come back with the original array names and component counts.
 * Other EXR files are grouped by the channel-name convention: R,G,B -> "Radiance",
 * A or alpha.A -> "Alpha", albedo.R/G/B -> "Albedo", Z -> "Depth", P.X/Y/Z -> "Position",
 * N.X/Y/Z -> "Normal", scatter.Z / scatter.P.* / scatter.N.* -> "ScatterDepth" /
 * "ScatterPosition" / "ScatterNormal", coverage.A -> "Coverage", footprint.A -> "Footprint",
 * denoised.R/G/B -> "Denoised";
 * any other channel joins the array named by the text before its last '.' (components ordered
 * R,G,B,A / X,Y,Z / numeric), and a channel without '.' is a 1-component array of its own name.
 * HALF and UINT channels are converted to float. The "Radiance" array, when present, is the
 * active scalars, else the first.
 *
 * Only the data window of single-part scan-line or tiled files is read (the first part of
 * multi-part files); a missing, unreadable or non-EXR file is an error naming the path and the
 * reason, and the output is empty.
 *
 * @sa vtkPTVEXRPassWriter
 */
#ifndef vtkPTVEXRPassReader_h
#define vtkPTVEXRPassReader_h

#include "vtkImageAlgorithm.h"
#include "vtkPTVFiltersModule.h" // for export macro

#include <string> // for std::string

class VTKPTVFILTERS_EXPORT vtkPTVEXRPassReader : public vtkImageAlgorithm
{
public:
  static vtkPTVEXRPassReader* New();
  vtkTypeMacro(vtkPTVEXRPassReader, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The .exr file to read. Default: none.
   */
  vtkSetFilePathMacro(FileName);
  vtkGetFilePathMacro(FileName);
  ///@}

  ///@{
  /**
   * Largest number of values (pixels x channels) one read may produce, all read as 4-byte
   * floats. A file whose data window and channels exceed it is refused with an error giving
   * them, before anything is allocated (a corrupt or hostile header can declare an image of
   * billions of pixels in a few bytes). Default: 2^31 - 1 = 2147483647 values (8 GiB).
   */
  vtkSetClampMacro(MaximumNumberOfValues, vtkIdType, 1, VTK_ID_MAX);
  vtkGetMacro(MaximumNumberOfValues, vtkIdType);
  ///@}

  /// 1 if @a fileName starts with the OpenEXR magic number, else 0.
  static int CanReadFile(const char* fileName);

protected:
  vtkPTVEXRPassReader();
  ~vtkPTVEXRPassReader() override;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  char* FileName = nullptr;
  vtkIdType MaximumNumberOfValues = 2147483647;

  /// The layout check of ptvEXRLayout.h and the size limit; false after reporting an error.
  bool CheckFile(const std::string& file);

private:
  vtkPTVEXRPassReader(const vtkPTVEXRPassReader&) = delete;
  void operator=(const vtkPTVEXRPassReader&) = delete;
};

#endif
