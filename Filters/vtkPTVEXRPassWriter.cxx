#include "vtkPTVEXRPassWriter.h"

#include "ptvAtomicWrite.h"
#include "ptvEXRChannels.h"
#include "ptvQuote.h"

#include "vtkAlgorithm.h"
#include "vtkDataArray.h"
#include "vtkErrorCode.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"

#include <ImfChannelList.h>
#include <ImfCompression.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>


#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <map>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkPTVEXRPassWriter);

namespace
{
using ptv::Quote;

} // namespace

//------------------------------------------------------------------------------
vtkPTVEXRPassWriter::vtkPTVEXRPassWriter() = default;

//------------------------------------------------------------------------------
vtkPTVEXRPassWriter::~vtkPTVEXRPassWriter()
{
  this->SetFileName(nullptr);
}

//------------------------------------------------------------------------------
void vtkPTVEXRPassWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
}

//------------------------------------------------------------------------------
vtkImageData* vtkPTVEXRPassWriter::GetInput()
{
  return vtkImageData::SafeDownCast(this->Superclass::GetInput());
}

//------------------------------------------------------------------------------
vtkImageData* vtkPTVEXRPassWriter::GetInput(int port)
{
  return vtkImageData::SafeDownCast(this->Superclass::GetInput(port));
}

//------------------------------------------------------------------------------
int vtkPTVEXRPassWriter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
  return 1;
}

