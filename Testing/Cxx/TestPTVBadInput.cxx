// Bad input, one ctest per case (PTV.Cxx.TestPTVBadInput.<case>; argv: the case name). Each case
// asserts the exact error or the documented fallback, that the process survives, and that the
// mapper/reader works again afterwards where that matters. docs/reliability.md lists the cases.
//   mapper:  nan_voxels inf_voxels all_nonfinite empty_volume one_voxel multi_component
//            scalar_types bit_scalars string_scalars no_scalars cell_scalars wrong_tuple_count
//            extreme_dims zero_spacing negative_spacing nonfinite_geometry singular_matrix
//            camera_inside zero_viewport one_pixel_viewport tf_transparent tf_opaque tf_empty
//            recovers
//   files:   vdb_zero_length vdb_header_only vdb_unwritable (damaged bytes: Testing/Fuzz/)
#include "ptvTestCheck.h"
#include "vtkBitArray.h"
#include "vtkCamera.h"
#include "vtkCellData.h"
#include "vtkColorTransferFunction.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkExecutive.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPTVExpertOptions.h"
#include "vtkPTVOpenVDBReader.h"
#include "vtkPTVOpenVDBWriter.h"
#include "vtkPathTracedVolumeMapper.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkRTAnalyticSource.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"
#include "vtkTestErrorObserver.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"
#include "vtksys/Directory.hxx"
#include "vtksys/SystemTools.hxx"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iostream>
#include <iterator>
#include <limits>
#include <map>
#include <string>
#include <vector>

namespace
{
// The last argument not belonging to a -X flag is the case name.
std::string CaseName(int argc, char* argv[])
{
  std::string name;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a.size() == 2 && a[0] == '-')
    {
      ++i;
      continue;
    }
    name = a;
  }
  return name;
}

// A small volume (values (i % 7) / 6, so every scalar type holds them exactly... after scaling)
// with a linear ramp transfer function; 32x32 window, Denoise off unless a case turns it on.
struct Scene
{
  vtkNew<vtkColorTransferFunction> Color;
  vtkNew<vtkPiecewiseFunction> Opacity;
  vtkNew<vtkVolumeProperty> Property;
  vtkNew<vtkPathTracedVolumeMapper> Mapper;
  vtkNew<vtkVolume> Volume;
  vtkNew<vtkRenderer> Renderer;
  vtkNew<vtkRenderWindow> Window;
  vtkNew<vtkTest::ErrorObserver> Observer;

  explicit Scene(vtkDataObject* input, int size = 32)
  {
    this->Color->AddRGBPoint(0, 0.2, 0.4, 1.0);
    this->Color->AddRGBPoint(6, 1.0, 0.9, 0.5);
    this->Opacity->AddPoint(0, 0.0);
    this->Opacity->AddPoint(6, 0.9);
    this->Property->SetColor(this->Color);
    this->Property->SetScalarOpacity(this->Opacity);
    this->Mapper->SetInputDataObject(input);
    this->Mapper->DenoiseOff();
    this->Mapper->ConvergeStillRendersOff(); // one frame per render
    this->Mapper->GetExpertOptions()->ScatterPassesOn(); // every traced pass is checked
    this->Mapper->AddObserver(vtkCommand::ErrorEvent, this->Observer);
    this->Mapper->AddObserver(vtkCommand::WarningEvent, this->Observer);
    this->Volume->SetMapper(this->Mapper);
    this->Volume->SetProperty(this->Property);
    this->Renderer->AddVolume(this->Volume);
    this->Renderer->SetBackground(0.4, 0.4, 0.4);
    this->Window->SetSize(size, size);
    this->Window->AddRenderer(this->Renderer);
    // A fixed camera on the 8^3 default volume, independent of the input's (maybe bad) bounds.
    vtkCamera* camera = this->Renderer->GetActiveCamera();
    camera->SetFocalPoint(3.5, 3.5, 3.5);
    camera->SetPosition(3.5, 3.5, 30);
    camera->SetViewUp(0, 1, 0);
    camera->Azimuth(25);
    camera->Elevation(15);
    this->Renderer->ResetCameraClippingRange(-100, 100, -100, 100, -100, 100);
  }

