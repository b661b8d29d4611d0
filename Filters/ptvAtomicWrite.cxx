#include "ptvAtomicWrite.h"

#include "ptvQuote.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <exception>

namespace ptv
{
namespace
{
std::string FolderOf(const std::string& file)
{
  const std::string::size_type slash = file.rfind('/');
  if (slash == std::string::npos)
  {
    return ".";
  }
  return slash == 0 ? "/" : file.substr(0, slash);
}

// Create an empty, new temporary file beside @a file. Returns its path, or "" with @a error.
std::string CreateTemporaryFile(const std::string& file, std::string& error)
{
  static std::atomic<unsigned> counter{ 0 };
  const std::string folder = FolderOf(file);
  const std::string::size_type slash = file.rfind('/');
  const std::string base = file.substr(slash == std::string::npos ? 0 : slash + 1);
  const auto ticks = static_cast<unsigned long long>(
    std::chrono::steady_clock::now().time_since_epoch().count());
  for (int attempt = 0; attempt < 100; ++attempt)
  {
    const std::string tmp = folder + "/." + base + ".tmp-" + std::to_string(::getpid()) + "-" +
      std::to_string(counter++) + "-" + std::to_string((ticks + attempt) % 1000000);
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0)
    {
      ::close(fd);
      return tmp;
    }
    if (errno != EEXIST)
    {
      error = "cannot create a temporary file in " + Quote(folder) + ": " + std::strerror(errno);
      return std::string();
    }
  }
  error = "cannot create a temporary file in " + Quote(folder) + ": too many name clashes";
  return std::string();
}
}

//------------------------------------------------------------------------------
WriteStep WriteAtomically(const std::string& file,
  const std::function<void(const std::string& temporary)>& write, std::string& error)
{
  error.clear();
  const std::string tmp = CreateTemporaryFile(file, error);
  if (tmp.empty())
  {
    return WriteStep::Create;
  }
  try
  {
    write(tmp);
  }
  catch (const std::exception& e)
  {
    std::remove(tmp.c_str());
    error = e.what();
    return WriteStep::Write;
  }
  catch (...)
  {
    std::remove(tmp.c_str());
    error = "unknown error";
    return WriteStep::Write;
  }
  if (std::rename(tmp.c_str(), file.c_str()) != 0)
  {
    const int err = errno;
    std::remove(tmp.c_str());
    error = "cannot rename " + Quote(tmp) + " to it: " + std::strerror(err);
    return WriteStep::Rename;
  }
  return WriteStep::None;
}
}
