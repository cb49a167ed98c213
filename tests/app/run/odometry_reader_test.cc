#include "app/run/odometry_reader.h"

#include <gtest/gtest.h>

#include "engine/sim/camera_renderer.h"
#include "engine/sim/synthetic_sequence.h"
#include "tests/common/frames_reader.h"

namespace semap::app {
namespace {

// Frames of a generated drive, with (or without) their exact poses; `blank` frames have black images.
class DriveReader : public test::FramesReader {
 public:
  DriveReader(const sim::SyntheticSequence& seq, int frames, bool with_poses, int blank = -1) {
    const sim::CameraRenderer renderer(seq.scene(), seq.options());
    for (int i = 0; i < frames; ++i) {
      Frame f;
      f.id = i;
      f.timestamp_s = seq.trajectory().timestamp_s(i);
      f.calibration = seq.rig().calibration;
      f.left = renderer.Render(f.calibration, seq.scene_from_cam2(i), {1.0, 2u * i + 1}).color;
      f.right = renderer.Render(f.calibration, seq.scene_from_cam3(i), {1.0, 2u * i + 2}).color;
      if (i == blank) {
        f.left.setTo(0);
        f.right.setTo(0);
      }
      if (with_poses) f.world_from_cam = seq.world_from_cam2(i);
      frames_.push_back(std::move(f));
    }
  }
};

sim::SynthOptions Drive(int frames) {
  sim::SynthOptions o;
  o.num_frames = frames;
  o.seed = 3;
  return o;
}

// The frames leave with the odometry's poses (what the map and the LCM camera-pose channel receive), in the
// sequence's world frame; the log holds one record per frame and the frames.csv figures.
TEST(OdometryReader, ReplacesThePosesWithTheEstimate) {
  const sim::SyntheticSequence seq(Drive(5));
  auto log = std::make_shared<OdometryLog>();
  OdometryReader reader(std::make_unique<DriveReader>(seq, 5, true), StereoOdometryOptions{}, true, log);
  for (int i = 0; i < 5; ++i) {
    const std::optional<Frame> f = reader.Next();
    ASSERT_TRUE(f && f->world_from_cam);
    const OdometryRecord r = log->Records().back();
    EXPECT_TRUE(f->world_from_cam->isApprox(r.result.world_from_cam));
    // The frame's depth uses the rectification offset the odometry's motion used.
    EXPECT_EQ(f->disparity_offset.constant_px, r.result.disparity_offset.constant_px);
    EXPECT_EQ(f->disparity_offset.per_row_px, r.result.disparity_offset.per_row_px);
    // Exact to a few centimetres: the estimate, not a copy of the truth (which it is only at frame 0).
    EXPECT_LT((f->world_from_cam->translation() - seq.world_from_cam2(i).translation()).norm(), 0.05);
  }
  EXPECT_FALSE(reader.Next());
  EXPECT_EQ(log->Records().size(), 5u);
  EXPECT_EQ(log->failures(), 0);
  const auto figures = log->Figures(3);
  ASSERT_EQ(figures.size(), 8u);
  EXPECT_EQ(figures[0].name, "odometry_status");
  EXPECT_EQ(figures[5].name, "odometry_disparity_offset_px");
  EXPECT_EQ(figures[6].name, "odometry_disparity_offset_per_row_px");
  EXPECT_EQ(figures[7].name, "odometry_keyframe");
  EXPECT_EQ(figures[0].value, 1.0);   // tracked
  EXPECT_GT(figures[2].value, 50.0);  // inliers
  EXPECT_TRUE(log->Figures(99).empty());
}

// The odometry's disparity offset reaches the frames' depth only with offset_in_depth.
TEST(OdometryReader, OffsetReachesTheDepthOnlyWhenAsked) {
  constexpr double kOffsetPx = 0.3;
  const sim::SyntheticSequence seq(Drive(2));
  for (const bool in_depth : {false, true}) {
    StereoOdometryOptions o;
    o.disparity_offset_px = kOffsetPx;
    o.offset_in_depth = in_depth;
    auto log = std::make_shared<OdometryLog>();
    OdometryReader reader(std::make_unique<DriveReader>(seq, 2, true), o, true, log);
    for (int i = 0; i < 2; ++i) {
      const std::optional<Frame> f = reader.Next();
      ASSERT_TRUE(f);
      EXPECT_EQ(log->Records().back().result.disparity_offset.constant_px, kOffsetPx);
      EXPECT_EQ(f->disparity_offset.constant_px, in_depth ? kOffsetPx : 0.0) << "in_depth " << in_depth;
    }
  }
}

// Beside the sequence's poses: the frames keep theirs; the odometry still runs and logs.
TEST(OdometryReader, BesideTheSequencesPosesKeepsThem) {
  const sim::SyntheticSequence seq(Drive(3));
  auto log = std::make_shared<OdometryLog>();
  OdometryReader reader(std::make_unique<DriveReader>(seq, 3, true), StereoOdometryOptions{}, false, log);
  for (int i = 0; i < 3; ++i) {
    const std::optional<Frame> f = reader.Next();
    ASSERT_TRUE(f && f->world_from_cam);
    EXPECT_TRUE(f->world_from_cam->isApprox(seq.world_from_cam2(i)));
  }
  EXPECT_EQ(log->Records().size(), 3u);
}

// A frame where tracking fails is not handed on with a guessed pose: Next() throws saying why, the trajectory
// keeps the guess, and the next frame is read and tracked.
TEST(OdometryReader, AFailedFrameThrowsAndTheNextIsTracked) {
  const sim::SyntheticSequence seq(Drive(5));
  auto log = std::make_shared<OdometryLog>();
  OdometryReader reader(std::make_unique<DriveReader>(seq, 5, false, 2), StereoOdometryOptions{}, true, log);
  ASSERT_TRUE(reader.Next());
  ASSERT_TRUE(reader.Next());
  try {
    reader.Next();
    FAIL() << "a blank frame was handed on";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("frame 2: visual odometry lost track"), std::string::npos)
        << e.what();
  }
  const std::optional<Frame> next = reader.Next();
  ASSERT_TRUE(next && next->world_from_cam);
  EXPECT_EQ(log->Records().back().result.status, OdometryStatus::kTracked);
  EXPECT_EQ(log->failures(), 1);
  EXPECT_EQ(log->Records().size(), 4u);
}

TEST(OdometryPlan, FollowsInputPoses) {
  Config c;
  EXPECT_TRUE(PlanOdometry(c, false, false, "seq").replace_poses);
  EXPECT_FALSE(PlanOdometry(c, true, false, "seq").run);
  c.pose_input.compare_odometry = true;
  const OdometryPlan beside = PlanOdometry(c, true, true, "seq");
  EXPECT_TRUE(beside.run);
  EXPECT_FALSE(beside.replace_poses);
  c.pose_input.poses = PoseSource::kOdometry;
  EXPECT_TRUE(PlanOdometry(c, true, false, "seq").replace_poses);
  c.pose_input.poses = PoseSource::kFile;
  EXPECT_FALSE(PlanOdometry(c, true, false, "seq").replace_poses);
  EXPECT_THROW(PlanOdometry(c, true, true, "seq"), ConfigError);  // a raw drive has OXTS, not a pose file
  EXPECT_THROW(PlanOdometry(c, false, false, "seq"), ConfigError);
  c.pose_input.poses = PoseSource::kOxts;
  EXPECT_NO_THROW(PlanOdometry(c, true, true, "seq"));
  try {
    PlanOdometry(c, false, true, "seq");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("input.poses: oxts"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace semap::app