//------------------------------------------------------------------------------
void vtkPTVEXRPassWriter::WriteData()
{
  vtkImageData* image = this->GetInput();
  if (!image)
  {
    vtkErrorMacro("No input: connect a vtkImageData of render passes to write.");
    this->SetErrorCode(vtkErrorCode::UnknownError);
    return;
  }
  if (!this->FileName || !*this->FileName)
  {
    vtkErrorMacro("No FileName was set; set it to the .exr file to write.");
    this->SetErrorCode(vtkErrorCode::NoFileNameError);
    return;
  }
  const std::string file = this->FileName;

  int extent[6];
  image->GetExtent(extent);
  const int width = extent[1] - extent[0] + 1;
  const int height = extent[3] - extent[2] + 1;
  const int depth = extent[5] - extent[4] + 1;
  if (width <= 0 || height <= 0 || depth <= 0)
  {
    vtkErrorMacro("The input image is empty (extent " << extent[0] << " " << extent[1] << " "
                                                      << extent[2] << " " << extent[3] << " "
                                                      << extent[4] << " " << extent[5]
                                                      << "); cannot write " << Quote(file)
                                                      << ".");
    this->SetErrorCode(vtkErrorCode::UnknownError);
    return;
  }
  if (depth != 1)
  {
    vtkErrorMacro("The input image is 3D (" << width << " x " << height << " x " << depth
                                            << " points); an EXR file holds 2D images (one "
                                               "point along z). Cannot write "
                                            << Quote(file) << ".");
    this->SetErrorCode(vtkErrorCode::UnknownError);
    return;
  }
  const vtkIdType pixels = static_cast<vtkIdType>(width) * height;

  // The arrays, their channels and float copies in EXR row order (top row first).
  vtkPointData* pd = image->GetPointData();
  std::vector<ptv::EXRPassLayout> layout;
  std::vector<std::vector<float>> buffers;
  std::map<std::string, std::string> owner; // channel -> array
  for (int a = 0; a < pd->GetNumberOfArrays(); ++a)
  {
    vtkAbstractArray* abstract = pd->GetAbstractArray(a);
    const std::string name = abstract->GetName() ? abstract->GetName() : "";
    vtkDataArray* array = vtkDataArray::SafeDownCast(abstract);
    if (name.empty())
    {
      vtkErrorMacro("Point-data array " << a << " has no name; every array needs one to name "
                                        << "its EXR channels. Cannot write " << Quote(file)
                                        << ".");
      this->SetErrorCode(vtkErrorCode::UnknownError);
      return;
    }
    if (!array)
    {
      vtkErrorMacro("Point-data array " << Quote(name) << " is a " << abstract->GetClassName()
                                        << ", not a numeric array; EXR stores numbers only. "
                                        << "Remove it first. Cannot write " << Quote(file)
                                        << ".");
      this->SetErrorCode(vtkErrorCode::UnknownError);
      return;
    }
    const int comps = array->GetNumberOfComponents();
    if (array->GetNumberOfTuples() != pixels || comps < 1)
    {
      vtkErrorMacro("Point-data array " << Quote(name) << " has " << array->GetNumberOfTuples()
                                        << " values of " << comps << " components for "
                                        << pixels << " pixels; cannot write " << Quote(file)
                                        << ".");
      this->SetErrorCode(vtkErrorCode::UnknownError);
      return;
    }
    ptv::EXRPassLayout pass{ name, ptv::EXRChannelsForPass(name, comps) };
    for (const std::string& channel : pass.Channels)
    {
      auto inserted = owner.emplace(channel, name);
      if (!inserted.second)
      {
        vtkErrorMacro("Point-data arrays " << Quote(inserted.first->second) << " and "
                                           << Quote(name) << " both map to the EXR channel "
                                           << Quote(channel) << "; rename one. Cannot write "
                                           << Quote(file) << ".");
        this->SetErrorCode(vtkErrorCode::UnknownError);
        return;
      }
    }
    std::vector<float> buffer(static_cast<size_t>(pixels) * comps);
    // Float arrays are copied as they are: through GetComponent's double a signalling NaN would
    // come back quiet (bits changed; found by fuzz_exr_pass_roundtrip).
    vtkFloatArray* floats = vtkFloatArray::SafeDownCast(array);
    for (int j = 0; j < height; ++j)
    {
      const vtkIdType src = static_cast<vtkIdType>(j) * width;
      const size_t dst = static_cast<size_t>(height - 1 - j) * width;
      for (int i = 0; i < width; ++i)
      {
        for (int c = 0; c < comps; ++c)
        {
          buffer[(dst + i) * comps + c] = floats
            ? floats->GetTypedComponent(src + i, c)
            : static_cast<float>(array->GetComponent(src + i, c));
        }
      }
    }
    layout.push_back(pass);
    buffers.push_back(std::move(buffer));
  }
  if (layout.empty())
  {
    vtkErrorMacro("The input image has no point-data arrays; nothing to write to " << Quote(file)
                                                                                    << ".");
    this->SetErrorCode(vtkErrorCode::UnknownError);
    return;
  }

  std::string error;
  const ptv::WriteStep failed = ptv::WriteAtomically(file,
    [&](const std::string& tmp)
    {
      Imf::Header header(width, height);
      header.compression() = Imf::ZIP_COMPRESSION;
      header.insert(ptv::kPassLayoutAttribute,
        Imf::StringAttribute(ptv::FormatEXRPassLayout(layout)));
      Imf::FrameBuffer frame;
      for (size_t p = 0; p < layout.size(); ++p)
      {
        const size_t comps = layout[p].Channels.size();
        for (size_t c = 0; c < comps; ++c)
        {
          header.channels().insert(layout[p].Channels[c], Imf::Channel(Imf::FLOAT));
          frame.insert(layout[p].Channels[c],
            Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(buffers[p].data() + c),
              comps * sizeof(float), comps * sizeof(float) * static_cast<size_t>(width)));
        }
      }
      Imf::OutputFile out(tmp.c_str(), header);
      out.setFrameBuffer(frame);
      out.writePixels(height);
    },
    error);
  if (failed != ptv::WriteStep::None)
  {
    vtkErrorMacro("Cannot write " << Quote(file) << ": "
                                  << (failed == ptv::WriteStep::Write ? "OpenEXR: " : "") << error
                                  << ".");
    this->SetErrorCode(failed == ptv::WriteStep::Write ? vtkErrorCode::OutOfDiskSpaceError
                                                       : vtkErrorCode::CannotOpenFileError);
  }
}
