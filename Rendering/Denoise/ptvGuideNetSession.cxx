#include "ptvGuideNetSession.h"

#include "ptvGuideNetMetadata.h"

#include <onnxruntime_cxx_api.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace ptv
{
namespace
{
const char* const CpuProvider = "CPUExecutionProvider";
const char* const CudaProvider = "CUDAExecutionProvider";

std::string ShapeString(const std::vector<int64_t>& shape)
{
  std::string s = "[";
  for (size_t i = 0; i < shape.size(); ++i)
  {
    s += (i ? ", " : "") + (shape[i] < 0 ? std::string("?") : std::to_string(shape[i]));
  }
  return s + "]";
}

/// Name and shape of one float tensor input/output; false (with a message) otherwise.
bool DescribeTensor(const Ort::TypeInfo& info, const char* what, std::vector<int64_t>& shape,
  std::vector<std::string>& problems)
{
  if (info.GetONNXType() != ONNX_TYPE_TENSOR)
  {
    problems.push_back(std::string(what) + " is not a tensor");
    return false;
  }
  auto tensor = info.GetTensorTypeAndShapeInfo();
  shape = tensor.GetShape();
  if (tensor.GetElementType() != ONNX_TENSOR_ELEMENT_DATA_TYPE_FLOAT)
  {
    problems.push_back(std::string(what) + " is not float32 (ONNX element type " +
      std::to_string(static_cast<int>(tensor.GetElementType())) + ")");
    return false;
  }
  return true;
}

/// Rows an output pixel of a "ptv.architecture" network depends on beyond its own
/// (kernel // 2 + kernel2 // 2 for its two convolutions; kernel2 defaults to kernel, hidden 0 is
/// one convolution), or -1 when it is not known or not local (a context branch pools regions).
int ReceptiveHalo(const std::string& architecture)
{
  int kernel = -1, kernel2 = -1, hidden = -1, context = 0;
  std::stringstream items(architecture);
  std::string item;
  while (std::getline(items, item, ','))
  {
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos)
    {
      return -1;
    }
    const std::string key = item.substr(0, eq);
    const int value = std::atoi(item.c_str() + eq + 1);
    if (key == "kernel")
    {
      kernel = value;
    }
    else if (key == "kernel2")
    {
      kernel2 = value;
    }
    else if (key == "hidden")
    {
      hidden = value;
    }
    else if (key == "context")
    {
      context = value;
    }
  }
  if (kernel < 1 || hidden < 0 || context != 0)
  {
    return -1;
  }
  kernel2 = kernel2 < 1 ? kernel : kernel2;
  return kernel / 2 + (hidden > 0 ? kernel2 / 2 : 0);
}
}

struct GuideNetSession::Internals
{
  Ort::Env Env{ ORT_LOGGING_LEVEL_ERROR, "ptv-guidenet" };
  Ort::Session Session{ nullptr };
  Ort::MemoryInfo Memory{ Ort::MemoryInfo::CreateCpu(OrtDeviceAllocator, OrtMemTypeDefault) };
  std::string InputName;
  std::string OutputName;
  std::vector<int64_t> InputShape;  // as declared by the model (-1 = dynamic)
  std::vector<int64_t> OutputShape; // idem
  std::array<int64_t, 4> RunInputShape{};
  std::array<int64_t, 4> RunOutputShape{};
  std::vector<float> TileIn, TileOut; ///< a band of rows (Run in bands)
};

//------------------------------------------------------------------------------
GuideNetSession::GuideNetSession() = default;

//------------------------------------------------------------------------------
GuideNetSession::~GuideNetSession() = default;

//------------------------------------------------------------------------------
std::string GuideNetSession::GetRuntimeVersion()
{
  const char* v = OrtGetApiBase()->GetVersionString();
  return v ? v : "";
}

//------------------------------------------------------------------------------
bool GuideNetSession::IsLoaded() const
{
  return this->Impl && this->Impl->Session;
}

//------------------------------------------------------------------------------
void GuideNetSession::Unload()
{
  if (this->Impl)
  {
    this->Impl->Session = Ort::Session(nullptr);
  }
  this->Path.clear();
  this->Provider.clear();
  this->Channels.clear();
  this->Levels.clear();
  this->GuideScale = 255.0;
  this->Demodulate = true;
  this->ImageOutput = false;
  this->GuideStride = 1;
  this->DefaultLevels = 0;
  this->OutputChannels = 0;
}

