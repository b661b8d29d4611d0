#include "vtkPTVEXRPassReader.h"

#include "ptvEXRChannels.h"
#include "Validators/ptvEXRLayout.h"
#include "ptvQuote.h"

#include "vtkDataObject.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfStringAttribute.h>
#include <ImfTestFile.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkPTVEXRPassReader);

namespace
{
using ptv::Quote;

// "" if @a file can be opened for reading, else the OS reason.
std::string OpenError(const std::string& file)
{
  std::FILE* f = std::fopen(file.c_str(), "rb");
  if (!f)
  {
    return std::strerror(errno);
  }
  std::fclose(f);
  return std::string();
}

} // namespace

//------------------------------------------------------------------------------
vtkPTVEXRPassReader::vtkPTVEXRPassReader()
{
  this->SetNumberOfInputPorts(0);
}

//------------------------------------------------------------------------------
vtkPTVEXRPassReader::~vtkPTVEXRPassReader()
{
  this->SetFileName(nullptr);
}

//------------------------------------------------------------------------------
void vtkPTVEXRPassReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "MaximumNumberOfValues: " << this->MaximumNumberOfValues << "\n";
}

//------------------------------------------------------------------------------
int vtkPTVEXRPassReader::CanReadFile(const char* fileName)
{
  if (!fileName || !*fileName)
  {
    return 0;
  }
  try
  {
    return Imf::isOpenExrFile(fileName) ? 1 : 0;
  }
  catch (const std::exception&)
  {
    return 0;
  }
}

//------------------------------------------------------------------------------
bool vtkPTVEXRPassReader::CheckFile(const std::string& file)
{
  std::string corrupt;
  ptv::EXRLayoutSummary size;
  if (!ptv::CheckEXRLayout(file, corrupt, &size))
  {
    vtkErrorMacro("Cannot read " << Quote(file) << ": " << corrupt << ".");
    return false;
  }
  const double values = double(size.Width) * double(size.Height) * size.Channels;
  if (values > double(this->MaximumNumberOfValues))
  {
    vtkErrorMacro("Cannot read " << Quote(file) << ": its " << size.Width << " x " << size.Height
                                 << " pixels x " << size.Channels
                                 << " channels exceed MaximumNumberOfValues ("
                                 << this->MaximumNumberOfValues << ").");
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
int vtkPTVEXRPassReader::FillOutputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkImageData");
  return 1;
}

//------------------------------------------------------------------------------
int vtkPTVEXRPassReader::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  if (!this->FileName || !*this->FileName)
  {
    vtkErrorMacro("No FileName was set; set it to the .exr file to read.");
    return 0;
  }
  const std::string file = this->FileName;
  const std::string why = OpenError(file);
  if (!why.empty())
  {
    vtkErrorMacro("Cannot read " << Quote(file) << ": " << why << ".");
    return 0;
  }
  if (!vtkPTVEXRPassReader::CanReadFile(file.c_str()))
  {
    vtkErrorMacro("Cannot read " << Quote(file) << ": not an OpenEXR file.");
    return 0;
  }
  if (!this->CheckFile(file))
  {
    return 0;
  }
  int width = 0;
  int height = 0;
  try
  {
    Imf::InputFile in(file.c_str());
    const Imath::Box2i window = in.header().dataWindow();
    width = window.max.x - window.min.x + 1;
    height = window.max.y - window.min.y + 1;
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro("Cannot read " << Quote(file) << ": " << e.what());
    return 0;
  }
  if (width <= 0 || height <= 0)
  {
    vtkErrorMacro("Cannot read " << Quote(file) << ": empty data window (" << width << " x "
                                 << height << ").");
    return 0;
  }
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  const int extent[6] = { 0, width - 1, 0, height - 1, 0, 0 };
  outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
  const double spacing[3] = { 1.0, 1.0, 1.0 };
  const double origin[3] = { 0.0, 0.0, 0.0 };
  outInfo->Set(vtkDataObject::SPACING(), spacing, 3);
  outInfo->Set(vtkDataObject::ORIGIN(), origin, 3);
  vtkDataObject::SetPointDataActiveScalarInfo(outInfo, VTK_FLOAT, 1);
  return 1;
}

