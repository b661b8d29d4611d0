// vtkPTVDenoiser's bilateral grid run alone on given guides (and its private CPU driver
// ptv::BilateralGridCpu):
//  (a) a constant image (constant radiance and albedo, random guides and weights) comes back
//      within 1e-6, for 1, 2 and 3 levels, clamp on and off;
//  (b) the output is bit-identical with 1, 2 and 3 threads;
//  (c) every invalid input is an error event naming the offending value, Execute returns false
//      and the output is left untouched; the object works again afterwards;
//  (d) 1x1 and 4097x3 images (with NaN/Inf/negative radiance) give finite output;
//  (e) repeated frames of one size allocate nothing: the driver's allocation counter stays
//      put and the output's "Denoised" array (and its memory) is reused; a grid keeps only
//      the range bins its pixels touch: guides of one value hold a zero column and two bins
//      per grid column of each row, below 1/8 of the dense grid's cells;
//  (f) the portable build of the row kernels (BilateralGridSettings::Portable, HWY_SCALAR here)
//      agrees with the dispatched one (AVX-512/AVX2/SSE4) within 1e-5 of the output range (the
//      dispatched build contracts multiply-adds into FMAs: one rounding less per term), and a
//      frame after a different frame equals the same frame on a fresh driver bit for bit (cells
//      a frame does not touch keep stale values that must never reach the result);
//  (g) the demodulation row kernel gives the scalar definition's pixels bit for bit on every
//      target (NaN, +-Inf, negative and huge values, rows of 1 to 37 pixels, with and without
//      albedo), and its luminance sum and lit count within float rounding of the scalar ones;
//  (h) the opacity riding along (Apply's alphaIn / alphaOut: one more float per finest-level
//      cell) equals a second Apply with one level on (alpha, alpha, alpha) as the radiance and
//      no demodulation or clamp -- within 8 roundings of 2^-24 (4.8e-7: the slice sums its eight
//      taps, each product and partial sum at most 1, in another order), for 1 and 3 levels, both builds of the kernels, 1 and 2 threads (bit-identical),
//      with NaN/Inf/negative opacities; the colour is bit-identical with and without it.
// The semantics themselves are checked against the torch reference and a brute-force evaluation
// of the definitions in Testing/Python/test_bilateral_grid.py.
#include "ptvTestCheck.h"
#include "ptvBilateralGridCpu.h"
#include "ptvGridDemodulateRows.h"
#include "Kernels/ptvBilateralGrid.h"
#include "vtkCommand.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPTVDenoiser.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkTestErrorObserver.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace
{

// A W x H x 1 image whose active scalars are a float array with the given values.
vtkSmartPointer<vtkImageData> MakeImage(
  int width, int height, int components, const std::vector<float>& values)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(width, height, 1);
  vtkNew<vtkFloatArray> array;
  array->SetName("values");
  array->SetNumberOfComponents(components);
  array->SetNumberOfTuples(static_cast<vtkIdType>(width) * height);
  std::memcpy(array->GetPointer(0), values.data(), values.size() * sizeof(float));
  image->GetPointData()->SetScalars(array);
  return image;
}

std::vector<float> Uniform(std::mt19937& rng, std::size_t n, float lo, float hi)
{
  std::uniform_real_distribution<float> dist(lo, hi);
  std::vector<float> v(n);
  for (float& x : v)
  {
    x = dist(rng);
  }
  return v;
}

struct Frame
{
  int Width = 0;
  int Height = 0;
  int Levels = 3;
  vtkSmartPointer<vtkImageData> Radiance, Albedo, Guides, Weights;
};