//------------------------------------------------------------------------------
bool GuideNetSession::Load(const std::string& path, std::string& error)
{
  this->Unload();
  error.clear();
  const std::string prefix = (path.empty() ? std::string("(no model file)") : path) + ": ";
  if (path.empty())
  {
    error = "no model file given";
    return false;
  }
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe)
    {
      error = prefix + "cannot open the model file (missing or unreadable)";
      return false;
    }
  }
  if (!OrtGetApiBase()->GetApi(ORT_API_VERSION))
  {
    error = prefix + "the ONNX Runtime library (" + GetRuntimeVersion() +
      ") is older than the headers this module was built with (API " +
      std::to_string(ORT_API_VERSION) + ")";
    return false;
  }

  std::vector<std::string> problems;
  GuideNetMetadata meta;
  int outputChannels = 0;
  int halo = -1;
  std::string provider = CpuProvider;
  try
  {
    if (!this->Impl)
    {
      this->Impl.reset(new Internals);
    }
    Internals& in = *this->Impl;

    auto makeOptions = [this]() {
      Ort::SessionOptions options;
      options.SetIntraOpNumThreads(this->NumberOfThreads);
      options.SetInterOpNumThreads(1);
      options.SetExecutionMode(ExecutionMode::ORT_SEQUENTIAL);
      options.SetGraphOptimizationLevel(GraphOptimizationLevel::ORT_ENABLE_ALL);
      // Idle intra-op threads would otherwise busy-wait after each run and steal the cores of
      // the path tracer (ptvThreads.h) that runs between two GuideNet calls.
      options.AddConfigEntry("session.intra_op.allow_spinning", "0");
      return options;
    };
    bool opened = false;
    if (this->AllowCuda)
    {
      const auto available = Ort::GetAvailableProviders();
      if (std::find(available.begin(), available.end(), CudaProvider) != available.end())
      {
        // Listed does not mean usable (CUDA/cuDNN libraries, a device): on any failure the
        // session is opened again on the CPU below; a broken model fails there as well.
        try
        {
          Ort::SessionOptions options = makeOptions();
          OrtCUDAProviderOptions cuda;
          options.AppendExecutionProvider_CUDA(cuda);
          in.Session = Ort::Session(in.Env, path.c_str(), options);
          provider = CudaProvider;
          opened = true;
        }
        catch (const Ort::Exception&)
        {
          provider = CpuProvider;
        }
      }
    }
    if (!opened)
    {
      in.Session = Ort::Session(in.Env, path.c_str(), makeOptions());
    }

    // Metadata.
    Ort::AllocatorWithDefaultOptions allocator;
    Ort::ModelMetadata metadata = in.Session.GetModelMetadata();
    auto lookup = [&](const char* key, std::string& value) {
      Ort::AllocatedStringPtr v = metadata.LookupCustomMetadataMapAllocated(key, allocator);
      if (!v)
      {
        return false;
      }
      value = v.get();
      return true;
    };
    meta = ReadGuideNetMetadata(lookup, problems);
    std::string architecture;
    halo = lookup("ptv.architecture", architecture) ? ReceptiveHalo(architecture) : -1;
    const std::vector<std::string>& channels = meta.Channels;
    const std::vector<std::pair<int, int>>& levels = meta.Levels;

    // Input: exactly one float tensor [1, C, H, W].
    const size_t nIn = in.Session.GetInputCount();
    const size_t nOut = in.Session.GetOutputCount();
    if (nIn != 1)
    {
      problems.push_back("model has " + std::to_string(nIn) + " inputs, expected 1");
    }
    else
    {
      in.InputName = in.Session.GetInputNameAllocated(0, allocator).get();
      const std::string what = "input \"" + in.InputName + "\"";
      if (DescribeTensor(in.Session.GetInputTypeInfo(0), what.c_str(), in.InputShape, problems))
      {
        const auto& s = in.InputShape;
        if (s.size() != 4)
        {
          problems.push_back(what + " has rank " + std::to_string(s.size()) + " " +
            ShapeString(s) + ", expected 4 ([1, C, H, W])");
        }
        else
        {
          if (s[0] > 1)
          {
            problems.push_back(what + " has batch size " + std::to_string(s[0]) +
              ", expected 1 or dynamic");
          }
          if (s[1] < 0)
          {
            problems.push_back(what + " has a dynamic channel dimension " + ShapeString(s));
          }
          else if (meta.HaveChannels && s[1] != static_cast<int64_t>(channels.size()))
          {
            problems.push_back("model declares " + std::to_string(s[1]) +
              " input channels but " + kChannelsKey + " lists " +
              std::to_string(channels.size()) + ": " + Join(channels, ","));
          }
        }
      }
    }
    // Output: exactly one float tensor [1, 2L - 1, H, W].
    if (nOut != 1)
    {
      problems.push_back("model has " + std::to_string(nOut) + " outputs, expected 1");
    }
    else
    {
      in.OutputName = in.Session.GetOutputNameAllocated(0, allocator).get();
      const std::string what = "output \"" + in.OutputName + "\"";
      if (DescribeTensor(in.Session.GetOutputTypeInfo(0), what.c_str(), in.OutputShape, problems))
      {
        const auto& s = in.OutputShape;
        // Guides and blend weights, then any padding channels ptv.outputs names "pad..." (ONNX
        // Runtime's fast convolutions want channel counts that are multiples of 8).
        const int64_t padding = meta.OutputPadding;
        const int64_t expected = 2 * static_cast<int64_t>(levels.size()) - 1 + padding;
        if (s.size() != 4)
        {
          problems.push_back(what + " has rank " + std::to_string(s.size()) + " " +
            ShapeString(s) + ", expected 4 ([1, 2L-1, H, W])");
        }
        else if (s[1] < 0)
        {
          problems.push_back(what + " has a dynamic channel dimension " + ShapeString(s));
        }
        else if (meta.Image && s[1] != 3)
        {
          problems.push_back(what + " has " + std::to_string(s[1]) +
            " channels, a denoiser-v1 model outputs 3 (RGB radiance)");
        }
        else if (meta.HaveLevels && s[1] != expected)
        {
          problems.push_back("model outputs " + std::to_string(s[1]) + " channels but " +
            kLevelsKey + " lists " + std::to_string(levels.size()) + " levels (expected 2L - 1 = " +
            std::to_string(expected - padding) + ": guides, then blend weights" +
            (padding ? ", then the " + std::to_string(padding) + " padding channels of " +
                kOutputsKey : std::string()) + ")");
        }
        else
        {
          outputChannels = static_cast<int>(s[1]);
        }
      }
    }
  }
  catch (const Ort::Exception& e)
  {
    problems.push_back(std::string("ONNX Runtime could not load the model: ") + e.what());
  }
  catch (const std::exception& e)
  {
    problems.push_back(std::string("could not load the model: ") + e.what());
  }

  if (!problems.empty())
  {
    error = prefix + Join(problems, "; ");
    this->Unload();
    return false;
  }
  this->Path = path;
  this->Provider = provider;
  this->Channels = std::move(meta.Channels);
  this->Levels = std::move(meta.Levels);
  this->GuideScale = meta.GuideScale;
  this->Demodulate = meta.Demodulate;
  this->ImageOutput = meta.Image;
  this->GuideStride = meta.GuideStride;
  this->DefaultLevels = meta.DefaultLevels;
  this->OutputChannels = outputChannels;
  this->TileHalo = halo;
  return true;
}