  std::vector<float> Pass(const char* name)
  {
    vtkNew<vtkImageData> image;
    vtkNew<vtkTest::ErrorObserver> quiet; // "not available" is a result here, not a failure
    const unsigned long tag = this->Mapper->AddObserver(vtkCommand::ErrorEvent, quiet);
    const bool ok = this->Mapper->GetPass(name, image);
    this->Mapper->RemoveObserver(tag);
    if (!ok)
    {
      return {};
    }
    vtkFloatArray* a = vtkFloatArray::SafeDownCast(image->GetPointData()->GetScalars());
    return std::vector<float>(a->GetPointer(0), a->GetPointer(0) + a->GetNumberOfValues());
  }

  // An error containing every needle was reported (and printed without VTK's "ERROR: In").
  void ExpectError(const std::string& label, const std::vector<std::string>& needles)
  {
    const std::string text = this->Observer->GetErrorMessage();
    Check(this->Observer->GetError(), label + ": an error must be reported");
    for (const std::string& n : needles)
    {
      Check(text.find(n) != std::string::npos, label + ": the error must mention \"" + n + "\"");
    }
    // The message line only: VTK's "ERROR: In <file>" line would fail the ctest.
    std::string first = text.substr(text.find('\n') + 1);
    std::cout << label << ": reported as expected: " << first.substr(0, first.find('\n')) << "\n";
    this->Observer->Clear();
  }

  void ExpectWarning(const std::string& label, const std::string& needle)
  {
    Check(this->Observer->GetWarning() &&
        this->Observer->GetWarningMessage().find(needle) != std::string::npos,
      label + ": a warning mentioning \"" + needle + "\" must be reported");
    Check(!this->Observer->GetError(), label + ": no error expected");
    this->Observer->Clear();
  }

  void ExpectQuiet(const std::string& label)
  {
    Check(!this->Observer->GetError() && !this->Observer->GetWarning(),
      label + ": no error/warning expected; got: " + this->Observer->GetErrorMessage() +
        this->Observer->GetWarningMessage());
    this->Observer->Clear();
  }
};

vtkSmartPointer<vtkImageData> Volume(int nx = 8, int ny = 8, int nz = 8, int type = VTK_FLOAT)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(nx, ny, nz);
  image->AllocateScalars(type, 1);
  vtkDataArray* a = image->GetPointData()->GetScalars();
  a->SetName("values");
  for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
  {
    a->SetTuple1(i, static_cast<double>((i * 5 + i / nx) % 7));
  }
  return image;
}

bool AllFinite(const std::vector<float>& v)
{
  for (float x : v)
  {
    if (!std::isfinite(x))
    {
      return false;
    }
  }
  return !v.empty();
}

double Mean(const std::vector<float>& v)
{
  double s = 0;
  for (float x : v)
  {
    s += x;
  }
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}

// A frame was traced and every traced pass is finite with @a pixels pixels.
void ExpectFrame(Scene& s, const std::string& label, int pixels = 32 * 32)
{
  Check(s.Mapper->GetAccumulatedFrames() == 1, label + ": one frame must be traced");
  for (int i = 0; i < 9; ++i)
  {
    const char* name = vtkPathTracedVolumeMapper::GetPassName(i);
    const auto pass = s.Pass(name);
    Check(AllFinite(pass) && pass.size() % pixels == 0 && pass.size() / pixels <= 3,
      label + ": pass " + name + " must be finite with " + std::to_string(pixels) + " pixels");
  }
}

// --- mapper cases ---------------------------------------------------------------------------

void NonFiniteVoxels(double value, const std::string& label)
{
  auto image = Volume();
  vtkDataArray* a = image->GetPointData()->GetScalars();
  vtkIdType bad = 0;
  for (vtkIdType i = 0; i < a->GetNumberOfTuples(); i += 7, ++bad)
  {
    a->SetTuple1(i, i % 2 ? value : -value);
  }
  Scene s(image);
  s.Window->Render();
  s.ExpectWarning(label, std::to_string(bad) + " voxels are NaN or infinite");
  ExpectFrame(s, label);
  s.Window->Render();
  s.ExpectQuiet(label + ": the warning is given once");
}