// Random HDR radiance with fireflies, albedo with zeros, guides in [0, 255], weights in [0, 1].
Frame RandomFrame(int width, int height, int levels, unsigned seed)
{
  std::mt19937 rng(seed);
  const std::size_t n = static_cast<std::size_t>(width) * height;
  std::vector<float> radiance = Uniform(rng, 3 * n, 0.f, 2.f);
  std::vector<float> albedo = Uniform(rng, 3 * n, 0.f, 1.f);
  for (std::size_t p = 0; p < n; p += 37)
  {
    radiance[3 * p] *= 1000.f;
    albedo[3 * p + 1] = 0.f;
  }
  Frame f;
  f.Width = width;
  f.Height = height;
  f.Levels = levels;
  f.Radiance = MakeImage(width, height, 3, radiance);
  f.Albedo = MakeImage(width, height, 3, albedo);
  f.Guides = MakeImage(width, height, levels, Uniform(rng, levels * n, 0.f, 255.f));
  if (levels > 1)
  {
    f.Weights = MakeImage(width, height, levels - 1, Uniform(rng, (levels - 1) * n, 0.f, 1.f));
  }
  return f;
}

// The grid alone: the images by name (Albedo: demodulate; nullptr removes one), Execute().
bool Apply(vtkPTVDenoiser* grid, vtkImageData* radiance, vtkImageData* albedo,
  vtkImageData* guides, vtkImageData* weights)
{
  grid->SetImage("Radiance", radiance);
  grid->SetImage("Albedo", albedo);
  grid->SetImage("Guides", guides);
  grid->SetImage("BlendWeights", weights);
  return grid->Execute();
}

const float* Output(vtkImageData* image)
{
  vtkFloatArray* a = vtkFloatArray::SafeDownCast(image->GetPointData()->GetArray("Denoised"));
  return a ? a->GetPointer(0) : nullptr;
}

bool AllFinite(vtkImageData* image, std::size_t n)
{
  const float* out = Output(image);
  if (!out)
  {
    return false;
  }
  for (std::size_t i = 0; i < 3 * n; ++i)
  {
    if (!std::isfinite(out[i]))
    {
      return false;
    }
  }
  return true;
}

//------------------------------------------------------------------------------
void TestConstantImage()
{
  const int width = 53;
  const int height = 41;
  const std::size_t n = static_cast<std::size_t>(width) * height;
  const float colour[3] = { 0.3f, 0.6f, 0.9f };
  const float albedoColour[3] = { 0.2f, 0.f, 0.8f };
  std::vector<float> radiance(3 * n);
  std::vector<float> albedo(3 * n);
  for (std::size_t p = 0; p < n; ++p)
  {
    for (int c = 0; c < 3; ++c)
    {
      radiance[3 * p + c] = colour[c];
      albedo[3 * p + c] = albedoColour[c];
    }
  }
  std::mt19937 rng(7);
  for (int levels = 1; levels <= 3; ++levels)
  {
    for (double clamp : { 8.0, 0.0 })
    {
      vtkNew<vtkPTVDenoiser> grid;
      grid->SetClamp(clamp);
      vtkImageData* output = grid->GetOutput();
      auto guides = MakeImage(width, height, levels, Uniform(rng, levels * n, 0.f, 255.f));
      auto weights = levels > 1
        ? MakeImage(width, height, levels - 1, Uniform(rng, (levels - 1) * n, 0.f, 1.f))
        : nullptr;
      const bool ok = Apply(grid, MakeImage(width, height, 3, radiance),
        MakeImage(width, height, 3, albedo), guides, weights);
      const std::string label =
        "constant image, " + std::to_string(levels) + " levels, clamp " + std::to_string(clamp);
      Check(ok, label + ": Execute must succeed");
      const float* out = Output(output);
      Check(out != nullptr, label + ": \"Denoised\" array");
      if (!out)
      {
        continue;
      }
      double worst = 0.0;
      for (std::size_t i = 0; i < 3 * n; ++i)
      {
        worst = std::max(worst, std::fabs(static_cast<double>(out[i]) - radiance[i]));
      }
      Check(worst <= 1e-6, label + ": max error " + std::to_string(worst) + " > 1e-6");
      Check(output->GetPointData()->GetScalars() ==
          output->GetPointData()->GetArray("Denoised"),
        label + ": \"Denoised\" must be the active scalars");
      int dims[3];
      output->GetDimensions(dims);
      Check(dims[0] == width && dims[1] == height && dims[2] == 1, label + ": dimensions");
    }
  }
}

