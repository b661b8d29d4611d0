/**
 * @file ptvThreads.h
 * @brief Private: the one place that turns a thread-count property into a vtkSMPTools scope.
 *
 * Debian's VTK defaults to the Sequential SMP backend, which would run every loop on one core;
 * unless one thread is asked for, the project's own loops then use "STDThread" (for their own
 * scope only: the application's backend choice is left alone). threads <= 0 means every core.
 */
#ifndef ptvThreads_h
#define ptvThreads_h

#include "vtkSMPTools.h"

#include <algorithm>
#include <string>
#include <thread>

namespace ptv
{
/// Run @a body inside a vtkSMPTools::LocalScope of @a threads threads (<= 0: every core).
template <class Body>
void WithThreads(int threads, const Body& body)
{
  std::string backend = vtkSMPTools::GetBackend() ? vtkSMPTools::GetBackend() : "Sequential";
  if (backend == "Sequential" && threads != 1)
  {
    backend = "STDThread";
  }
  if (threads <= 0)
  {
    threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  }
  vtkSMPTools::LocalScope(vtkSMPTools::Config{ threads, backend, false }, body);
}

/// The number of threads @a threads stands for (<= 0: every core).
inline int ResolvedThreads(int threads)
{
  return threads > 0 ? threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}
}

#endif