void AllNonFinite()
{
  auto image = Volume();
  image->GetPointData()->GetScalars()->Fill(std::numeric_limits<double>::quiet_NaN());
  Scene s(image);
  s.Window->Render();
  s.ExpectError("all NaN", { "every voxel is NaN or infinite" });
  Check(s.Mapper->GetAccumulatedFrames() == 0, "all NaN: nothing traced");
}

void EmptyVolume()
{
  vtkNew<vtkImageData> empty;
  Scene s(empty);
  s.Window->Render();
  s.ExpectError("empty volume", { "empty volume (dimensions 0 x 0 x 0)" });
  Check(s.Mapper->GetAccumulatedFrames() == 0, "empty volume: nothing traced");
}

void OneVoxel()
{
  auto one = Volume(1, 1, 1);
  one->GetPointData()->GetScalars()->SetTuple1(0, 6);
  Scene s(one);
  s.Window->Render();
  s.ExpectQuiet("one voxel");
  ExpectFrame(s, "one voxel");
  Check(Mean(s.Pass("Alpha")) == 0.0, "one voxel: a zero-thickness box shows nothing");
}

void MultiComponent()
{
  for (int comps : { 2, 3, 4 })
  {
    auto image = vtkSmartPointer<vtkImageData>::New();
    image->SetDimensions(4, 4, 4);
    image->AllocateScalars(VTK_UNSIGNED_CHAR, comps);
    image->GetPointData()->GetScalars()->SetName("rgb");
    Scene s(image);
    s.Window->Render();
    s.ExpectError("multi-component " + std::to_string(comps),
      { "'rgb' has " + std::to_string(comps) + " components", "vtkImageExtractComponents" });
    Check(s.Mapper->GetAccumulatedFrames() == 0, "multi-component: nothing traced");
  }
}

// Every numeric type holds 0..6 exactly, so every type must give the float image bit for bit.
void ScalarTypes()
{
  std::vector<float> reference;
  {
    Scene s(Volume());
    s.Window->Render();
    reference = s.Pass("Radiance");
  }
  Check(AllFinite(reference) && Mean(reference) > 0, "float reference renders");
  for (int type : { VTK_CHAR, VTK_SIGNED_CHAR, VTK_UNSIGNED_CHAR, VTK_SHORT, VTK_UNSIGNED_SHORT,
         VTK_INT, VTK_UNSIGNED_INT, VTK_LONG, VTK_UNSIGNED_LONG, VTK_LONG_LONG,
         VTK_UNSIGNED_LONG_LONG, VTK_ID_TYPE, VTK_DOUBLE })
  {
    Scene s(Volume(8, 8, 8, type));
    s.Window->Render();
    const std::string label = std::string("scalar type ") + vtkImageScalarTypeNameMacro(type);
    s.ExpectQuiet(label);
    Check(s.Pass("Radiance") == reference, label + ": same image as float");
  }
}

// vtkBitArray is a vtkDataArray outside vtkArrayDispatch's lists: the generic path reads it.
void BitScalars()
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(8, 8, 8);
  vtkNew<vtkBitArray> bits;
  bits->SetName("bits");
  bits->SetNumberOfTuples(512);
  for (vtkIdType i = 0; i < 512; ++i)
  {
    bits->SetValue(i, (i * 5 + i / 8) % 7 > 3 ? 1 : 0);
  }
  image->GetPointData()->SetScalars(bits);
  Scene s(image);
  s.Opacity->RemoveAllPoints();
  s.Opacity->AddPoint(0, 0);
  s.Opacity->AddPoint(1, 0.9);
  s.Window->Render();
  s.ExpectQuiet("bit scalars");
  ExpectFrame(s, "bit scalars");
  Check(Mean(s.Pass("Alpha")) > 0, "bit scalars: something is visible");
}

// A non-numeric array chosen by name is not a vtkDataArray: "no point scalars".
void StringScalars()
{
  auto image = Volume();
  vtkNew<vtkStringArray> labels;
  labels->SetName("labels");
  labels->SetNumberOfValues(512);
  image->GetPointData()->AddArray(labels);
  Scene s(image);
  s.Mapper->SetScalarModeToUsePointFieldData();
  s.Mapper->SelectScalarArray("labels");
  s.Window->Render();
  s.ExpectError("string array", { "no point scalars" });
}

