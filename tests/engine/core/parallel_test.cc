#include "engine/core/parallel.h"

#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

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

// Each index is a task of its own: as many bodies as TBB has threads can wait for one another, each on its own
// thread (batched onto one thread, the first would wait out the deadline alone).
TEST(ParallelForEachIndex, RunsEveryIndexAsItsOwnTask) {
  const int threads = tbb::this_task_arena::max_concurrency();
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  std::atomic<int> joined{0};
  std::mutex mutex;
  std::set<std::thread::id> ids;
  std::vector<int> visits(threads, 0);
  ParallelForEachIndex(0, threads, [&](int i) {
    ++visits[i];
    ++joined;
    while (joined.load() < threads && std::chrono::steady_clock::now() < deadline) std::this_thread::yield();
    std::lock_guard<std::mutex> lock(mutex);
    ids.insert(std::this_thread::get_id());
  });
  EXPECT_EQ(joined.load(), threads);
  EXPECT_EQ(ids.size(), static_cast<std::size_t>(threads));
  EXPECT_EQ(std::set<int>(visits.begin(), visits.end()), std::set<int>{1});
}

}  // namespace
}  // namespace semap
