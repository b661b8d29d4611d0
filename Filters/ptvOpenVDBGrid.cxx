// Reading OpenVDB grids (ptvOpenVDBGrid.h); with ptvOpenVDBWrite.cxx and
// Validators/ptvOpenVDBLayout.cxx, the only translation units that include OpenVDB headers.
#include "ptvOpenVDBGrid.h"
#include "ptvOpenVDBGuard.h"
#include "Validators/ptvOpenVDBLayout.h"
#include "ptvQuote.h"

#include <openvdb/Exceptions.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Dense.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <cstdint>
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
std::string Where(const std::string& file, const std::string& gridName)
{
  return "grid " + Quote(gridName) + " of file " + Quote(file);
}

//------------------------------------------------------------------------------
// Check that the file can be opened for reading before handing it to OpenVDB, whose own message
// for a missing file does not say why.
bool CheckReadable(const std::string& file, std::string& error)
{
  if (file.empty())
  {
    error = "no file name given";
    return false;
  }
  std::error_code ec;
  const std::filesystem::path path(file);
  if (!std::filesystem::exists(path, ec))
  {
    error = "file " + Quote(file) + " does not exist";
    return false;
  }
  if (std::filesystem::is_directory(path, ec))
  {
    error = Quote(file) + " is a directory, not an OpenVDB file";
    return false;
  }
  std::FILE* probe = std::fopen(file.c_str(), "rb");
  if (!probe)
  {
    error = "cannot open file " + Quote(file) + ": " + std::strerror(errno);
    return false;
  }
  std::fclose(probe);
  return CheckOpenVDBLayout(file, error);
}

//------------------------------------------------------------------------------
// Opens a VDB file without delayed loading (no memory mapping, so a truncated file fails while
// reading instead of later, on first access to the voxels).
struct OpenFile
{
  explicit OpenFile(const std::string& file)
    : File(file)
  {
    this->File.open(/*delayLoad=*/false);
  }
  ~OpenFile()
  {
    try
    {
      if (this->File.isOpen())
      {
        this->File.close();
      }
    }
    catch (...)
    {
    }
  }
  OpenFile(const OpenFile&) = delete;
  OpenFile& operator=(const OpenFile&) = delete;

  openvdb::io::File File;
};

//------------------------------------------------------------------------------
GridInfo MakeGridInfo(const openvdb::GridBase& grid)
{
  GridInfo info;
  info.Name = grid.getName();
  info.ValueType = grid.valueType();
  info.GridClass = openvdb::GridBase::gridClassToString(grid.getGridClass());
  if (auto count =
        grid.getMetadata<openvdb::Int64Metadata>(openvdb::GridBase::META_FILE_VOXEL_COUNT))
  {
    info.ActiveVoxelCount = static_cast<long long>(count->value());
  }
  auto bmin = grid.getMetadata<openvdb::Vec3IMetadata>(openvdb::GridBase::META_FILE_BBOX_MIN);
  auto bmax = grid.getMetadata<openvdb::Vec3IMetadata>(openvdb::GridBase::META_FILE_BBOX_MAX);
  if (bmin && bmax)
  {
    info.HasBBox = true;
    for (int c = 0; c < 3; ++c)
    {
      info.BBoxMin[c] = bmin->value()[c];
      info.BBoxMax[c] = bmax->value()[c];
    }
  }
  return info;
}

//------------------------------------------------------------------------------
std::vector<GridInfo> ListOpenFile(openvdb::io::File& vdb)
{
  std::vector<GridInfo> grids;
  openvdb::GridPtrVecPtr metas = vdb.readAllGridMetadata();
  if (metas)
  {
    for (const auto& grid : *metas)
    {
      if (grid)
      {
        grids.push_back(MakeGridInfo(*grid));
      }
    }
  }
  return grids;
}

//------------------------------------------------------------------------------
// Find @a gridName among the grids of the open @a vdb (of @a file) and check that it is a scalar
// grid.
bool FindScalarGrid(openvdb::io::File& vdb, const std::string& file, const std::string& gridName,
  GridInfo& found, std::string& error)
{
  const std::vector<GridInfo> grids = ListOpenFile(vdb);
  auto it = std::find_if(grids.begin(), grids.end(),
    [&gridName](const GridInfo& info) { return info.Name == gridName; });
  if (it == grids.end())
  {
    error = "no grid named " + Quote(gridName) + " in file " + Quote(file) +
      "; available grids: " + DescribeGrids(grids);
    return false;
  }
  if (!it->IsScalar())
  {
    error = "grid " + Quote(gridName) + " of file " + Quote(file) + " is of type " +
      it->ValueType + "; only scalar float/double grids are supported";
    return false;
  }
  found = *it;
  return true;
}

