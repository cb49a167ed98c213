#include "engine/core/stopwatch.h"

#include <gtest/gtest.h>

namespace semap {
namespace {

// The steady clock never runs backwards: the elapsed time starts at zero or more and never decreases.
TEST(Stopwatch, ElapsedTimeIsNonNegativeAndNeverDecreases) {
  const Stopwatch stopwatch;
  double last_ms = stopwatch.ElapsedMs();
  EXPECT_GE(last_ms, 0.0);
  for (int i = 0; i < 1000; ++i) {
    const double now_ms = stopwatch.ElapsedMs();
    EXPECT_GE(now_ms, last_ms);
    last_ms = now_ms;
  }
}

}  // namespace
}  // namespace semap
