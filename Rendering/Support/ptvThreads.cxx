#include "ptvThreads.h"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <vector>

#if defined(__linux__)
#include <sched.h>
#endif

namespace ptv
{
namespace
{
/// True on a thread while it runs a pool's chunk: a loop inside a loop runs on that thread.
thread_local bool tInChunk = false;

/**
 * How long a thread polls before it sleeps on a condition variable: a worker waiting for the
 * next loop, the caller waiting for the workers' last chunks. The denoiser runs about eight
 * loops back to back per frame, 0.1-4 ms each at 512^2; waking a sleeping thread cost about
 * 50 us each time on this VM, twice per loop (0.4 ms of a 7 ms denoise at 512^2). Short enough
 * that a worker idling between two frames, or while ONNX Runtime runs, gives its core back.
 */
constexpr std::chrono::microseconds kSpin(50);

/// Polls @a ready for up to kSpin; whether it became true.
template <class Ready>
bool SpinFor(const Ready& ready)
{
  const auto until = std::chrono::steady_clock::now() + kSpin;
  do
  {
    if (ready())
    {
      return true;
    }
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
  } while (std::chrono::steady_clock::now() < until);
  return ready();
}

/// The shared pool (see ptvThreads.h). One loop (a "job") at a time; workers join a job only
/// while it is open, so the caller never waits for a worker that wakes late.
class Pool
{
public:
  ~Pool()
  {
    {
      std::lock_guard<std::mutex> lock(this->Mutex);
      this->Stop = true;
    }
    this->Wake.notify_all();
    for (std::thread& t : this->Workers)
    {
      t.join();
    }
  }

  void Run(int threads, std::size_t chunks, void (*call)(const void*, std::size_t),
    const void* context)
  {
    if (tInChunk) // never try_lock a mutex this thread may own
    {
      for (std::size_t c = 0; c < chunks; ++c)
      {
        call(context, c);
      }
      return;
    }
    std::unique_lock<std::mutex> busy(this->Busy, std::try_to_lock);
    if (threads <= 1 || chunks <= 1 || !busy.owns_lock())
    {
      for (std::size_t c = 0; c < chunks; ++c)
      {
        call(context, c);
      }
      return;
    }
    const std::size_t helpers = std::min<std::size_t>(threads - 1, chunks - 1);
    while (this->Workers.size() < helpers)
    {
      const int index = static_cast<int>(this->Workers.size());
      this->Workers.emplace_back([this, index]() { this->Work(index); });
    }
    {
      std::lock_guard<std::mutex> lock(this->Mutex);
      this->Call = call;
      this->Context = context;
      this->Chunks = chunks;
      this->Shares = static_cast<int>(std::min<std::size_t>(helpers + 1, kMaxShares));
      for (int s = 0; s < this->Shares; ++s)
      {
        this->ShareBegin[s] = chunks * static_cast<std::size_t>(s) / this->Shares;
        this->Counters[s].Taken.store(0);
      }
      this->ShareBegin[this->Shares] = chunks;
      this->Finished.store(0);
      this->Helpers = static_cast<int>(helpers);
      this->Open = true;
      ++this->Generation;
      this->Published.store(this->Generation); // what polling workers watch
    }
    this->Wake.notify_all();
    this->Drain(0);
    SpinFor([this]() { return this->Finished.load() == this->Chunks && this->Inside.load() == 0; });
    std::unique_lock<std::mutex> lock(this->Mutex);
    this->Done.wait(lock, [this]() { return this->Finished.load() == this->Chunks; });
    this->Open = false; // late workers stay asleep; wait for those inside to leave
    this->Done.wait(lock, [this]() { return this->Inside == 0; });
  }

private:
  /// Runs chunks until none is left: participant @a p's own share first, then the others'.
  void Drain(int p)
  {
    tInChunk = true;
    const int shares = this->Shares;
    for (int k = 0; k < shares; ++k)
    {
      const int s = (p + k) % shares;
      const std::size_t begin = this->ShareBegin[s];
      const std::size_t end = this->ShareBegin[s + 1];
      for (std::size_t c = begin + this->Counters[s].Taken.fetch_add(1); c < end;
           c = begin + this->Counters[s].Taken.fetch_add(1))
      {
        this->Call(this->Context, c);
        if (this->Finished.fetch_add(1) + 1 == this->Chunks)
        {
          std::lock_guard<std::mutex> lock(this->Mutex);
          this->Done.notify_all();
        }
      }
    }
    tInChunk = false;
  }

  void Work(int index)
  {
    unsigned long long seen = 0;
    std::unique_lock<std::mutex> lock(this->Mutex);
    for (;;)
    {
      if (!this->Stop && this->Generation == seen)
      {
        lock.unlock(); // poll for the next loop a moment before sleeping
        SpinFor([&]() { return this->Published.load() != seen; });
        lock.lock();
      }
      this->Wake.wait(lock,
        [&]()
        { return this->Stop || (this->Open && this->Generation != seen && index < this->Helpers); });
      if (this->Stop)
      {
        return;
      }
      seen = this->Generation;
      ++this->Inside;
      lock.unlock();
      this->Drain(index + 1);
      lock.lock();
      if (--this->Inside == 0)
      {
        this->Done.notify_all();
      }
    }
  }

  std::mutex Busy; // held by the thread whose loop runs on the pool
  std::mutex Mutex;
  std::condition_variable Wake, Done;
  std::vector<std::thread> Workers;
  bool Stop = false;
  bool Open = false;
  unsigned long long Generation = 0;
  int Helpers = 0;
  std::atomic<int> Inside{ 0 }; // changed under Mutex, polled without it
  std::atomic<unsigned long long> Published{ 0 }; // Generation, polled without Mutex
  void (*Call)(const void*, std::size_t) = nullptr;
  const void* Context = nullptr;
  std::size_t Chunks = 0;
  // The loop's chunks in Shares contiguous shares, one per participant (the caller is 0, worker
  // i is i + 1; more participants than kMaxShares share them): share s is chunks
  // [ShareBegin[s], ShareBegin[s + 1]), Counters[s].Taken of them handed out so far (it runs
  // past the share's size as threads find it empty). Each counter has a cache line of its own,
  // so that a participant taking chunks of its own share does not write the line another
  // participant's counter is on.
  static constexpr int kMaxShares = 64;
  int Shares = 1;
  std::size_t ShareBegin[kMaxShares + 1] = {};
  struct alignas(64) ShareCounter
  {
    std::atomic<std::size_t> Taken{ 0 };
  };
  ShareCounter Counters[kMaxShares];
  std::atomic<std::size_t> Finished{ 0 };
};
}

//------------------------------------------------------------------------------
int AvailableCores()
{
  static const int cores = []()
  {
    int n = static_cast<int>(std::thread::hardware_concurrency());
#if defined(__linux__)
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof(set), &set) == 0 && CPU_COUNT(&set) > 0)
    {
      n = CPU_COUNT(&set);
    }
#endif
    return std::max(n, 1);
  }();
  return cores;
}

//------------------------------------------------------------------------------
void RunChunks(int threads, std::size_t chunks, void (*call)(const void*, std::size_t),
  const void* context)
{
  static Pool pool;
  pool.Run(ResolvedThreads(threads), chunks, call, context);
}
}