//------------------------------------------------------------------------------
// Uniform voxel size of @a grid's transform, or false (with a message naming the transform) for
// non-linear, rotated, sheared, mirrored or non-uniformly scaled transforms.
bool UniformVoxelSize(const openvdb::GridBase& grid, const std::string& file, double& voxelSize,
  std::string& error)
{
  const openvdb::math::Transform& xform = grid.constTransform();
  const std::string where = Where(file, grid.getName());
  if (!xform.isLinear())
  {
    error = where + " uses a non-linear transform (" + xform.mapType() +
      "); only uniform-scale linear transforms are supported";
    return false;
  }
  const openvdb::Mat4d m = xform.baseMap()->getAffineMap()->getMat4();
  const double s = m[0][0];
  bool uniform = std::isfinite(s) && s > 0.0;
  for (int r = 0; r < 3 && uniform; ++r)
  {
    for (int c = 0; c < 3 && uniform; ++c)
    {
      const double expected = (r == c) ? s : 0.0;
      uniform = std::abs(m[r][c] - expected) <= 1e-9 * s;
    }
  }
  if (!uniform)
  {
    const openvdb::Vec3d vs = xform.voxelSize();
    std::ostringstream msg;
    msg << where << " has a transform of type " << xform.mapType() << " (voxel size " << vs[0]
        << " x " << vs[1] << " x " << vs[2]
        << ") that is not a uniform scale plus translation (non-uniform, rotated, sheared or "
           "mirrored); only uniform-scale linear transforms are supported";
    error = msg.str();
    return false;
  }
  voxelSize = s;
  return true;
}

//------------------------------------------------------------------------------
void SetWorldGeometry(const openvdb::GridBase& grid, double voxelSize, DenseVolume& volume)
{
  const openvdb::Vec3d origin = grid.constTransform().indexToWorld(
    openvdb::Coord(volume.IndexMin[0], volume.IndexMin[1], volume.IndexMin[2]));
  for (int c = 0; c < 3; ++c)
  {
    volume.Origin[c] = origin[c];
    volume.Spacing[c] = voxelSize;
  }
}

//------------------------------------------------------------------------------
template <typename GridT>
void CopyToDense(const openvdb::GridBase& base, DenseVolume& volume)
{
  using ValueT = typename GridT::ValueType;
  const GridT& grid = static_cast<const GridT&>(base);
  const openvdb::Coord lo(volume.IndexMin[0], volume.IndexMin[1], volume.IndexMin[2]);
  const openvdb::Coord hi(lo[0] + volume.Dims[0] - 1, lo[1] + volume.Dims[1] - 1,
    lo[2] + volume.Dims[2] - 1);
  openvdb::tools::Dense<ValueT, openvdb::tools::LayoutXYZ> dense(
    openvdb::CoordBBox(lo, hi), static_cast<ValueT*>(volume.Data));
  openvdb::tools::copyToDense(grid, dense);
}

// Run @a body(vdb, info) on the scalar grid @a gridName of @a file, opened, found and checked
// (FindScalarGrid), inside Guard: how every read of one grid starts.
template <typename Body>
bool WithScalarGrid(
  const std::string& file, const std::string& gridName, std::string& error, Body&& body)
{
  return Guard("cannot read " + Where(file, gridName), error, [&]() {
    OpenFile vdb(file);
    GridInfo info;
    return FindScalarGrid(vdb.File, file, gridName, info, error) && body(vdb, info);
  });
}

} // anonymous namespace

//------------------------------------------------------------------------------
std::size_t DenseVolume::GetNumberOfValues() const
{
  if (this->Dims[0] <= 0 || this->Dims[1] <= 0 || this->Dims[2] <= 0)
  {
    return 0;
  }
  return static_cast<std::size_t>(this->Dims[0]) * static_cast<std::size_t>(this->Dims[1]) *
    static_cast<std::size_t>(this->Dims[2]);
}

//------------------------------------------------------------------------------
bool CanOpenFile(const std::string& file)
{
  std::string error;
  if (!CheckReadable(file, error))
  {
    return false;
  }
  return Guard("", error, [&]() {
    OpenFile vdb(file);
    return vdb.File.isOpen();
  });
}

//------------------------------------------------------------------------------
bool ListGrids(const std::string& file, std::vector<GridInfo>& grids, std::string& error)
{
  grids.clear();
  if (!CheckReadable(file, error))
  {
    return false;
  }
  return Guard("cannot read OpenVDB file " + Quote(file), error, [&]() {
    OpenFile vdb(file);
    grids = ListOpenFile(vdb.File);
    return true;
  });
}

