#include "engine/pipeline/timing_stats.h"

#include <gtest/gtest.h>

namespace semap {
namespace {

TEST(TimingStats, MeanMaxAndNearestRankPercentiles) {
  TimingStats t(1000);
  for (int i = 1; i <= 100; ++i) t.Add(i);
  EXPECT_DOUBLE_EQ(t.mean(), 50.5);
  EXPECT_DOUBLE_EQ(t.max(), 100.0);
  EXPECT_DOUBLE_EQ(t.Percentile(0.5), 50.0);
  EXPECT_DOUBLE_EQ(t.Percentile(0.95), 95.0);
  EXPECT_DOUBLE_EQ(t.Percentile(1.0), 100.0);
  EXPECT_DOUBLE_EQ(t.last(), 100.0);
}

TEST(TimingStats, PercentilesUseTheRecentWindowOnly) {
  TimingStats t(10);
  for (int i = 0; i < 100; ++i) t.Add(1000.0);
  for (int i = 0; i < 10; ++i) t.Add(1.0);
  EXPECT_DOUBLE_EQ(t.Percentile(0.95), 1.0);
  EXPECT_DOUBLE_EQ(t.max(), 1000.0);  // over the whole run
  EXPECT_EQ(t.count(), 110u);
}

TEST(TimingStats, EmptyIsZero) {
  TimingStats t;
  EXPECT_EQ(t.Percentile(0.5), 0.0);
  EXPECT_EQ(t.mean(), 0.0);
}

}  // namespace
}  // namespace semap
