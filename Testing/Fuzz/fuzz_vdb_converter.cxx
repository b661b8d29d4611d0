// libFuzzer: the dense <-> sparse converters (vtkImageData -> vtkPTVOpenVDBWriter -> OpenVDB grid
// -> vtkPTVOpenVDBReader -> vtkImageData) on images built from the bytes:
//   byte 0-2: dims 1..8 each; byte 3: spacing (1 + b) / 16 (or 0 / negative / NaN for b >= 250);
//   bytes 4-6: origin -8..7; byte 7: float (0) or double (1) values; byte 8: background;
//   the rest: the voxel values (4 or 8 bytes each, NaN/Inf included; missing ones are 0).
// Invariant: a rejected image gives an error and no file; a written one reads back as the bounding
// box of its non-background voxels, at the right origin, every value bit-identical.
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkObject.h"
#include "vtkPTVOpenVDBReader.h"
#include "vtkPTVOpenVDBWriter.h"
#include "vtkPointData.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>

#include <unistd.h>

namespace
{
[[noreturn]] void Fail(const char* why)
{
  std::fprintf(stderr, "converter invariant broken: %s\n", why);
  std::abort();
}

template <typename T>
bool Same(T a, T b)
{
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  static const std::string file = [] {
    vtkObject::GlobalWarningDisplayOff();
    const char* dir = std::getenv("TMPDIR");
    return std::string(dir && *dir ? dir : "/tmp") + "/ptv_fuzz_conv_" +
      std::to_string(getpid()) + ".vdb";
  }();
  if (size < 9)
  {
    return 0;
  }
  const int dims[3] = { 1 + data[0] % 8, 1 + data[1] % 8, 1 + data[2] % 8 };
  double spacing = (1 + data[3]) / 16.0;
  if (data[3] == 250)
  {
    spacing = 0;
  }
  else if (data[3] == 251)
  {
    spacing = -0.5;
  }
  else if (data[3] >= 252)
  {
    spacing = std::numeric_limits<double>::quiet_NaN();
  }
  const double origin[3] = { data[4] % 16 - 8.0, data[5] % 16 - 8.0, data[6] % 16 - 8.0 };
  const bool isDouble = data[7] & 1;
  const double background = (data[8] % 4) - 1.0; // -1, 0, 1, 2
  data += 9;
  size -= 9;

  vtkNew<vtkImageData> image;
  image->SetDimensions(dims[0], dims[1], dims[2]);
  image->SetSpacing(spacing, spacing, spacing);
  image->SetOrigin(origin);
  image->AllocateScalars(isDouble ? VTK_DOUBLE : VTK_FLOAT, 1);
  vtkDataArray* values = image->GetPointData()->GetScalars();
  values->SetName("density");
  const std::size_t width = isDouble ? 8 : 4;
  for (vtkIdType i = 0; i < values->GetNumberOfTuples(); ++i)
  {
    unsigned char bytes[8] = { 0 };
    const std::size_t at = static_cast<std::size_t>(i) * width;
    if (at < size)
    {
      std::memcpy(bytes, data + at, std::min(width, size - at));
    }
    if (isDouble)
    {
      double v;
      std::memcpy(&v, bytes, 8);
      static_cast<vtkDoubleArray*>(values)->SetValue(i, v);
    }
    else
    {
      float v;
      std::memcpy(&v, bytes, 4);
      static_cast<vtkFloatArray*>(values)->SetValue(i, v);
    }
  }

  std::remove(file.c_str());
  vtkNew<vtkPTVOpenVDBWriter> writer;
  writer->SetInputData(image);
  writer->SetFileName(file.c_str());
  writer->SetBackground(background);
  const bool written = writer->Write() == 1;
  const bool exists = access(file.c_str(), F_OK) == 0;
  if (written != exists)
  {
    Fail(written ? "Write() succeeded without a file" : "a failed Write() left a file");
  }
  const bool validSpacing = spacing > 0 && std::isfinite(spacing);
  if (written != validSpacing)
  {
    Fail(written ? "an invalid spacing was written" : "a valid image was rejected");
  }
  if (!written)
  {
    return 0;
  }

  // Which voxels are active (differ from the background, bitwise for NaN).
  int lo[3] = { dims[0], dims[1], dims[2] }, hi[3] = { -1, -1, -1 };
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i)
      {
        const double v = values->GetTuple1(i + dims[0] * (j + dims[1] * k));
        if (!(v == background))
        {
          const int ijk[3] = { i, j, k };
          for (int c = 0; c < 3; ++c)
          {
            lo[c] = std::min(lo[c], ijk[c]);
            hi[c] = std::max(hi[c], ijk[c]);
          }
        }
      }

  vtkNew<vtkPTVOpenVDBReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  vtkImageData* out = reader->GetOutput();
  if (hi[0] < 0) // nothing active: the reader reports an empty grid
  {
    if (out->GetNumberOfPoints() != 0)
    {
      Fail("an all-background grid read as data");
    }
    return 0;
  }
  int outDims[3];
  out->GetDimensions(outDims);
  for (int c = 0; c < 3; ++c)
  {
    if (outDims[c] != hi[c] - lo[c] + 1)
    {
      Fail("the read box is not the active bounding box");
    }
    const double expected = origin[c] + lo[c] * spacing;
    if (std::abs(out->GetOrigin()[c] - expected) > 1e-6 * (1 + std::abs(expected)))
    {
      Fail("the read origin is wrong");
    }
  }
  vtkDataArray* read = out->GetPointData()->GetScalars();
  if (!read || read->GetDataType() != values->GetDataType())
  {
    Fail("the read values have another type");
  }
  for (int k = 0; k < outDims[2]; ++k)
    for (int j = 0; j < outDims[1]; ++j)
      for (int i = 0; i < outDims[0]; ++i)
      {
        const vtkIdType src = (lo[0] + i) + dims[0] * ((lo[1] + j) + dims[1] * (lo[2] + k));
        const vtkIdType dst = i + outDims[0] * (j + outDims[1] * k);
        const bool same = isDouble
          ? Same(static_cast<vtkDoubleArray*>(values)->GetValue(src),
              static_cast<vtkDoubleArray*>(read)->GetValue(dst))
          : Same(static_cast<vtkFloatArray*>(values)->GetValue(src),
              static_cast<vtkFloatArray*>(read)->GetValue(dst));
        const bool bothBackground = values->GetTuple1(src) == background &&
          read->GetTuple1(dst) == background;
        if (!same && !bothBackground)
        {
          Fail("a value changed in the round trip");
        }
      }
  return 0;
}