//------------------------------------------------------------------------------
bool GuideNetSession::CanRun(int height, int width, std::string& error) const
{
  error.clear();
  if (!this->IsLoaded())
  {
    error = "no GuideNet model loaded";
    return false;
  }
  if (height <= 0 || width <= 0)
  {
    error = "empty input (" + std::to_string(width) + " x " + std::to_string(height) + ")";
    return false;
  }
  const Internals& in = *this->Impl;
  for (const auto* shape : { &in.InputShape, &in.OutputShape })
  {
    if (((*shape)[2] >= 0 && (*shape)[2] != height) || ((*shape)[3] >= 0 && (*shape)[3] != width))
    {
      error = this->Path + ": the model has a fixed size " + ShapeString(*shape) +
        ", the input is " + std::to_string(width) + " x " + std::to_string(height);
      return false;
    }
  }
  return true;
}

//------------------------------------------------------------------------------
bool GuideNetSession::RunsInBands(int height, int width) const
{
  return this->IsLoaded() && this->TileHalo >= 0 && this->Impl->InputShape[2] < 0 &&
    static_cast<std::size_t>(std::max(height, 0)) * static_cast<std::size_t>(std::max(width, 0)) >
    this->TilePixels;
}

//------------------------------------------------------------------------------
bool GuideNetSession::Run(
  const float* features, int height, int width, float* out, std::string& error)
{
  if (!features || !out)
  {
    error = "empty input (" + std::to_string(width) + " x " + std::to_string(height) + ")";
    return false;
  }
  if (!this->RunsInBands(height, width))
  {
    return this->CanRun(height, width, error) && this->RunRows(features, height, width, out, error);
  }
  const std::size_t plane = static_cast<std::size_t>(height) * static_cast<std::size_t>(width);
  const int64_t c = this->GetNumberOfInputChannels();
  return this->Run(
    [&](int first, int last, float* planes)
    {
      const std::size_t band = static_cast<std::size_t>(last - first) * width;
      for (int64_t k = 0; k < c; ++k)
      {
        const float* from = features + k * plane + static_cast<std::size_t>(first) * width;
        std::copy(from, from + band, planes + k * band);
      }
    },
    height, width, out, error);
}

