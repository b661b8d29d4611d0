// The capture file behind ptvCudaCapture.h: a magic word, the layout's sizes, the name, the raw
// TraceParams, then each array as (encoding, count, values). Voxels that are all integers in
// int16's range (CT), none of them -0, are stored as int16, exactly; everything else as float32.
#include "ptvCudaCapture.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>

namespace ptv
{
namespace
{
constexpr char kMagic[8] = { 'P', 'T', 'V', 'C', 'A', 'P', '0', '1' };
constexpr std::uint8_t kFloat32 = 0, kInt16 = 1, kInt8 = 2;

template <typename T>
const T* DataOrNull(const std::vector<T>& v)
{
  return v.empty() ? nullptr : v.data();
}

class Writer
{
public:
  explicit Writer(const std::string& file)
    : Out(file, std::ios::binary)
  {
  }
  bool Good() const { return static_cast<bool>(this->Out); }
  void Bytes(const void* p, std::size_t n) { this->Out.write(static_cast<const char*>(p), n); }
  template <typename T>
  void Pod(const T& v)
  {
    this->Bytes(&v, sizeof(T));
  }
  void Floats(const std::vector<float>& v)
  {
    bool integral = !v.empty();
    for (float x : v)
    {
      if (!(x >= -32768.f && x <= 32767.f && std::floor(x) == x) || (x == 0.f && std::signbit(x)))
      {
        integral = false;
        break;
      }
    }
    this->Pod(integral ? kInt16 : kFloat32);
    this->Pod(static_cast<std::uint64_t>(v.size()));
    if (integral)
    {
      std::vector<std::int16_t> narrow(v.begin(), v.end());
      this->Bytes(narrow.data(), narrow.size() * sizeof(std::int16_t));
    }
    else
    {
      this->Bytes(v.data(), v.size() * sizeof(float));
    }
  }
  void Int8s(const std::vector<int8_t>& v)
  {
    this->Pod(kInt8);
    this->Pod(static_cast<std::uint64_t>(v.size()));
    this->Bytes(v.data(), v.size());
  }
  bool Close()
  {
    this->Out.close();
    return static_cast<bool>(this->Out);
  }

private:
  std::ofstream Out;
};

class Reader
{
public:
  explicit Reader(const std::string& file)
    : In(file, std::ios::binary)
  {
  }
  bool Good() const { return this->Ok && static_cast<bool>(this->In); }
  void Bytes(void* p, std::size_t n)
  {
    if (this->Ok && !this->In.read(static_cast<char*>(p), n))
    {
      this->Ok = false;
    }
  }
  template <typename T>
  T Pod()
  {
    T v{};
    this->Bytes(&v, sizeof(T));
    return v;
  }
  /// An array of at most @a limit values (a sanity bound from the header, so a corrupt count
  /// cannot ask for terabytes).
  template <typename T>
  void Array(std::vector<T>& v, std::uint64_t limit, std::uint8_t expected)
  {
    const auto encoding = this->Pod<std::uint8_t>();
    const auto count = this->Pod<std::uint64_t>();
    const bool known = expected == kInt8 ? encoding == kInt8
                                         : (encoding == kFloat32 || encoding == kInt16);
    if (!this->Ok || !known || count > limit)
    {
      this->Ok = false;
      return;
    }
    v.resize(count);
    if (encoding == kInt16)
    {
      std::vector<std::int16_t> narrow(count);
      this->Bytes(narrow.data(), count * sizeof(std::int16_t));
      std::copy(narrow.begin(), narrow.end(), v.begin());
    }
    else
    {
      this->Bytes(v.data(), count * sizeof(T));
    }
  }

private:
  std::ifstream In;
  bool Ok = true;
};
}

//------------------------------------------------------------------------------
void PointParams(TraceCapture& c)
{
  TraceParams& p = c.Params;
  p.Volume.Scalars = DataOrNull(c.Scalars);
  p.Volume.Type = kScalarFloat; // captures store the voxels as float
  p.Volume.Colors = DataOrNull(c.Colors);
  p.Volume.ColorScalars = DataOrNull(c.ColorScalars);
  p.Transfer.RGBA = DataOrNull(c.TransferRGBA);
  p.Transfer.GradientOpacity = DataOrNull(c.GradientOpacity);
  p.Transfer.StepRGBA = DataOrNull(c.StepRGBA);
  p.Transfer.ShadowAlpha = DataOrNull(c.ShadowAlpha);
  p.ColorTable.RGBA = DataOrNull(c.ColorTableRGBA);
  p.MaxDistance = DataOrNull(c.MaxDistance);
  p.Occupancy.Distance = DataOrNull(c.Occupancy);
}

//------------------------------------------------------------------------------
std::vector<float> FirstGuide(const TraceCapture& c)
{
  const std::size_t pixels = static_cast<std::size_t>(c.Width()) * c.Height();
  std::vector<float> g(pixels);
  for (std::size_t i = 0; i < pixels; ++i)
  {
    g[i] = c.Guides[i * c.GuideLevels];
  }
  return g;
}

//------------------------------------------------------------------------------
bool WriteCapture(const std::string& file, const TraceCapture& c, std::string& error)
{
  const std::string temporary = file + ".partial";
  Writer w(temporary);
  if (!w.Good())
  {
    error = "cannot write " + temporary;
    return false;
  }
  w.Bytes(kMagic, sizeof(kMagic));
  w.Pod(static_cast<std::uint32_t>(sizeof(TraceParams)));
  w.Pod(static_cast<std::uint32_t>(c.Name.size()));
  w.Bytes(c.Name.data(), c.Name.size());
  w.Pod(c.Params);
  for (const std::vector<float>* v : { &c.Scalars, &c.Colors, &c.ColorScalars, &c.TransferRGBA,
         &c.GradientOpacity, &c.StepRGBA, &c.ShadowAlpha, &c.ColorTableRGBA, &c.MaxDistance })
  {
    w.Floats(*v);
  }
  w.Int8s(c.Occupancy);
  for (int k = 0; k < 2; ++k)
  {
    w.Pod(static_cast<std::int32_t>(c.Samples[k]));
    for (const std::vector<float>& pass : c.Cpu[k])
    {
      w.Floats(pass);
    }
  }
  w.Pod(static_cast<std::int32_t>(c.GuideLevels));
  w.Bytes(c.SpatialStep, sizeof(c.SpatialStep));
  w.Bytes(c.RangeStep, sizeof(c.RangeStep));
  w.Pod(c.Clamp);
  for (const std::vector<float>* v :
    { &c.Radiance, &c.Albedo, &c.Guides, &c.Weights, &c.GridCpu[0], &c.GridCpu[1] })
  {
    w.Floats(*v);
  }
  if (!w.Close() || std::rename(temporary.c_str(), file.c_str()) != 0)
  {
    std::remove(temporary.c_str());
    error = "cannot write " + file;
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
bool ReadCapture(const std::string& file, TraceCapture& c, std::string& error)
{
  Reader r(file);
  if (!r.Good())
  {
    error = "cannot open " + file;
    return false;
  }
  char magic[sizeof(kMagic)] = {};
  r.Bytes(magic, sizeof(magic));
  if (!r.Good() || std::memcmp(magic, kMagic, sizeof(kMagic)) != 0)
  {
    error = file + " is not a capture of this version (no PTVCAP01 header)";
    return false;
  }
  const auto layout = r.Pod<std::uint32_t>();
  if (layout != sizeof(TraceParams))
  {
    error = file + " was written by a build whose TraceParams has " + std::to_string(layout) +
      " bytes (this one: " + std::to_string(sizeof(TraceParams)) + "); write it again";
    return false;
  }
  const auto nameLength = r.Pod<std::uint32_t>();
  if (!r.Good() || nameLength > 256)
  {
    error = file + ": corrupt header";
    return false;
  }
  c.Name.assign(nameLength, '\0');
  r.Bytes(&c.Name[0], nameLength);
  c.Params = r.Pod<TraceParams>();
  const int* dims = c.Params.Volume.Dims;
  const std::uint64_t voxels = static_cast<std::uint64_t>(dims[0] > 0 ? dims[0] : 0) *
    static_cast<std::uint64_t>(dims[1] > 0 ? dims[1] : 0) * (dims[2] > 0 ? dims[2] : 0);
  const int width = c.Params.Camera.Width, height = c.Params.Camera.Height;
  if (!r.Good() || voxels == 0 || width < 1 || height < 1 || width > 16384 || height > 16384)
  {
    error = file + ": corrupt parameters (volume or image size)";
    return false;
  }
  const std::uint64_t pixels = static_cast<std::uint64_t>(width) * height;
  const std::uint64_t tables = 4ull << 20; // transfer tables are far smaller
  r.Array(c.Scalars, voxels, kFloat32);
  r.Array(c.Colors, 3 * voxels, kFloat32);
  r.Array(c.ColorScalars, voxels, kFloat32);
  for (std::vector<float>* v : { &c.TransferRGBA, &c.GradientOpacity, &c.StepRGBA,
         &c.ShadowAlpha, &c.ColorTableRGBA })
  {
    r.Array(*v, tables, kFloat32);
  }
  r.Array(c.MaxDistance, pixels, kFloat32);
  r.Array(c.Occupancy, 8 * voxels, kInt8);
  for (int k = 0; k < 2; ++k)
  {
    c.Samples[k] = r.Pod<std::int32_t>();
    for (std::vector<float>& pass : c.Cpu[k])
    {
      r.Array(pass, 3 * pixels, kFloat32);
    }
  }
  c.GuideLevels = r.Pod<std::int32_t>();
  r.Bytes(c.SpatialStep, sizeof(c.SpatialStep));
  r.Bytes(c.RangeStep, sizeof(c.RangeStep));
  c.Clamp = r.Pod<float>();
  const std::uint64_t levels = c.GuideLevels >= 1 && c.GuideLevels <= kMaxGridLevels
    ? static_cast<std::uint64_t>(c.GuideLevels)
    : 0;
  r.Array(c.Radiance, 3 * pixels, kFloat32);
  r.Array(c.Albedo, 3 * pixels, kFloat32);
  r.Array(c.Guides, levels * pixels, kFloat32);
  r.Array(c.Weights, levels * pixels, kFloat32);
  r.Array(c.GridCpu[0], 3 * pixels, kFloat32);
  r.Array(c.GridCpu[1], 3 * pixels, kFloat32);
  if (!r.Good())
  {
    error = file + " is truncated or corrupt";
    return false;
  }
  const std::size_t n = static_cast<std::size_t>(pixels);
  const bool sized = c.Scalars.size() == voxels && levels > 0 && c.Radiance.size() == 3 * n &&
    c.Albedo.size() == 3 * n && c.Guides.size() == levels * n &&
    c.Weights.size() == (levels - 1) * n && c.GridCpu[0].size() == 3 * n &&
    c.GridCpu[1].size() == 3 * n && c.Cpu[0][CapturedRadiance].size() == 3 * n &&
    c.Cpu[1][CapturedRadiance].size() == 3 * n && c.Cpu[0][CapturedDepth].size() == n &&
    c.Cpu[1][CapturedDepth].size() == n && c.Cpu[0][CapturedNormal].size() == 3 * n &&
    c.Cpu[1][CapturedNormal].size() == 3 * n && c.TransferRGBA.size() == 4ull * c.Params.Transfer.Size;
  if (!sized)
  {
    error = file + ": array sizes disagree with its volume, image or guide levels";
    return false;
  }
  PointParams(c);
  return true;
}
}
