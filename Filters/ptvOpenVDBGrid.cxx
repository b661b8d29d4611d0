// With ptvOpenVDBLayout.cxx, the only translation units that include OpenVDB headers
// (see ptvOpenVDBGrid.h).
#include "ptvOpenVDBGrid.h"
#include "ptvAtomicWrite.h"
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
void InitializeOpenVDB()
{
  static std::once_flag once;
  std::call_once(once, []() { openvdb::initialize(); });
}

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

//------------------------------------------------------------------------------
// Whether openvdb::tools::copyFromDense (tolerance 0) would change a value. It decides with
// math::isApproxEqual(a, b, 0) == !(|a - b| > 0), both for "equals the background" and when it
// merges equal voxels into tiles (LeafNode::isConstant, pruneTiles). That is a == b except
// (1) NaN: |NaN - b| > 0 is false, so a NaN voxel silently became inactive background (found by
// fuzz_vdb_converter) and a leaf starting with NaN would merge into one NaN tile; a NaN
// background made every voxel background; (2) +0 and -0 compare equal, so a leaf mixing them
// merges into one sign. Infinities are exact (Inf - Inf is NaN: "equal"; -Inf vs Inf differ).
template <typename ValueT>
bool NeedsExactCopy(const ValueT* values, std::size_t count, ValueT background)
{
  if (std::isnan(background))
  {
    return true;
  }
  for (std::size_t n = 0; n < count; ++n)
  {
    if (std::isnan(values[n]) || (values[n] == 0 && std::signbit(values[n])))
    {
      return true;
    }
  }
  return false;
}

//------------------------------------------------------------------------------
template <typename GridT>
openvdb::GridBase::Ptr MakeGrid(
  const std::string& name, const DenseVolume& volume, double background)
{
  using ValueT = typename GridT::ValueType;
  typename GridT::Ptr grid = GridT::create(static_cast<ValueT>(background));
  const openvdb::Coord lo(volume.IndexMin[0], volume.IndexMin[1], volume.IndexMin[2]);
  const openvdb::Coord hi(lo[0] + volume.Dims[0] - 1, lo[1] + volume.Dims[1] - 1,
    lo[2] + volume.Dims[2] - 1);
  const ValueT bg = static_cast<ValueT>(background);
  const ValueT* values = static_cast<const ValueT*>(volume.Data);
  const std::size_t count = volume.GetNumberOfValues();
  if (NeedsExactCopy(values, count, bg))
  {
    // Voxel by voxel: every value that is not == background (NaN included) becomes an active
    // voxel holding exactly its bits; no tile merging (see NeedsExactCopy).
    typename GridT::Accessor acc = grid->getAccessor();
    std::size_t n = 0;
    for (int k = 0; k < volume.Dims[2]; ++k)
    {
      for (int j = 0; j < volume.Dims[1]; ++j)
      {
        for (int i = 0; i < volume.Dims[0]; ++i, ++n)
        {
          if (!(values[n] == bg))
          {
            acc.setValueOn(openvdb::Coord(lo[0] + i, lo[1] + j, lo[2] + k), values[n]);
          }
        }
      }
    }
  }
  else
  {
    // copyFromDense only reads the values; Dense has no read-only flavour.
    openvdb::tools::Dense<ValueT, openvdb::tools::LayoutXYZ> dense(
      openvdb::CoordBBox(lo, hi), static_cast<ValueT*>(const_cast<void*>(volume.Data)));
    // Tolerance 0: exactly the background value becomes inactive background.
    openvdb::tools::copyFromDense(dense, *grid, static_cast<ValueT>(0));
  }

  // index -> world: world = Origin + (ijk - IndexMin) * s = ijk * s + (Origin - IndexMin * s).
  const double s = volume.Spacing[0];
  openvdb::math::Transform::Ptr xform = openvdb::math::Transform::createLinearTransform(s);
  xform->postTranslate(openvdb::Vec3d(volume.Origin[0] - volume.IndexMin[0] * s,
    volume.Origin[1] - volume.IndexMin[1] * s, volume.Origin[2] - volume.IndexMin[2] * s));
  grid->setTransform(xform);
  grid->setGridClass(openvdb::GRID_FOG_VOLUME);
  grid->setName(name);
  return grid;
}

