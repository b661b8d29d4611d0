// Voxels in their own type (issue #62): the kernels read 8- and 16-bit integer volumes and plain
// float volumes in place, without a float copy, and sample them bit for bit as their float copy.
//  - Kernels: for each integer type, SampleTrilinear, SampleNearest, GradientIndex and
//    VoxelValue of a random volume read in place equal those of its float copy exactly (every
//    read converts one voxel to float exactly before any arithmetic) at 3000 points in and
//    around the grid;
//  - FrameInputs: which arrays are read in place (the array's own memory and type) and which
//    are copied: a small integer volume (below kInPlaceIntegerVoxels), floats with NaN, floats
//    with an offset float cannot resolve, 2-component colour data, int32;
//  - End to end: a 1024 x 256 x 256 unsigned 16-bit volume (64 Mi voxels, read in place) renders
//    the same Radiance, bit for bit, as the same values in a float array (also in place, the
//    float path) and as the same values in a double array (copied);
//  - A 1024^3 unsigned 16-bit volume (2 GiB, issue #62) renders on one rank with less than
//    1 GiB of extra peak memory (its float copy alone would be 4 GiB).
#include "ptvFrameInputs.h"
#include "ptvScalarChannel.h"
#include "ptvTestCheck.h"
#include "ptvTestMemory.h"
#include "ptvTestScene.h"

#include "vtkDoubleArray.h"
#include "vtkIntArray.h"
#include "vtkShortArray.h"
#include "vtkSignedCharArray.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnsignedShortArray.h"

#include <cmath>
#include <cstdint>
#include <fstream>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace
{
bool SameBits(float a, float b)
{
  return std::memcmp(&a, &b, sizeof(float)) == 0;
}

template <typename T>
void KernelsReadInPlace(int type, const char* name)
{
  const int dims[3] = { 9, 7, 5 };
  const std::size_t n = 9 * 7 * 5;
  std::mt19937 random(7);
  std::uniform_int_distribution<int> value(
    std::numeric_limits<T>::min(), std::numeric_limits<T>::max());
  std::vector<T> voxels(n);
  std::vector<float> copy(n);
  for (std::size_t v = 0; v < n; ++v)
  {
    voxels[v] = static_cast<T>(value(random));
    copy[v] = static_cast<float>(voxels[v]);
  }
  ptv::VolumeGrid inPlace{}, floats{};
  inPlace.Scalars = voxels.data();
  inPlace.Type = type;
  floats.Scalars = copy.data();
  for (ptv::VolumeGrid* g : { &inPlace, &floats })
  {
    std::copy(dims, dims + 3, g->Dims);
  }
  std::uniform_real_distribution<float> coordinate(-1.5f, 10.5f);
  int differ = 0;
  for (int s = 0; s < 3000; ++s)
  {
    const ptv::Vec3 p = ptv::MakeVec3(coordinate(random), coordinate(random), coordinate(random));
    const ptv::Vec3 ga = ptv::GradientIndex(inPlace, p), gb = ptv::GradientIndex(floats, p);
    differ += !SameBits(ptv::SampleTrilinear(inPlace, p), ptv::SampleTrilinear(floats, p)) ||
      !SameBits(ptv::SampleNearest(inPlace, p), ptv::SampleNearest(floats, p)) ||
      !SameBits(ga.x, gb.x) || !SameBits(ga.y, gb.y) || !SameBits(ga.z, gb.z);
  }
  for (int k = 0; k < dims[2]; ++k)
  {
    for (int i = 0; i < dims[0]; ++i)
    {
      differ += !SameBits(ptv::VoxelValue(inPlace, i, 3, k), ptv::VoxelValue(floats, i, 3, k));
    }
  }
  Check(differ == 0,
    std::string(name) + " read in place samples as its float copy (" + std::to_string(differ) +
      " differ)");
}

vtkSmartPointer<vtkImageData> Image(vtkDataArray* array, int nx, int ny, int nz)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(nx, ny, nz);
  image->GetPointData()->SetScalars(array);
  return image;
}