//------------------------------------------------------------------------------
bool GuideNetSession::Run(
  const BandInput& input, int height, int width, float* out, std::string& error)
{
  if (!out || !this->CanRun(height, width, error))
  {
    if (error.empty())
    {
      error = "no output buffer";
    }
    return false;
  }
  Internals& in = *this->Impl;
  const int64_t c = this->GetNumberOfInputChannels();
  const int64_t o = this->GetNumberOfOutputs();
  const std::size_t rowPixels = static_cast<std::size_t>(width);
  // Bands of rows, each with the rows its convolutions reach: the same output, run by run.
  const int rows = this->RunsInBands(height, width)
    ? static_cast<int>(std::max<std::size_t>(this->TilePixels / rowPixels, 1))
    : height;
  const int halo = std::max(this->TileHalo, 0);
  const std::size_t plane = static_cast<std::size_t>(height) * rowPixels;
  for (int t0 = 0; t0 < height; t0 += rows)
  {
    const int t1 = std::min(t0 + rows, height);
    const int in0 = std::max(t0 - halo, 0);
    const int in1 = std::min(t1 + halo, height);
    const std::size_t band = static_cast<std::size_t>(in1 - in0) * rowPixels;
    in.TileIn.resize(static_cast<std::size_t>(c) * band);
    in.TileOut.resize(static_cast<std::size_t>(o) * band);
    input(in0, in1, in.TileIn.data());
    if (!this->RunRows(in.TileIn.data(), in1 - in0, width, in.TileOut.data(), error))
    {
      return false;
    }
    for (int64_t k = 0; k < o; ++k)
    {
      const float* from = in.TileOut.data() + k * band + (t0 - in0) * rowPixels;
      std::copy(from, from + (t1 - t0) * rowPixels, out + k * plane + t0 * rowPixels);
    }
  }
  return true;
}

//------------------------------------------------------------------------------
bool GuideNetSession::RunRows(
  const float* features, int height, int width, float* out, std::string& error)
{
  Internals& in = *this->Impl;
  const int64_t c = this->GetNumberOfInputChannels();
  const int64_t o = this->GetNumberOfOutputs();
  const int64_t h = height;
  const int64_t w = width;
  in.RunInputShape = { 1, c, h, w };
  in.RunOutputShape = { 1, o, h, w };
  try
  {
    // ORT never writes an input tensor; the C API just has no const overload.
    Ort::Value input = Ort::Value::CreateTensor<float>(in.Memory, const_cast<float*>(features),
      static_cast<size_t>(c * h * w), in.RunInputShape.data(), in.RunInputShape.size());
    Ort::Value output = Ort::Value::CreateTensor<float>(in.Memory, out,
      static_cast<size_t>(o * h * w), in.RunOutputShape.data(), in.RunOutputShape.size());
    const char* inputNames[] = { in.InputName.c_str() };
    const char* outputNames[] = { in.OutputName.c_str() };
    in.Session.Run(Ort::RunOptions{ nullptr }, inputNames, &input, 1, outputNames, &output, 1);
  }
  catch (const Ort::Exception& e)
  {
    error = this->Path + ": ONNX Runtime failed to run the model: " + e.what();
    return false;
  }
  return true;
}
}