//------------------------------------------------------------------------------
void TestThreadsBitIdentical()
{
  for (int levels : { 1, 3 })
  {
    Frame f = RandomFrame(129, 77, levels, 11);
    const std::size_t n = static_cast<std::size_t>(f.Width) * f.Height;
    std::vector<float> reference;
    for (int threads : { 1, 2, 3 })
    {
      vtkNew<vtkPTVDenoiser> grid;
      grid->SetNumberOfThreads(threads);
      vtkImageData* output = grid->GetOutput();
      Check(Apply(grid, f.Radiance, f.Albedo, f.Guides, f.Weights),
        "threads: Execute must succeed");
      const float* out = Output(output);
      if (!out)
      {
        Check(false, "threads: no output");
        continue;
      }
      if (reference.empty())
      {
        reference.assign(out, out + 3 * n);
        continue;
      }
      Check(std::memcmp(reference.data(), out, 3 * n * sizeof(float)) == 0,
        std::to_string(levels) + " levels: " + std::to_string(threads) +
          " threads must be bit-identical to 1 thread");
    }
  }
}

// (f) portable vs dispatched kernels; no trace of an earlier frame.
void TestPortableKernelsAndReuse()
{
  auto data = [](vtkImageData* image)
  { return vtkFloatArray::SafeDownCast(image->GetPointData()->GetScalars())->GetPointer(0); };
  for (int levels : { 1, 3 })
  {
    Frame f = RandomFrame(131, 79, levels, 21);
    Frame other = RandomFrame(131, 79, levels, 22);
    const std::size_t n = static_cast<std::size_t>(f.Width) * f.Height;
    ptv::BilateralGridSettings settings;
    settings.Levels = levels;
    settings.Threads = 2;
    std::vector<float> dispatched(3 * n), portable(3 * n), fresh(3 * n);
    const float* weights = levels > 1 ? data(f.Weights) : nullptr;
    ptv::BilateralGridCpu reused;
    reused.Apply(settings, f.Width, f.Height, data(other.Radiance), data(other.Albedo),
      data(other.Guides), levels > 1 ? data(other.Weights) : nullptr, dispatched.data());
    reused.Apply(settings, f.Width, f.Height, data(f.Radiance), data(f.Albedo), data(f.Guides),
      weights, dispatched.data());
    const std::string target = reused.GetLastKernelTarget();
    ptv::BilateralGridCpu first;
    first.Apply(settings, f.Width, f.Height, data(f.Radiance), data(f.Albedo), data(f.Guides),
      weights, fresh.data());
    Check(std::memcmp(fresh.data(), dispatched.data(), 3 * n * sizeof(float)) == 0,
      std::to_string(levels) + " levels: a frame after another must equal it on a fresh driver");
    settings.Portable = true;
    ptv::BilateralGridCpu baseline;
    baseline.Apply(settings, f.Width, f.Height, data(f.Radiance), data(f.Albedo),
      data(f.Guides), weights, portable.data());
    const std::string portableTarget = baseline.GetLastKernelTarget();
    Check(portableTarget == "SCALAR" || portableTarget == "EMU128",
      "portable kernels run the baseline target, got " + portableTarget);
    float lo = dispatched[0], hi = dispatched[0];
    double worst = 0.0;
    for (std::size_t i = 0; i < 3 * n; ++i)
    {
      lo = std::min(lo, dispatched[i]);
      hi = std::max(hi, dispatched[i]);
      worst = std::max(worst, std::fabs(static_cast<double>(dispatched[i]) - portable[i]));
    }
    const double span = static_cast<double>(hi) - lo;
    std::cout << levels << " levels: kernels " << target << " vs " << portableTarget
              << ", max difference " << worst << " (range " << span << ")\n";
    Check(span > 0 && worst <= 1e-5 * span,
      std::to_string(levels) + " levels: portable and dispatched kernels differ by " +
        std::to_string(worst) + " (range " + std::to_string(span) + ")");
  }
}

//------------------------------------------------------------------------------
struct ErrorCase
{
  std::string Label;
  std::vector<std::string> Needles;
};

