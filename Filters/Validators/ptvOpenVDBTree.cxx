// Tree-block walk of float/double grids (see ptvOpenVDBTree.h). The layout followed is OpenVDB
// 10's: Tree::readTopology, RootNode/InternalNode/LeafNode::readTopology, then readBuffers in the
// order OpenVDB visits the nodes, each value block as io::readCompressedValues reads it.
#include "ptvOpenVDBTree.h"

#include "ptvBoundedReader.h"

#include <openvdb/io/Compression.h>
#include <openvdb/openvdb.h>

#include <array>
#include <bitset>
#include <map>
#include <vector>

namespace ptv
{
namespace
{

using RootT = openvdb::FloatTree::RootNodeType;
using UpperT = RootT::ChildNodeType; // 32^3 values
using LowerT = UpperT::ChildNodeType; // 16^3 values
using LeafT = LowerT::ChildNodeType;  // 8^3 values
static_assert(std::is_same<openvdb::DoubleTree::RootNodeType::ChildNodeType::ChildNodeType::
                               ChildNodeType::NodeMaskType,
                LeafT::NodeMaskType>::value,
  "float and double trees share their node layout");

// A node mask as stored: NUM_VALUES bits in little-endian 64-bit words.
struct Mask
{
  std::vector<std::uint64_t> Words;

  bool Read(BoundedReader& r, std::uint32_t numValues)
  {
    this->Words.assign(numValues / 64, 0);
    return r.Bytes(this->Words.data(), numValues / 8);
  }
  std::uint32_t CountOn() const
  {
    std::uint32_t n = 0;
    for (std::uint64_t w : this->Words)
    {
      n += static_cast<std::uint32_t>(std::bitset<64>(w).count());
    }
    return n;
  }
  bool IsOn(std::uint32_t i) const { return (this->Words[i >> 6] >> (i & 63)) & 1u; }
};

class Walk
{
public:
  Walk(BoundedReader& r, const TreeBlocks& grid, std::string& why)
    : R(r)
    , ValueBytes(grid.IsDouble ? sizeof(double) : sizeof(float))
    , StoredBytes(grid.SavedAsHalf ? 2 : this->ValueBytes)
    , Compression(grid.Compression)
    , Why(why)
  {
  }

  // io::readCompressedValues of a node with @a numValues values, @a active of them active.
  bool Values(std::uint32_t numValues, std::uint32_t active)
  {
    std::int8_t metadata = 0;
    if (!this->R.Value(metadata))
    {
      return this->Fail("a value block's header runs past its section");
    }
    // NO_MASK_AND_ONE_INACTIVE_VAL, MASK_AND_ONE_INACTIVE_VAL, MASK_AND_TWO_INACTIVE_VALS: one
    // or two inactive values (full size); MASK_AND_*: a selection mask.
    const bool oneInactive = metadata == 2 || metadata == 4 || metadata == 5;
    const bool selection = metadata == 3 || metadata == 4 || metadata == 5;
    if ((oneInactive && !this->R.Bytes(nullptr, this->ValueBytes)) ||
      (metadata == 5 && !this->R.Bytes(nullptr, this->ValueBytes)) ||
      (selection && !this->R.Bytes(nullptr, numValues / 8)))
    {
      return this->Fail("a value block's inactive values run past its section");
    }
    const bool maskCompressed = (this->Compression & openvdb::io::COMPRESS_ACTIVE_MASK) != 0;
    const std::uint64_t count = (maskCompressed && metadata != 6) ? active : numValues;
    const std::uint64_t bytes = count * this->StoredBytes;
    if (this->StoredBytes == 2 && count == 0)
    {
      return true; // HalfReader reads nothing at all for no values
    }
    if ((this->Compression & (openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ZIP)) == 0)
    {
      return this->R.Bytes(nullptr, bytes) || this->Fail("a raw value block runs past its section");
    }
    std::int64_t stored = 0;
    if (!this->R.Value(stored))
    {
      return this->Fail("a value block's size runs past its section");
    }
    if (stored <= 0)
    {
      // Stored uncompressed: OpenVDB 10.0 reads the declared size into a buffer of `bytes`.
      const std::uint64_t size = 0 - static_cast<std::uint64_t>(stored);
      if (size != bytes)
      {
        return this->Fail("an uncompressed value block declares " + std::to_string(size) +
          " bytes for " + std::to_string(count) + " values of " +
          std::to_string(this->StoredBytes) + " bytes");
      }
      return this->R.Bytes(nullptr, size) ||
        this->Fail("an uncompressed value block runs past its section");
    }
    return this->R.Bytes(nullptr, static_cast<std::uint64_t>(stored)) ||
      this->Fail("a compressed value block of " + std::to_string(stored) +
        " bytes runs past its section");
  }

