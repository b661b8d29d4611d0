// Every shipped preset file loads; the paper's two-band presets are exact boxes (opacity 0.7
// with colour (1,1,0) in the outer band, 1.0 with (1,1,1) in the inner band, 0 elsewhere);
// malformed files and unknown names give errors that name the problem.
#include "ptvTestCheck.h"
#include "vtkColorTransferFunction.h"
#include "vtkCommand.h"
#include "vtkNew.h"
#include "vtkPTVTransferFunctionPreset.h"
#include "vtkPiecewiseFunction.h"
#include "vtkTestErrorObserver.h"
#include "vtkVolumeProperty.h"
#include "vtksys/Directory.hxx"
#include "vtksys/SystemTools.hxx"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>

namespace
{

// Check a two-band preset: sample the opacity function densely; every sample is 0, 0.7 or 1.0
// except within a tiny edge width; 0.7 samples are yellow, 1.0 samples white.
void CheckTwoBand(vtkPTVTransferFunctionPreset* presets, const std::string& name)
{
  vtkNew<vtkColorTransferFunction> color;
  vtkNew<vtkPiecewiseFunction> opacity;
  Check(presets->ApplyPreset(name.c_str(), color, opacity), "apply " + name);
  double range[2];
  opacity->GetRange(range);
  const int n = 20000;
  int outer = 0, inner = 0, zero = 0, edge = 0;
  for (int i = 0; i <= n; ++i)
  {
    const double dx = (range[1] - range[0]) / n;
    const double x = range[0] + dx * i;
    const double a = opacity->GetValue(x);
    double rgb[3];
    color->GetColor(x, rgb);
    // On a band edge the ramp can pass through 0.7 exactly: only plateau samples (same opacity
    // one sample to either side) count as band samples.
    const bool plateau = std::abs(opacity->GetValue(x - dx) - a) < 1e-9 &&
      std::abs(opacity->GetValue(x + dx) - a) < 1e-9;
    if (!plateau && a != 0.0)
    {
      ++edge;
    }
    else if (std::abs(a - 0.7) < 1e-9)
    {
      ++outer;
      Check(std::abs(rgb[0] - 1) + std::abs(rgb[1] - 1) + std::abs(rgb[2]) < 1e-6,
        name + ": outer band colour must be (1,1,0) at x=" + std::to_string(x));
    }
    else if (std::abs(a - 1.0) < 1e-9)
    {
      ++inner;
      Check(std::abs(rgb[0] - 1) + std::abs(rgb[1] - 1) + std::abs(rgb[2] - 1) < 1e-6,
        name + ": inner band colour must be (1,1,1) at x=" + std::to_string(x));
    }
    else if (a == 0.0)
    {
      ++zero;
    }
    else
    {
      ++edge;
    }
  }
  std::cout << name << ": outer " << outer << " inner " << inner << " transparent " << zero
            << " edge " << edge << " of " << n + 1 << " samples\n";
  Check(outer > n / 100 && inner > n / 100 && zero > n / 100, name + ": all three bands present");
  Check(edge < n / 200, name + ": band edges must be sharp (box-shaped), got " +
      std::to_string(edge) + " intermediate samples");
}
}

int TestPTVTransferFunctionPreset(int argc, char* argv[])
{
  const std::string dir = vtkPTVTransferFunctionPreset::GetDefaultPresetDirectory();
  vtksys::Directory listing;
  Check(static_cast<bool>(listing.Load(dir)), "preset directory " + dir + " readable");
  int files = 0, twoBands = 0;
  for (unsigned long i = 0; i < listing.GetNumberOfFiles(); ++i)
  {
    const std::string file = listing.GetFile(i);
    if (vtksys::SystemTools::GetFilenameLastExtension(file) != ".json")
    {
      continue;
    }
    ++files;
    vtkNew<vtkPTVTransferFunctionPreset> presets;
    presets->SetFileName((dir + "/" + file).c_str());
    Check(presets->Load(), "load " + file);
    Check(presets->GetNumberOfPresets() >= 2, file + " holds a two-band and a smooth preset");
    for (int p = 0; p < presets->GetNumberOfPresets(); ++p)
    {
      const std::string name = presets->GetPresetName(p);
      vtkNew<vtkVolumeProperty> property;
      Check(presets->ApplyPreset(name.c_str(), property), "apply to property " + name);
      if (name.find("Two-Band") != std::string::npos)
      {
        ++twoBands;
        CheckTwoBand(presets, name);
      }
    }
  }
  Check(files >= 3, "at least one preset file per dataset (head, stent, concrete)");
  Check(twoBands >= 3, "a two-band preset per dataset");

  // Error cases, observed (not printed).
  std::string tempDir = vtksys::SystemTools::GetCurrentWorkingDirectory();
  for (int i = 1; i + 1 < argc; ++i)
  {
    if (std::string(argv[i]) == "-T")
    {
      tempDir = argv[i + 1];
    }
  }
  vtkNew<vtkTest::ErrorObserver> errors;
  vtkNew<vtkPTVTransferFunctionPreset> bad;
  bad->AddObserver(vtkCommand::ErrorEvent, errors);

  bad->SetFileName((tempDir + "/no-such-preset.json").c_str());
  Check(!bad->Load(), "missing file fails");
  Check(errors->CheckErrorMessage("no-such-preset.json") == 0, "missing-file error names it");

  const std::string malformed = tempDir + "/malformed-preset.json";
  std::ofstream(malformed) << "[{\"Name\": \"x\", \"RGBPoints\": [0, 1, 1]}]";
  bad->SetFileName(malformed.c_str());
  Check(!bad->Load(), "RGBPoints of wrong length fails");
  Check(errors->CheckErrorMessage("RGBPoints") == 0, "error names the field");

  std::ofstream(malformed) << "[{\"Name\": ";
  Check(!bad->Load(), "truncated JSON fails");
  Check(errors->CheckErrorMessage("Malformed JSON") == 0, "error says malformed");

  std::ofstream(malformed) << "[{\"Name\": \"ok\", \"RGBPoints\": [0, 1, 1, 1]}]";
  Check(bad->Load() && bad->GetNumberOfPresets() == 1, "minimal preset loads");
  vtkNew<vtkColorTransferFunction> c;
  Check(!bad->ApplyPreset("nope", c, nullptr), "unknown preset fails");
  Check(errors->CheckErrorMessage("'nope'") == 0, "unknown-preset error names it");
  Check(bad->GetPresetName(5) == nullptr, "out-of-range index gives nullptr");

  return TestResult();
}
