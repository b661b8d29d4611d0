// The plugin's parallel loops (ptvThreads.h): every index runs exactly once in ranges of the
// asked grain, for any size, grain and thread count; two chunks really run at the same time on
// two threads; a loop inside a loop and loops started from two threads at once complete with
// the right result (they run inline while the pool is busy); each thread starts on its own
// share of a loop. Runs under ThreadSanitizer too
// (scripts/sanitize.sh --thread).
#include "ptvTestCheck.h"
#include "ptvThreads.h"

#include <atomic>
#include <chrono>
#include <cstddef>
#include <string>
#include <thread>
#include <vector>

namespace
{
void TestCoverage()
{
  for (int threads : { 0, 1, 2, 3, 8 })
  {
    for (int n : { 0, 1, 2, 7, 1000 })
    {
      for (int grain : { 0, 1, 3, 64 })
      {
        std::vector<std::atomic<int>> visits(static_cast<std::size_t>(n));
        std::atomic<int> tooLong{ 0 }, outside{ 0 };
        const int base = 5; // a range that does not start at 0
        ptv::ParallelFor(threads, base, base + n, grain,
          [&](int first, int last)
          {
            if (grain > 0 && last - first > grain)
            {
              ++tooLong;
            }
            for (int i = first; i < last; ++i)
            {
              if (i < base || i >= base + n)
              {
                ++outside;
                continue;
              }
              ++visits[static_cast<std::size_t>(i - base)];
            }
          });
        bool once = true;
        for (const auto& v : visits)
        {
          once = once && v.load() == 1;
        }
        const std::string what = "threads " + std::to_string(threads) + ", n " +
          std::to_string(n) + ", grain " + std::to_string(grain);
        Check(once, what + ": every index exactly once");
        Check(tooLong.load() == 0, what + ": no range longer than the grain");
        Check(outside.load() == 0, what + ": no index outside the range");
      }
    }
  }
  // std::size_t indices, as the per-pixel loops use them.
  std::atomic<std::size_t> sum{ 0 };
  ptv::ParallelFor(2, std::size_t(0), std::size_t(100000), std::size_t(4096),
    [&](std::size_t first, std::size_t last)
    {
      std::size_t s = 0;
      for (std::size_t i = first; i < last; ++i)
      {
        s += i;
      }
      sum += s;
    });
  Check(sum.load() == std::size_t(100000) * 99999 / 2, "size_t range: sum of its indices");
}

// A rendezvous of two chunks: counts this one in and waits until two have come (false after
// 20 s: they did not run at the same time).
bool MeetTheOther(std::atomic<int>& started)
{
  ++started;
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (started.load() < 2)
  {
    if (std::chrono::steady_clock::now() > until)
    {
      return false;
    }
    std::this_thread::yield();
  }
  return true;
}

// Chunk 0 waits until chunk 1 has started and the other way round: only two threads running at
// once get past it (a sequential loop would wait out the timeout).
void TestRunsInParallel()
{
  std::atomic<int> started{ 0 };
  std::atomic<bool> timedOut{ false };
  ptv::ParallelFor(2, 0, 2, 1,
    [&](int, int)
    {
      if (!MeetTheOther(started))
      {
        timedOut = true;
      }
    });
  Check(!timedOut.load(), "two chunks run at the same time on two threads");
}

void TestNestedAndConcurrent()
{
  // A loop inside a loop runs on the chunk's own thread.
  std::atomic<int> inner{ 0 };
  ptv::ParallelFor(2, 0, 8, 1,
    [&](int, int) { ptv::ParallelFor(2, 0, 10, 1, [&](int a, int b) { inner += b - a; }); });
  Check(inner.load() == 80, "a loop inside a loop visits every inner index once per outer one");

  // Two threads start loops at the same time, many times: one gets the pool, the other runs its
  // chunks itself; both results are exact.
  std::atomic<int> wrong{ 0 };
  auto loops = [&](int seed)
  {
    for (int rep = 0; rep < 200; ++rep)
    {
      const int n = 50 + (rep * 7 + seed) % 300;
      std::atomic<long> sum{ 0 };
      ptv::ParallelFor(2, 0, n, 0,
        [&](int a, int b)
        {
          long s = 0;
          for (int i = a; i < b; ++i)
          {
            s += i;
          }
          sum += s;
        });
      if (sum.load() != static_cast<long>(n) * (n - 1) / 2)
      {
        ++wrong;
      }
    }
  };
  std::thread a(loops, 1), b(loops, 2);
  a.join();
  b.join();
  Check(wrong.load() == 0, "loops started from two threads at once give exact results");
}

// Each thread runs its own contiguous share of a loop first (ptvThreads.h): with two threads and
// 2 * 32 chunks where chunk 0 and chunk 32 wait for each other, chunk 0 (the first share's
// start) runs on the calling thread and the worker starts with chunk 32 (the second's) -- the
// same worker in every loop, so consecutive loops over the same rows keep them on one core.
void TestShares()
{
  const std::thread::id caller = std::this_thread::get_id();
  std::thread::id firstWorker;
  int callerFirst = 0, sameWorker = 0, workerStarts = 0;
  const int loops = 20;
  for (int rep = 0; rep < loops; ++rep)
  {
    std::thread::id ran[64];
    std::atomic<int> started{ 0 }, workerFirst{ -1 };
    std::atomic<bool> timedOut{ false };
    ptv::ParallelFor(2, 0, 64, 1,
      [&](int a, int)
      {
        ran[a] = std::this_thread::get_id();
        int none = -1;
        if (ran[a] != caller)
        {
          workerFirst.compare_exchange_strong(none, a);
        }
        if ((a == 0 || a == 32) && !MeetTheOther(started))
        {
          timedOut = true;
        }
      });
    Check(!timedOut.load(), "chunks 0 and 32 run at the same time");
    callerFirst += ran[0] == caller;
    if (rep == 0)
    {
      firstWorker = ran[32];
    }
    sameWorker += ran[32] == firstWorker && ran[32] != caller;
    workerStarts += workerFirst.load() == 32;
  }
  Check(callerFirst == loops, "the first share starts on the calling thread: " +
      std::to_string(callerFirst) + " of " + std::to_string(loops) + " loops");
  Check(workerStarts == loops, "the worker's first chunk is its share's first (32): " +
      std::to_string(workerStarts) + " of " + std::to_string(loops) + " loops");
  Check(sameWorker == loops, "the second share runs on the same worker: " +
      std::to_string(sameWorker) + " of " + std::to_string(loops) + " loops");
}
}

int TestPTVThreads(int, char*[])
{
  TestCoverage();
  TestRunsInParallel();
  TestShares();
  TestNestedAndConcurrent();
  return TestResult();
}