//------------------------------------------------------------------------------
std::string DescribeGrids(const std::vector<GridInfo>& grids)
{
  if (grids.empty())
  {
    return "(none)";
  }
  std::string text;
  for (const GridInfo& info : grids)
  {
    if (!text.empty())
    {
      text += ", ";
    }
    text += Quote(info.Name) + " (" + info.ValueType + ")";
  }
  return text;
}

//------------------------------------------------------------------------------
bool ReadScalarGridInfo(
  const std::string& file, const std::string& gridName, DenseVolume& volume, std::string& error)
{
  if (!CheckReadable(file, error))
  {
    return false;
  }
  return WithScalarGrid(file, gridName, error, [&](OpenFile& vdb, const GridInfo& info) {
    openvdb::GridBase::Ptr meta = vdb.File.readGridMetadata(gridName);
    double voxelSize = 1.0;
    if (!UniformVoxelSize(*meta, file, voxelSize, error))
    {
      return false;
    }

    openvdb::CoordBBox bbox;
    if (info.ActiveVoxelCount >= 0 && info.HasBBox)
    {
      if (info.ActiveVoxelCount == 0)
      {
        error = Where(file, gridName) + " is empty (it has no active voxels)";
        return false;
      }
      bbox = openvdb::CoordBBox(openvdb::Coord(info.BBoxMin[0], info.BBoxMin[1], info.BBoxMin[2]),
        openvdb::Coord(info.BBoxMax[0], info.BBoxMax[1], info.BBoxMax[2]));
    }
    else
    {
      // No statistics metadata: read the (sparse) grid to find its active bounding box.
      openvdb::GridBase::Ptr grid = vdb.File.readGrid(gridName);
      if (grid->activeVoxelCount() == 0)
      {
        error = Where(file, gridName) + " is empty (it has no active voxels)";
        return false;
      }
      bbox = grid->evalActiveVoxelBoundingBox();
    }
    if (bbox.empty())
    {
      error = Where(file, gridName) + " is empty (it has no active voxels)";
      return false;
    }

    // In 64 bits: the box comes from the file and may span the whole int32 range, where
    // CoordBBox::dim() and a product of three extents overflow (fuzz_openvdb_reader, UBSan).
    long long dim[3];
    for (int c = 0; c < 3; ++c)
    {
      dim[c] = static_cast<long long>(bbox.max()[c]) - bbox.min()[c] + 1;
      if (dim[c] <= 0 || dim[c] > std::numeric_limits<int>::max())
      {
        std::ostringstream msg;
        msg << Where(file, gridName) << " has an active voxel bounding box that VTK cannot index: "
            << bbox.min() << " to " << bbox.max();
        error = msg.str();
        return false;
      }
      volume.Dims[c] = static_cast<int>(dim[c]);
      volume.IndexMin[c] = bbox.min()[c];
    }
    volume.IsDouble = (info.ValueType == "double");
    SetWorldGeometry(*meta, voxelSize, volume);
    return true;
  });
}

//------------------------------------------------------------------------------
bool ReadScalarGrid(
  const std::string& file, const std::string& gridName, DenseVolume& volume, std::string& error)
{
  if (!CheckReadable(file, error))
  {
    return false;
  }
  if (volume.GetNumberOfValues() == 0 || !volume.Data)
  {
    error = "cannot read " + Where(file, gridName) + ": empty box or no output buffer";
    return false;
  }
  return WithScalarGrid(file, gridName, error, [&](OpenFile& vdb, const GridInfo& info) {
    const bool isDouble = (info.ValueType == "double");
    if (isDouble != volume.IsDouble)
    {
      error = Where(file, gridName) + " is of type " + info.ValueType +
        " but a buffer of another type was given (was the file modified?)";
      return false;
    }
    openvdb::GridBase::Ptr grid = vdb.File.readGrid(gridName);
    double voxelSize = 1.0;
    if (!UniformVoxelSize(*grid, file, voxelSize, error))
    {
      return false;
    }
    if (isDouble && grid->isType<openvdb::DoubleGrid>())
    {
      CopyToDense<openvdb::DoubleGrid>(*grid, volume);
    }
    else if (!isDouble && grid->isType<openvdb::FloatGrid>())
    {
      CopyToDense<openvdb::FloatGrid>(*grid, volume);
    }
    else
    {
      error = Where(file, gridName) + " has an unsupported tree configuration (" + grid->type() +
        "); only the standard FloatGrid and DoubleGrid are supported";
      return false;
    }
    SetWorldGeometry(*grid, voxelSize, volume);
    return true;
  });
}

} // namespace ptv
