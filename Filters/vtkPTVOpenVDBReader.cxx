#include "vtkPTVOpenVDBReader.h"

#include "ptvOpenVDBGrid.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkErrorCode.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"

#include <algorithm>
#include <string>
#include <vector>

namespace
{
// ptv:: messages start in lower case and already name the file and grid.
std::string Capitalized(std::string text)
{
  if (!text.empty() && text[0] >= 'a' && text[0] <= 'z')
  {
    text[0] = static_cast<char>(text[0] - 'a' + 'A');
  }
  return text;
}
} // anonymous namespace

//------------------------------------------------------------------------------
class vtkPTVOpenVDBReader::vtkInternals
{
public:
  std::vector<ptv::GridInfo> Grids;
  vtkNew<vtkStringArray> ScalarGridNames;
  // Selected grid and its geometry (whole extent), from the last RequestInformation.
  bool HasActiveGrid = false;
  std::string ActiveGrid;
  ptv::DenseVolume Volume;

  void Reset()
  {
    this->Grids.clear();
    this->ScalarGridNames->Reset();
    this->ScalarGridNames->SetNumberOfValues(0);
    this->HasActiveGrid = false;
    this->ActiveGrid.clear();
    this->Volume = ptv::DenseVolume();
  }
};

vtkStandardNewMacro(vtkPTVOpenVDBReader);

//------------------------------------------------------------------------------
vtkPTVOpenVDBReader::vtkPTVOpenVDBReader()
  : Internals(new vtkInternals)
{
  this->SetNumberOfInputPorts(0);
  this->SetNumberOfOutputPorts(1);
}

//------------------------------------------------------------------------------
vtkPTVOpenVDBReader::~vtkPTVOpenVDBReader()
{
  this->SetFileName(nullptr);
  this->SetGridName(nullptr);
  delete this->Internals;
}

//------------------------------------------------------------------------------
void vtkPTVOpenVDBReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "GridName: "
     << (this->GridName && *this->GridName ? this->GridName : "(first scalar grid)") << "\n";
  os << indent << "MaximumNumberOfVoxels: " << this->MaximumNumberOfVoxels << "\n";
  os << indent << "ActiveGridName: "
     << (this->Internals->HasActiveGrid ? this->Internals->ActiveGrid.c_str() : "(none)") << "\n";
  os << indent << "NumberOfGrids: " << this->Internals->Grids.size() << "\n";
  for (const ptv::GridInfo& info : this->Internals->Grids)
  {
    os << indent.GetNextIndent() << "'" << info.Name << "': " << info.ValueType << ", "
       << info.GridClass << "\n";
  }
}

//------------------------------------------------------------------------------
const char* vtkPTVOpenVDBReader::GetActiveGridName()
{
  return this->Internals->HasActiveGrid ? this->Internals->ActiveGrid.c_str() : nullptr;
}

//------------------------------------------------------------------------------
int vtkPTVOpenVDBReader::GetNumberOfGrids()
{
  return static_cast<int>(this->Internals->Grids.size());
}

//------------------------------------------------------------------------------
const char* vtkPTVOpenVDBReader::GetGridName(int index)
{
  if (index < 0 || index >= this->GetNumberOfGrids())
  {
    return nullptr;
  }
  return this->Internals->Grids[index].Name.c_str();
}

//------------------------------------------------------------------------------
const char* vtkPTVOpenVDBReader::GetGridType(int index)
{
  if (index < 0 || index >= this->GetNumberOfGrids())
  {
    return nullptr;
  }
  return this->Internals->Grids[index].ValueType.c_str();
}

//------------------------------------------------------------------------------
vtkStringArray* vtkPTVOpenVDBReader::GetScalarGridNames()
{
  return this->Internals->ScalarGridNames;
}

//------------------------------------------------------------------------------
int vtkPTVOpenVDBReader::CanReadFile(const char* filename)
{
  if (!filename || !*filename)
  {
    return 0;
  }
  return ptv::CanOpenFile(filename) ? 1 : 0;
}

