#include "ptvTestVDBWriters.h"

#include <openvdb/Exceptions.h>
#include <openvdb/openvdb.h>

#include <exception>
#include <mutex>

namespace ptvtest
{
namespace
{
// Run @a body after openvdb::initialize(), turning any exception into @a error after @a context.
template <typename Body>
bool Guard(const std::string& context, std::string& error, Body&& body)
{
  static std::once_flag once;
  try
  {
    std::call_once(once, []() { openvdb::initialize(); });
    return body();
  }
  catch (const std::exception& e)
  {
    error = context + ": " + e.what();
  }
  return false;
}
}

//------------------------------------------------------------------------------
bool WriteTestVectorGrid(const std::string& file, const std::string& vectorGridName,
  const std::string& scalarGridName, std::string& error)
{
  return Guard("cannot write '" + file + "'", error, [&]() {
    openvdb::GridPtrVec vdbGrids;
    openvdb::Vec3SGrid::Ptr vectors = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
    vectors->setName(vectorGridName);
    auto acc = vectors->getAccessor();
    for (int i = 0; i < 4; ++i)
    {
      acc.setValue(openvdb::Coord(i, 2 * i, 1), openvdb::Vec3s(1.0f, float(i), -2.0f));
    }
    vdbGrids.push_back(vectors);
    if (!scalarGridName.empty())
    {
      openvdb::FloatGrid::Ptr scalars = openvdb::FloatGrid::create(0.0f);
      scalars->setName(scalarGridName);
      scalars->setGridClass(openvdb::GRID_FOG_VOLUME);
      auto sacc = scalars->getAccessor();
      for (int i = 0; i < 3; ++i)
      {
        sacc.setValue(openvdb::Coord(i, i, i), 1.0f + float(i));
      }
      vdbGrids.push_back(scalars);
    }
    openvdb::io::File(file).write(vdbGrids);
    return true;
  });
}

//------------------------------------------------------------------------------
bool WriteTestTransformedGrid(const std::string& file, const std::string& gridName,
  const std::string& transform, std::string& error)
{
  return Guard("cannot write '" + file + "'", error, [&]() {
    openvdb::math::Transform::Ptr xform;
    if (transform == "nonuniform")
    {
      xform = openvdb::math::Transform::createLinearTransform(1.0);
      xform->preScale(openvdb::Vec3d(1.0, 2.0, 1.0));
    }
    else if (transform == "rotated")
    {
      xform = openvdb::math::Transform::createLinearTransform(0.5);
      xform->postRotate(0.25 * openvdb::math::pi<double>(), openvdb::math::Z_AXIS);
    }
    else if (transform == "frustum")
    {
      xform = openvdb::math::Transform::createFrustumTransform(
        openvdb::BBoxd(openvdb::Vec3d(0.0), openvdb::Vec3d(8.0)), /*taper=*/0.5, /*depth=*/2.0);
    }
    else
    {
      error = "unknown test transform '" + transform + "'";
      return false;
    }
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
    grid->setName(gridName);
    grid->setTransform(xform);
    auto acc = grid->getAccessor();
    for (int i = 0; i < 3; ++i)
    {
      acc.setValue(openvdb::Coord(i, 1, 2), 1.0f + float(i));
    }
    openvdb::io::File(file).write(openvdb::GridPtrVec{ grid });
    return true;
  });
}

//------------------------------------------------------------------------------
bool WriteTestStorageGrid(const std::string& file, const std::string& gridName,
  unsigned int compression, bool asHalf, std::string& error)
{
  return Guard("cannot write '" + file + "'", error, [&]() {
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
    grid->setName(gridName);
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    grid->setSaveFloatAsHalf(asHalf);
    auto acc = grid->getAccessor();
    for (int k = 0; k < 20; ++k)
    {
      for (int j = 0; j < 20; ++j)
      {
        for (int i = 0; i < 20; ++i)
        {
          const openvdb::Coord ijk(i, j, k);
          const int n = i + 3 * j + 7 * k;
          if (n % 5 == 0)
          {
            acc.setValueOff(ijk, (n % 2) ? 1.0f : -1.0f); // two distinct inactive values
          }
          else
          {
            acc.setValueOn(ijk, 0.25f * float(n % 17)); // exact in half precision
          }
        }
      }
    }
    grid->tree().addTile(1, openvdb::Coord(64, 0, 0), 2.0f, true); // an 8^3 active tile
    openvdb::io::File vdb(file);
    vdb.setCompression(compression);
    vdb.write(openvdb::GridPtrVec{ grid });
    vdb.close();
    return true;
  });
}

} // namespace ptvtest