/// What FrameInputs makes of @a array: in place (its memory) or a float copy.
void ExpectStorage(vtkDataArray* array, int nx, int ny, int nz, bool dependent, int type,
  const std::string& what)
{
  auto image = Image(array, nx, ny, nz);
  ptv::FrameInputs inputs;
  std::string error;
  vtkIdType nonFinite = 0;
  Check(inputs.UpdateVolume(image, array, dependent, error, nonFinite), what + ": " + error);
  const bool inPlace = inputs.GetScalarData() == array->GetVoidPointer(0);
  Check(inPlace == (type != -1), what + (inPlace ? " is read in place" : " is copied"));
  Check(inputs.GetScalarType() == (type == -1 ? ptv::kScalarFloat : type),
    what + ": stored type " + std::to_string(inputs.GetScalarType()));
}

template <typename ArrayT>
vtkSmartPointer<ArrayT> Filled(vtkIdType n, int components = 1)
{
  auto array = vtkSmartPointer<ArrayT>::New();
  array->SetNumberOfComponents(components);
  array->SetNumberOfTuples(n);
  for (vtkIdType v = 0; v < n * components; ++v)
  {
    array->SetValue(v, static_cast<typename ArrayT::ValueType>(v % 97));
  }
  return array;
}

void FrameInputsChooseStorage()
{
  const vtkIdType n = 8 * 8 * 8;
  ExpectStorage(Filled<vtkUnsignedShortArray>(n), 8, 8, 8, false, -1,
    "a small unsigned 16-bit volume");
  ExpectStorage(Filled<vtkFloatArray>(n), 8, 8, 8, false, ptv::kScalarFloat, "a float volume");
  auto nan = Filled<vtkFloatArray>(n);
  nan->SetValue(5, std::numeric_limits<float>::quiet_NaN());
  ExpectStorage(nan, 8, 8, 8, false, -1, "a float volume with NaN");
  auto offset = Filled<vtkFloatArray>(n);
  for (vtkIdType v = 0; v < n; ++v)
  {
    offset->SetValue(v, 1e7f + static_cast<float>(v % 3));
  }
  ExpectStorage(offset, 8, 8, 8, false, -1, "floats 1e7 + [0, 2]");
  ExpectStorage(Filled<vtkUnsignedShortArray>(n, 2), 8, 8, 8, true, -1,
    "2-component colour data");
  ExpectStorage(Filled<vtkIntArray>(n), 8, 8, 8, false, -1, "a 32-bit integer volume");
  // The size rule itself, on small arrays.
  double range[2] = { 0, 96 };
  Check(ptv::InPlaceScalarType(Filled<vtkSignedCharArray>(n), range, 0, n) == ptv::kScalarInt8 &&
      ptv::InPlaceScalarType(Filled<vtkUnsignedCharArray>(n), range, 0, n) ==
        ptv::kScalarUInt8 &&
      ptv::InPlaceScalarType(Filled<vtkShortArray>(n), range, 0, n) == ptv::kScalarInt16 &&
      ptv::InPlaceScalarType(Filled<vtkShortArray>(n), range, 0, n + 1) == -1,
    "8- and 16-bit arrays of at least the given voxels are read in place");
}

/// @a s showing the nx x ny x nz volume @a array with a ramp from 0 (blue, transparent up to
/// 1500) to 4000 (yellow) of opacity @a peak at @a top, not denoised.
void ShowRamp(AnalyticScene& s, vtkDataArray* array, int nx, int ny, int nz, double top,
  double peak)
{
  s.Mapper->SetInputData(Image(array, nx, ny, nz));
  s.Color->RemoveAllPoints();
  s.Color->AddRGBPoint(0, 0.2, 0.4, 1.0);
  s.Color->AddRGBPoint(4000, 1.0, 0.9, 0.5);
  s.Opacity->RemoveAllPoints();
  s.Opacity->AddPoint(0, 0.0);
  s.Opacity->AddPoint(1500, 0.0);
  s.Opacity->AddPoint(top, peak);
  s.Mapper->SetDenoise(false);
  s.Renderer->ResetCamera();
}

/// Radiance of one frame of the 1024 x 256 x 256 ramp volume given as @a array.
std::vector<float> RenderBig(vtkDataArray* array)
{
  AnalyticScene s(48);
  ShowRamp(s, array, 1024, 256, 256, 4000, 0.6);
  s.Window->Render();
  return s.Pass("Radiance");
}

