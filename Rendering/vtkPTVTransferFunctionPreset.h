/**
 * @class vtkPTVTransferFunctionPreset
 * @brief Reads colour/opacity presets in ParaView's preset JSON format and applies them.
 *
 * A preset file is a JSON list of objects with "Name", "RGBPoints" ([x, r, g, b, ...]),
 * optional "Points" for the opacity function ([x, opacity, midpoint, sharpness, ...]) and
 * optional "ColorSpace" ("RGB" default, "HSV", "Lab", "Diverging"). The same files import into
 * ParaView's colour-map editor and are read by `pathtracedvolume.presets` in Python.
 * The project's presets live in Data/TransferFunctions (GetDefaultPresetDirectory()).
 *
 * Errors (missing file, malformed JSON, unknown preset, bad point lists) are reported with
 * vtkErrorMacro naming the file, preset and field, and the methods return false.
 */
#ifndef vtkPTVTransferFunctionPreset_h
#define vtkPTVTransferFunctionPreset_h

#include "vtkObject.h"
#include "vtkPTVRenderingModule.h" // for export macro

#include <memory> // for std::unique_ptr
#include <string> // for std::string

class vtkColorTransferFunction;
class vtkPiecewiseFunction;
class vtkVolumeProperty;

class VTKPTVRENDERING_EXPORT vtkPTVTransferFunctionPreset : public vtkObject
{
public:
  static vtkPTVTransferFunctionPreset* New();
  vtkTypeMacro(vtkPTVTransferFunctionPreset, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The preset file to read. Default: none. Setting it clears presets loaded before.
   */
  vtkSetFilePathMacro(FileName);
  vtkGetFilePathMacro(FileName);
  ///@}

  /**
   * Parse FileName. Returns false (and reports why) on a missing file or malformed content;
   * previously loaded presets are kept in that case.
   */
  bool Load();

  /// Number of presets loaded by the last successful Load().
  int GetNumberOfPresets() const;

  /// Name of preset @a index (0-based), or nullptr when out of range.
  const char* GetPresetName(int index) const;

  /// Whether a preset of that name was loaded.
  bool HasPreset(const char* name) const;

  /**
   * Replace the content of @a color and @a opacity with the named preset. @a opacity may be
   * nullptr; a preset without "Points" leaves @a opacity unchanged.
   */
  bool ApplyPreset(
    const char* name, vtkColorTransferFunction* color, vtkPiecewiseFunction* opacity);

  /// Apply to the property's colour (component 0) and scalar opacity functions.
  bool ApplyPreset(const char* name, vtkVolumeProperty* property);

  /**
   * The folder of the shipped presets: $PTV_DATA_DIR/TransferFunctions when PTV_DATA_DIR is set,
   * else Data/TransferFunctions in the plugin folder (beside libvtkPTVRendering.so).
   */
  static std::string GetDefaultPresetDirectory();

protected:
  vtkPTVTransferFunctionPreset();
  ~vtkPTVTransferFunctionPreset() override;

  char* FileName = nullptr;

private:
  vtkPTVTransferFunctionPreset(const vtkPTVTransferFunctionPreset&) = delete;
  void operator=(const vtkPTVTransferFunctionPreset&) = delete;

  struct vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
