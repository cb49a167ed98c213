#include "engine/core/parallel.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <thread>
#include <vector>

namespace semap {
namespace {

// Every index is visited exactly once, each body writing only its own slots.
TEST(ParallelFor, VisitsEveryIndexOnce) {
  std::vector<int> visits(10'001, 0);
  ParallelFor(std::size_t(0), visits.size(), 64, [&](std::size_t first, std::size_t last) {
    for (std::size_t i = first; i != last; ++i) ++visits[i];
  });
  EXPECT_EQ(std::set<int>(visits.begin(), visits.end()), std::set<int>{1});
}

// The body runs once on each of TBB's threads: as many calls as threads, each on a thread of its own.
TEST(OnEveryThread, CallsTheBodyOnceOnEachThread) {
  std::mutex mutex;
  std::set<std::thread::id> ids;
  int calls = 0;
  const bool each_once = OnEveryThread(std::chrono::seconds(5), [&] {
    std::lock_guard<std::mutex> lock(mutex);
    ++calls;
    ids.insert(std::this_thread::get_id());
  });
  const int threads = tbb::this_task_arena::max_concurrency();
  EXPECT_TRUE(each_once);
  EXPECT_EQ(calls, threads);
  EXPECT_EQ(ids.size(), static_cast<std::size_t>(threads));
}

}  // namespace
}  // namespace semap