  // InternalNode/LeafNode::readTopology; appends each leaf's number of active values, in the
  // order readBuffers visits the leaves.
  bool Topology(int level, std::vector<std::uint16_t>& leaves)
  {
    if (level == 0)
    {
      Mask values;
      if (!values.Read(this->R, LeafT::NUM_VALUES))
      {
        return this->Fail("a leaf's mask runs past the topology");
      }
      leaves.push_back(static_cast<std::uint16_t>(values.CountOn()));
      return true;
    }
    const std::uint32_t numValues = level == 2 ? UpperT::NUM_VALUES : LowerT::NUM_VALUES;
    Mask children, values;
    if (!children.Read(this->R, numValues) || !values.Read(this->R, numValues))
    {
      return this->Fail("an internal node's masks run past the topology");
    }
    if (!this->Values(numValues, values.CountOn()))
    {
      return false;
    }
    for (std::uint32_t i = 0; i < numValues; ++i)
    {
      if (children.IsOn(i) && !this->Topology(level - 1, leaves))
      {
        return false;
      }
    }
    return true;
  }

  bool Fail(const std::string& what)
  {
    if (this->Why.empty())
    {
      this->Why = what;
    }
    return false;
  }

  BoundedReader& R;
  const std::uint64_t ValueBytes;
  const std::uint64_t StoredBytes;
  const std::uint32_t Compression;
  std::string& Why;
};

} // namespace

//------------------------------------------------------------------------------
bool CheckTreeBlocks(std::ifstream& in, const TreeBlocks& grid, std::string& why)
{
  why.clear();
  // The transform, between the metadata and the topology, is parsed by OpenVDB itself (its size
  // depends on the map type; only fixed-size reads).
  in.clear();
  in.seekg(static_cast<std::streamoff>(grid.TransformPos));
  openvdb::io::setVersion(
    in, openvdb::VersionId(grid.LibraryMajor, grid.LibraryMinor), grid.FileVersion);
  openvdb::math::Transform transform;
  transform.read(in);
  const std::streamoff topology = in ? static_cast<std::streamoff>(in.tellg()) : -1;
  if (topology < 0 || static_cast<std::uint64_t>(topology) > grid.BlockPos)
  {
    why = "its transform runs past its data block";
    return false;
  }

  // Tree::readTopology's buffer count, then RootNode::readTopology: background, numbers of tiles
  // and children (OpenVDB loops over both without checking its stream: fuzz_openvdb_reader had 4
  // billion tiles), the tiles, then each child's origin and subtree.
  BoundedReader r(in, grid.BlockPos);
  r.Position = static_cast<std::uint64_t>(topology);
  Walk walk(r, grid, why);
  std::int32_t buffers = 0;
  std::uint32_t tiles = 0, children = 0;
  if (!r.Value(buffers) || !r.Bytes(nullptr, walk.ValueBytes) || !r.Value(tiles) ||
    !r.Value(children))
  {
    why = "its topology runs past its data block";
    return false;
  }
  const std::uint64_t tileBytes = 3 * sizeof(std::int32_t) + walk.ValueBytes + 1;
  const std::uint64_t childBytes = 3 * sizeof(std::int32_t) + 2 * (UpperT::NUM_VALUES / 8);
  if (tiles * tileBytes + children * childBytes > r.Left())
  {
    why = "its root declares " + std::to_string(tiles) + " tiles and " +
      std::to_string(children) + " child nodes, more than the " + std::to_string(r.Left()) +
      " bytes before its data block hold";
    return false;
  }
  r.Bytes(nullptr, tiles * tileBytes);
  // The root keeps its children in a map by origin (a repeated origin replaces the earlier
  // child) and reads their buffers in the map's order.
  std::map<std::array<std::int32_t, 3>, std::vector<std::uint16_t>> table;
  for (std::uint32_t c = 0; c < children; ++c)
  {
    std::array<std::int32_t, 3> origin;
    std::vector<std::uint16_t> leaves;
    if (!r.Value(origin) || !walk.Topology(2, leaves))
    {
      return walk.Fail("its topology runs past its data block");
    }
    table[origin] = std::move(leaves);
  }

  // readBuffers continues where the topology ended: per leaf its value mask (seeked over; the
  // topology's mask counts) and its values.
  r.Limit = grid.EndPos;
  for (const auto& node : table)
  {
    for (std::uint16_t active : node.second)
    {
      if (!r.Bytes(nullptr, LeafT::NUM_VALUES / 8) || !walk.Values(LeafT::NUM_VALUES, active))
      {
        return walk.Fail("a leaf's data runs past the grid's end");
      }
    }
  }
  return true;
}

} // namespace ptv
