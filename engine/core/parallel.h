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

#include <cstddef>

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

// Calls body(i) for each i in [begin, end), every index a task of its own (TBB's simple partitioner, grain
// 1), with ParallelFor's guarantees: for loops whose bodies must not be batched onto one thread (e.g. one
// per thread, each waiting for the others). Thread-safe.
template <typename Index, typename Body>
void ParallelForEachIndex(Index begin, Index end, const Body& body) {
  char fork = 0, join = 0;
  core_internal::Release(&fork);
  tbb::parallel_for(
      tbb::blocked_range<Index>(begin, end, 1),
      [&](const tbb::blocked_range<Index>& r) {
        core_internal::Acquire(&fork);
        for (Index i = r.begin(); i != r.end(); ++i) body(i);
        core_internal::Release(&join);
      },
      tbb::simple_partitioner());
  core_internal::Acquire(&join);
}

}  // namespace semap
