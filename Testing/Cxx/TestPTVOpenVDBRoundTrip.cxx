// vtkPTVOpenVDBWriter -> vtkPTVOpenVDBReader round trips:
//  1. float image, 23x17x11, spacing 0.5, origin (-3, 2, 1.25), zeros scattered inside but active
//     voxels on every face: same dims/origin/spacing, bit-identical values (zeros = background).
//  2. double image with Background -1 and a non-active array selected by ArrayName.
//  3. a border region equal to the background (and an extent not starting at 0): the reader
//     returns the bounding box of the active voxels only, its origin shifted to the world position
//     of the box's first voxel, values unchanged there; a sub-extent request and piece requests
//     read just their part.
//  4. grid listing: files with two scalar grids and with a vec3s grid listed before a scalar one;
//     default grid selection, GridName selection, CanReadFile.
//  5. non-finite values (regression, found by fuzz_vdb_converter): NaN voxels used to become
//     inactive background silently (OpenVDB's copyFromDense treats NaN as equal to anything);
//     NaN, +-Inf and -0 (background 1) must read back bit for bit, float and double, including a
//     whole 8^3 leaf starting with NaN, and the fuzzer's seed image (1, 2, NaN, +Inf, zeros).
#include "ptvTestCheck.h"
#include "ptvTestVDBWriters.h"
#include "ptvOpenVDBGrid.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPTVOpenVDBReader.h"
#include "vtkPTVOpenVDBWriter.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"
#include "vtkTestUtilities.h"
#include "vtksys/SystemTools.hxx"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h> // for getpid

namespace
{

// An image of @a type (VTK_FLOAT or VTK_DOUBLE) whose point (i, j, k) (structured indices within
// @a extent) holds f(i, j, k) in a point-data array named @a name, set as active scalars.
vtkSmartPointer<vtkImageData> MakeImage(const int extent[6], double spacing, const double origin[3],
  int type, const std::string& name, const std::function<double(int, int, int)>& f)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetExtent(const_cast<int*>(extent));
  image->SetSpacing(spacing, spacing, spacing);
  image->SetOrigin(const_cast<double*>(origin));
  vtkSmartPointer<vtkDataArray> values;
  if (type == VTK_DOUBLE)
  {
    values = vtkSmartPointer<vtkDoubleArray>::New();
  }
  else
  {
    values = vtkSmartPointer<vtkFloatArray>::New();
  }
  values->SetName(name.c_str());
  values->SetNumberOfTuples(image->GetNumberOfPoints());
  vtkIdType n = 0;
  for (int k = extent[4]; k <= extent[5]; ++k)
  {
    for (int j = extent[2]; j <= extent[3]; ++j)
    {
      for (int i = extent[0]; i <= extent[1]; ++i)
      {
        values->SetComponent(n++, 0, f(i, j, k));
      }
    }
  }
  image->GetPointData()->SetScalars(values);
  return image;
}

// Zeros on a sparse lattice inside, non-zero (positive and negative) elsewhere: every face of the
// box holds active voxels, so the active bounding box is the whole box.
double Field(int i, int j, int k)
{
  if ((i + 2 * j + 3 * k) % 7 == 0 && i > 0 && j > 0 && k > 0)
  {
    return 0.0;
  }
  const double v = 0.75 + 0.5 * std::sin(0.37 * i) * std::cos(0.23 * j) + 0.01 * k;
  return (k % 2) ? v : -v;
}

bool Near(double a, double b, double tol = 1e-6)
{
  return std::abs(a - b) <= tol;
}

std::string Vec(const double* v)
{
  std::ostringstream s;
  s << "(" << v[0] << ", " << v[1] << ", " << v[2] << ")";
  return s.str();
}

bool Write(vtkImageData* image, const std::string& file, const char* gridName, double background,
  const char* arrayName = nullptr)
{
  vtkNew<vtkPTVOpenVDBWriter> writer;
  writer->SetInputData(image);
  writer->SetFileName(file.c_str());
  if (gridName)
  {
    writer->SetGridName(gridName);
  }
  writer->SetBackground(background);
  writer->SetArrayName(arrayName);
  return writer->Write() == 1;
}

