/**
 * @class vtkPTVEXRPassWriter
 * @brief Writes the point-data arrays of a 2D vtkImageData (render passes) to one multi-channel
 * float32 OpenEXR file.
 *
 * Meant for the passes of vtkPathTracedVolumeMapper (vtkPathTracedVolumeMapper::GetPasses()
 * gives them all as one image), but any 2D image works: every numeric point-data array becomes
 * one EXR channel per component, stored as 32-bit float (other types are converted), ZIP
 * compressed, scan lines, the image's top row (largest j) first as EXR expects. Channel names
 * follow the EXR conventions:
 *
 * | array | channels | array | channels |
 * |---|---|---|---|
 * | Radiance | R, G, B | Alpha | A |
 * | Albedo | albedo.R/G/B | Depth | Z |
 * | Position | P.X/Y/Z | Normal | N.X/Y/Z |
 * | ScatterDepth | scatter.Z | ScatterPosition | scatter.P.X/Y/Z |
 * | ScatterNormal | scatter.N.X/Y/Z | Denoised | denoised.R/G/B |
 * | Coverage | coverage.A | | |
 * | Footprint | footprint.A | | |
 *
 * Any other array (or a known name with another number of components) is written as
 * `<name>.Y` (1 component), `<name>.R/G/B` (3), `<name>.R/G/B/A` (4) or `<name>.0`, `.1`, ...
 * (other counts). The header's string attribute "ptv.passes" records which channels belong to
 * which array ("Radiance=R,G,B;Alpha=A;..."), so vtkPTVEXRPassReader restores the arrays exactly.
 *
 * The input must be 2D in x and y (one point along z) with at least one numeric point-data
 * array; string and other non-numeric arrays are errors (they have no EXR channel), as are two
 * arrays that would give the same channel name. Spacing and origin are not stored (EXR pixels).
 *
 * The file is written to a temporary file in FileName's folder, then renamed into place: a
 * failed write (unwritable or missing folder, full disk, ...) leaves neither a partial file nor
 * the temporary one, and reports a vtkErrorMacro naming the path and the reason; Write()
 * returns 0 and GetErrorCode() is set.
 *
 * @sa vtkPTVEXRPassReader, vtkPathTracedVolumeMapper::GetPasses
 */
#ifndef vtkPTVEXRPassWriter_h
#define vtkPTVEXRPassWriter_h

#include "vtkPTVFiltersModule.h" // for export macro
#include "vtkWriter.h"

class vtkImageData;

class VTKPTVFILTERS_EXPORT vtkPTVEXRPassWriter : public vtkWriter
{
public:
  static vtkPTVEXRPassWriter* New();
  vtkTypeMacro(vtkPTVEXRPassWriter, vtkWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The .exr file to write (replaced if it exists). Default: none.
   */
  vtkSetFilePathMacro(FileName);
  vtkGetFilePathMacro(FileName);
  ///@}

  ///@{
  /**
   * The input image (port 0).
   */
  vtkImageData* GetInput();
  vtkImageData* GetInput(int port);
  ///@}

  /// ".exr"
  const char* GetFileExtensions() { return ".exr"; }

  /// "OpenEXR render passes"
  const char* GetDescriptiveName() { return "OpenEXR render passes"; }

protected:
  vtkPTVEXRPassWriter();
  ~vtkPTVEXRPassWriter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  void WriteData() override;

  char* FileName = nullptr;

private:
  vtkPTVEXRPassWriter(const vtkPTVEXRPassWriter&) = delete;
  void operator=(const vtkPTVEXRPassWriter&) = delete;
};

#endif
