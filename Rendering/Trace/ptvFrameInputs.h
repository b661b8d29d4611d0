/**
 * @file ptvFrameInputs.h
 * @brief Private: turns the VTK scene (image, volume property, camera, lights, z-buffer) into
 *        the kernel's plain structs, owning the host memory behind them.
 *
 * The float copy of the voxels (and the occupancy's per-brick value ranges) is rebuilt only when
 * the image or array changes, the transfer-function tables and brick distances only when the
 * volume property changes (MTime). Build() fills the per-frame structs (with ptvSceneToKernel's
 * pieces) and a signature of everything that changes the image, so the frame loop resets its
 * accumulation when (and only when) it differs.
 */
#ifndef ptvFrameInputs_h
#define ptvFrameInputs_h

#include "Kernels/ptvIntegrator.h"
#include "ptvFrameSettings.h"
#include "ptvFrameSignature.h"
#include "ptvPieces.h"

#include "vtkDataArray.h"    // for the array read in place
#include "vtkSmartPointer.h" // for the array read in place
#include "vtkType.h"

#include <cstdint>
#include <string>
#include <vector>

class vtkImageData;
class vtkRenderer;
class vtkVolume;
class vtkVolumeProperty;

namespace ptv
{
class FrameInputs
{
public:
  /**
   * Copy the scalars to float when image or array changed. Non-finite voxels become "no data"
   * (transparent); their count is returned in @a nonFinite. False + @a error on unusable input.
   * With @a dependent (vtkVolumeProperty IndependentComponents off), 2- and 4-component arrays
   * are colour data: the last component is the opacity channel, the others the colour (see
   * VolumeGrid::Colors); otherwise only 1-component arrays are accepted.
   */
  bool UpdateVolume(vtkImageData* image, vtkDataArray* scalars, bool dependent,
    std::string& error, vtkIdType& nonFinite);

  /// Rebuild the transfer tables (and the occupancy grid) when the property, the skipping
  /// switch or the isosurfaces (@a iso, Count 0 for composite, with @a isoValues in double)
  /// changed.
  bool UpdateTransfer(vtkVolumeProperty* property, bool skipping, const IsoSurfaces& iso,
    const double* isoValues, std::string& error);

  /**
   * Fill @a params for a @a width x @a height frame of @a ren. @a zbuffer (window depths in
   * [0,1], may be empty) limits rays at opaque geometry. @a signature receives every value that
   * changes the image.
   */
  bool Build(vtkRenderer* ren, vtkVolume* vol, vtkImageData* image, const FrameSettings& settings,
    int width, int height, const std::vector<float>& zbuffer, TraceParams& params,
    FrameSignature& signature, std::string& error);

  /**
   * A piece of a distributed volume: span the tables over the whole volume's scalar ranges
   * (@a ranges: the scalars', then the colour channel's), light it by the whole volume's world
   * @a bounds, and sample camera rays on the grid of the whole volume's @a extent (structured
   * point indices), so that every piece classifies, lights and samples alike; nullptr: this
   * image's own (the default). Call before UpdateTransfer.
   */
  void SetWholeVolume(const double ranges[4], const double bounds[6], const double extent[6]);

  /// This image's own scalar ranges (the scalars', then the colour channel's), valid after
  /// UpdateVolume.
  void GetLocalRanges(double ranges[4]) const;

  /// The voxels the kernels read (VolumeGrid::Scalars) and their ScalarType, valid after
  /// UpdateVolume: the input array's own memory where it is read in place, else a float copy.
  const void* GetScalarData() const
  {
    return this->InPlace ? this->InPlace->GetVoidPointer(0)
                         : (this->Scalars.empty() ? nullptr : this->Scalars.data());
  }
  int GetScalarType() const { return this->ScalarType; }

  /// Changes whenever the float copy of the voxels is rebuilt (device copies key on it).
  unsigned long long GetVolumeVersion() const { return this->VolumeVersion; }

  /// Where this piece lies, for compositing (valid after Build): its own box in the volume's
  /// structured coordinates, and the camera seen in them.
  PieceView GetPieceView(const TraceParams& params) const;