// Compare @a out (read back) with @a in over out's extent, where out index (i, j, k) corresponds
// to in's structured index (i + offset[0], ...).
void CompareValues(vtkImageData* in, vtkDataArray* inValues, vtkImageData* out,
  const int offset[3], const std::string& label)
{
  vtkDataArray* outValues = out->GetPointData()->GetScalars();
  int ext[6];
  out->GetExtent(ext);
  int mismatches = 0;
  for (int k = ext[4]; k <= ext[5]; ++k)
  {
    for (int j = ext[2]; j <= ext[3]; ++j)
    {
      for (int i = ext[0]; i <= ext[1]; ++i)
      {
        int inIjk[3] = { i + offset[0], j + offset[1], k + offset[2] };
        int outIjk[3] = { i, j, k };
        const vtkIdType inId = in->ComputePointId(inIjk);
        const vtkIdType outId = out->ComputePointId(outIjk);
        const double a = inValues->GetComponent(inId, 0);
        const double b = outValues->GetComponent(outId, 0);
        if (a != b && mismatches++ < 5)
        {
          std::ostringstream msg;
          msg << label << ": value at (" << i << ", " << j << ", " << k << ") is " << b
              << ", expected " << a;
          Check(false, msg.str());
        }
      }
    }
  }
  Check(mismatches == 0, label + ": " + std::to_string(mismatches) + " values differ");
}

// Case 1 and 2: the whole box round trip.
void WholeBoxRoundTrip(const std::string& dir, int type)
{
  const std::string label = type == VTK_DOUBLE ? "double" : "float";
  const std::string file = dir + "/ptv_roundtrip_" + label + ".vdb";
  const int extent[6] = { 0, 22, 0, 16, 0, 10 };
  const double origin[3] = { -3.0, 2.0, 1.25 };
  const double background = type == VTK_DOUBLE ? -1.0 : 0.0;
  vtkSmartPointer<vtkImageData> image = MakeImage(extent, 0.5, origin, type, "field",
    [background](int i, int j, int k) {
      // For the double case: some interior voxels equal the (non-zero) background.
      if (background != 0.0 && (i * j + k) % 11 == 5 && i > 0 && j > 0 && k > 0)
      {
        return background;
      }
      return Field(i, j, k);
    });
  const char* arrayName = nullptr;
  if (type == VTK_DOUBLE)
  {
    // Write a non-active array selected by name; the active scalars are a decoy of another type.
    // (SetScalars drops the previous scalars array, so add "field" back afterwards.)
    vtkSmartPointer<vtkDataArray> field = image->GetPointData()->GetScalars();
    vtkNew<vtkFloatArray> decoy;
    decoy->SetName("decoy");
    decoy->SetNumberOfTuples(image->GetNumberOfPoints());
    decoy->FillValue(42.0f);
    image->GetPointData()->SetScalars(decoy);
    image->GetPointData()->AddArray(field);
    arrayName = "field";
  }
  vtkDataArray* inValues = image->GetPointData()->GetArray("field");
  Check(Write(image, file, nullptr, background, arrayName), label + ": Write() must succeed");
  Check(vtksys::SystemTools::FileExists(file), label + ": file must exist: " + file);
  Check(!vtksys::SystemTools::FileExists(file + ".tmp-" + std::to_string(getpid())),
    label + ": no temporary file may remain");

  vtkNew<vtkPTVOpenVDBReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  vtkImageData* out = reader->GetOutput();
  int dims[3];
  out->GetDimensions(dims);
  Check(dims[0] == 23 && dims[1] == 17 && dims[2] == 11,
    label + ": dims must be 23x17x11, got " + std::to_string(dims[0]) + "x" +
      std::to_string(dims[1]) + "x" + std::to_string(dims[2]));
  int outExt[6];
  out->GetExtent(outExt);
  Check(outExt[0] == 0 && outExt[2] == 0 && outExt[4] == 0, label + ": extent must start at 0");
  double* o = out->GetOrigin();
  double* s = out->GetSpacing();
  Check(Near(o[0], -3.0) && Near(o[1], 2.0) && Near(o[2], 1.25),
    label + ": origin must be (-3, 2, 1.25), got " + Vec(o));
  Check(Near(s[0], 0.5) && Near(s[1], 0.5) && Near(s[2], 0.5),
    label + ": spacing must be 0.5, got " + Vec(s));
  vtkDataArray* outValues = out->GetPointData()->GetScalars();
  Check(outValues != nullptr, label + ": output must have active scalars");
  if (!outValues)
  {
    return;
  }
  Check(std::string(outValues->GetName() ? outValues->GetName() : "") == "density",
    label + ": array must be named after the grid ('density')");
  Check(outValues->GetDataType() == type, label + ": array type must be " + label);
  Check(outValues->GetNumberOfComponents() == 1, label + ": array must have 1 component");
  const int offset[3] = { 0, 0, 0 };
  CompareValues(image, inValues, out, offset, label);

  Check(reader->GetNumberOfGrids() == 1, label + ": one grid expected");
  Check(reader->GetGridName(0) && std::string(reader->GetGridName(0)) == "density",
    label + ": grid 0 must be 'density'");
  Check(reader->GetGridType(0) && std::string(reader->GetGridType(0)) == label,
    label + ": grid 0 type must be " + label);
  Check(reader->GetGridName(1) == nullptr && reader->GetGridType(-1) == nullptr,
    label + ": out-of-range grid indices give nullptr");
  Check(vtkPTVOpenVDBReader::CanReadFile(file.c_str()) == 1,
    label + ": CanReadFile must accept the written file");
}