void NoScalars()
{
  vtkNew<vtkImageData> image;
  image->SetDimensions(4, 4, 4);
  Scene s(image);
  s.Window->Render();
  s.ExpectError("no scalars", { "no point scalars", "SelectScalarArray" });
}

void CellScalars()
{
  vtkNew<vtkImageData> image;
  image->SetDimensions(4, 4, 4);
  vtkNew<vtkFloatArray> cells;
  cells->SetName("cells");
  cells->SetNumberOfTuples(27);
  cells->Fill(1.0);
  image->GetCellData()->SetScalars(cells);
  Scene s(image);
  s.Window->Render();
  s.ExpectError("cell scalars", { "cell scalars are not supported", "vtkCellDataToPointData" });
}

void WrongTupleCount()
{
  auto image = Volume(4, 4, 4);
  image->GetPointData()->GetScalars()->SetNumberOfTuples(10);
  Scene s(image);
  s.Window->Render();
  s.ExpectError("wrong tuple count", { "'values' has 10 values but the image has 64 points" });
}

// 1 x 1 x 100000 (zero thickness: nothing to see) and 2 x 2 x 100000 seen from the side.
void ExtremeDims()
{
  for (int axis = 0; axis < 3; ++axis)
  {
    int dims[3] = { 1, 1, 1 };
    dims[axis] = 100000;
    Scene s(Volume(dims[0], dims[1], dims[2]));
    s.Window->Render();
    const std::string label = "1x1x100000 along axis " + std::to_string(axis);
    s.ExpectQuiet(label);
    ExpectFrame(s, label);
    Check(Mean(s.Pass("Alpha")) == 0.0, label + ": zero thickness shows nothing");
  }
  Scene s(Volume(2, 2, 100000));
  vtkCamera* camera = s.Renderer->GetActiveCamera();
  camera->SetFocalPoint(0.5, 0.5, 50000);
  camera->SetPosition(0.5, 6, 50000);
  camera->SetViewUp(0, 0, 1);
  s.Renderer->ResetCameraClippingRange(0, 1, 0, 1, 49990, 50010);
  s.Window->Render();
  s.ExpectQuiet("2x2x100000");
  ExpectFrame(s, "2x2x100000");
  const double covered = Mean(s.Pass("Alpha"));
  Check(covered > 0.01 && covered < 0.9, "2x2x100000: the stick covers part of the view");
}

void ZeroSpacing()
{
  auto image = Volume();
  image->SetSpacing(1, 0, 1);
  Scene s(image);
  s.Window->Render();
  s.ExpectError("zero spacing", { "zero image spacing (1, 0, 1)" });
  Check(s.Mapper->GetAccumulatedFrames() == 0, "zero spacing: nothing traced");
}

// Negative spacing mirrors the axis: mirrored voxels at mirrored positions give the same image.
void NegativeSpacing()
{
  std::vector<float> reference;
  {
    Scene s(Volume());
    s.Window->Render();
    reference = s.Pass("Alpha");
  }
  auto mirrored = Volume();
  auto source = Volume();
  vtkDataArray* in = source->GetPointData()->GetScalars();
  vtkDataArray* out = mirrored->GetPointData()->GetScalars();
  for (int k = 0; k < 8; ++k)
    for (int j = 0; j < 8; ++j)
      for (int i = 0; i < 8; ++i)
      {
        out->SetTuple1(i + 8 * (j + 8 * k), in->GetTuple1((7 - i) + 8 * (j + 8 * k)));
      }
  mirrored->SetSpacing(-1, 1, 1);
  mirrored->SetOrigin(7, 0, 0);
  Scene s(mirrored);
  s.Window->Render();
  s.ExpectQuiet("negative spacing");
  ExpectFrame(s, "negative spacing");
  const auto alpha = s.Pass("Alpha");
  double diff = 0;
  for (std::size_t i = 0; i < alpha.size() && i < reference.size(); ++i)
  {
    diff = std::max(diff, static_cast<double>(std::abs(alpha[i] - reference[i])));
  }
  std::cout << "negative spacing: max |alpha - mirrored alpha| = " << diff << "\n";
  Check(alpha.size() == reference.size() && Mean(reference) > 0.05 && diff < 0.02,
    "negative spacing: mirrored volume gives the same coverage");
}

