// Layout check of OpenEXR files (see ptvEXRLayout.h). Follows the file layout of the OpenEXR
// specification ("OpenEXR File Layout"): magic, version + flags, header(s), offset table(s).
#include "ptvEXRLayout.h"

#include "ptvBoundedReader.h"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace ptv
{
namespace
{

constexpr std::int32_t kMagic = 20000630;
constexpr std::uint32_t kTiled = 0x200, kLongNames = 0x400, kNonImage = 0x800,
                        kMultiPart = 0x1000;

// Attribute types whose value OpenEXR reads with a fixed number of bytes, whatever the declared
// size says (a different size would make it read the rest of the header out of step).
const std::map<std::string, std::int32_t>& FixedSizes()
{
  static const std::map<std::string, std::int32_t> sizes = { { "box2i", 16 }, { "box2f", 16 },
    { "chromaticities", 32 }, { "compression", 1 }, { "deepImageState", 1 }, { "double", 8 },
    { "envmap", 1 }, { "float", 4 }, { "int", 4 }, { "keycode", 28 }, { "lineOrder", 1 },
    { "m33f", 36 }, { "m33d", 72 }, { "m44f", 64 }, { "m44d", 128 }, { "rational", 8 },
    { "tiledesc", 9 }, { "timecode", 8 }, { "v2i", 8 }, { "v2f", 8 }, { "v2d", 16 },
    { "v3i", 12 }, { "v3f", 12 }, { "v3d", 24 } };
  return sizes;
}

// Scan lines per chunk for each compression (Imf::getCompressionNumScanlines); -1: unknown.
int LinesPerChunk(int compression)
{
  static const int lines[] = { 1, 1, 1, 16, 32, 16, 32, 32, 32, 256 };
  return compression >= 0 && compression < 10 ? lines[compression] : -1;
}

// What the offset table needs from one part's header.
struct Part
{
  bool HasWindow = false;
  std::int32_t Window[4] = { 0, 0, 0, 0 }; // xMin, yMin, xMax, yMax
  int Compression = 0;
  bool HasTiles = false;
  std::uint32_t Tile[2] = { 0, 0 };
  bool HasChunkCount = false;
  std::int32_t ChunkCount = 0;
  std::string Type; // multi-part "type": scanlineimage, tiledimage, deepscanline, deeptile
  int Channels = 0;
};

// chlist: per channel a name (NUL-terminated, up to 255 characters), int32 pixel type,
// uint8 pLinear, 3 reserved bytes, int32 x and y sampling; a NUL ends the list.
bool CheckChannelList(BoundedReader& r, int& channels, std::string& why)
{
  for (int channel = 0;; ++channel)
  {
    channels = channel;
    std::string name;
    if (!r.TerminatedString(name, 255))
    {
      why = "channel " + std::to_string(channel) + "'s name is too long or cut short";
      return false;
    }
    if (name.empty())
    {
      return true;
    }
    std::int32_t type = 0, xs = 0, ys = 0;
    std::uint8_t flags[4];
    if (!r.Value(type) || !r.Value(flags) || !r.Value(xs) || !r.Value(ys))
    {
      why = "channel '" + name + "' is cut short";
      return false;
    }
    if (type < 0 || type > 2 || xs < 1 || ys < 1)
    {
      why = "channel '" + name + "' has pixel type " + std::to_string(type) + " and sampling " +
        std::to_string(xs) + " x " + std::to_string(ys);
      return false;
    }
  }
}

// The value of one attribute, inside [r.Position, r.Position + size) (r.Limit is set to its end).
bool CheckValue(
  BoundedReader& r, const std::string& type, std::int32_t size, int& channels, std::string& why)
{
  const auto fixed = FixedSizes().find(type);
  if (fixed != FixedSizes().end())
  {
    if (size != fixed->second)
    {
      why = "declares " + std::to_string(size) + " bytes for a " + type + " (" +
        std::to_string(fixed->second) + " bytes)";
      return false;
    }
    return r.Bytes(nullptr, static_cast<std::uint64_t>(size));
  }
  if (type == "chlist")
  {
    return CheckChannelList(r, channels, why);
  }
  if (type == "preview")
  {
    std::uint32_t w = 0, h = 0;
    if (!r.Value(w) || !r.Value(h) || std::uint64_t(w) * h * 4 != r.Left())
    {
      why = "a preview image of " + std::to_string(w) + " x " + std::to_string(h) +
        " RGBA8 pixels in " + std::to_string(size) + " bytes";
      return false;
    }
    return r.Bytes(nullptr, r.Left());
  }
  if (type == "stringvector")
  {
    while (r.Left() > 0)
    {
      std::int32_t n = 0;
      if (!r.Value(n) || n < 0 || !r.Bytes(nullptr, static_cast<std::uint64_t>(n)))
      {
        why = "a string of " + std::to_string(n) + " characters runs past the attribute";
        return false;
      }
    }
    return true;
  }
  if (type == "floatvector" && size % 4 != 0)
  {
    why = "a float vector of " + std::to_string(size) + " bytes";
    return false;
  }
  // string, floatvector, idmanifest and unknown (opaque) types read exactly the declared size.
  return r.Bytes(nullptr, static_cast<std::uint64_t>(size));
}

// Remembers the attributes the offset table depends on.
void Note(BoundedReader& r, std::uint64_t start, const std::string& name, const std::string& type,
  Part& part)
{
  const std::uint64_t end = r.Position;
  r.Position = start;
  if (name == "dataWindow" && type == "box2i")
  {
    part.HasWindow = r.Value(part.Window);
  }
  else if (name == "compression" && type == "compression")
  {
    std::uint8_t c = 0;
    r.Value(c);
    part.Compression = c;
  }
  else if (name == "tiles" && type == "tiledesc")
  {
    part.HasTiles = r.Value(part.Tile);
  }
  else if (name == "chunkCount" && type == "int")
  {
    part.HasChunkCount = r.Value(part.ChunkCount);
  }
  else if (name == "type" && type == "string" && end - start <= 64)
  {
    part.Type.assign(static_cast<std::size_t>(end - start), '\0');
    r.Bytes(part.Type.empty() ? nullptr : &part.Type[0], end - start);
  }
  r.Position = end;
}

// One header: attributes until an empty name. @a empty: the header had no attribute at all.
bool CheckHeader(BoundedReader& r, std::uint64_t maxName, Part& part, bool& empty, std::string& why)
{
  empty = true;
  for (int index = 0;; ++index)
  {
    std::string name, type;
    std::int32_t size = 0;
    if (!r.TerminatedString(name, maxName))
    {
      why = "attribute " + std::to_string(index) + "'s name is longer than " +
        std::to_string(maxName) + " characters or cut short";
      return false;
    }
    if (name.empty())
    {
      return true;
    }
    empty = false;
    if (!r.TerminatedString(type, maxName) || type.empty() || !r.Value(size))
    {
      why = "attribute '" + name + "' has no valid type name or size";
      return false;
    }
    if (size < 0 || static_cast<std::uint64_t>(size) > r.Left())
    {
      why = "attribute '" + name + "' (" + type + ") declares " + std::to_string(size) +
        " bytes, but " + std::to_string(r.Left()) + " remain in the file";
      return false;
    }
    const std::uint64_t start = r.Position;
    r.Limit = start + static_cast<std::uint64_t>(size);
    int channels = 0;
    const bool ok = CheckValue(r, type, size, channels, why) && r.Position == r.Limit;
    r.Limit = r.FileSize;
    if (!ok)
    {
      why = "attribute '" + name + "' (" + type + "): " +
        (why.empty() ? std::string("its value does not fill its declared size") : why);
      return false;
    }
    Note(r, start, name, type, part);
    if (name == "channels" && type == "chlist")
    {
      part.Channels = channels;
    }
  }
}

// Number of offset-table entries of one part (a lower bound for tiled images with levels).
bool ChunkCount(const Part& part, bool multiPart, bool tiled, std::uint64_t& chunks,
  std::string& why)
{
  if (multiPart)
  {
    if (!part.HasChunkCount || part.ChunkCount < 0)
    {
      why = "a part has no valid chunkCount";
      return false;
    }
    chunks = static_cast<std::uint64_t>(part.ChunkCount);
    return true;
  }
  if (!part.HasWindow)
  {
    why = "no dataWindow";
    return false;
  }
  const std::int64_t w = std::int64_t(part.Window[2]) - part.Window[0] + 1;
  const std::int64_t h = std::int64_t(part.Window[3]) - part.Window[1] + 1;
  if (w < 1 || h < 1)
  {
    why = "an empty data window (" + std::to_string(w) + " x " + std::to_string(h) + ")";
    return false;
  }
  if (tiled)
  {
    if (!part.HasTiles || part.Tile[0] == 0 || part.Tile[1] == 0)
    {
      why = "a tiled image without a valid tile size";
      return false;
    }
    chunks = static_cast<std::uint64_t>((w + part.Tile[0] - 1) / part.Tile[0]) *
      static_cast<std::uint64_t>((h + part.Tile[1] - 1) / part.Tile[1]);
    return true;
  }
  const int lines = LinesPerChunk(part.Compression);
  if (lines < 0)
  {
    why = "unknown compression " + std::to_string(part.Compression);
    return false;
  }
  chunks = static_cast<std::uint64_t>((h + lines - 1) / lines);
  return true;
}

} // namespace

//------------------------------------------------------------------------------
bool CheckEXRLayout(const std::string& file, std::string& error, EXRLayoutSummary* summary)
{
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(file, ec);
  std::ifstream in(file, std::ios::binary);
  if (ec || !in)
  {
    error = "cannot open the file" + (ec ? ": " + ec.message() : std::string());
    return false;
  }
  BoundedReader r(in, static_cast<std::uint64_t>(size));
  const std::string corrupt = "not a valid OpenEXR file (truncated or corrupt: ";
  std::int32_t magic = 0;
  std::uint32_t version = 0;
  if (!r.Value(magic) || magic != kMagic || !r.Value(version))
  {
    error = corrupt + "no OpenEXR magic number and version)";
    return false;
  }
  const std::uint32_t flags = version & ~0xffu;
  if ((version & 0xffu) != 2 || (flags & ~(kTiled | kLongNames | kNonImage | kMultiPart)) != 0)
  {
    error = "unsupported OpenEXR version " + std::to_string(version & 0xffu) + " with flags " +
      std::to_string(flags) + " (version 2 with the tiled, long-name, deep and multi-part flags " +
      "expected)";
    return false;
  }
  const bool multiPart = (flags & kMultiPart) != 0;
  const std::uint64_t maxName = (flags & kLongNames) ? 255 : 31;
  std::vector<Part> parts;
  std::string why;
  for (;;)
  {
    Part part;
    bool empty = true;
    if (!CheckHeader(r, maxName, part, empty, why))
    {
      error = corrupt + "header " + std::to_string(parts.size()) + ": " + why + ")";
      return false;
    }
    if (empty && (multiPart && !parts.empty()))
    {
      break; // the empty header that ends a multi-part file's headers
    }
    if (empty)
    {
      error = corrupt + "a header without attributes)";
      return false;
    }
    parts.push_back(part);
    if (!multiPart)
    {
      break;
    }
  }
  std::uint64_t tableBytes = 0;
  for (std::size_t p = 0; p < parts.size(); ++p)
  {
    const bool tiled =
      multiPart ? parts[p].Type.find("tile") != std::string::npos : (flags & kTiled) != 0;
    std::uint64_t chunks = 0;
    if (!ChunkCount(parts[p], multiPart, tiled, chunks, why))
    {
      error = corrupt + "part " + std::to_string(p) + ": " + why + ")";
      return false;
    }
    if (p == 0 && summary && parts[0].HasWindow)
    {
      summary->Width = std::int64_t(parts[0].Window[2]) - parts[0].Window[0] + 1;
      summary->Height = std::int64_t(parts[0].Window[3]) - parts[0].Window[1] + 1;
      summary->Channels = parts[0].Channels;
    }
    tableBytes += 8 * chunks;
    if (tableBytes > r.Left())
    {
      error = corrupt + "the offset tables need " + std::to_string(tableBytes) + " bytes for " +
        std::to_string(chunks) + " chunks of part " + std::to_string(p) + ", but " +
        std::to_string(r.Left()) + " remain after the headers)";
      return false;
    }
  }
  return true;
}

} // namespace ptv
