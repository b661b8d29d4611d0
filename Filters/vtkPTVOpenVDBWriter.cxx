#include "vtkPTVOpenVDBWriter.h"

#include "ptvOpenVDBGrid.h"

#include "vtkAlgorithm.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkErrorCode.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkMatrix3x3.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"

#include <cmath>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkPTVOpenVDBWriter);

//------------------------------------------------------------------------------
vtkPTVOpenVDBWriter::vtkPTVOpenVDBWriter()
{
  this->SetGridName("density");
}

//------------------------------------------------------------------------------
vtkPTVOpenVDBWriter::~vtkPTVOpenVDBWriter()
{
  this->SetFileName(nullptr);
  this->SetGridName(nullptr);
  this->SetArrayName(nullptr);
}

//------------------------------------------------------------------------------
void vtkPTVOpenVDBWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "GridName: " << (this->GridName ? this->GridName : "(none)") << "\n";
  os << indent << "ArrayName: "
     << (this->ArrayName && *this->ArrayName ? this->ArrayName : "(active scalars)") << "\n";
  os << indent << "Background: " << this->Background << "\n";
}

//------------------------------------------------------------------------------
vtkImageData* vtkPTVOpenVDBWriter::GetInput()
{
  return vtkImageData::SafeDownCast(this->Superclass::GetInput());
}

//------------------------------------------------------------------------------
vtkImageData* vtkPTVOpenVDBWriter::GetInput(int port)
{
  return vtkImageData::SafeDownCast(this->Superclass::GetInput(port));
}

//------------------------------------------------------------------------------
int vtkPTVOpenVDBWriter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
  return 1;
}

