// Layout check of OpenVDB files (see ptvOpenVDBLayout.h); shares ptvOpenVDBGrid.cxx's rule that
// OpenVDB headers stay out of every other translation unit.
#include "ptvOpenVDBLayout.h"

#include "ptvBoundedReader.h"
#include "ptvOpenVDBTree.h"
#include "ptvQuote.h"

#include <openvdb/io/DelayedLoadMetadata.h>
#include <openvdb/openvdb.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <mutex>
#include <sstream>

namespace ptv
{
namespace
{

//------------------------------------------------------------------------------
// One block of io::DelayedLoadMetadata::readValue: a uint32 byte count, then either a Blosc
// buffer of that many bytes (count > 0) or @a count raw values of @a valueSize bytes (count 0).
// OpenVDB allocates the byte count, then sizes its vector from the Blosc header's uncompressed
// size and decompresses with the header's compressed size; so the buffer must fit the metadata,
// hold a whole Blosc header (16 bytes), and the header must say exactly @a count values and at
// most the buffer's bytes.
bool CheckDelayedLoadBlock(BoundedReader& r, std::uint64_t count, std::uint64_t valueSize,
  bool mayBeAbsent, const char* what, std::string& why)
{
  std::uint32_t bytes = 0;
  if (!r.Value(bytes))
  {
    why = std::string("its ") + what + " size runs past the metadata";
    return false;
  }
  if (mayBeAbsent && bytes == std::numeric_limits<std::uint32_t>::max())
  {
    return true; // no compressed sizes stored
  }
  if (bytes == 0)
  {
    if (!r.Bytes(nullptr, count * valueSize))
    {
      why = std::string("its ") + what + " (" + std::to_string(count) +
        " raw values) runs past the metadata";
      return false;
    }
    return true;
  }
  const std::uint64_t start = r.Position;
  std::uint32_t header[4] = { 0, 0, 0, 0 }; // version bytes and flags, nbytes, blocksize, cbytes
  if (bytes < sizeof(header) || !r.Value(header) || !r.Bytes(nullptr, bytes - sizeof(header)))
  {
    why = std::string("its compressed ") + what + " (" + std::to_string(bytes) +
      " bytes) does not fit the metadata or holds no Blosc header";
    return false;
  }
  // OpenVDB pads buffers under 128 bytes to 128 before compressing them (BLOSC_PAD_BYTES).
  const std::uint64_t expected = count * valueSize;
  const bool sizeOk = header[1] == expected || (expected < 128 && header[1] == 128);
  if (!sizeOk || header[3] > bytes || r.Position != start + bytes)
  {
    why = std::string("its compressed ") + what + " declares " + std::to_string(header[1]) +
      " bytes for " + std::to_string(count) + " values and " + std::to_string(header[3]) +
      " compressed bytes in a buffer of " + std::to_string(bytes);
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
// The value of an io::DelayedLoadMetadata (type "__delayedload", written by OpenVDB in each grid
// as "file_delayed_load"), which readValue parses: uint32 leaf count, the per-leaf mask block and
// the per-leaf compressed-size block. Every leaf stores at least its 64-byte value mask in the
// file, so the count cannot exceed the file size / 64 (fuzz_openvdb_reader: 7.4 GB from a count).
bool CheckDelayedLoad(BoundedReader& r, std::uint32_t size, std::string& why)
{
  if (size == 0)
  {
    return true; // readValue returns without reading
  }
  const std::uint64_t end = r.Position + size;
  const std::uint64_t sectionLimit = r.Limit;
  r.Limit = end;
  std::uint32_t count = 0;
  bool ok = r.Value(count);
  if (!ok)
  {
    why = "its leaf count runs past the metadata";
  }
  else if (count > r.FileSize / 64)
  {
    ok = false;
    why = "it declares " + std::to_string(count) + " leaves, more than a file of " +
      std::to_string(r.FileSize) + " bytes can hold";
  }
  ok = ok && CheckDelayedLoadBlock(r, count, sizeof(openvdb::io::DelayedLoadMetadata::MaskType),
               false, "leaf mask", why);
  ok = ok && CheckDelayedLoadBlock(r, count,
               sizeof(openvdb::io::DelayedLoadMetadata::CompressedSizeType), true,
               "leaf size table", why);
  r.Position = end;
  r.Limit = sectionLimit;
  return ok;
}

//------------------------------------------------------------------------------
// A MetaMap as OpenVDB's MetaMap::readMeta reads it: uint32 count, then per entry the name, the
// type name and Metadata::read's uint32 size + value. TypedMetadata<T> reads sizeof(T) whatever
// the size says, so a fixed-size type (int32, vec3i, ...) must declare exactly that size.
bool CheckMetaMap(BoundedReader& r, std::string& why)
{
  std::uint32_t count = 0;
  if (!r.Value(count))
  {
    why = "the metadata count lies beyond the end of the file";
    return false;
  }
  // Each entry takes at least 12 bytes (three uint32 sizes).
  if (count > (r.Limit - r.Position) / 12)
  {
    why = "the metadata declares " + std::to_string(count) + " entries, more than fit";
    return false;
  }
  for (std::uint32_t i = 0; i < count; ++i)
  {
    std::string name, type;
    std::uint32_t size = 0;
    if (!r.SizedString(name) || !r.SizedString(type) || !r.Value(size))
    {
      why = "metadata entry " + std::to_string(i) + " runs past its section";
      return false;
    }
    // Fixed-size value types; string and unknown types read the declared size, __delayedload
    // parses its value (checked below).
    static const char* const fixedSize[] = { "bool", "int32", "int64", "float", "double",
      "vec2i", "vec2s", "vec2d", "vec3i", "vec3s", "vec3d", "vec4i", "vec4s", "vec4d", "mat4s",
      "mat4d" };
    if (std::find(std::begin(fixedSize), std::end(fixedSize), type) != std::end(fixedSize) &&
      openvdb::Metadata::isRegisteredType(type))
    {
      const openvdb::Metadata::Ptr meta = openvdb::Metadata::createMetadata(type);
      if (meta && meta->size() != size)
      {
        why = "metadata '" + name + "' of type " + type + " declares " + std::to_string(size) +
          " bytes instead of " + std::to_string(meta->size());
        return false;
      }
    }
    if (size > r.Left())
    {
      why = "metadata '" + name + "' declares " + std::to_string(size) +
        " bytes, more than its section holds";
      return false;
    }
    if (type == openvdb::io::DelayedLoadMetadata::staticTypeName())
    {
      if (!CheckDelayedLoad(r, size, why))
      {
        why = "metadata '" + name + "' of type " + type + ": " + why;
        return false;
      }
    }
    else
    {
      r.Bytes(nullptr, size);
    }
  }
  return true;
}

//------------------------------------------------------------------------------
// The walk itself (see ptvOpenVDBLayout.h).
bool CheckLayoutOf(const std::string& file, std::string& error)
{
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(file, ec);
  if (ec)
  {
    error = "cannot read the size of " + Quote(file) + ": " + ec.message();
    return false;
  }
  std::ifstream in(file, std::ios::binary);
  if (!in)
  {
    error = "cannot open file " + Quote(file);
    return false;
  }
  const std::string what = "file " + Quote(file) + " is not a valid OpenVDB file (truncated or " +
    "corrupt: ";
  BoundedReader r(in, static_cast<std::uint64_t>(size));
  std::int64_t magic = 0;
  std::uint32_t version = 0, major = 0, minor = 0;
  if (!r.Value(magic) || magic != openvdb::OPENVDB_MAGIC)
  {
    error = what + "no VDB magic number)";
    return false;
  }
  if (!r.Value(version) || !r.Value(major) || !r.Value(minor))
  {
    error = what + "the header is cut short)";
    return false;
  }
  if (version < openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION)
  {
    // Older layouts are not walked; rather than handing them to OpenVDB unchecked (a zeroed
    // version field let a 2.5 GB string through), they are refused.
    error = "file " + Quote(file) + " has OpenVDB format version " + std::to_string(version) +
      ", older than OpenVDB 3.0's 222, which this reader does not support (or it is corrupt); " +
      "re-save it with a current OpenVDB";
    return false;
  }
  char hasOffsets = 0;
  char uuid[36];
  if (!r.Value(hasOffsets) || !r.Bytes(uuid, sizeof(uuid)))
  {
    error = what + "the header is cut short)";
    return false;
  }
  std::string why;
  if (!CheckMetaMap(r, why))
  {
    error = what + "file metadata: " + why + ")";
    return false;
  }
  if (!hasOffsets)
  {
    // Written by openvdb::io::Stream: the grids follow one another without offsets, so nothing
    // bounds what OpenVDB would read (fuzz_openvdb_reader: a 2 GB grid name). Refused.
    error = "file " + Quote(file) + " has no grid offsets (written as a stream, or corrupt); " +
      "this reader needs a file written by openvdb::io::File";
    return false;
  }
  std::int32_t count = 0;
  if (!r.Value(count) || count < 0)
  {
    error = what + "no valid grid count)";
    return false;
  }
  for (std::int32_t g = 0; g < count; ++g)
  {
    std::string name, type, parent;
    std::int64_t gridPos = 0, blockPos = 0, endPos = 0;
    if (!r.SizedString(name) || !r.SizedString(type) || !r.SizedString(parent) ||
      !r.Value(gridPos) || !r.Value(blockPos) || !r.Value(endPos))
    {
      error = what + "grid descriptor " + std::to_string(g) + " is cut short)";
      return false;
    }
    const std::int64_t here = static_cast<std::int64_t>(r.Position);
    const std::int64_t fileSize = static_cast<std::int64_t>(size);
    if (gridPos < here || blockPos < gridPos || endPos < blockPos || endPos > fileSize)
    {
      std::ostringstream msg;
      msg << what << "grid " << Quote(openvdb::io::GridDescriptor::nameAsString(name))
          << " declares the offsets "
          << gridPos << " / " << blockPos << " / " << endPos << " but the file has " << fileSize
          << " bytes)";
      error = msg.str();
      return false;
    }
    // The grid's compression flags and metadata lie between gridPos and blockPos.
    r.Position = static_cast<std::uint64_t>(gridPos);
    r.Limit = static_cast<std::uint64_t>(blockPos);
    std::uint32_t compression = 0;
    if (!r.Value(compression) || !CheckMetaMap(r, why))
    {
      error = what + "grid " + Quote(openvdb::io::GridDescriptor::nameAsString(name)) + ": " +
        (why.empty() ? std::string("its header is cut short") : why) + ")";
      return false;
    }
    // Then the transform, which starts with its map type name (math::Transform::read).
    const std::uint64_t transformPos = r.Position;
    std::string mapType;
    if (!r.SizedString(mapType))
    {
      error = what + "grid " + Quote(openvdb::io::GridDescriptor::nameAsString(name)) +
        ": its transform's type name runs past the grid's data block)";
      return false;
    }
    // Then, for the grids this reader reads, the topology and voxel blocks (other grids' are
    // never read: their metadata only is listed).
    TreeBlocks tree;
    const std::string half = "_HalfFloat"; // io::GridDescriptor's "saved as half" type suffix
    if (type.size() > half.size() && type.compare(type.size() - half.size(), half.size(), half) == 0)
    {
      type.resize(type.size() - half.size());
      tree.SavedAsHalf = true;
    }
    tree.IsDouble = type == openvdb::DoubleGrid::gridType();
    if (tree.IsDouble || type == openvdb::FloatGrid::gridType())
    {
      tree.Compression = compression;
      tree.FileVersion = version;
      tree.LibraryMajor = major;
      tree.LibraryMinor = minor;
      tree.TransformPos = transformPos;
      tree.BlockPos = static_cast<std::uint64_t>(blockPos);
      tree.EndPos = static_cast<std::uint64_t>(endPos);
      const bool treeOk = CheckTreeBlocks(in, tree, why);
      r.Resync();
      if (!treeOk)
      {
        error = what + "grid " + Quote(openvdb::io::GridDescriptor::nameAsString(name)) + ": " +
          why + ")";
        return false;
      }
    }
    r.Position = static_cast<std::uint64_t>(endPos);
    r.Limit = r.FileSize;
  }
  return true;
}

} // namespace

//------------------------------------------------------------------------------
bool CheckOpenVDBLayout(const std::string& file, std::string& error)
{
  try
  {
    static std::once_flag once;
    std::call_once(once, []() { openvdb::initialize(); }); // for Metadata::isRegisteredType
    return CheckLayoutOf(file, error);
  }
  catch (const std::exception& e)
  {
    error = "cannot read OpenVDB file " + Quote(file) + ": " + e.what();
  }
  return false;
}

} // namespace ptv