//------------------------------------------------------------------------------
int vtkPTVEXRPassReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkImageData* output = vtkImageData::GetData(outputVector, 0);
  if (!output)
  {
    return 0;
  }
  output->Initialize();
  if (!this->FileName || !*this->FileName)
  {
    vtkErrorMacro("No FileName was set; set it to the .exr file to read.");
    return 0;
  }
  const std::string file = this->FileName;
  if (!this->CheckFile(file)) // the file may have changed since RequestInformation
  {
    return 0;
  }
  try
  {
    Imf::InputFile in(file.c_str());
    const Imf::Header& header = in.header();
    const Imath::Box2i window = header.dataWindow();
    const int width = window.max.x - window.min.x + 1;
    const int height = window.max.y - window.min.y + 1;
    if (width <= 0 || height <= 0)
    {
      vtkErrorMacro("Cannot read " << Quote(file) << ": empty data window.");
      return 0;
    }
    std::vector<std::string> names;
    for (auto it = header.channels().begin(); it != header.channels().end(); ++it)
    {
      names.emplace_back(it.name());
    }
    if (names.empty())
    {
      vtkErrorMacro("Cannot read " << Quote(file) << ": the file has no channels.");
      return 0;
    }
    std::vector<ptv::EXRPassLayout> layout;
    const auto* attribute =
      header.findTypedAttribute<Imf::StringAttribute>(ptv::kPassLayoutAttribute);
    if (!attribute || !ptv::ParseEXRPassLayout(attribute->value(), names, layout))
    {
      layout = ptv::GroupEXRChannels(names);
    }
    else
    {
      // Channels the layout does not mention (added by another tool) are grouped as usual.
      std::vector<std::string> rest;
      for (const std::string& n : names)
      {
        bool used = false;
        for (const ptv::EXRPassLayout& pass : layout)
        {
          for (const std::string& c : pass.Channels)
          {
            used = used || c == n;
          }
        }
        if (!used)
        {
          rest.push_back(n);
        }
      }
      for (const ptv::EXRPassLayout& pass : ptv::GroupEXRChannels(rest))
      {
        layout.push_back(pass);
      }
    }

    // Read every channel as float, top row first, then flip into VTK's bottom-first order.
    const size_t pixels = static_cast<size_t>(width) * height;
    std::vector<std::vector<float>> buffers(layout.size());
    Imf::FrameBuffer frame;
    for (size_t p = 0; p < layout.size(); ++p)
    {
      const size_t comps = layout[p].Channels.size();
      buffers[p].assign(pixels * comps, 0.0f);
      // The slice's base is addressed with the data window's coordinates.
      char* base = reinterpret_cast<char*>(buffers[p].data()) -
        (static_cast<std::ptrdiff_t>(window.min.x) +
          static_cast<std::ptrdiff_t>(window.min.y) * width) *
          static_cast<std::ptrdiff_t>(comps * sizeof(float));
      for (size_t c = 0; c < comps; ++c)
      {
        frame.insert(layout[p].Channels[c],
          Imf::Slice(Imf::FLOAT, base + c * sizeof(float), comps * sizeof(float),
            comps * sizeof(float) * static_cast<size_t>(width)));
      }
    }
    in.setFrameBuffer(frame);
    in.readPixels(window.min.y, window.max.y);

    output->SetExtent(0, width - 1, 0, height - 1, 0, 0);
    output->SetSpacing(1.0, 1.0, 1.0);
    output->SetOrigin(0.0, 0.0, 0.0);
    int scalars = 0;
    for (size_t p = 0; p < layout.size(); ++p)
    {
      const int comps = static_cast<int>(layout[p].Channels.size());
      vtkNew<vtkFloatArray> array;
      array->SetName(layout[p].Name.c_str());
      array->SetNumberOfComponents(comps);
      array->SetNumberOfTuples(static_cast<vtkIdType>(pixels));
      float* dst = array->GetPointer(0);
      for (int j = 0; j < height; ++j)
      {
        const float* src = buffers[p].data() + static_cast<size_t>(height - 1 - j) * width * comps;
        std::copy(src, src + static_cast<size_t>(width) * comps,
          dst + static_cast<size_t>(j) * width * comps);
      }
      output->GetPointData()->AddArray(array);
      if (layout[p].Name == "Radiance")
      {
        scalars = static_cast<int>(p);
      }
    }
    output->GetPointData()->SetActiveScalars(layout[scalars].Name.c_str());
  }
  catch (const std::exception& e)
  {
    output->Initialize();
    vtkErrorMacro("Cannot read " << Quote(file) << ": " << e.what());
    return 0;
  }
  return 1;
}