// Execute on @a grid with these images, expecting failure with an error naming @a needles and
// an untouched output.
void ExpectError(vtkPTVDenoiser* grid, vtkTest::ErrorObserver* observer, const ErrorCase& c,
  vtkImageData* radiance, vtkImageData* albedo, vtkImageData* guides, vtkImageData* weights)
{
  vtkImageData* output = grid->GetOutput();
  int dimsBefore[3];
  output->GetDimensions(dimsBefore);
  const vtkMTimeType mtime = output->GetMTime();
  const int arrays = output->GetPointData()->GetNumberOfArrays();
  observer->Clear();
  const bool ok = Apply(grid, radiance, albedo, guides, weights);
  Check(!ok, c.Label + ": Execute must return false");
  Check(observer->GetError(), c.Label + ": an error must be reported");
  // The message text only, without VTK's "ERROR: In <file>" line (ctest fails on that).
  const std::string text = observer->GetErrorMessage();
  std::string first = text.substr(text.find('\n') + 1);
  first = first.substr(0, first.find('\n'));
  for (const std::string& needle : c.Needles)
  {
    Check(first.find(needle) != std::string::npos,
      c.Label + ": the error must mention \"" + needle + "\"; got: " + first);
  }
  int dims[3];
  output->GetDimensions(dims);
  Check(dims[0] == dimsBefore[0] && dims[1] == dimsBefore[1] && dims[2] == dimsBefore[2] &&
      output->GetMTime() == mtime && output->GetPointData()->GetNumberOfArrays() == arrays,
    c.Label + ": the output must be untouched");
  std::cout << c.Label << ": reported as expected: " << first << "\n";
  observer->Clear();
}

