#include "vtkPTVBilateralGrid.h"

#include "ptvBilateralGridRunner.h"

#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"

#include <sstream>
#include <string>

struct vtkPTVBilateralGrid::vtkInternals
{
  ptv::BilateralGridSettings Settings;
  ptv::BilateralGridRunner Grid;
  ptv::BilateralGridTimings Timings;
};

vtkStandardNewMacro(vtkPTVBilateralGrid);

namespace
{
const char* const kOutputName = "Denoised";

std::string Dimensions(const int dims[3])
{
  std::ostringstream s;
  s << dims[0] << " x " << dims[1] << " x " << dims[2];
  return s.str();
}
}

//------------------------------------------------------------------------------
vtkPTVBilateralGrid::vtkPTVBilateralGrid()
  : Internals(new vtkInternals)
{
}

//------------------------------------------------------------------------------
vtkPTVBilateralGrid::~vtkPTVBilateralGrid() = default;

//------------------------------------------------------------------------------
void vtkPTVBilateralGrid::SetSpatialStep(int level, int step)
{
  if (level < 0 || level >= ptv::kMaxGridLevels)
  {
    vtkErrorMacro("SetSpatialStep: level " << level << " is out of range [0, "
                                           << ptv::kMaxGridLevels - 1 << "]");
    return;
  }
  step = step < 1 ? 1 : (step > ptv::kMaxGridStep ? ptv::kMaxGridStep : step);
  if (this->Internals->Settings.SpatialStep[level] != step)
  {
    this->Internals->Settings.SpatialStep[level] = step;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
int vtkPTVBilateralGrid::GetSpatialStep(int level)
{
  if (level < 0 || level >= ptv::kMaxGridLevels)
  {
    vtkErrorMacro("GetSpatialStep: level " << level << " is out of range [0, "
                                           << ptv::kMaxGridLevels - 1 << "]");
    return 0;
  }
  return this->Internals->Settings.SpatialStep[level];
}

//------------------------------------------------------------------------------
void vtkPTVBilateralGrid::SetRangeStep(int level, int step)
{
  if (level < 0 || level >= ptv::kMaxGridLevels)
  {
    vtkErrorMacro("SetRangeStep: level " << level << " is out of range [0, "
                                         << ptv::kMaxGridLevels - 1 << "]");
    return;
  }
  step = step < 1 ? 1 : (step > ptv::kMaxGridStep ? ptv::kMaxGridStep : step);
  if (this->Internals->Settings.RangeStep[level] != step)
  {
    this->Internals->Settings.RangeStep[level] = step;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
int vtkPTVBilateralGrid::GetRangeStep(int level)
{
  if (level < 0 || level >= ptv::kMaxGridLevels)
  {
    vtkErrorMacro("GetRangeStep: level " << level << " is out of range [0, "
                                         << ptv::kMaxGridLevels - 1 << "]");
    return 0;
  }
  return this->Internals->Settings.RangeStep[level];
}

//------------------------------------------------------------------------------
double vtkPTVBilateralGrid::GetLastDemodulateTime() const
{
  return this->Internals->Timings.Demodulate;
}

//------------------------------------------------------------------------------
double vtkPTVBilateralGrid::GetLastSplatTime() const
{
  return this->Internals->Timings.Splat;
}

//------------------------------------------------------------------------------
double vtkPTVBilateralGrid::GetLastSliceTime() const
{
  return this->Internals->Timings.Slice;
}

//------------------------------------------------------------------------------
bool vtkPTVBilateralGrid::Apply(vtkImageData* radiance, vtkImageData* albedo,
  vtkImageData* guides, vtkImageData* weights, vtkImageData* output)
{
  const int levels = this->NumberOfLevels;
  if (!output)
  {
    vtkErrorMacro("Apply: output is nullptr");
    return false;
  }
  if (output == radiance || output == albedo || output == guides ||
    (levels > 1 && output == weights))
  {
    vtkErrorMacro("Apply: output must be a separate image, not one of the inputs");
    return false;
  }

  // Checks one input image; returns its float scalars, or nullptr after reporting why.
  int size[3] = { 0, 0, 0 };
  auto check = [&](vtkImageData* image, const char* role, int components) -> vtkFloatArray*
  {
    if (!image)
    {
      vtkErrorMacro("Apply: " << role << " is nullptr");
      return nullptr;
    }
    int dims[3];
    image->GetDimensions(dims);
    if (dims[0] < 1 || dims[1] < 1 || dims[2] < 1)
    {
      vtkErrorMacro(
        "Apply: " << role << " is a zero-size image (dimensions " << Dimensions(dims) << ")");
      return nullptr;
    }
    if (dims[2] != 1)
    {
      vtkErrorMacro("Apply: " << role << " must be a 2D image (W x H x 1), got dimensions "
                              << Dimensions(dims));
      return nullptr;
    }
    if (size[0] == 0)
    {
      size[0] = dims[0];
      size[1] = dims[1];
      size[2] = 1;
    }
    else if (dims[0] != size[0] || dims[1] != size[1])
    {
      vtkErrorMacro("Apply: " << role << " dimensions " << Dimensions(dims)
                              << " differ from the radiance dimensions " << Dimensions(size));
      return nullptr;
    }
    vtkDataArray* scalars = image->GetPointData()->GetScalars();
    if (!scalars)
    {
      vtkErrorMacro("Apply: " << role << " has no active point scalars");
      return nullptr;
    }
    const char* name = scalars->GetName() ? scalars->GetName() : "(unnamed)";
    vtkFloatArray* array = vtkFloatArray::FastDownCast(scalars);
    if (!array)
    {
      vtkErrorMacro("Apply: " << role << " scalars \"" << name << "\" are a "
                              << scalars->GetClassName() << " of "
                              << scalars->GetDataTypeAsString()
                              << ", expected a vtkFloatArray (float)");
      return nullptr;
    }
    if (array->GetNumberOfComponents() != components)
    {
      vtkErrorMacro("Apply: " << role << " scalars \"" << name << "\" have "
                              << array->GetNumberOfComponents() << " components, expected "
                              << components << " (NumberOfLevels " << levels << ")");
      return nullptr;
    }
    const vtkIdType points = static_cast<vtkIdType>(dims[0]) * dims[1];
    if (array->GetNumberOfTuples() != points)
    {
      vtkErrorMacro("Apply: " << role << " scalars \"" << name << "\" have "
                              << array->GetNumberOfTuples() << " tuples, expected " << points
                              << " (dimensions " << Dimensions(dims) << ")");
      return nullptr;
    }
    return array;
  };

  vtkFloatArray* radianceArray = check(radiance, "radiance", 3);
  if (!radianceArray)
  {
    return false;
  }
  vtkFloatArray* albedoArray = nullptr;
  if (this->Demodulate)
  {
    albedoArray = check(albedo, "albedo", 3);
    if (!albedoArray)
    {
      return false;
    }
  }
  vtkFloatArray* guidesArray = check(guides, "guides", levels);
  if (!guidesArray)
  {
    return false;
  }
  vtkFloatArray* weightsArray = nullptr;
  if (levels > 1)
  {
    if (!weights)
    {
      vtkErrorMacro("Apply: weights is nullptr, but NumberOfLevels " << levels << " needs "
                                                                     << levels - 1
                                                                     << " blend weight maps");
      return false;
    }
    weightsArray = check(weights, "weights", levels - 1);
    if (!weightsArray)
    {
      return false;
    }
  }

  // Output: the inputs' geometry and a "Denoised" array, reused when it has the right size.
  const int width = size[0];
  const int height = size[1];
  const vtkIdType points = static_cast<vtkIdType>(width) * height;
  int outputDims[3];
  output->GetDimensions(outputDims);
  if (outputDims[0] != width || outputDims[1] != height || outputDims[2] != 1)
  {
    output->GetPointData()->Initialize();
  }
  output->SetExtent(0, width - 1, 0, height - 1, 0, 0);
  output->SetOrigin(radiance->GetOrigin());
  output->SetSpacing(radiance->GetSpacing());
  output->SetDirectionMatrix(radiance->GetDirectionMatrix());
  vtkFloatArray* result =
    vtkFloatArray::FastDownCast(output->GetPointData()->GetAbstractArray(kOutputName));
  const bool shared = result == radianceArray || result == albedoArray || result == guidesArray ||
    result == weightsArray; // an input array also attached to the output: never overwrite it
  if (!result || shared || result->GetNumberOfComponents() != 3 ||
    result->GetNumberOfTuples() != points)
  {
    vtkNew<vtkFloatArray> created;
    created->SetName(kOutputName);
    created->SetNumberOfComponents(3);
    created->SetNumberOfTuples(points);
    output->GetPointData()->RemoveArray(kOutputName);
    output->GetPointData()->AddArray(created);
    result = created;
  }
  output->GetPointData()->SetActiveScalars(kOutputName);

  this->Internals->Settings.Levels = levels;
  this->Internals->Settings.Clamp = this->Clamp;
  this->Internals->Settings.Threads = this->NumberOfThreads;
  const float* albedoData = albedoArray ? albedoArray->GetPointer(0) : nullptr;
  const float* weightsData = weightsArray ? weightsArray->GetPointer(0) : nullptr;
  vtkInternals& in = *this->Internals;
  std::string error;
  in.Grid.Apply(in.Settings, this->UseCuda, width, height, radianceArray->GetPointer(0),
    albedoData, guidesArray->GetPointer(0), weightsData, result->GetPointer(0), error);
  if (this->UseCuda && !in.Grid.GetLastOnCuda())
  {
    vtkErrorMacro("Apply: UseCuda is on but the CUDA grid cannot run (" << error
                                                                      << "); using the CPU");
  }
  in.Timings = in.Grid.GetLastTimings();
  result->Modified();
  output->Modified();
  return true;
}

//------------------------------------------------------------------------------
bool vtkPTVBilateralGrid::GetLastApplyOnCuda() const
{
  return this->Internals->Grid.GetLastOnCuda();
}

//------------------------------------------------------------------------------
void vtkPTVBilateralGrid::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  const ptv::BilateralGridSettings& s = this->Internals->Settings;
  os << indent << "NumberOfLevels: " << this->NumberOfLevels << "\n";
  for (int l = 0; l < ptv::kMaxGridLevels; ++l)
  {
    os << indent << "Level " << l << ": SpatialStep " << s.SpatialStep[l] << ", RangeStep "
       << s.RangeStep[l] << "\n";
  }
  os << indent << "Clamp: " << this->Clamp << "\n";
  os << indent << "Demodulate: " << (this->Demodulate ? "On" : "Off") << "\n";
  os << indent << "UseCuda: " << (this->UseCuda ? "On" : "Off")
     << " (last Apply on " << (this->Internals->Grid.GetLastOnCuda() ? "CUDA" : "the CPU")
     << ")\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
  os << indent << "LastDemodulateTime: " << this->Internals->Timings.Demodulate << " ms\n";
  os << indent << "LastSplatTime: " << this->Internals->Timings.Splat << " ms\n";
  os << indent << "LastSliceTime: " << this->Internals->Timings.Slice << " ms\n";
}