// NaN / infinite spacing or origin: an error naming the value, nothing traced, no NaN frame.
void NonFiniteGeometry()
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  struct Case
  {
    std::string Label;
    double Spacing[3];
    double Origin[3];
    std::string Needle;
  };
  const Case cases[] = {
    { "NaN spacing", { nan, 1, 1 }, { 0, 0, 0 }, "non-finite image spacing (nan, 1, 1)" },
    { "infinite spacing", { 1, inf, 1 }, { 0, 0, 0 }, "non-finite image spacing (1, inf, 1)" },
    { "NaN origin", { 1, 1, 1 }, { 0, 0, nan }, "non-finite image origin (0, 0, nan)" },
  };
  for (const Case& c : cases)
  {
    auto image = Volume();
    image->SetSpacing(c.Spacing);
    image->SetOrigin(c.Origin);
    Scene s(image);
    s.Window->Render();
    s.ExpectError(c.Label, { c.Needle });
    Check(s.Mapper->GetAccumulatedFrames() == 0, c.Label + ": nothing traced");
  }
}

void SingularMatrix()
{
  Scene s(Volume());
  s.Volume->SetScale(1, 0, 1);
  s.Window->Render();
  s.ExpectError("singular volume matrix", { "index-to-world transform is singular" });
  Check(s.Mapper->GetAccumulatedFrames() == 0, "singular matrix: nothing traced");
}

void CameraInside()
{
  Scene s(Volume(32, 32, 32));
  vtkCamera* camera = s.Renderer->GetActiveCamera();
  camera->SetPosition(15, 15, 15);
  camera->SetFocalPoint(15, 15, 40);
  s.Renderer->ResetCameraClippingRange(0, 31, 0, 31, 0, 31);
  s.Window->Render();
  s.ExpectQuiet("camera inside");
  ExpectFrame(s, "camera inside");
  Check(Mean(s.Pass("Alpha")) > 0.5, "camera inside: the volume around the camera is visible");
}

void ZeroViewport()
{
  Scene s(Volume());
  s.Renderer->SetViewport(0.5, 0.5, 0.5, 0.5);
  s.Window->Render();
  s.ExpectQuiet("zero viewport");
  Check(s.Mapper->GetAccumulatedFrames() == 0, "zero viewport: nothing traced");
  s.Renderer->SetViewport(0, 0, 1, 1);
  s.Window->Render();
  ExpectFrame(s, "viewport back to full size");
}

// A 1x1 window, traced and denoised (fixed guide: the 1-pixel image is the grid's corner case).
void OnePixelViewport()
{
  Scene s(Volume(), 1);
  s.Mapper->DenoiseOn();
  s.Mapper->GetExpertOptions()->DenoiserUseNetworkOff();
  s.Renderer->GetActiveCamera()->Zoom(8); // the one pixel looks at the volume
  s.Window->Render();
  s.ExpectQuiet("1x1 viewport");
  ExpectFrame(s, "1x1 viewport", 1);
  const auto denoised = s.Pass("Denoised");
  Check(denoised.size() == 3 && AllFinite(denoised), "1x1 viewport: one finite denoised pixel");
  Check(Mean(s.Pass("Alpha")) > 0, "1x1 viewport: the pixel sees the volume");
}

void TransferTransparent()
{
  Scene s(Volume());
  s.Opacity->RemoveAllPoints();
  s.Opacity->AddPoint(0, 0);
  s.Opacity->AddPoint(6, 0);
  s.Mapper->DenoiseOn();
  s.Mapper->GetExpertOptions()->DenoiserUseNetworkOff();
  s.Window->Render();
  s.ExpectQuiet("transparent transfer function");
  ExpectFrame(s, "transparent transfer function");
  Check(Mean(s.Pass("Alpha")) == 0.0, "transparent: alpha 0 everywhere");
  const auto radiance = s.Pass("Radiance");
  Check(AllFinite(s.Pass("Denoised")), "transparent: the denoised image is finite");
  Check(std::abs(Mean(radiance) - Mean(s.Pass("Denoised"))) < 1e-3,
    "transparent: denoising the background changes nothing");
}