//------------------------------------------------------------------------------
int vtkPTVOpenVDBReader::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkInternals& internals = *this->Internals;
  internals.Reset();
  this->SetErrorCode(vtkErrorCode::NoError);

  // On failure: no extent, and no data left over from an earlier successful read.
  auto fail = [&](unsigned long code) {
    const int empty[6] = { 0, -1, 0, -1, 0, -1 };
    outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), empty, 6);
    outInfo->Remove(vtkAlgorithm::CAN_PRODUCE_SUB_EXTENT());
    if (vtkImageData* output = vtkImageData::GetData(outInfo))
    {
      output->Initialize();
    }
    this->SetErrorCode(code);
    return 0;
  };

  if (!this->FileName || !*this->FileName)
  {
    vtkErrorMacro("No FileName was set; set it to the .vdb file to read.");
    return fail(vtkErrorCode::NoFileNameError);
  }
  const std::string file = this->FileName;

  std::string error;
  if (!ptv::ListGrids(file, internals.Grids, error))
  {
    vtkErrorMacro(<< Capitalized(error));
    return fail(vtkErrorCode::FileFormatError);
  }
  for (const ptv::GridInfo& info : internals.Grids)
  {
    if (info.IsScalar())
    {
      internals.ScalarGridNames->InsertNextValue(info.Name);
    }
  }

  // Resolve the grid to read.
  std::string grid;
  if (this->GridName && *this->GridName)
  {
    grid = this->GridName;
    auto it = std::find_if(internals.Grids.begin(), internals.Grids.end(),
      [&grid](const ptv::GridInfo& info) { return info.Name == grid; });
    if (it == internals.Grids.end())
    {
      vtkErrorMacro("No grid named '" << grid << "' in OpenVDB file '" << file
                                      << "'; available grids: "
                                      << ptv::DescribeGrids(internals.Grids));
      return fail(vtkErrorCode::FileFormatError);
    }
    if (!it->IsScalar())
    {
      vtkErrorMacro("Cannot read grid '" << grid << "' of OpenVDB file '" << file
                                         << "': grid '" << grid << "' is of type "
                                         << it->ValueType
                                         << "; only scalar float/double grids are supported");
      return fail(vtkErrorCode::FileFormatError);
    }
  }
  else
  {
    auto it = std::find_if(internals.Grids.begin(), internals.Grids.end(),
      [](const ptv::GridInfo& info) { return info.IsScalar(); });
    if (it == internals.Grids.end())
    {
      vtkErrorMacro("OpenVDB file '" << file
                                     << "' has no scalar float/double grid; its grids are: "
                                     << ptv::DescribeGrids(internals.Grids));
      return fail(vtkErrorCode::FileFormatError);
    }
    grid = it->Name;
  }

  ptv::DenseVolume volume;
  if (!ptv::ReadScalarGridInfo(file, grid, volume, error))
  {
    vtkErrorMacro(<< Capitalized(error));
    return fail(vtkErrorCode::FileFormatError);
  }

  internals.HasActiveGrid = true;
  internals.ActiveGrid = grid;
  internals.Volume = volume;

  const int extent[6] = { 0, volume.Dims[0] - 1, 0, volume.Dims[1] - 1, 0, volume.Dims[2] - 1 };
  outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
  outInfo->Set(vtkDataObject::SPACING(), volume.Spacing, 3);
  outInfo->Set(vtkDataObject::ORIGIN(), volume.Origin, 3);
  vtkDataObject::SetPointDataActiveScalarInfo(
    outInfo, volume.IsDouble ? VTK_DOUBLE : VTK_FLOAT, 1);
  // RequestData reads exactly the requested extent, so pieces (e.g. MPI ranks in ParaView) each
  // get their own block instead of the whole volume.
  outInfo->Set(vtkAlgorithm::CAN_PRODUCE_SUB_EXTENT(), 1);
  return 1;
}

//------------------------------------------------------------------------------
int vtkPTVOpenVDBReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkImageData* output = vtkImageData::GetData(outInfo);
  vtkInternals& internals = *this->Internals;
  if (!output)
  {
    vtkErrorMacro("No vtkImageData output to fill.");
    return 0;
  }
  output->Initialize();
  if (!internals.HasActiveGrid || !this->FileName)
  {
    vtkErrorMacro("No grid was selected; the information pass failed or was not run.");
    return 0;
  }

  // Read the requested extent (the whole extent unless a consumer asked for less).
  const ptv::DenseVolume& whole = internals.Volume;
  int extent[6] = { 0, whole.Dims[0] - 1, 0, whole.Dims[1] - 1, 0, whole.Dims[2] - 1 };
  if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT()))
  {
    int update[6];
    outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), update);
    bool valid = true;
    for (int c = 0; c < 3; ++c)
    {
      update[2 * c] = std::max(update[2 * c], extent[2 * c]);
      update[2 * c + 1] = std::min(update[2 * c + 1], extent[2 * c + 1]);
      valid = valid && update[2 * c] <= update[2 * c + 1];
    }
    if (!valid)
    {
      // An empty request: nothing to read.
      return 1;
    }
    std::copy(update, update + 6, extent);
  }

  ptv::DenseVolume volume = whole;
  for (int c = 0; c < 3; ++c)
  {
    volume.Dims[c] = extent[2 * c + 1] - extent[2 * c] + 1;
    volume.IndexMin[c] = whole.IndexMin[c] + extent[2 * c];
  }

  const double voxels = double(volume.Dims[0]) * volume.Dims[1] * volume.Dims[2];
  if (voxels > double(this->MaximumNumberOfVoxels))
  {
    vtkErrorMacro("Grid '" << internals.ActiveGrid << "' of '" << this->FileName << "' spans "
                           << volume.Dims[0] << " x " << volume.Dims[1] << " x " << volume.Dims[2]
                           << " voxels (the dense box of its active voxels), "
                           << "more than MaximumNumberOfVoxels (" << this->MaximumNumberOfVoxels
                           << "); request a smaller update extent or raise the limit.");
    this->SetErrorCode(vtkErrorCode::OutOfDiskSpaceError);
    return 0;
  }

  vtkSmartPointer<vtkDataArray> values;
  if (whole.IsDouble)
  {
    values = vtkSmartPointer<vtkDoubleArray>::New();
  }
  else
  {
    values = vtkSmartPointer<vtkFloatArray>::New();
  }
  values->SetName(internals.ActiveGrid.empty() ? "values" : internals.ActiveGrid.c_str());
  values->SetNumberOfComponents(1);
  if (!values->SetNumberOfValues(static_cast<vtkIdType>(volume.GetNumberOfValues())))
  {
    vtkErrorMacro("Cannot allocate " << volume.GetNumberOfValues() << " values for grid '"
                                     << internals.ActiveGrid << "' of '" << this->FileName
                                     << "'.");
    this->SetErrorCode(vtkErrorCode::OutOfDiskSpaceError);
    return 0;
  }
  volume.Data = values->GetVoidPointer(0);

  std::string error;
  if (!ptv::ReadScalarGrid(this->FileName, internals.ActiveGrid, volume, error))
  {
    vtkErrorMacro(<< Capitalized(error));
    this->SetErrorCode(vtkErrorCode::FileFormatError);
    return 0;
  }

  output->SetExtent(extent);
  output->SetSpacing(whole.Spacing);
  output->SetOrigin(whole.Origin);
  output->GetPointData()->SetScalars(values);
  return 1;
}