//------------------------------------------------------------------------------
void vtkPTVOpenVDBWriter::WriteData()
{
  vtkImageData* image = this->GetInput();
  if (!image)
  {
    vtkErrorMacro("No input: connect a vtkImageData to write.");
    this->SetErrorCode(vtkErrorCode::UnknownError);
    return;
  }
  if (!this->FileName || !*this->FileName)
  {
    vtkErrorMacro("No FileName was set; set it to the .vdb file to write.");
    this->SetErrorCode(vtkErrorCode::NoFileNameError);
    return;
  }
  const std::string file = this->FileName;
  const std::string gridName = this->GridName ? this->GridName : "";

  // The array to write.
  vtkDataArray* array = nullptr;
  if (this->ArrayName && *this->ArrayName)
  {
    int index = -1;
    vtkAbstractArray* abstract = image->GetPointData()->GetAbstractArray(this->ArrayName, index);
    if (!abstract)
    {
      vtkErrorMacro("The input has no point-data array named '" << this->ArrayName
                                                                << "'; cannot write '" << file
                                                                << "'.");
      this->SetErrorCode(vtkErrorCode::UnknownError);
      return;
    }
    array = vtkDataArray::SafeDownCast(abstract);
    if (!array)
    {
      vtkErrorMacro("Point-data array '" << this->ArrayName << "' is a "
                                         << abstract->GetClassName()
                                         << ", not a numeric array; cannot write '" << file
                                         << "'.");
      this->SetErrorCode(vtkErrorCode::UnknownError);
      return;
    }
  }
  else
  {
    array = image->GetPointData()->GetScalars();
    if (!array)
    {
      vtkErrorMacro("The input has no point-data scalars (set ArrayName to choose an array); "
                    "cannot write '"
        << file << "'.");
      this->SetErrorCode(vtkErrorCode::UnknownError);
      return;
    }
  }
  const std::string arrayName = array->GetName() ? array->GetName() : "(unnamed)";
  const int type = array->GetDataType();
  if (type != VTK_FLOAT && type != VTK_DOUBLE)
  {
    vtkErrorMacro("Array '" << arrayName << "' is of type " << array->GetDataTypeAsString()
                            << "; only float or double scalars can be written to OpenVDB. "
                               "Convert it first, e.g. with vtkImageCast (OutputScalarType "
                               "float). Cannot write '"
                            << file << "'.");
    this->SetErrorCode(vtkErrorCode::UnknownError);
    return;
  }
  if (array->GetNumberOfComponents() != 1)
  {
    vtkErrorMacro("Array '" << arrayName << "' has " << array->GetNumberOfComponents()
                            << " components; only 1-component scalars can be written to "
                               "OpenVDB (extract one component first, e.g. with "
                               "vtkImageExtractComponents). Cannot write '"
                            << file << "'.");
    this->SetErrorCode(vtkErrorCode::UnknownError);
    return;
  }

  // Geometry.
  int extent[6];
  image->GetExtent(extent);
  const vtkIdType numPoints = image->GetNumberOfPoints();
  if (numPoints <= 0 || extent[1] < extent[0] || extent[3] < extent[2] || extent[5] < extent[4])
  {
    vtkErrorMacro("The input image is empty; cannot write '" << file << "'.");
    this->SetErrorCode(vtkErrorCode::UnknownError);
    return;
  }
  if (array->GetNumberOfTuples() != numPoints)
  {
    vtkErrorMacro("Array '" << arrayName << "' has " << array->GetNumberOfTuples()
                            << " values for " << numPoints << " points; cannot write '" << file
                            << "'.");
    this->SetErrorCode(vtkErrorCode::UnknownError);
    return;
  }
  vtkMatrix3x3* direction = image->GetDirectionMatrix();
  if (direction)
  {
    for (int r = 0; r < 3; ++r)
    {
      for (int c = 0; c < 3; ++c)
      {
        const double expected = (r == c) ? 1.0 : 0.0;
        if (std::abs(direction->GetElement(r, c) - expected) > 1e-12)
        {
          const double* d = direction->GetData();
          vtkErrorMacro("The input image has a non-identity direction matrix ("
            << d[0] << " " << d[1] << " " << d[2] << "; " << d[3] << " " << d[4] << " " << d[5]
            << "; " << d[6] << " " << d[7] << " " << d[8]
            << "); only axis-aligned images can be written to OpenVDB. Cannot write '" << file
            << "'.");
          this->SetErrorCode(vtkErrorCode::UnknownError);
          return;
        }
      }
    }
  }
  double spacing[3];
  image->GetSpacing(spacing);
  const double s = spacing[0];
  if (!(s > 0.0) || !(spacing[1] > 0.0) || !(spacing[2] > 0.0) ||
    std::abs(spacing[1] - s) > 1e-6 * s || std::abs(spacing[2] - s) > 1e-6 * s)
  {
    vtkErrorMacro("The input image has non-uniform or non-positive spacing ("
      << spacing[0] << ", " << spacing[1] << ", " << spacing[2]
      << "); OpenVDB voxels have one positive size along x, y and z (resample the image, e.g. "
         "with vtkImageResample, first). Cannot write '"
      << file << "'.");
    this->SetErrorCode(vtkErrorCode::UnknownError);
    return;
  }

  ptv::DenseVolume volume;
  image->GetOrigin(volume.Origin);
  for (int c = 0; c < 3; ++c)
  {
    volume.Dims[c] = extent[2 * c + 1] - extent[2 * c] + 1;
    // VDB index = VTK structured index, so the transform is just the image's origin + spacing.
    volume.IndexMin[c] = extent[2 * c];
    volume.Spacing[c] = s;
    volume.Origin[c] += extent[2 * c] * s;
  }
  volume.IsDouble = (type == VTK_DOUBLE);

  // Contiguous values: use the array's memory when it is a plain AOS array, else copy.
  std::vector<double> doubles;
  std::vector<float> floats;
  if (auto* fa = vtkFloatArray::FastDownCast(array))
  {
    volume.Data = fa->GetPointer(0);
  }
  else if (auto* da = vtkDoubleArray::FastDownCast(array))
  {
    volume.Data = da->GetPointer(0);
  }
  else if (volume.IsDouble)
  {
    doubles.resize(static_cast<size_t>(numPoints));
    for (vtkIdType i = 0; i < numPoints; ++i)
    {
      doubles[i] = array->GetComponent(i, 0);
    }
    volume.Data = doubles.data();
  }
  else
  {
    floats.resize(static_cast<size_t>(numPoints));
    for (vtkIdType i = 0; i < numPoints; ++i)
    {
      floats[i] = static_cast<float>(array->GetComponent(i, 0));
    }
    volume.Data = floats.data();
  }

  std::string error;
  if (!ptv::WriteScalarGrid(file, gridName, volume, this->Background, error))
  {
    // The message names the file (and the OS error when the file cannot be created).
    if (!error.empty() && error[0] >= 'a' && error[0] <= 'z')
    {
      error[0] = static_cast<char>(error[0] - 'a' + 'A');
    }
    vtkErrorMacro(<< error);
    this->SetErrorCode(vtkErrorCode::CannotOpenFileError);
    return;
  }
}
