#include "engine/pipeline/internal/label_budget.h"

#include <gtest/gtest.h>

#include <limits>

namespace semap::pipeline_internal {
namespace {

TEST(LabelBudget, GapIsTheSegmentersTimeOverTheTimeLeft) {
  // 2 cores at 10 Hz: 200 ms of CPU a frame.
  EXPECT_EQ(LabelBudget::GapFor(100.0, 2, 150.0, 100.0, 30), 2);   // 50 ms left: 100 ms of ENet over 2 frames
  EXPECT_EQ(LabelBudget::GapFor(100.0, 2, 150.0, 101.0, 30), 3);   // rounded up
  EXPECT_EQ(LabelBudget::GapFor(100.0, 2, 20.0, 90.0, 30), 1);     // time to spare: every frame
  EXPECT_EQ(LabelBudget::GapFor(100.0, 2, 199.0, 500.0, 30), 30);  // 1 ms left: as seldom as allowed
  EXPECT_EQ(LabelBudget::GapFor(100.0, 2, 250.0, 50.0, 30), 30);   // behind already
  EXPECT_EQ(LabelBudget::GapFor(50.0, 1, 10.0, 80.0, 30), 2);      // twice the rate on one core: 40 ms left
}

TEST(LabelBudget, FirstGapUntilEveryCostIsMeasured) {
  LabelBudget b(100.0, 2, 6, 30);
  EXPECT_EQ(b.GapFrames(), 6);
  b.RecordStageMs(0, 100.0);
  b.RecordStageMs(2, 50.0);
  b.RecordSegmentMs(100.0);
  EXPECT_EQ(b.GapFrames(), 6);  // the simplification not measured yet
  b.RecordStageMs(1, 0.0);
  EXPECT_EQ(b.GapFrames(), 2);  // 150 ms a frame: 50 ms left for 100 ms of ENet
}

TEST(LabelBudget, RunningMeansFollowTheNewestTimes) {
  LabelBudget b(100.0, 2, 1, 30);
  b.RecordStageMs(0, 100.0);
  b.RecordStageMs(1, 0.0);
  b.RecordStageMs(2, 0.0);
  b.RecordSegmentMs(100.0);
  EXPECT_EQ(b.GapFrames(), 1);  // 100 ms left
  // The depth slows to 200 ms: the mean moves by kSmoothing of the step per frame.
  b.RecordStageMs(0, 200.0);  // 120 ms: 80 ms left, 100 / 80 → 2
  EXPECT_EQ(b.GapFrames(), 2);
  for (int i = 0; i < 50; ++i) b.RecordStageMs(0, 200.0);  // → 200 ms: nothing left
  EXPECT_EQ(b.GapFrames(), 30);
  // Non-finite or negative times are not measurements.
  b.RecordStageMs(0, std::numeric_limits<double>::quiet_NaN());
  b.RecordSegmentMs(-1.0);
  EXPECT_EQ(b.GapFrames(), 30);
}

}  // namespace
}  // namespace semap::pipeline_internal