  /// World-space axis-aligned bounds of the volume (valid after Build()).
  const double* GetWorldBounds() const { return this->WorldBounds; }

private:
  /// A scalar in the units the voxels are stored in ((v - Shift) * Scale).
  float Stored(double value) const;
  /// @a iso with its values (@a values, the data's units) in the stored units.
  IsoSurfaces StoredIso(const IsoSurfaces& iso, const double* values) const;
  /// The camera rays' box of a distributed piece (FrameSettings::PieceExtent); false + @a error
  /// when the piece does not lie inside @a image.
  bool SetPiece(const FrameSettings& settings, vtkImageData* image, TraceParams& p,
    FrameSignature& signature, std::string& error);
  /// Point p.Transfer's StepRGBA and ShadowAlpha at copies of the table corrected for p's camera
  /// and shadow steps (rebuilt when the table or a step changes); none with gradient opacity.
  void SetStepTables(TraceParams& p);

  vtkMTimeType VolumeTime = 0;
  unsigned long long VolumeVersion = 0; ///< +1 per rebuild of Scalars/Colors/ColorScalars
  vtkDataArray* VolumeArray = nullptr; // identity only, never dereferenced after UpdateVolume
  /// The input array where the kernels read it in place (ptvScalarChannel.h; its voxels are of
  /// ScalarType), else null and the voxels are the float copy Scalars.
  vtkSmartPointer<vtkDataArray> InPlace;
  int ScalarType = kScalarFloat;
  std::vector<float> Scalars; ///< the float copy, (v - Shift) * Scale: see StoredAs in the .cxx
  double Shift = 0.0, Scale = 1.0;
  int Dims[3] = { 0, 0, 0 };
  double Range[2] = { 0, 1 };      ///< the tables' range: LocalRange, or the whole volume's
  double LocalRange[2] = { 0, 1 }; ///< the scalars' own range
  bool Dependent = false;
  std::vector<float> ColorScalars; ///< 2-component colour data: the colour channel
  double ColorShift = 0.0, ColorScale = 1.0;
  double ColorRange[2] = { 0, 1 }; ///< its range (the colour table spans it)
  double LocalColorRange[2] = { 0, 1 };
  bool Whole = false;              ///< SetWholeVolume gave the ranges and bounds
  double WholeBounds[6] = { 0, 0, 0, 0, 0, 0 };
  double WholeExtent[6] = { 0, -1, 0, -1, 0, -1 };
  double IndexOffset[3] = { 0, 0, 0 }; ///< the image's first point in structured coordinates
  PieceBox OwnBox = { { 0, -1, 0, -1, 0, -1 } }; ///< structured coordinates
  std::vector<float> Colors;       ///< 4-component colour data: RGB per voxel
  std::vector<float> ColorRGBA;    ///< the colour function over ColorRange (alpha unused)

  vtkMTimeType TransferTime = 0;
  bool TransferSkipping = false;
  std::vector<float> RGBA;
  std::vector<float> GradientOpacity;
  std::vector<float> StepRGBA;    ///< RGBA with the opacity of one camera step (see SetStepTables)
  std::vector<float> ShadowAlpha; ///< the opacity of one shadow/environment step
  std::vector<int> OpaqueBefore;  ///< TransferTable::OpaqueBefore of RGBA
  float StepTableKey[2] = { -1.0f, -1.0f }; ///< the step / unit distance they were built for
  double GradientMax = 1.0; ///< the gradient table's end, in the data's units
  int Nearest = 0;
  std::vector<float> BrickRanges;    ///< per brick (lo, hi) of the voxels, see ptvOccupancy.h
  std::vector<int8_t> BrickDistance; ///< per brick, see Kernels/ptvOccupancy.h
  IsoSurfaces OccupancyIso;          ///< the isosurfaces BrickDistance was built for
  int BrickCounts[3] = { 0, 0, 0 };

  std::vector<float> MaxDistance;
  double WorldBounds[6] = { 0, 0, 0, 0, 0, 0 };
};
}

#endif
