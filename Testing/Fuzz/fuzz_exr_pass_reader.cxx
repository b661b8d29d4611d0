// libFuzzer: arbitrary bytes as an .exr file through vtkPTVEXRPassReader (and CanReadFile).
// The reader must either produce an image whose every array has one tuple per pixel, or report
// an error with an empty output; never crash, hang or allocate without bound (scripts/fuzz.sh
// caps memory with -rss_limit_mb / -malloc_limit_mb).
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPTVEXRPassReader.h"
#include "vtkPointData.h"
#include "ptvFuzzFile.h"

#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  const std::string file = WriteFuzzFile(data, size, ".exr");

  vtkPTVEXRPassReader::CanReadFile(file.c_str());
  vtkNew<vtkPTVEXRPassReader> reader;
  reader->SetFileName(file.c_str());
  // 2^24 values (64 MB of floats), under the run's 1 GB malloc limit: a larger image must be
  // refused by the reader, not allocated.
  reader->SetMaximumNumberOfValues(vtkIdType(1) << 24);
  reader->Update();
  vtkImageData* out = reader->GetOutput();
  const vtkIdType points = out->GetNumberOfPoints();
  vtkPointData* pd = out->GetPointData();
  if (points > 0 && pd->GetNumberOfArrays() == 0)
  {
    std::abort(); // an image without passes
  }
  for (int a = 0; a < pd->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* array = pd->GetArray(a);
    if (!array || array->GetNumberOfTuples() != points || !array->GetName())
    {
      std::abort(); // a pass that does not cover the image, or has no name
    }
  }
  return 0;
}
