/**
 * @file ptvTestVDBWriters.h
 * @brief Shared by the C++ tests: small OpenVDB files of kinds the project's writer never
 *        produces (vector grids, unsupported transforms, every storage compression), for the
 *        reader's tests. Written directly with OpenVDB (not atomically); errors go into @a error.
 */
#ifndef ptvTestVDBWriters_h
#define ptvTestVDBWriters_h

#include <string>

namespace ptvtest
{
/**
 * Write @a file with a small Vec3s grid named @a vectorGridName (a few active
 * voxels) and, when @a scalarGridName is not empty, a small float grid of that name after it.
 */
bool WriteTestVectorGrid(const std::string& file,
  const std::string& vectorGridName, const std::string& scalarGridName, std::string& error);

/**
 * Write @a file with a small float grid named @a gridName whose transform is not
 * supported: @a transform is "nonuniform" (ScaleMap, voxel size 1 x 2 x 1), "rotated"
 * (AffineMap, 45 degrees about z) or "frustum" (NonlinearFrustumMap).
 */
bool WriteTestTransformedGrid(const std::string& file,
  const std::string& gridName, const std::string& transform, std::string& error);

/**
 * Write @a file (directly, not atomically) with a float grid named @a gridName
 * stored with OpenVDB's io::COMPRESS_* flags @a compression (0: raw, 1: zip, 2: active mask,
 * 4: blosc, or'ed), as half floats if @a asHalf (type suffix "_HalfFloat"). The grid: voxels
 * (i, j, k) in [0, 20)^3, inactive with values -1 or +1 where (i + 3j + 7k) % 5 == 0, else active
 * with 0.25 * ((i + 3j + 7k) % 17) (exact as half floats); plus an active 8^3 tile of 2 at
 * (64, 0, 0). Every value block layout of io::readCompressedValues occurs.
 */
bool WriteTestStorageGrid(const std::string& file,
  const std::string& gridName, unsigned int compression, bool asHalf, std::string& error);

}

#endif