// Case 3: only an inner block differs from the background; the image extent does not start at 0.
void BorderBackgroundRoundTrip(const std::string& dir)
{
  const std::string file = dir + "/ptv_roundtrip_border.vdb";
  const int extent[6] = { -2, 9, 1, 10, 0, 7 }; // 12 x 10 x 8 points
  const double origin[3] = { 1.0, -0.5, 4.0 };
  const double spacing = 0.25;
  // Active (non-zero) block: i in [1, 9], j in [1, 8], k in [2, 7] (structured indices).
  auto f = [](int i, int j, int k) {
    if (i < 1 || j > 8 || k < 2)
    {
      return 0.0;
    }
    return 2.0 + 0.1 * i - 0.05 * j + 0.3 * k;
  };
  vtkSmartPointer<vtkImageData> image =
    MakeImage(extent, spacing, origin, VTK_FLOAT, "blob", f);
  Check(Write(image, file, "blob", 0.0), "border: Write() must succeed");

  vtkNew<vtkPTVOpenVDBReader> reader;
  reader->SetFileName(file.c_str());
  reader->SetGridName("blob");
  reader->Update();
  vtkImageData* out = reader->GetOutput();
  int dims[3];
  out->GetDimensions(dims);
  Check(dims[0] == 9 && dims[1] == 8 && dims[2] == 6,
    "border: dims must be the active box 9x8x6, got " + std::to_string(dims[0]) + "x" +
      std::to_string(dims[1]) + "x" + std::to_string(dims[2]));
  // World position of structured index (1, 1, 2) of the input.
  const double expected[3] = { origin[0] + 1 * spacing, origin[1] + 1 * spacing,
    origin[2] + 2 * spacing };
  double* o = out->GetOrigin();
  Check(Near(o[0], expected[0]) && Near(o[1], expected[1]) && Near(o[2], expected[2]),
    "border: origin must move to the first active voxel " + Vec(expected) + ", got " + Vec(o));
  const int offset[3] = { 1, 1, 2 };
  vtkDataArray* inValues = image->GetPointData()->GetScalars();
  if (out->GetPointData()->GetScalars())
  {
    CompareValues(image, inValues, out, offset, "border");
    Check(std::string(out->GetPointData()->GetScalars()->GetName()) == "blob",
      "border: array must be named 'blob'");
  }
  else
  {
    Check(false, "border: output must have scalars");
  }

  // Sub-extent request (on a fresh reader: the first one already holds a larger extent, which
  // the pipeline considers up to date): only that block is read, at the same world positions.
  const int sub[6] = { 2, 5, 1, 3, 4, 5 };
  vtkNew<vtkPTVOpenVDBReader> subReader;
  subReader->SetFileName(file.c_str());
  subReader->UpdateExtent(sub);
  int got[6];
  out = subReader->GetOutput();
  out->GetExtent(got);
  Check(got[0] == 2 && got[1] == 5 && got[2] == 1 && got[3] == 3 && got[4] == 4 && got[5] == 5,
    "border: a sub-extent request must give that extent");
  if (out->GetPointData()->GetScalars())
  {
    CompareValues(image, inValues, out, offset, "border sub-extent");
  }

  // Piece requests (as from ParaView's MPI ranks): two pieces that together cover the box.
  int pieceExtents[2][6];
  for (int piece = 0; piece < 2; ++piece)
  {
    vtkNew<vtkPTVOpenVDBReader> pieceReader;
    pieceReader->SetFileName(file.c_str());
    pieceReader->UpdatePiece(piece, 2, 0);
    out = pieceReader->GetOutput();
    out->GetExtent(pieceExtents[piece]);
    Check(out->GetNumberOfPoints() > 0 && out->GetNumberOfPoints() < 9 * 8 * 6,
      "border: piece " + std::to_string(piece) + " of 2 must be a part of the box");
    if (out->GetPointData()->GetScalars())
    {
      CompareValues(image, inValues, out, offset, "border piece " + std::to_string(piece));
    }
  }
  int covered[6];
  for (int c = 0; c < 3; ++c)
  {
    covered[2 * c] = std::min(pieceExtents[0][2 * c], pieceExtents[1][2 * c]);
    covered[2 * c + 1] = std::max(pieceExtents[0][2 * c + 1], pieceExtents[1][2 * c + 1]);
  }
  Check(covered[0] == 0 && covered[1] == 8 && covered[2] == 0 && covered[3] == 7 &&
      covered[4] == 0 && covered[5] == 5,
    "border: the two pieces must cover the whole 9x8x6 box");
}