void TestErrors()
{
  vtkNew<vtkPTVDenoiser> grid;
  vtkNew<vtkTest::ErrorObserver> observer;
  grid->AddObserver(vtkCommand::ErrorEvent, observer);
  grid->AddObserver(vtkCommand::WarningEvent, observer);

  const int w = 12;
  const int h = 7;
  Frame f = RandomFrame(w, h, 3, 3);
  // A previous result in the output, so "untouched" is meaningful.
  Check(Apply(grid, f.Radiance, f.Albedo, f.Guides, f.Weights), "errors: first Execute");
  const std::size_t n = static_cast<std::size_t>(w) * h;

  ExpectError(grid, observer, { "no radiance", { "No Radiance image" } }, nullptr, f.Albedo,
    f.Guides, f.Weights);
  ExpectError(grid, observer, { "no weights", { "3 levels of 'Guides' need 'BlendWeights'" } },
    f.Radiance, f.Albedo, f.Guides, nullptr);
  ExpectError(grid, observer, { "weights without guides", { "'BlendWeights' is set without" } },
    f.Radiance, f.Albedo, nullptr, f.Weights);

  vtkNew<vtkImageData> empty;
  ExpectError(grid, observer, { "zero-size radiance", { "'Radiance'", "W x H x 1", "0 x 0 x 0" } },
    empty, f.Albedo, f.Guides, f.Weights);
  auto emptyWithArray = vtkSmartPointer<vtkImageData>::New();
  emptyWithArray->SetExtent(0, -1, 0, -1, 0, 0);
  ExpectError(grid, observer, { "zero-size albedo", { "'Albedo'", "W x H x 1", "0 x 0 x 1" } },
    f.Radiance, emptyWithArray, f.Guides, f.Weights);

  auto volume = vtkSmartPointer<vtkImageData>::New();
  volume->SetDimensions(w, h, 2);
  volume->AllocateScalars(VTK_FLOAT, 3);
  ExpectError(grid, observer, { "3D radiance", { "'Radiance'", "W x H x 1", "12 x 7 x 2" } },
    volume, f.Albedo, f.Guides, f.Weights);

  auto wider = MakeImage(w + 1, h, 3, std::vector<float>(3 * (w + 1) * h, 0.5f));
  ExpectError(grid, observer, { "albedo size", { "'Albedo'", "13 x 7", "12 x 7" } }, f.Radiance,
    wider, f.Guides, f.Weights);
  auto taller = MakeImage(w, h + 2, 2, std::vector<float>(2 * w * (h + 2), 0.5f));
  ExpectError(grid, observer, { "weights size", { "'BlendWeights'", "12 x 9", "12 x 7" } },
    f.Radiance, f.Albedo, f.Guides, taller);

  auto rgba = MakeImage(w, h, 4, std::vector<float>(4 * n, 0.5f));
  ExpectError(grid, observer, { "radiance components", { "'Radiance'", "4 components", "3" } },
    rgba, f.Albedo, f.Guides, f.Weights);
  auto twoGuides = MakeImage(w, h, 2, std::vector<float>(2 * n, 10.f));
  ExpectError(grid, observer,
    { "guide/weight components", { "'BlendWeights' has 2 components", "need 1" } }, f.Radiance,
    f.Albedo, twoGuides, f.Weights);
  auto fourGuides = MakeImage(w, h, 4, std::vector<float>(4 * n, 10.f));
  ExpectError(grid, observer, { "four guides", { "'Guides' has 4 components", "1 to 3" } },
    f.Radiance, f.Albedo, fourGuides, nullptr);
  auto oneWeight = MakeImage(w, h, 1, std::vector<float>(n, 0.5f));
  ExpectError(grid, observer,
    { "weight components", { "'BlendWeights' has 1 components", "need 2" } }, f.Radiance,
    f.Albedo, f.Guides, oneWeight);
  grid->SetNumberOfLevels(1);
  ExpectError(grid, observer,
    { "levels vs guides", { "'Guides' has 3 components but NumberOfLevels is 1" } }, f.Radiance,
    f.Albedo, f.Guides, f.Weights);
  grid->SetNumberOfLevels(0);

  auto doubles = vtkSmartPointer<vtkImageData>::New();
  doubles->SetDimensions(w, h, 1);
  doubles->AllocateScalars(VTK_DOUBLE, 3);
  doubles->GetPointData()->GetScalars()->SetName("rgb64");
  ExpectError(grid, observer, { "double albedo", { "'Albedo'", "rgb64", "double", "float" } },
    f.Radiance, doubles, f.Guides, f.Weights);

  auto noScalars = vtkSmartPointer<vtkImageData>::New();
  noScalars->SetDimensions(w, h, 1);
  ExpectError(grid, observer, { "no scalars", { "'Guides'", "no point array" } }, f.Radiance,
    f.Albedo, noScalars, f.Weights);

  auto shortArray = vtkSmartPointer<vtkImageData>::New();
  shortArray->SetDimensions(w, h, 1);
  vtkNew<vtkFloatArray> few;
  few->SetNumberOfComponents(3);
  few->SetNumberOfTuples(5);
  shortArray->GetPointData()->SetScalars(few);
  ExpectError(grid, observer, { "short array", { "'Radiance'", "5 tuples", "12 x 7" } },
    shortArray, f.Albedo, f.Guides, f.Weights);

  // Invalid level indices of the per-level settings.
  observer->Clear();
  grid->SetSpatialStep(3, 4);
  Check(observer->GetError() &&
      observer->GetErrorMessage().find("level 3 is out of range") != std::string::npos,
    "SetSpatialStep(3): error naming the level");
  observer->Clear();
  Check(grid->GetRangeStep(-1) == 0 && observer->GetError(), "GetRangeStep(-1): error, 0");
  observer->Clear();
  grid->SetRangeStep(0, 0);
  Check(grid->GetRangeStep(0) == 1 && !observer->GetError(), "SetRangeStep clamps to 1");
  grid->SetSpatialStep(0, 100000);
  Check(grid->GetSpatialStep(0) == 256, "SetSpatialStep clamps to 256");
  grid->SetSpatialStep(0, 4);
  grid->SetRangeStep(0, 4);

  // One level: no weights; the object works again after the errors.
  auto oneGuide = MakeImage(w, h, 1, std::vector<float>(n, 100.f));
  observer->Clear();
  Check(Apply(grid, f.Radiance, f.Albedo, oneGuide, nullptr) && !observer->GetError(),
    "one level without weights must succeed after the errors");
  Check(AllFinite(grid->GetOutput(), n), "one level without weights: finite output");
}

