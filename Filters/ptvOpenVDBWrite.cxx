// Writing dense volumes as OpenVDB grids (ptvOpenVDBGrid.h); with ptvOpenVDBGrid.cxx and
// Validators/ptvOpenVDBLayout.cxx, the only translation units that include OpenVDB headers.
#include "ptvAtomicWrite.h"
#include "ptvOpenVDBGrid.h"
#include "ptvOpenVDBGuard.h"
#include "ptvQuote.h"

#include <openvdb/tools/Dense.h>

#include <cmath>
#include <sstream>

namespace ptv
{
namespace
{


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

} // anonymous namespace

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