// Case 5: NaN / Inf / -0 voxels round-trip bit for bit.
template <typename T>
void NonFiniteRoundTrip(const std::string& dir, double background, int nx, int ny, int nz,
  const std::function<T(int, int, int)>& f, const std::string& label)
{
  const std::string file = dir + "/ptv_roundtrip_nonfinite.vdb";
  const int extent[6] = { 0, nx - 1, 0, ny - 1, 0, nz - 1 };
  const double origin[3] = { -8.0, -8.0, -8.0 };
  const int type = sizeof(T) == 8 ? VTK_DOUBLE : VTK_FLOAT;
  vtkSmartPointer<vtkImageData> image = MakeImage(extent, 1.0, origin, type, "density",
    [](int, int, int) { return 0.0; });
  vtkDataArray* in = image->GetPointData()->GetScalars();
  T* inData = static_cast<T*>(in->GetVoidPointer(0));
  // Active bounding box (values that are not == background; NaN never is).
  int lo[3] = { nx, ny, nz }, hi[3] = { -1, -1, -1 };
  vtkIdType n = 0;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i, ++n)
      {
        inData[n] = f(i, j, k);
        if (!(inData[n] == static_cast<T>(background)))
        {
          const int ijk[3] = { i, j, k };
          for (int c = 0; c < 3; ++c)
          {
            lo[c] = std::min(lo[c], ijk[c]);
            hi[c] = std::max(hi[c], ijk[c]);
          }
        }
      }
  Check(Write(image, file, "density", background), label + ": Write() must succeed");
  vtkNew<vtkPTVOpenVDBReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  vtkImageData* out = reader->GetOutput();
  int dims[3];
  out->GetDimensions(dims);
  bool boxOk = true;
  for (int c = 0; c < 3; ++c)
  {
    boxOk = boxOk && dims[c] == hi[c] - lo[c] + 1;
  }
  Check(boxOk,
    label + ": the read box must be the box of the non-background voxels (NaN lost?), got " +
      std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "x" + std::to_string(dims[2]));
  vtkDataArray* outValues = out->GetPointData()->GetScalars();
  if (!boxOk || !outValues || outValues->GetDataType() != type)
  {
    Check(false, label + ": no values of the input's type to compare");
    return;
  }
  const T* outData = static_cast<const T*>(outValues->GetVoidPointer(0));
  int mismatches = 0;
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i)
      {
        const T a = inData[(lo[0] + i) + nx * ((lo[1] + j) + ny * (lo[2] + k))];
        const T b = outData[i + dims[0] * (j + dims[1] * k)];
        const bool bothBackground =
          a == static_cast<T>(background) && b == static_cast<T>(background);
        if (std::memcmp(&a, &b, sizeof(T)) != 0 && !bothBackground && mismatches++ < 5)
        {
          std::ostringstream msg;
          msg << label << ": value at (" << i << ", " << j << ", " << k << ") is " << b
              << ", expected " << a;
          Check(false, msg.str());
        }
      }
  Check(mismatches == 0, label + ": " + std::to_string(mismatches) + " values differ");
}

