/**
 * @file ptvOpenVDBGuard.h
 * @brief OpenVDB's one-time initialisation and the exception guard every reader and writer call
 * runs in (private to ptvOpenVDBGrid.cxx and ptvOpenVDBWrite.cxx, the units that include OpenVDB).
 */
#ifndef ptvOpenVDBGuard_h
#define ptvOpenVDBGuard_h

#include <openvdb/Exceptions.h>
#include <openvdb/openvdb.h>

#include <exception>
#include <mutex>
#include <string>

namespace ptv
{
/// openvdb::initialize(), once per process.
inline void InitializeOpenVDB()
{
  static std::once_flag once;
  std::call_once(once, []() { openvdb::initialize(); });
}


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

} // namespace ptv

#endif // ptvOpenVDBGuard_h
