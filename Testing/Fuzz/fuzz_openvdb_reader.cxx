// libFuzzer: arbitrary bytes as a .vdb file through vtkPTVOpenVDBReader (and CanReadFile).
// The reader must either produce an image or report an error; never crash, hang or allocate
// without bound (scripts/fuzz.sh caps memory with -rss_limit_mb / -malloc_limit_mb).
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPTVOpenVDBReader.h"
#include "vtkPointData.h"
#include "ptvFuzzFile.h"

#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  const std::string file = WriteFuzzFile(data, size, ".vdb");

  vtkPTVOpenVDBReader::CanReadFile(file.c_str());
  vtkNew<vtkPTVOpenVDBReader> reader;
  reader->SetFileName(file.c_str());
  // 2^24 voxels (64 MB as float), under the run's 1 GB malloc limit: a larger dense box must be
  // refused by the reader, not allocated.
  reader->SetMaximumNumberOfVoxels(vtkIdType(1) << 24);
  reader->Update();
  vtkImageData* out = reader->GetOutput();
  const vtkIdType points = out->GetNumberOfPoints();
  vtkDataArray* values = out->GetPointData()->GetScalars();
  if (points > 0 && (!values || values->GetNumberOfTuples() != points))
  {
    std::abort(); // an image without its values
  }
  return 0;
}