template <typename T>
void NonFiniteRoundTrips(const std::string& dir, const std::string& type)
{
  const T nan = std::numeric_limits<T>::quiet_NaN();
  const T inf = std::numeric_limits<T>::infinity();
  // The fuzzer's seed small_float: 4x3x2, first row 1, 2, NaN, +Inf, the rest 0 (background 0).
  NonFiniteRoundTrip<T>(dir, 0.0, 4, 3, 2,
    [&](int i, int j, int k) -> T {
      const T row[4] = { 1, 2, nan, inf };
      return (j == 0 && k == 0) ? row[i] : T(0);
    },
    type + " fuzz seed");
  // Every kind of value, background 1 (so -0 and +0 are active and must keep their sign).
  NonFiniteRoundTrip<T>(dir, 1.0, 11, 9, 10,
    [&](int i, int j, int k) -> T {
      switch ((i + 3 * j + 5 * k) % 7)
      {
        case 0: return nan;
        case 1: return inf;
        case 2: return -inf;
        case 3: return T(-0.0);
        case 4: return T(0.0);
        case 5: return T(1); // background
        default: return T(0.5 * i - j);
      }
    },
    type + " mixed");
  // One whole 8^3 leaf that starts with NaN, every other voxel 3 (OpenVDB's tile merging compares
  // with the first value), next to an all-NaN leaf and an all +Inf leaf.
  NonFiniteRoundTrip<T>(dir, 0.0, 24, 8, 8,
    [&](int i, int, int) -> T {
      if (i < 8)
      {
        return i == 0 ? nan : T(3);
      }
      return i < 16 ? nan : inf;
    },
    type + " leaves");
}