//------------------------------------------------------------------------------
void TestOddSizesFinite()
{
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (auto size : { std::pair<int, int>(1, 1), std::pair<int, int>(4097, 3),
         std::pair<int, int>(3, 4097) })
  {
    for (int levels : { 1, 3 })
    {
      Frame f = RandomFrame(size.first, size.second, levels, 5);
      const std::size_t n = static_cast<std::size_t>(size.first) * size.second;
      float* radiance = vtkFloatArray::SafeDownCast(f.Radiance->GetPointData()->GetScalars())
                          ->GetPointer(0);
      const float bad[] = { nan, inf, -inf, -1.f, 3e38f };
      for (std::size_t i = 0; i < 3 * n; i += 7)
      {
        radiance[i] = bad[(i / 7) % 5];
      }
      vtkNew<vtkPTVDenoiser> grid;
      grid->SetNumberOfThreads(2);
      const std::string label = std::to_string(size.first) + "x" +
        std::to_string(size.second) + ", " + std::to_string(levels) + " levels";
      Check(Apply(grid, f.Radiance, f.Albedo, f.Guides, f.Weights),
        label + ": Execute must succeed");
      Check(AllFinite(grid->GetOutput(), n), label + ": output must be finite");
    }
  }
}

//------------------------------------------------------------------------------
void TestNoAllocationGrowth()
{
  // The driver: buffers are (re)allocated on the first frame and on size changes only.
  Frame f = RandomFrame(200, 150, 3, 9);
  auto data = [](vtkImageData* image)
  { return vtkFloatArray::SafeDownCast(image->GetPointData()->GetScalars())->GetPointer(0); };
  ptv::BilateralGridCpu cpu;
  ptv::BilateralGridSettings settings;
  settings.Threads = 2;
  std::vector<float> out(3 * 200 * 150);
  cpu.Apply(settings, 200, 150, data(f.Radiance), data(f.Albedo), data(f.Guides),
    data(f.Weights), out.data());
  const std::size_t first = cpu.GetAllocationCount();
  Check(first > 0, "driver: the first frame allocates");
  for (int i = 0; i < 5; ++i)
  {
    cpu.Apply(settings, 200, 150, data(f.Radiance), data(f.Albedo), data(f.Guides),
      data(f.Weights), out.data());
  }
  Check(cpu.GetAllocationCount() == first,
    "driver: repeated frames of one size must not allocate (" + std::to_string(first) + " -> " +
      std::to_string(cpu.GetAllocationCount()) + ")");
  Frame small = RandomFrame(100, 150, 3, 9);
  cpu.Apply(settings, 100, 150, data(small.Radiance), data(small.Albedo), data(small.Guides),
    data(small.Weights), out.data());
  const std::size_t resized = cpu.GetAllocationCount();
  Check(resized > first, "driver: a new size reallocates");
  cpu.Apply(settings, 100, 150, data(small.Radiance), data(small.Albedo), data(small.Guides),
    data(small.Weights), out.data());
  Check(cpu.GetAllocationCount() == resized, "driver: stable again after a size change");

  // Sparse cells: with every guide 100.5 (one bin pair per column) the three levels hold
  // per row a zero column (Bins cells) and two bins of each inner column (4 floats a cell).
  float* guides = data(f.Guides);
  std::fill(guides, guides + 3 * 200 * 150, 100.5f);
  cpu.Apply(settings, 200, 150, data(f.Radiance), data(f.Albedo), data(f.Guides),
    data(f.Weights), out.data());
  std::size_t expected = 0, dense = 0;
  for (int l = 0; l < 3; ++l)
  {
    const ptv::GridLevel g = ptv::LevelGeometry(settings, l, 200, 150);
    const std::size_t rows = g.Height + 2, bins = g.Depth + 1, columns = g.Width + 2;
    expected += 16 * (rows * bins + g.Height * 2 * g.Width);
    dense += 16 * rows * columns * bins;
  }
  Check(cpu.GetCellBytes() == expected && 8 * expected < dense,
    "sparse cells: one guide value holds " + std::to_string(cpu.GetCellBytes()) +
      " bytes of cells (expected " + std::to_string(expected) + ", dense " +
      std::to_string(dense) + ")");

  // The VTK class: the output's "Denoised" array and its memory are reused.
  vtkNew<vtkPTVDenoiser> grid;
  vtkImageData* output = grid->GetOutput();
  Check(Apply(grid, f.Radiance, f.Albedo, f.Guides, f.Weights), "reuse: first Execute");
  vtkDataArray* array = output->GetPointData()->GetArray("Denoised");
  const float* memory = Output(output);
  vtkMTimeType mtime = output->GetMTime();
  for (int i = 0; i < 3; ++i)
  {
    Check(Apply(grid, f.Radiance, f.Albedo, f.Guides, f.Weights), "reuse: Execute");
  }
  Check(output->GetPointData()->GetArray("Denoised") == array && Output(output) == memory,
    "reuse: the \"Denoised\" array must be reused for the same size");
  Check(output->GetMTime() > mtime, "reuse: the output must be marked modified");
  Check(output->GetPointData()->GetNumberOfArrays() == 1, "reuse: one array in the output");
  std::cout << "timings 200x150, 3 levels (ms): demodulate + splat " << grid->GetLastSplatTime()
            << ", slice " << grid->GetLastSliceTime() << "\n";
}
}

