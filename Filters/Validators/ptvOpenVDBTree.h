/**
 * @file ptvOpenVDBTree.h
 * @brief Walks a float/double grid's tree blocks the way OpenVDB will read them (private).
 *
 * Part of the check run before OpenVDB reads a file (ptvOpenVDBLayout.cxx). OpenVDB 10.0 trusts
 * the counts and block sizes inside a grid's topology and voxel data: the root's tile and child
 * counts drive loops that do not check the stream, and io::bloscFromStream reads an uncompressed
 * block's declared size into its buffer before comparing it with the buffer's size (a heap
 * overflow on a crafted file, found by fuzz_openvdb_reader; upstream now checks first). This
 * walk follows RootNode/InternalNode/LeafNode::readTopology and readBuffers and
 * io::readCompressedValues for the 5-4-3 float and double trees, without allocating anything the
 * file sizes, and checks every count and block against the bytes that hold it.
 */
#ifndef ptvOpenVDBTree_h
#define ptvOpenVDBTree_h

#include <cstdint> // for std::uint32_t
#include <fstream> // for std::ifstream
#include <string>  // for std::string

namespace ptv
{

/// Where one grid lies in the file and how it was written.
struct TreeBlocks
{
  bool IsDouble = false;        ///< Tree_double_5_4_3 (else Tree_float_5_4_3)
  bool SavedAsHalf = false;     ///< type name had the "_HalfFloat" suffix
  std::uint32_t Compression = 0; ///< the grid's io::COMPRESS_* flags
  std::uint32_t FileVersion = 0; ///< format version of the file (>= 222)
  std::uint32_t LibraryMajor = 0, LibraryMinor = 0;
  std::uint64_t TransformPos = 0; ///< offset of the transform (after the grid's metadata)
  std::uint64_t BlockPos = 0;     ///< end of the topology (start of the voxel data)
  std::uint64_t EndPos = 0;       ///< end of the grid
};

/// True when every count and block of the grid's tree fits; otherwise false with @a why.
bool CheckTreeBlocks(std::ifstream& in, const TreeBlocks& grid, std::string& why);

} // namespace ptv

#endif