// Case 4: grid listing and selection.
void GridListing(const std::string& dir)
{
  // Two scalar grids in one file, written through the private API.
  const std::string file = dir + "/ptv_roundtrip_two_grids.vdb";
  std::vector<float> density(4 * 3 * 2);
  std::vector<double> temperature(5 * 5 * 5);
  for (size_t n = 0; n < density.size(); ++n)
  {
    density[n] = 0.5f + static_cast<float>(n);
  }
  for (size_t n = 0; n < temperature.size(); ++n)
  {
    temperature[n] = 300.0 + 0.125 * static_cast<double>(n);
  }
  ptv::DenseVolume d;
  d.Dims[0] = 4;
  d.Dims[1] = 3;
  d.Dims[2] = 2;
  d.Spacing[0] = d.Spacing[1] = d.Spacing[2] = 2.0;
  d.Data = density.data();
  ptv::DenseVolume t;
  t.Dims[0] = t.Dims[1] = t.Dims[2] = 5;
  t.IndexMin[0] = -2;
  t.Origin[0] = 10.0;
  t.IsDouble = true;
  t.Data = temperature.data();
  std::string error;
  Check(ptv::WriteScalarGrids(file, { { "density", &d }, { "temperature", &t } }, 0.0, error),
    "two grids: WriteScalarGrids failed: " + error);

  std::vector<ptv::GridInfo> grids;
  Check(ptv::ListGrids(file, grids, error), "two grids: ListGrids failed: " + error);
  Check(grids.size() == 2, "two grids: ListGrids must find 2 grids");
  if (grids.size() == 2)
  {
    Check(grids[0].ActiveVoxelCount == 24 && grids[1].ActiveVoxelCount == 125,
      "two grids: active voxel counts must be 24 and 125");
    Check(grids[1].HasBBox && grids[1].BBoxMin[0] == -2 && grids[1].BBoxMax[0] == 2,
      "two grids: temperature bbox must span x in [-2, 2]");
  }

  vtkNew<vtkPTVOpenVDBReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  Check(reader->GetNumberOfGrids() == 2, "two grids: GetNumberOfGrids() must be 2");
  if (reader->GetNumberOfGrids() == 2)
  {
    Check(std::string(reader->GetGridName(0)) == "density" &&
        std::string(reader->GetGridType(0)) == "float",
      "two grids: grid 0 must be density (float)");
    Check(std::string(reader->GetGridName(1)) == "temperature" &&
        std::string(reader->GetGridType(1)) == "double",
      "two grids: grid 1 must be temperature (double)");
  }
  Check(reader->GetScalarGridNames()->GetNumberOfValues() == 2,
    "two grids: both grids are readable scalar grids");
  Check(reader->GetActiveGridName() && std::string(reader->GetActiveGridName()) == "density",
    "two grids: the default grid is the first scalar grid");
  vtkDataArray* values = reader->GetOutput()->GetPointData()->GetScalars();
  Check(values && values->GetDataType() == VTK_FLOAT && values->GetNumberOfTuples() == 24 &&
      values->GetComponent(23, 0) == 23.5,
    "two grids: default read must give the 24 density values");

  reader->SetGridName("temperature");
  reader->Update();
  vtkImageData* out = reader->GetOutput();
  values = out->GetPointData()->GetScalars();
  Check(values && values->GetDataType() == VTK_DOUBLE && values->GetNumberOfTuples() == 125 &&
      std::string(values->GetName()) == "temperature",
    "two grids: GridName=temperature must give 125 doubles named 'temperature'");
  if (values && values->GetNumberOfTuples() == 125)
  {
    Check(values->GetComponent(124, 0) == 300.0 + 0.125 * 124,
      "two grids: temperature values must round trip exactly");
  }
  Check(Near(out->GetOrigin()[0], 10.0) && Near(out->GetSpacing()[0], 1.0),
    "two grids: temperature origin x 10 and spacing 1");

  // A vec3s grid listed before a scalar grid (OpenVDB lists grids sorted by name): listed, and
  // skipped by the default selection.
  const std::string mixed = dir + "/ptv_roundtrip_mixed.vdb";
  Check(ptvtest::WriteTestVectorGrid(mixed, "flow", "smoke", error),
    "mixed: WriteTestVectorGrid failed: " + error);
  vtkNew<vtkPTVOpenVDBReader> mixedReader;
  mixedReader->SetFileName(mixed.c_str());
  mixedReader->Update();
  Check(mixedReader->GetNumberOfGrids() == 2, "mixed: two grids expected");
  if (mixedReader->GetNumberOfGrids() == 2)
  {
    Check(std::string(mixedReader->GetGridName(0)) == "flow" &&
        std::string(mixedReader->GetGridType(0)) == "vec3s",
      std::string("mixed: grid 0 must be flow (vec3s), got ") + mixedReader->GetGridName(0) +
        " (" + mixedReader->GetGridType(0) + ")");
  }
  Check(mixedReader->GetScalarGridNames()->GetNumberOfValues() == 1 &&
      mixedReader->GetScalarGridNames()->GetValue(0) == "smoke",
    "mixed: the only scalar grid is smoke");
  values = mixedReader->GetOutput()->GetPointData()->GetScalars();
  Check(values && std::string(values->GetName()) == "smoke" && values->GetNumberOfTuples() == 27,
    "mixed: default read must give the 3x3x3 box of grid 'smoke'");

  // CanReadFile on non-VDB input.
  const std::string text = dir + "/ptv_roundtrip_not_vdb.vdb";
  {
    std::ofstream textFile(text);
    textFile << "this is a text file, not an OpenVDB file\n";
  }
  Check(vtkPTVOpenVDBReader::CanReadFile(text.c_str()) == 0, "CanReadFile must reject text");
  Check(vtkPTVOpenVDBReader::CanReadFile((dir + "/no_such_file.vdb").c_str()) == 0,
    "CanReadFile must reject a missing file");
  Check(vtkPTVOpenVDBReader::CanReadFile(nullptr) == 0, "CanReadFile(nullptr) must be 0");
  Check(vtkPTVOpenVDBReader::CanReadFile(dir.c_str()) == 0, "CanReadFile must reject a folder");
}

} // anonymous namespace

int TestPTVOpenVDBRoundTrip(int argc, char* argv[])
{
  const std::string dir = TempDir(argc, argv);
  WholeBoxRoundTrip(dir, VTK_FLOAT);
  WholeBoxRoundTrip(dir, VTK_DOUBLE);
  BorderBackgroundRoundTrip(dir);
  GridListing(dir);
  NonFiniteRoundTrips<float>(dir, "float");
  NonFiniteRoundTrips<double>(dir, "double");
  if (failures)
  {
    std::cerr << failures << " check(s) failed\n";
    return EXIT_FAILURE;
  }
  std::cout << "TestPTVOpenVDBRoundTrip passed\n";
  return EXIT_SUCCESS;
}