// (g) the demodulation row kernel against the scalar definitions.
void TestDemodulateRows()
{
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> uniform(-0.5f, 3.0f);
  const float specials[] = { std::numeric_limits<float>::quiet_NaN(),
    std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(), -1.0f,
    0.0f, 3e38f, 1e31f, 1e-30f };
  int mismatches = 0;
  double worstSum = 0.0;
  for (int width = 1; width <= 37; ++width)
  {
    std::vector<float> radiance(3 * width), albedo(3 * width);
    for (int i = 0; i < 3 * width; ++i)
    {
      radiance[i] = rng() % 5 == 0 ? specials[rng() % 8] : uniform(rng);
      albedo[i] = rng() % 5 == 0 ? specials[rng() % 8] : uniform(rng) / 3.0f;
    }
    for (bool demodulate : { false, true })
    {
      const float* a = demodulate ? albedo.data() : nullptr;
      double sum = 0.0;
      std::size_t lit = 0;
      std::vector<float> expected(4 * width);
      for (int x = 0; x < width; ++x)
      {
        const ptv::Vec3 d = ptv::Demodulate(radiance.data() + 3 * x, a ? a + 3 * x : nullptr);
        const float cell[4] = { d.x, d.y, d.z, 1.0f };
        std::copy(cell, cell + 4, expected.data() + 4 * x);
        const float lum = ptv::Luminance(d);
        sum += lum;
        lit += lum > 0.f ? 1 : 0;
      }
      for (bool portable : { false, true })
      {
        std::vector<float> got(4 * width + 1, -7.0f); // one sentinel past the row
        const ptv::DemodulatedRow row =
          ptv::DemodulateRow(radiance.data(), a, width, got.data(), portable);
        mismatches += std::memcmp(got.data(), expected.data(), 4 * width * sizeof(float)) != 0;
        Check(got[4 * width] == -7.0f, "demodulate: wrote past the row");
        Check(row.Lit == lit, "demodulate: lit count " + std::to_string(row.Lit) + ", expected " +
            std::to_string(lit));
        // Summed in another order: each of the <= 37 float terms rounds once more, at most.
        const double err = std::fabs(row.Luminance - sum);
        worstSum = std::max(worstSum, err / std::max(sum, 1e-30));
        Check(err <= 37 * 6e-8 * std::max(std::fabs(sum), 1e-30) + 1e-30,
          "demodulate: luminance sum " + std::to_string(row.Luminance) + ", expected " +
            std::to_string(sum));
      }
    }
  }
  std::cout << "demodulate rows: " << mismatches << " rows differ from the scalar definition; "
            << "worst relative luminance-sum difference " << worstSum << "\n";
  Check(mismatches == 0, "demodulate: pixels differ from the scalar definition");
}