void TransferOpaque()
{
  Scene s(Volume());
  s.Opacity->RemoveAllPoints();
  s.Opacity->AddPoint(0, 1);
  s.Opacity->AddPoint(6, 1);
  s.Mapper->DenoiseOn();
  s.Mapper->GetExpertOptions()->DenoiserUseNetworkOff();
  s.Window->Render();
  s.ExpectQuiet("opaque transfer function");
  ExpectFrame(s, "opaque transfer function");
  const double covered = Mean(s.Pass("Alpha"));
  Check(covered > 0.1 && covered < 0.95, "opaque: the box covers part of the view");
  Check(AllFinite(s.Pass("Denoised")), "opaque: the denoised image is finite");
}

// No opacity points at all: VTK's table is 0, i.e. transparent (not an error).
void TransferEmpty()
{
  Scene s(Volume());
  s.Opacity->RemoveAllPoints();
  s.Color->RemoveAllPoints();
  s.Window->Render();
  s.ExpectQuiet("empty transfer functions");
  ExpectFrame(s, "empty transfer functions");
  Check(Mean(s.Pass("Alpha")) == 0.0, "empty transfer functions: transparent");
}

// One mapper through a series of bad inputs, then a good one: it renders as a fresh one would.
void Recovers()
{
  std::vector<float> fresh;
  {
    Scene s(Volume());
    s.Window->Render();
    fresh = s.Pass("Radiance");
  }
  Scene s(Volume());
  vtkNew<vtkImageData> empty;
  s.Mapper->SetInputData(empty);
  s.Window->Render();
  s.ExpectError("recovers: empty", { "empty volume" });
  auto zero = Volume();
  zero->SetSpacing(0, 1, 1);
  s.Mapper->SetInputData(zero);
  s.Window->Render();
  s.ExpectError("recovers: zero spacing", { "zero image spacing" });
  s.Mapper->SetInputData(Volume());
  s.Window->Render();
  s.ExpectQuiet("recovers: good input");
  Check(s.Pass("Radiance") == fresh, "recovers: same image as a fresh mapper");
}

// --- file cases -----------------------------------------------------------------------------

std::string WriteGoodVdb(const std::string& dir)
{
  const std::string file = dir + "/ptv_badinput_good.vdb";
  vtkNew<vtkPTVOpenVDBWriter> writer;
  writer->SetInputData(Volume(6, 5, 4));
  writer->SetFileName(file.c_str());
  Check(writer->Write() == 1, "writing the reference .vdb");
  return file;
}

