// libFuzzer: vtkPTVEXRPassWriter -> vtkPTVEXRPassReader round trip of small pass images built
// from the bytes:
//   byte 0: width 1..8; byte 1: height 1..8; byte 2: number of arrays 1..4;
//   per array 2 bytes: name (one of kNames: the known passes, their names with another
//   component count, names whose channels collide with a known pass, plain names) and
//   components 1..5; the rest: float32 values, NaN/Inf included (missing ones are 0).
// Invariant: Write() either fails (an error, no file left) or succeeds, and then the reader
// returns the same size and, for each written array, an array of the same name, component count
// and bit-identical values.
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkObject.h"
#include "vtkPTVEXRPassReader.h"
#include "vtkPTVEXRPassWriter.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <unistd.h>

namespace
{
[[noreturn]] void Fail(const std::string& why)
{
  std::fprintf(stderr, "EXR pass round trip broken: %s\n", why.c_str());
  std::abort();
}

const char* const kNames[] = { "Radiance", "Alpha", "Albedo", "Depth", "Position", "Normal",
  "ScatterDepth", "ScatterPosition", "ScatterNormal", "Coverage", "Footprint", "Denoised",
  "BlendWeights", "R", "A", "Z", "albedo", "P", "mask", "x.y", "Radiance.R", "weights" };
constexpr int kNumNames = sizeof(kNames) / sizeof(kNames[0]);
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  static const std::string file = [] {
    vtkObject::GlobalWarningDisplayOff();
    const char* dir = std::getenv("TMPDIR");
    return std::string(dir && *dir ? dir : "/tmp") + "/ptv_fuzz_passes_" +
      std::to_string(getpid()) + ".exr";
  }();
  if (size < 3)
  {
    return 0;
  }
  const int width = 1 + data[0] % 8;
  const int height = 1 + data[1] % 8;
  const int numArrays = 1 + data[2] % 4;
  data += 3;
  size -= 3;
  vtkNew<vtkImageData> image;
  image->SetDimensions(width, height, 1);
  std::vector<vtkSmartPointer<vtkFloatArray>> arrays;
  for (int a = 0; a < numArrays; ++a)
  {
    const uint8_t nameByte = size > 0 ? data[0] : 0;
    const uint8_t compByte = size > 1 ? data[1] : 0;
    const size_t used = size < 2 ? size : 2;
    data += used;
    size -= used;
    const std::string name = kNames[nameByte % kNumNames];
    bool duplicate = false;
    for (const auto& other : arrays)
    {
      duplicate = duplicate || name == other->GetName();
    }
    if (duplicate) // vtkPointData keeps one array per name; that is not the writer's business
    {
      continue;
    }
    auto array = vtkSmartPointer<vtkFloatArray>::New();
    array->SetName(name.c_str());
    array->SetNumberOfComponents(1 + compByte % 5);
    array->SetNumberOfTuples(static_cast<vtkIdType>(width) * height);
    arrays.push_back(array);
    image->GetPointData()->AddArray(array);
  }
  for (const auto& array : arrays)
  {
    float* values = array->GetPointer(0);
    const size_t count = static_cast<size_t>(array->GetNumberOfValues());
    for (size_t n = 0; n < count; ++n)
    {
      unsigned char bytes[4] = { 0, 0, 0, 0 };
      const size_t take = size < 4 ? size : 4;
      std::memcpy(bytes, data, take);
      data += take;
      size -= take;
      std::memcpy(values + n, bytes, 4);
    }
  }

  std::remove(file.c_str());
  vtkNew<vtkPTVEXRPassWriter> writer;
  writer->SetInputData(image);
  writer->SetFileName(file.c_str());
  const bool written = writer->Write() == 1;
  const bool exists = access(file.c_str(), F_OK) == 0;
  if (written != exists)
  {
    Fail(written ? "Write() succeeded without a file" : "a failed Write() left a file");
  }
  if (!written)
  {
    return 0;
  }
  vtkNew<vtkPTVEXRPassReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  vtkImageData* out = reader->GetOutput();
  int dims[3];
  out->GetDimensions(dims);
  if (dims[0] != width || dims[1] != height || dims[2] != 1)
  {
    Fail("the read image has another size");
  }
  for (const auto& array : arrays)
  {
    auto* read = vtkFloatArray::SafeDownCast(out->GetPointData()->GetArray(array->GetName()));
    if (!read)
    {
      Fail(std::string("array '") + array->GetName() + "' is missing after the round trip");
    }
    if (read->GetNumberOfComponents() != array->GetNumberOfComponents() ||
      read->GetNumberOfTuples() != array->GetNumberOfTuples())
    {
      Fail(std::string("array '") + array->GetName() + "' changed its shape");
    }
    if (std::memcmp(read->GetPointer(0), array->GetPointer(0),
          sizeof(float) * static_cast<size_t>(array->GetNumberOfValues())) != 0)
    {
      Fail(std::string("a value of array '") + array->GetName() + "' changed");
    }
  }
  if (out->GetPointData()->GetNumberOfArrays() != static_cast<int>(arrays.size()))
  {
    Fail("the read image has another number of arrays");
  }
  return 0;
}
