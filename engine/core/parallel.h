// The engine's parallel loop: oneTBB's parallel_for, with its fork and join made visible to ThreadSanitizer.
//
// Debian's libtbb is not built with TSan, so TSan cannot see what parallel_for guarantees: the bodies start
// after everything the caller did before the loop, and the loop returns after every body has returned. It
// then reports the caller's later reads of what the bodies wrote (and the bodies' reads of what the caller
// wrote) as races. In TSan builds each body acquires what the caller released just before the loop and
// releases what the caller acquires just after it: exactly those two edges, nothing else (a race between two
// bodies is still reported). In other builds the annotations compile to nothing.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <cstddef>
#include <thread>

#if defined(__SANITIZE_THREAD__)
#define SEMAP_TSAN_ANNOTATIONS 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define SEMAP_TSAN_ANNOTATIONS 1
#endif
#endif

#ifdef SEMAP_TSAN_ANNOTATIONS
#include <sanitizer/tsan_interface.h>
#endif

namespace semap {
namespace core_internal {

inline void Release([[maybe_unused]] void* edge) {
#ifdef SEMAP_TSAN_ANNOTATIONS
  __tsan_release(edge);
#endif
}

inline void Acquire([[maybe_unused]] void* edge) {
#ifdef SEMAP_TSAN_ANNOTATIONS
  __tsan_acquire(edge);
#endif
}

}  // namespace core_internal

// Calls body(first, last) on disjoint sub-ranges [first, last) covering [begin, end), each of about `grain`
// indices or more, in parallel on TBB's workers (and the calling thread); returns when every call has
// returned. The bodies run concurrently: each may write only what its own indices own. Thread-safe.
template <typename Index, typename Body>
void ParallelFor(Index begin, Index end, std::size_t grain, const Body& body) {
  // Two addresses naming the edges for TSan: caller → bodies (fork) and bodies → caller (join).
  char fork = 0, join = 0;
  core_internal::Release(&fork);
  tbb::parallel_for(tbb::blocked_range<Index>(begin, end, grain), [&](const tbb::blocked_range<Index>& r) {
    core_internal::Acquire(&fork);
    body(r.begin(), r.end());
    core_internal::Release(&join);
  });
  core_internal::Acquire(&join);
}

// Calls body() on each of TBB's max_concurrency() threads, the caller's included, starting the workers that
// are not running yet: each of max_concurrency() tasks (TBB's simple partitioner: one task per index) waits
// until all have started, for at most `max_wait`, then calls body(). Returns true when every task saw all
// started within the wait: then no thread ran two, and body() ran once on each thread. ParallelFor's
// guarantees otherwise. Thread-safe.
template <typename Body>
bool OnEveryThread(std::chrono::milliseconds max_wait, const Body& body) {
  const int threads = tbb::this_task_arena::max_concurrency();
  const auto deadline = std::chrono::steady_clock::now() + max_wait;
  std::atomic<int> started{0}, saw_all{0};
  char fork = 0, join = 0;
  core_internal::Release(&fork);
  tbb::parallel_for(
      tbb::blocked_range<int>(0, threads, 1),
      [&](const tbb::blocked_range<int>& r) {
        core_internal::Acquire(&fork);
        for (int i = r.begin(); i != r.end(); ++i) {
          ++started;
          while (started.load() < threads && std::chrono::steady_clock::now() < deadline)
            std::this_thread::yield();
          if (started.load() == threads) ++saw_all;
          body();
        }
        core_internal::Release(&join);
      },
      tbb::simple_partitioner());
  core_internal::Acquire(&join);
  return saw_all.load() == threads;
}

}  // namespace semap