std::vector<char> Bytes(const std::string& file)
{
  std::ifstream in(file, std::ios::binary);
  return std::vector<char>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void WriteBytes(const std::string& file, const std::vector<char>& bytes)
{
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// Reads @a file; returns whether it succeeded. Errors are observed, never printed as failures.
bool ReadVdb(const std::string& file, std::string& error, vtkIdType& points)
{
  vtkNew<vtkPTVOpenVDBReader> reader;
  vtkNew<vtkTest::ErrorObserver> observer;
  reader->AddObserver(vtkCommand::ErrorEvent, observer);
  reader->AddObserver(vtkCommand::WarningEvent, observer);
  reader->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, observer);
  reader->GetExecutive()->AddObserver(vtkCommand::WarningEvent, observer);
  reader->SetFileName(file.c_str());
  reader->Update();
  error = observer->GetErrorMessage();
  points = reader->GetOutput()->GetNumberOfPoints();
  return !observer->GetError();
}

void VdbZeroLength(const std::string& dir)
{
  const std::string file = dir + "/ptv_badinput_zero.vdb";
  WriteBytes(file, {});
  std::string error;
  vtkIdType points = 0;
  Check(!ReadVdb(file, error, points) && points == 0, "zero-length .vdb must fail, empty output");
  Check(error.find(file) != std::string::npos, "zero-length .vdb: the error names the file");
  Check(vtkPTVOpenVDBReader::CanReadFile(file.c_str()) == 0, "CanReadFile: zero-length");
}

void VdbHeaderOnly(const std::string& dir)
{
  const auto good = Bytes(WriteGoodVdb(dir));
  // Not 128 bytes: OpenVDB itself then allocates ~2.3 GB before failing (docs/reliability.md).
  for (std::size_t n : { 4, 8, 16, 64 })
  {
    const std::string file = dir + "/ptv_badinput_header" + std::to_string(n) + ".vdb";
    WriteBytes(file, std::vector<char>(good.begin(), good.begin() + std::min(n, good.size())));
    std::string error;
    vtkIdType points = 0;
    Check(!ReadVdb(file, error, points) && points == 0 && error.find(file) != std::string::npos,
      "first " + std::to_string(n) + " bytes of a .vdb: an error naming the file");
  }
}

void VdbUnwritable(const std::string& dir)
{
  // A folder in place of the file, and a read-only folder (when not root, which ignores modes).
  const std::string folder = dir + "/ptv_badinput_is_a_folder.vdb";
  vtksys::SystemTools::MakeDirectory(folder);
  vtkNew<vtkPTVOpenVDBWriter> writer;
  vtkNew<vtkTest::ErrorObserver> observer;
  writer->AddObserver(vtkCommand::ErrorEvent, observer);
  writer->SetInputData(Volume());
  writer->SetFileName(folder.c_str());
  Check(writer->Write() == 0, "writing onto a folder must fail");
  Check(observer->GetError() && observer->GetErrorMessage().find(folder) != std::string::npos,
    "writing onto a folder: the error names the path");
  Check(vtksys::SystemTools::FileIsDirectory(folder), "the folder is left alone");
  std::vector<std::string> left;
  vtksys::Directory listing;
  Check(listing.Load(dir).IsSuccess(), "list the temp folder");
  for (unsigned long i = 0; i < listing.GetNumberOfFiles(); ++i)
  {
    const std::string name = listing.GetFile(i);
    if (name.find("ptv_badinput_is_a_folder.vdb.tmp") == 0)
    {
      left.push_back(name);
    }
  }
  Check(left.empty(), "writing onto a folder: no temporary file may remain");
}
}

int TestPTVBadInput(int argc, char* argv[])
{
  const std::string dir = TempDir(argc, argv);
  const std::map<std::string, std::function<void()>> cases = {
    { "nan_voxels",
      [] { NonFiniteVoxels(std::numeric_limits<double>::quiet_NaN(), "NaN voxels"); } },
    { "inf_voxels",
      [] { NonFiniteVoxels(std::numeric_limits<double>::infinity(), "infinite voxels"); } },
    { "all_nonfinite", AllNonFinite },
    { "empty_volume", EmptyVolume },
    { "one_voxel", OneVoxel },
    { "multi_component", MultiComponent },
    { "scalar_types", ScalarTypes },
    { "bit_scalars", BitScalars },
    { "string_scalars", StringScalars },
    { "no_scalars", NoScalars },
    { "cell_scalars", CellScalars },
    { "wrong_tuple_count", WrongTupleCount },
    { "extreme_dims", ExtremeDims },
    { "zero_spacing", ZeroSpacing },
    { "negative_spacing", NegativeSpacing },
    { "nonfinite_geometry", NonFiniteGeometry },
    { "singular_matrix", SingularMatrix },
    { "camera_inside", CameraInside },
    { "zero_viewport", ZeroViewport },
    { "one_pixel_viewport", OnePixelViewport },
    { "tf_transparent", TransferTransparent },
    { "tf_opaque", TransferOpaque },
    { "tf_empty", TransferEmpty },
    { "recovers", Recovers },
    { "vdb_zero_length", [&dir] { VdbZeroLength(dir); } },
    { "vdb_header_only", [&dir] { VdbHeaderOnly(dir); } },
    { "vdb_unwritable", [&dir] { VdbUnwritable(dir); } },
  };
  const std::string name = CaseName(argc, argv);
  auto it = cases.find(name);
  if (it == cases.end())
  {
    std::cerr << "FAILED: unknown case '" << name << "'; cases:";
    for (const auto& c : cases)
    {
      std::cerr << " " << c.first;
    }
    std::cerr << "\n";
    return EXIT_FAILURE;
  }
  it->second();
  return TestResult();
}
