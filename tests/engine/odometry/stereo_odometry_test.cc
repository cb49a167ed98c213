#include "engine/odometry/stereo_odometry.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

#include "engine/core/check.h"
#include "engine/sim/camera_renderer.h"
#include "engine/sim/synthetic_sequence.h"

namespace semap {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kFramePeriodS = 0.1;

// The tolerances follow from the pixel noise. A feature is located to about kLocationNoisePx (rendered
// noise, blur and KLT together, generously), so a stereo point at depth z has a depth error of about
// z^2 * noise / (f * b); the motion averages at least kMinPoints such points. At the generated street's
// typical depth the frame-to-frame translation error is then below kTypicalDepthM^2 * noise / (f b sqrt(N)),
// and the rotation error below noise / (f sqrt(N)) times kRotationCoupling: a yaw and a sideways step shift
// distant points alike, so the estimate shares its rotation error with the translation (about twice the
// uncoupled figure over a street's depths). Tests allow kSigmas of that.
constexpr double kLocationNoisePx = 0.5;
constexpr double kRotationCoupling = 2.0;
constexpr double kTypicalDepthM = 15.0;
constexpr double kMinPoints = 100.0;
constexpr double kSigmas = 3.0;

double TranslationTolerancePerFrameM(const StereoCalibration& c) {
  return kSigmas * kTypicalDepthM * kTypicalDepthM * kLocationNoisePx /
         (c.fx_px * c.baseline_m * std::sqrt(kMinPoints));
}
double RotationTolerancePerFrameRad(const StereoCalibration& c) {
  return kSigmas * kRotationCoupling * kLocationNoisePx / (c.fx_px * std::sqrt(kMinPoints));
}

double AngleRad(const Pose3d& p) { return Eigen::AngleAxisd(p.linear()).angle(); }

sim::SynthOptions Street(int frames) {
  sim::SynthOptions o;
  o.num_frames = frames;
  o.seed = 3;
  return o;
}

// Renders the stereo pair of a left camera at `scene_from_cam` (right camera at +baseline along x).
struct Pair {
  cv::Mat left, right;
};
// `right_offset_px` shifts the right camera's principal point: a rectification that is off by that much.
Pair Render(const sim::SyntheticSequence& seq, const sim::CameraRenderer& renderer,
            const Pose3d& scene_from_cam, std::uint64_t seed, double right_offset_px = 0.0) {
  const StereoCalibration& c = seq.rig().calibration;
  Pose3d scene_from_right = scene_from_cam;
  scene_from_right.translation() += scene_from_cam.linear() * Eigen::Vector3d(c.baseline_m, 0.0, 0.0);
  StereoCalibration right = c;
  right.cx_px += right_offset_px;
  return {renderer.Render(c, scene_from_cam, {1.0, 2 * seed + 1}).color,
          renderer.Render(right, scene_from_right, {1.0, 2 * seed + 2}).color};
}

// Along the generated drive, each frame-to-frame motion matches the truth within the noise-derived tolerance.
TEST(StereoOdometry, RecoversTheMotionOfARigDrivingThroughATexturedStreet) {
  constexpr int kFrames = 12;
  const sim::SyntheticSequence seq(Street(kFrames));
  const sim::CameraRenderer renderer(seq.scene(), seq.options());
  const StereoCalibration& c = seq.rig().calibration;
  StereoOdometry odometry(StereoOdometryOptions{}, c);
  odometry.SetFirstPose(seq.world_from_cam2(0));
  Pose3d previous = seq.world_from_cam2(0);
  for (int i = 0; i < kFrames; ++i) {
    const Pair pair = Render(seq, renderer, seq.scene_from_cam2(i), i);
    const OdometryResult r = odometry.Track(pair.left, pair.right, i * kFramePeriodS);
    if (i == 0) {
      EXPECT_EQ(r.status, OdometryStatus::kFirst);
      EXPECT_TRUE(r.world_from_cam.isApprox(seq.world_from_cam2(0)));
      EXPECT_GE(r.stereo_features, kMinPoints);
    } else {
      ASSERT_EQ(r.status, OdometryStatus::kTracked) << "frame " << i << ": " << r.problem;
      EXPECT_GE(r.inliers, kMinPoints);
      const Pose3d truth = seq.world_from_cam2(i - 1).inverse() * seq.world_from_cam2(i);
      const Pose3d estimate = previous.inverse() * r.world_from_cam;
      const Pose3d error = truth.inverse() * estimate;
      EXPECT_LT(error.translation().norm(), TranslationTolerancePerFrameM(c)) << "frame " << i;
      EXPECT_LT(AngleRad(error), RotationTolerancePerFrameRad(c)) << "frame " << i;
      EXPECT_GT(truth.translation().norm(), 0.5);  // the rig does move
    }
    EXPECT_GT(r.cpu_ms, 0.0);
    previous = r.world_from_cam;
  }
  EXPECT_EQ(odometry.frames_tracked(), kFrames - 1);
  EXPECT_EQ(odometry.frames_bridged(), 0);
}

// A rig whose right camera is rectified 0.6 px off (every disparity 0.6 px short, so every depth too far
// and every step too long): the odometry finds the offset from how the depths follow the motion, and its
// path is far closer to the truth's length than with the offset ignored.
TEST(StereoOdometry, FindsARectificationOffsetAndKeepsTheScale) {
  constexpr int kFrames = 12;
  constexpr double kOffsetPx = 0.6;
  const sim::SyntheticSequence seq(Street(kFrames));
  const sim::CameraRenderer renderer(seq.scene(), seq.options());
  const StereoCalibration& c = seq.rig().calibration;
  StereoOdometryOptions estimate, ignore;
  estimate.estimate_disparity_offset = OffsetEstimate::kConstant;
  ignore.estimate_disparity_offset = OffsetEstimate::kOff;
  StereoOdometry estimating(estimate, c), ignoring(ignore, c);
  double truth_m = 0.0, estimating_m = 0.0, ignoring_m = 0.0;
  Pose3d previous_estimating = Pose3d::Identity(), previous_ignoring = Pose3d::Identity();
  OdometryResult last;
  for (int i = 0; i < kFrames; ++i) {
    const Pair pair = Render(seq, renderer, seq.scene_from_cam2(i), i, kOffsetPx);
    last = estimating.Track(pair.left, pair.right, i * kFramePeriodS);
    const OdometryResult r = ignoring.Track(pair.left, pair.right, i * kFramePeriodS);
    if (i > 0) {
      ASSERT_EQ(last.status, OdometryStatus::kTracked) << "frame " << i << ": " << last.problem;
      ASSERT_EQ(r.status, OdometryStatus::kTracked) << "frame " << i << ": " << r.problem;
      EXPECT_LE(last.frame_offset_sigma_px, 0.25) << "frame " << i;  // a moving rig tells the offset
      truth_m += (seq.world_from_cam2(i - 1).inverse() * seq.world_from_cam2(i)).translation().norm();
      estimating_m += (previous_estimating.inverse() * last.world_from_cam).translation().norm();
      ignoring_m += (previous_ignoring.inverse() * r.world_from_cam).translation().norm();
    }
    previous_estimating = last.world_from_cam;
    previous_ignoring = r.world_from_cam;
  }
  EXPECT_EQ(ignoring.frames_tracked(), kFrames - 1);
  // The mean of 10 frames' estimates (the last frame's is not yet in the offset it used), each good to
  // about 0.1 px on this street.
  EXPECT_NEAR(last.disparity_offset.constant_px, kOffsetPx, 0.15);
  // Ignored, 0.6 px of the ~25 px disparity at the street's typical 15 m stretch every step by ~2 %.
  const double ignoring_error = std::abs(ignoring_m - truth_m) / truth_m;
  const double estimating_error = std::abs(estimating_m - truth_m) / truth_m;
  EXPECT_GT(ignoring_error, 0.01);
  EXPECT_LT(estimating_error, 0.5 * ignoring_error);
}

// A rig standing still (new image noise every frame) stays where it started.
TEST(StereoOdometry, StandingStillStaysPut) {
  const sim::SyntheticSequence seq(Street(1));
  const sim::CameraRenderer renderer(seq.scene(), seq.options());
  const StereoCalibration& c = seq.rig().calibration;
  StereoOdometry odometry(StereoOdometryOptions{}, c);
  constexpr int kFrames = 8;
  OdometryResult r;
  for (int i = 0; i < kFrames; ++i) {
    const Pair pair = Render(seq, renderer, seq.scene_from_cam2(0), i);
    r = odometry.Track(pair.left, pair.right, i * kFramePeriodS);
    if (i > 0) ASSERT_EQ(r.status, OdometryStatus::kTracked) << r.problem;
  }
  // Frame-to-frame errors add up like a random walk.
  const double steps = std::sqrt(static_cast<double>(kFrames - 1));
  EXPECT_LT(r.world_from_cam.translation().norm(), steps * TranslationTolerancePerFrameM(c));
  EXPECT_LT(AngleRad(r.world_from_cam), steps * RotationTolerancePerFrameRad(c));
}

// A rig turning on the spot (about its vertical axis, no translation): the rotation is recovered and the
// position does not move.
TEST(StereoOdometry, PureRotation) {
  const sim::SyntheticSequence seq(Street(1));
  const sim::CameraRenderer renderer(seq.scene(), seq.options());
  const StereoCalibration& c = seq.rig().calibration;
  StereoOdometry odometry(StereoOdometryOptions{}, c);
  constexpr int kFrames = 8;
  constexpr double kStepRad = 2.0 * kPi / 180.0;  // 2° per frame: 20°/s at 10 Hz, a car turning a corner
  const Pose3d scene_from_cam0 = seq.scene_from_cam2(0);
  OdometryResult r;
  for (int i = 0; i < kFrames; ++i) {
    Pose3d turn = Pose3d::Identity();
    turn.linear() =
        Eigen::AngleAxisd(i * kStepRad, Eigen::Vector3d::UnitY()).toRotationMatrix();  // camera y: down
    const Pair pair = Render(seq, renderer, scene_from_cam0 * turn, i);
    r = odometry.Track(pair.left, pair.right, i * kFramePeriodS);
    if (i > 0) ASSERT_EQ(r.status, OdometryStatus::kTracked) << "frame " << i << ": " << r.problem;
  }
  const double steps = std::sqrt(static_cast<double>(kFrames - 1));
  EXPECT_LT(r.world_from_cam.translation().norm(), steps * TranslationTolerancePerFrameM(c));
  const Eigen::AngleAxisd aa(r.world_from_cam.linear());
  EXPECT_NEAR(aa.angle(), (kFrames - 1) * kStepRad, steps * RotationTolerancePerFrameRad(c));
  EXPECT_GT(std::abs(aa.axis().y()), 0.99);
}

// A blank frame (a covered lens, a dropped exposure) is bridged with the constant-velocity guess and never
// becomes the reference: the next frame is tracked from the last good one and lands on the truth again.
TEST(StereoOdometry, BlankFrameIsBridgedAndTrackingResumes) {
  constexpr int kFrames = 7;
  constexpr int kBlank = 4;
  const sim::SyntheticSequence seq(Street(kFrames));
  const sim::CameraRenderer renderer(seq.scene(), seq.options());
  const StereoCalibration& c = seq.rig().calibration;
  StereoOdometry odometry(StereoOdometryOptions{}, c);
  odometry.SetFirstPose(seq.world_from_cam2(0));
  for (int i = 0; i < kFrames; ++i) {
    Pair pair = Render(seq, renderer, seq.scene_from_cam2(i), i);
    if (i == kBlank) {
      pair.left.setTo(0);
      pair.right.setTo(0);
    }
    const OdometryResult r = odometry.Track(pair.left, pair.right, i * kFramePeriodS);
    if (i == kBlank) {
      EXPECT_EQ(r.status, OdometryStatus::kBridged);
      EXPECT_FALSE(r.problem.empty());
      // The guess: the drive goes on at its speed (a straight stretch), within a few tolerances.
      EXPECT_LT((r.world_from_cam.translation() - seq.world_from_cam2(i).translation()).norm(), 0.2);
    } else if (i > 0) {
      ASSERT_EQ(r.status, OdometryStatus::kTracked) << "frame " << i << ": " << r.problem;
      const double steps = std::sqrt(static_cast<double>(i));
      EXPECT_LT((r.world_from_cam.translation() - seq.world_from_cam2(i).translation()).norm(),
                steps * TranslationTolerancePerFrameM(c))
          << "frame " << i;
    }
  }
  EXPECT_EQ(odometry.frames_bridged(), 1);
  EXPECT_EQ(odometry.restarts(), 0);
}

// More failed frames in a row than max_bridged_frames: tracking restarts on the next frame that has features,
// and that frame says so.
TEST(StereoOdometry, RestartsAfterTooManyFailedFrames) {
  const sim::SyntheticSequence seq(Street(1));
  const sim::CameraRenderer renderer(seq.scene(), seq.options());
  const StereoCalibration& c = seq.rig().calibration;
  StereoOdometryOptions o;
  o.max_bridged_frames = 1;
  StereoOdometry odometry(o, c);
  const Pair good = Render(seq, renderer, seq.scene_from_cam2(0), 0);
  const cv::Mat blank = cv::Mat::zeros(good.left.size(), good.left.type());
  EXPECT_EQ(odometry.Track(good.left, good.right, 0.0).status, OdometryStatus::kFirst);
  EXPECT_EQ(odometry.Track(blank, blank, 0.1).status, OdometryStatus::kBridged);
  // The second failure in a row exceeds max_bridged_frames, but a blank frame cannot be a reference.
  EXPECT_EQ(odometry.Track(blank, blank, 0.2).status, OdometryStatus::kBridged);
  // Far off (another place): nothing tracks; tracking restarts here.
  Pose3d elsewhere = seq.scene_from_cam2(0);
  elsewhere.translation() += elsewhere.linear() * Eigen::Vector3d(0.0, 0.0, 30.0);
  const Pair far = Render(seq, renderer, elsewhere, 3);
  const OdometryResult r = odometry.Track(far.left, far.right, 0.3);
  EXPECT_EQ(r.status, OdometryStatus::kRestarted) << r.problem;
  EXPECT_EQ(odometry.restarts(), 1);
  // And the next frame tracks from it.
  const Pair again = Render(seq, renderer, elsewhere, 4);
  EXPECT_EQ(odometry.Track(again.left, again.right, 0.4).status, OdometryStatus::kTracked);
}

TEST(StereoOdometry, FirstBlankFrameThenTexture) {
  const sim::SyntheticSequence seq(Street(2));
  const sim::CameraRenderer renderer(seq.scene(), seq.options());
  const StereoCalibration& c = seq.rig().calibration;
  StereoOdometry odometry(StereoOdometryOptions{}, c);
  const Pair good = Render(seq, renderer, seq.scene_from_cam2(1), 1);
  const cv::Mat blank = cv::Mat::zeros(good.left.size(), good.left.type());
  const OdometryResult first = odometry.Track(blank, blank, 0.0);
  EXPECT_EQ(first.status, OdometryStatus::kFirst);
  EXPECT_EQ(first.stereo_features, 0);
  // No reference to track from: this frame becomes one (a restart), its pose the identity guess.
  const OdometryResult r = odometry.Track(good.left, good.right, 0.1);
  EXPECT_EQ(r.status, OdometryStatus::kRestarted);
  EXPECT_TRUE(r.world_from_cam.isApprox(Pose3d::Identity()));
}

// With keyframe_max_frames = 3 a frame is tracked from a reference up to three frames back: at most two
// frames in a row keep the reference, and the poses stay within the chained tolerance of the truth. With 1,
// every frame is the next one's reference.
TEST(StereoOdometry, KeyframesKeepTheReferenceForUpToMaxFrames) {
  constexpr int kFrames = 8;
  const sim::SyntheticSequence seq(Street(kFrames));
  const sim::CameraRenderer renderer(seq.scene(), seq.options());
  const StereoCalibration& c = seq.rig().calibration;
  StereoOdometryOptions every_third, every_frame;
  every_third.keyframe_max_frames = 3;
  every_frame.keyframe_max_frames = 1;
  StereoOdometry keyframed(every_third, c), chained(every_frame, c);
  keyframed.SetFirstPose(seq.world_from_cam2(0));
  int kept_in_a_row = 0, kept = 0;
  for (int i = 0; i < kFrames; ++i) {
    const Pair pair = Render(seq, renderer, seq.scene_from_cam2(i), i);
    const OdometryResult k = keyframed.Track(pair.left, pair.right, i * kFramePeriodS);
    const OdometryResult f = chained.Track(pair.left, pair.right, i * kFramePeriodS);
    EXPECT_TRUE(f.keyframe) << "frame " << i;
    if (i == 0) {
      EXPECT_TRUE(k.keyframe);
      continue;
    }
    ASSERT_EQ(k.status, OdometryStatus::kTracked) << "frame " << i << ": " << k.problem;
    EXPECT_GT(k.stereo_features, 0) << "frame " << i;  // the next frame has a reference either way
    kept_in_a_row = k.keyframe ? 0 : kept_in_a_row + 1;
    kept += !k.keyframe;
    EXPECT_LE(kept_in_a_row, every_third.keyframe_max_frames - 1) << "frame " << i;
    const double steps = std::sqrt(static_cast<double>(i));
    EXPECT_LT((k.world_from_cam.translation() - seq.world_from_cam2(i).translation()).norm(),
              steps * TranslationTolerancePerFrameM(c))
        << "frame " << i;
  }
  EXPECT_GT(kept, 0);  // on a steady street the reference is kept
  EXPECT_EQ(keyframed.frames_tracked(), kFrames - 1);
}

TEST(StereoOdometry, ImagesThatDoNotFitTheCalibrationThrow) {
  const sim::SyntheticSequence seq(Street(1));
  StereoOdometry odometry(StereoOdometryOptions{}, seq.rig().calibration);
  const cv::Mat small = cv::Mat::zeros(10, 10, CV_8UC1);
  EXPECT_THROW(odometry.Track(small, small, 0.0), std::invalid_argument);
  EXPECT_THROW(odometry.Track(cv::Mat(), cv::Mat(), 0.0), std::invalid_argument);
}

TEST(StereoOdometryOptions, CheckNamesTheField) {
  StereoOdometryOptions o;
  EXPECT_NO_THROW(o.Check());
  o.klt_window_px = 10;
  try {
    o.Check();
    FAIL() << "even window accepted";
  } catch (const InvalidOption& e) {
    EXPECT_EQ(e.field(), "klt_window_px");
  }
  o = {};
  o.min_inliers = 2;
  EXPECT_THROW(o.Check(), InvalidOption);
  o = {};
  o.max_speed_mps = -1.0;
  EXPECT_THROW(o.Check(), InvalidOption);
  o = {};
  o.keyframe_max_frames = 0;
  EXPECT_THROW(o.Check(), InvalidOption);
  o = {};
  o.keyframe_min_inlier_ratio = 1.5;
  EXPECT_THROW(o.Check(), InvalidOption);
  EXPECT_THROW(StereoOdometry(StereoOdometryOptions{}, StereoCalibration{}), InvalidOption);
}

TEST(OdometryStatus, Names) {
  EXPECT_STREQ(OdometryStatusName(OdometryStatus::kFirst), "first");
  EXPECT_STREQ(OdometryStatusName(OdometryStatus::kTracked), "tracked");
  EXPECT_STREQ(OdometryStatusName(OdometryStatus::kBridged), "bridged");
  EXPECT_STREQ(OdometryStatusName(OdometryStatus::kRestarted), "restarted");
}

}  // namespace
}  // namespace semap
