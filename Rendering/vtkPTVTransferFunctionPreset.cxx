#include "vtkPTVTransferFunctionPreset.h"

#include "ptvDataDirectory.h"

#include "vtkColorTransferFunction.h"
#include "vtkObjectFactory.h"
#include "vtkPiecewiseFunction.h"
#include "vtkVolumeProperty.h"
#include "vtksys/SystemTools.hxx"

#include "vtk_jsoncpp.h"

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>


namespace
{
struct Preset
{
  std::string Name;
  std::string ColorSpace = "RGB";
  std::vector<double> RGBPoints; // x r g b
  std::vector<double> Points;    // x y midpoint sharpness
};
}

struct vtkPTVTransferFunctionPreset::vtkInternals
{
  std::vector<Preset> Presets;

  const Preset* Find(const char* name) const
  {
    if (name)
    {
      for (const auto& p : this->Presets)
      {
        if (p.Name == name)
        {
          return &p;
        }
      }
    }
    return nullptr;
  }
};

vtkStandardNewMacro(vtkPTVTransferFunctionPreset);

//------------------------------------------------------------------------------
vtkPTVTransferFunctionPreset::vtkPTVTransferFunctionPreset()
  : Internals(new vtkInternals)
{
}

//------------------------------------------------------------------------------
vtkPTVTransferFunctionPreset::~vtkPTVTransferFunctionPreset()
{
  this->SetFileName(nullptr);
}

//------------------------------------------------------------------------------
std::string vtkPTVTransferFunctionPreset::GetDefaultPresetDirectory()
{
  return ptv::DataDirectory() + "/TransferFunctions";
}

//------------------------------------------------------------------------------
bool vtkPTVTransferFunctionPreset::Load()
{
  if (!this->FileName || !*this->FileName)
  {
    vtkErrorMacro(<< "No FileName set.");
    return false;
  }
  std::ifstream in(this->FileName);
  if (!in)
  {
    vtkErrorMacro(<< "Cannot open preset file '" << this->FileName << "'.");
    return false;
  }
  Json::Value root;
  Json::CharReaderBuilder builder;
  std::string errors;
  if (!Json::parseFromStream(builder, in, &root, &errors))
  {
    vtkErrorMacro(<< "Malformed JSON in '" << this->FileName << "': " << errors);
    return false;
  }
  if (!root.isArray())
  {
    vtkErrorMacro(<< "'" << this->FileName << "' must hold a JSON list of presets.");
    return false;
  }

  auto readNumbers = [this](const Json::Value& preset, const char* field, std::size_t stride,
                       const std::string& name, std::vector<double>& out) -> bool
  {
    const Json::Value& v = preset[field];
    if (!v.isArray() || v.size() == 0 || v.size() % stride != 0)
    {
      vtkErrorMacro(<< "Preset '" << name << "' in '" << this->FileName << "': field '" << field
                    << "' must be a non-empty list of numbers whose length is a multiple of "
                    << stride << ".");
      return false;
    }
    for (const auto& x : v)
    {
      if (!x.isNumeric())
      {
        vtkErrorMacro(<< "Preset '" << name << "' in '" << this->FileName << "': field '" << field
                      << "' holds a non-number.");
        return false;
      }
      out.push_back(x.asDouble());
    }
    return true;
  };

  std::vector<Preset> presets;
  for (const auto& item : root)
  {
    Preset p;
    if (!item.isObject() || !item["Name"].isString())
    {
      vtkErrorMacro(<< "'" << this->FileName << "': every preset needs a string 'Name'.");
      return false;
    }
    p.Name = item["Name"].asString();
    if (item.isMember("ColorSpace"))
    {
      p.ColorSpace = item["ColorSpace"].asString();
    }
    if (!readNumbers(item, "RGBPoints", 4, p.Name, p.RGBPoints))
    {
      return false;
    }
    if (item.isMember("Points") && !readNumbers(item, "Points", 4, p.Name, p.Points))
    {
      return false;
    }
    presets.push_back(std::move(p));
  }
  this->Internals->Presets = std::move(presets);
  this->Modified();
  return true;
}

//------------------------------------------------------------------------------
int vtkPTVTransferFunctionPreset::GetNumberOfPresets() const
{
  return static_cast<int>(this->Internals->Presets.size());
}

//------------------------------------------------------------------------------
const char* vtkPTVTransferFunctionPreset::GetPresetName(int index) const
{
  if (index < 0 || index >= this->GetNumberOfPresets())
  {
    return nullptr;
  }
  return this->Internals->Presets[index].Name.c_str();
}

//------------------------------------------------------------------------------
bool vtkPTVTransferFunctionPreset::HasPreset(const char* name) const
{
  return this->Internals->Find(name) != nullptr;
}

//------------------------------------------------------------------------------
bool vtkPTVTransferFunctionPreset::ApplyPreset(
  const char* name, vtkColorTransferFunction* color, vtkPiecewiseFunction* opacity)
{
  const Preset* p = this->Internals->Find(name);
  if (!p)
  {
    std::ostringstream names;
    for (const auto& q : this->Internals->Presets)
    {
      names << " '" << q.Name << "'";
    }
    vtkErrorMacro(<< "Unknown preset '" << (name ? name : "(null)") << "'; loaded:"
                  << (names.str().empty() ? " none" : names.str()));
    return false;
  }
  if (!color)
  {
    vtkErrorMacro(<< "ApplyPreset needs a vtkColorTransferFunction.");
    return false;
  }
  color->RemoveAllPoints();
  if (p->ColorSpace == "HSV")
  {
    color->SetColorSpaceToHSV();
  }
  else if (p->ColorSpace == "Lab" || p->ColorSpace == "CIELAB")
  {
    color->SetColorSpaceToLab();
  }
  else if (p->ColorSpace == "Diverging")
  {
    color->SetColorSpaceToDiverging();
  }
  else
  {
    color->SetColorSpaceToRGB();
  }
  for (std::size_t i = 0; i < p->RGBPoints.size(); i += 4)
  {
    const double* q = &p->RGBPoints[i];
    color->AddRGBPoint(q[0], q[1], q[2], q[3]);
  }
  if (opacity && !p->Points.empty())
  {
    opacity->RemoveAllPoints();
    for (std::size_t i = 0; i < p->Points.size(); i += 4)
    {
      opacity->AddPoint(p->Points[i], p->Points[i + 1], p->Points[i + 2], p->Points[i + 3]);
    }
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkPTVTransferFunctionPreset::ApplyPreset(const char* name, vtkVolumeProperty* property)
{
  if (!property)
  {
    vtkErrorMacro(<< "ApplyPreset needs a vtkVolumeProperty.");
    return false;
  }
  vtkColorTransferFunction* color = property->GetRGBTransferFunction(0);
  vtkPiecewiseFunction* opacity = property->GetScalarOpacity(0);
  if (!this->ApplyPreset(name, color, opacity))
  {
    return false;
  }
  property->SetColor(0, color);
  property->SetScalarOpacity(0, opacity);
  return true;
}

//------------------------------------------------------------------------------
void vtkPTVTransferFunctionPreset::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "NumberOfPresets: " << this->GetNumberOfPresets() << "\n";
  for (const auto& p : this->Internals->Presets)
  {
    os << indent.GetNextIndent() << p.Name << "\n";
  }
}