//------------------------------------------------------------------------------
bool CheckVolumeToWrite(const std::string& file, const std::string& name,
  const DenseVolume& volume, std::string& error)
{
  const std::string where = "cannot write grid " + Quote(name) + " to " + Quote(file) + ": ";
  if (volume.GetNumberOfValues() == 0 || !volume.Data)
  {
    error = where + "the volume is empty";
    return false;
  }
  const double s = volume.Spacing[0];
  if (!(s > 0.0) || !std::isfinite(s))
  {
    std::ostringstream msg;
    msg << where << "the spacing must be positive (got " << s << ")";
    error = msg.str();
    return false;
  }
  for (int c = 1; c < 3; ++c)
  {
    if (!(std::abs(volume.Spacing[c] - s) <= 1e-6 * s))
    {
      std::ostringstream msg;
      msg << where << "non-uniform spacing (" << volume.Spacing[0] << ", " << volume.Spacing[1]
          << ", " << volume.Spacing[2]
          << ") cannot be represented: OpenVDB voxels have the same size along x, y and z";
      error = msg.str();
      return false;
    }
  }
  return true;
}

//------------------------------------------------------------------------------
// Write @a grids to a temporary file beside @a file, then rename it into place.
bool WriteGridsAtomically(
  const std::string& file, const openvdb::GridPtrVec& grids, std::string& error)
{
  if (file.empty())
  {
    error = "no file name given";
    return false;
  }
  const WriteStep failed = WriteAtomically(file,
    [&](const std::string& tmp)
    {
      openvdb::io::File out(tmp);
      out.write(grids);
      out.close();
    },
    error);
  if (failed != WriteStep::None)
  {
    error = "cannot write " + Quote(file) + ": " + error;
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
// Run @a body, turning any exception into @a error prefixed with @a context.
template <typename Body>
bool Guard(const std::string& context, std::string& error, Body&& body)
{
  try
  {
    InitializeOpenVDB();
    return body();
  }
  catch (const openvdb::Exception& e)
  {
    error = context + ": " + e.what();
  }
  catch (const std::exception& e)
  {
    error = context + ": " + e.what();
  }
  catch (...)
  {
    error = context + ": unknown error";
  }
  return false;
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

//------------------------------------------------------------------------------
bool WriteScalarGrid(const std::string& file, const std::string& gridName,
  const DenseVolume& volume, double background, std::string& error)
{
  return WriteScalarGrids(file, { { gridName, &volume } }, background, error);
}

//------------------------------------------------------------------------------
bool WriteScalarGrids(const std::string& file,
  const std::vector<std::pair<std::string, const DenseVolume*>>& grids, double background,
  std::string& error)
{
  if (grids.empty())
  {
    error = "cannot write " + Quote(file) + ": no grid given";
    return false;
  }
  for (const auto& entry : grids)
  {
    if (!entry.second)
    {
      error = "cannot write grid " + Quote(entry.first) + " to " + Quote(file) + ": no volume";
      return false;
    }
    if (!CheckVolumeToWrite(file, entry.first, *entry.second, error))
    {
      return false;
    }
  }
  return Guard("cannot write " + Quote(file), error, [&]() {
    openvdb::GridPtrVec vdbGrids;
    for (const auto& entry : grids)
    {
      const DenseVolume& volume = *entry.second;
      vdbGrids.push_back(volume.IsDouble
          ? MakeGrid<openvdb::DoubleGrid>(entry.first, volume, background)
          : MakeGrid<openvdb::FloatGrid>(entry.first, volume, background));
    }
    return WriteGridsAtomically(file, vdbGrids, error);
  });
}

} // namespace ptv
