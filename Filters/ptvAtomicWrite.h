/**
 * @file ptvAtomicWrite.h
 * @brief Private: write a file through a temporary beside it and rename it into place, so that a
 *        failed or interrupted write never leaves a truncated file or a stray temporary.
 *
 * The one scheme both writers use (vtkPTVEXRPassWriter, vtkPTVOpenVDBWriter via ptvOpenVDBGrid):
 * an exclusive new file ".<name>.tmp-<pid>-<n>-<t>" in the target's folder (mode 0666 less the
 * umask, as the final file would get), written by the caller, then std::rename onto the target
 * (atomic within one file system).
 */
#ifndef ptvAtomicWrite_h
#define ptvAtomicWrite_h

#include <functional>
#include <string>

namespace ptv
{
/// Which step of WriteAtomically() failed.
enum class WriteStep
{
  None,   ///< success
  Create, ///< the temporary could not be created (the OS reason is in the error)
  Write,  ///< the caller's write threw (its message is the error)
  Rename  ///< the temporary could not be renamed onto the target
};

/**
 * Call @a write with the path of a new, empty temporary file beside @a file; when it returns,
 * rename the temporary onto @a file. On failure (creation, an exception from @a write, rename)
 * the temporary is removed and @a error says why ("cannot create a temporary file in 'dir':
 * ...", the exception's text, "cannot rename 'tmp' to it: ..."); the return value says which
 * step failed.
 */
WriteStep WriteAtomically(const std::string& file,
  const std::function<void(const std::string& temporary)>& write, std::string& error);
}

#endif