// (h) the opacity beside the colour against a separate one-level pass over (a, a, a).
void TestOpacityAlongside()
{
  const int w = 203, h = 77;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  auto data = [](vtkImageData* image)
  { return vtkFloatArray::SafeDownCast(image->GetPointData()->GetScalars())->GetPointer(0); };
  std::mt19937 rng(11);
  std::vector<float> alpha = Uniform(rng, n, 0.f, 1.f);
  const float specials[] = { std::numeric_limits<float>::quiet_NaN(),
    std::numeric_limits<float>::infinity(), -1.f, 0.f, 1.f };
  for (std::size_t p = 0; p < n; p += 13)
  {
    alpha[p] = specials[(p / 13) % 5];
  }
  std::vector<float> rgb(3 * n);
  for (std::size_t p = 0; p < n; ++p)
  {
    rgb[3 * p] = rgb[3 * p + 1] = rgb[3 * p + 2] = alpha[p];
  }
  double worst = 0.0;
  for (int levels : { 1, 3 })
  {
    Frame f = RandomFrame(w, h, levels, 21 + levels);
    std::vector<float> fine(n);
    for (std::size_t p = 0; p < n; ++p)
    {
      fine[p] = data(f.Guides)[p * levels];
    }
    for (bool portable : { false, true })
    {
      ptv::BilateralGridSettings settings;
      settings.Levels = levels;
      settings.Portable = portable;
      std::vector<float> plain(3 * n), out[2], got[2];
      for (int t = 0; t < 2; ++t)
      {
        settings.Threads = t + 1;
        ptv::BilateralGridCpu cpu;
        out[t].resize(3 * n);
        got[t].assign(n, -7.f);
        cpu.Apply(settings, w, h, data(f.Radiance), data(f.Albedo), data(f.Guides),
          f.Weights ? data(f.Weights) : nullptr, out[t].data(), alpha.data(), got[t].data());
        if (t == 0)
        {
          cpu.Apply(settings, w, h, data(f.Radiance), data(f.Albedo), data(f.Guides),
            f.Weights ? data(f.Weights) : nullptr, plain.data());
        }
      }
      const std::string what =
        std::to_string(levels) + " level(s), " + (portable ? "portable" : "dispatched");
      Check(out[0] == plain, "opacity: the colour must not change with it, " + what);
      Check(out[0] == out[1] && got[0] == got[1], "opacity: 1 vs 2 threads differ, " + what);
      ptv::BilateralGridSettings one = settings;
      one.Levels = 1;
      one.Clamp = 0.0;
      one.Threads = 1;
      std::vector<float> separate(3 * n);
      ptv::BilateralGridCpu cpu;
      cpu.Apply(one, w, h, rgb.data(), nullptr, fine.data(), nullptr, separate.data());
      for (std::size_t p = 0; p < n; ++p)
      {
        const double d = std::fabs(static_cast<double>(got[0][p]) - separate[3 * p]);
        worst = std::max(worst, std::isfinite(got[0][p]) ? d : 1e9);
      }
    }
  }
  std::cout << "opacity alongside the colour: worst |fused - separate pass| " << worst << "\n";
  Check(worst <= 8 * 5.97e-8, "opacity: differs from a separate pass by " + std::to_string(worst));
}

int TestPTVBilateralGrid(int, char*[])
{
  TestConstantImage();
  TestThreadsBitIdentical();
  TestErrors();
  TestOddSizesFinite();
  TestNoAllocationGrowth();
  TestPortableKernelsAndReuse();
  TestDemodulateRows();
  TestOpacityAlongside();
  if (failures)
  {
    std::cerr << failures << " check(s) failed\n";
    return EXIT_FAILURE;
  }
  std::cout << "all checks passed\n";
  return EXIT_SUCCESS;
}