void BigVolumeEndToEnd()
{
  const vtkIdType n = vtkIdType(1024) * 256 * 256;
  Check(n >= ptv::kInPlaceIntegerVoxels, "the big volume is at the in-place size");
  auto shorts = vtkSmartPointer<vtkUnsignedShortArray>::New();
  shorts->SetNumberOfTuples(n);
  unsigned short* v = shorts->GetPointer(0);
  for (vtkIdType z = 0, i = 0; z < 256; ++z)
  {
    for (vtkIdType y = 0; y < 256; ++y)
    {
      for (vtkIdType x = 0; x < 1024; ++x, ++i)
      {
        const double r = std::hypot(x / 4.0 - 128.0, std::hypot(y - 128.0, z - 128.0));
        v[i] = static_cast<unsigned short>(std::max(0.0, 4000.0 - 30.0 * r) + (i % 7));
      }
    }
  }
  const std::vector<float> fromShorts = RenderBig(shorts);
  Check(!fromShorts.empty(), "the in-place volume renders");
  std::vector<float> fromFloats, fromDoubles;
  {
    auto floats = vtkSmartPointer<vtkFloatArray>::New();
    floats->SetNumberOfTuples(n);
    std::copy(v, v + n, floats->GetPointer(0));
    fromFloats = RenderBig(floats);
  }
  {
    auto doubles = vtkSmartPointer<vtkDoubleArray>::New();
    doubles->SetNumberOfTuples(n);
    std::copy(v, v + n, doubles->GetPointer(0));
    fromDoubles = RenderBig(doubles);
  }
  double sum = 0.0;
  for (float x : fromShorts)
  {
    sum += x;
  }
  Check(sum > 0.0, "the big volume is visible");
  Check(fromShorts == fromFloats, "unsigned 16-bit in place renders as floats in place");
  Check(fromShorts == fromDoubles, "unsigned 16-bit in place renders as its float copy");
}


void GiantVolumeOneRank()
{
  const vtkIdType side = 1024, n = side * side * side;
  auto shorts = vtkSmartPointer<vtkUnsignedShortArray>::New();
  shorts->SetNumberOfTuples(n);
  unsigned short* v = shorts->GetPointer(0);
  for (vtkIdType z = 0, i = 0; z < side; ++z)
  {
    for (vtkIdType y = 0; y < side; ++y)
    {
      const double ry = (y - 512.0) * (y - 512.0) + (z - 512.0) * (z - 512.0);
      for (vtkIdType x = 0; x < side; ++x, ++i)
      {
        const double r = std::sqrt(ry + (x - 512.0) * (x - 512.0));
        v[i] = static_cast<unsigned short>(std::abs(r - 400.0) < 24.0 ? 3000 : 100);
      }
    }
  }
  AnalyticScene s(64);
  ShowRamp(s, shorts, side, side, side, 3000, 0.8);
  const double held = StatusBytes("VmRSS");
  ResetPeakMemory();
  s.Window->Render();
  const double extra = StatusBytes("VmHWM") - held;
  const std::vector<float> alpha = s.Pass("Alpha");
  double covered = 0.0;
  for (float a : alpha)
  {
    covered += a;
  }
  Check(covered > 0.1 * static_cast<double>(alpha.size()),
    "the 1024^3 16-bit volume renders (" + std::to_string(covered) + " covered pixels)");
  Check(held > 0.0 && extra < 1024.0 * 1048576.0,
    "the 1024^3 16-bit volume renders with " + std::to_string(extra / 1048576.0) +
      " MiB of extra peak memory (< 1024)");
}
}

int TestPTVScalarStorage(int, char*[])
{
  KernelsReadInPlace<std::uint8_t>(ptv::kScalarUInt8, "unsigned 8-bit");
  KernelsReadInPlace<std::int8_t>(ptv::kScalarInt8, "signed 8-bit");
  KernelsReadInPlace<std::uint16_t>(ptv::kScalarUInt16, "unsigned 16-bit");
  KernelsReadInPlace<std::int16_t>(ptv::kScalarInt16, "signed 16-bit");
  FrameInputsChooseStorage();
  BigVolumeEndToEnd();
  GiantVolumeOneRank();
  return TestResult();
}
