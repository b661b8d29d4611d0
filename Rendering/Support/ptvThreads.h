/**
 * @file ptvThreads.h
 * @brief Private: the project's parallel loops, on one persistent pool of worker threads.
 *
 * Debian's VTK 9.2 runs vtkSMPTools loops on the Sequential backend by default, and its
 * STDThread backend starts and joins a new pool of threads in every For call (about 0.1 ms
 * here). A frame runs a dozen short loops (the denoiser's stages take 0.1-4 ms each at 512^2),
 * so the project's loops share one pool instead: its workers are started on first use, poll for
 * the next loop for 50 us and then sleep on a condition variable (no longer spinning that would
 * take cores from ONNX Runtime), and the calling thread works too, polling as briefly for the
 * workers' last chunks before it sleeps. A loop's chunks are cut into one contiguous share per
 * thread (the calling thread's first); each thread runs its own share from its start, then
 * takes what is left of the others' (work stealing). So consecutive loops over the same rows
 * run most rows on the same core as the loop before, which finds them in its own cache: the
 * bilateral grid's slice, reading the cells its splat wrote, ran 0.4 ms (25 %) slower on 2
 * threads at 512^2 when any thread could take any rows. Every caller partitions its work
 * so that the result does not depend on which thread runs a chunk, so images are bit-identical
 * for any number of threads. One loop runs on the pool at a time: a loop started while the pool
 * is busy (another render thread, or a loop inside a loop) runs its chunks on its own thread.
 */
#ifndef ptvThreads_h
#define ptvThreads_h

#include <algorithm>
#include <cstddef>
#include <thread>

namespace ptv
{
/**
 * The cores this process may run on: its CPU affinity mask where the system has one (mpirun
 * binds each rank to a core by default; containers and taskset limit it too), else every core;
 * at least 1. Read once.
 */
int AvailableCores();

/// The number of threads @a threads stands for (<= 0: every available core).
inline int ResolvedThreads(int threads)
{
  return threads > 0 ? threads : AvailableCores();
}

/// Calls @a call(@a context, c) for every chunk c in [0, @a chunks) on up to @a threads threads
/// (<= 0: every core), the calling thread included; returns when every chunk has run.
void RunChunks(int threads, std::size_t chunks, void (*call)(const void*, std::size_t),
  const void* context);

/**
 * Calls @a body(first, last) over [@a begin, @a end) in ranges of @a grain items (the last one
 * shorter) on up to @a threads threads (<= 0: every core). @a grain <= 0 picks about four ranges
 * per thread.
 */
template <class Index, class Body>
void ParallelFor(int threads, Index begin, Index end, Index grain, const Body& body)
{
  if (end <= begin)
  {
    return;
  }
  const std::size_t n = static_cast<std::size_t>(end - begin);
  std::size_t g = grain > 0 ? static_cast<std::size_t>(grain) : 0;
  if (g == 0)
  {
    const std::size_t parts = 4 * static_cast<std::size_t>(ResolvedThreads(threads));
    g = std::max<std::size_t>(1, (n + parts - 1) / parts);
  }
  struct Context
  {
    Index Begin;
    std::size_t Count, Grain;
    const Body* Run;
  } context{ begin, n, g, &body };
  RunChunks(threads, (n + g - 1) / g,
    [](const void* p, std::size_t chunk)
    {
      const Context& c = *static_cast<const Context*>(p);
      const std::size_t first = chunk * c.Grain;
      const std::size_t last = std::min(c.Count, first + c.Grain);
      (*c.Run)(static_cast<Index>(c.Begin + static_cast<Index>(first)),
        static_cast<Index>(c.Begin + static_cast<Index>(last)));
    },
    &context);
}
}

#endif
