// The steps of StereoOdometry::Track (internal/stereo_tracking.h) on a generated street with exact depth and
// a known motion, and on point sets made from known 3D points: each step's result against the geometry the
// test computes itself (projections of the true points, disparities of the true depths, weighted means).
#include "engine/odometry/internal/stereo_tracking.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>

#include "engine/sim/camera_renderer.h"
#include "engine/sim/synthetic_sequence.h"
#include "tests/engine/odometry/kitti_calibration.h"

namespace semap::odometry_internal {
namespace {

// Two frames of the generated street (its rig: the left camera, the right one at +baseline along x), with the
// left camera's exact depth of the first.
class StreetPair : public ::testing::Test {
 protected:
  static sim::SynthOptions Street() {
    sim::SynthOptions o;
    o.num_frames = 2;
    o.seed = 3;
    return o;
  }
  StreetPair()
      : seq_(Street()),
        renderer_(seq_.scene(), seq_.options()),
        c_(seq_.rig().calibration),
        matcher_(o_, c_) {}

  struct Pair {
    cv::Mat left, right, left_depth_m;
  };
  Pair Render(int frame) const {
    const Pose3d scene_from_cam = seq_.scene_from_cam2(frame);
    Pose3d scene_from_right = scene_from_cam;
    scene_from_right.translation() += scene_from_cam.linear() * Eigen::Vector3d(c_.baseline_m, 0.0, 0.0);
    const auto seed = static_cast<std::uint64_t>(frame);
    const sim::CameraImage left = renderer_.Render(c_, scene_from_cam, {1.0, 2 * seed + 1});
    return {left.color, renderer_.Render(c_, scene_from_right, {1.0, 2 * seed + 2}).color, left.depth_m};
  }
  // cur_from_ref from frame 0 to frame 1, from the sequence's poses.
  Pose3d TrueMotion() const { return seq_.scene_from_cam2(1).inverse() * seq_.scene_from_cam2(0); }
  // The exact depth at the pixel nearest `p` where the surface is smooth there (the 3 × 3 pixels around it
  // within 2 % of it: no depth edge, where a corner's nearest pixel may see the other side); 0 elsewhere.
  static double SmoothDepthAt(const cv::Mat& depth_m, const cv::Point2f& p) {
    const int u = static_cast<int>(std::lround(p.x)), v = static_cast<int>(std::lround(p.y));
    const double z = depth_m.at<float>(v, u);
    for (int dv = -1; dv <= 1; ++dv) {
      for (int du = -1; du <= 1; ++du) {
        if (!(std::abs(depth_m.at<float>(v + dv, u + du) - z) <= 0.02 * z)) return 0.0;
      }
    }
    return z;
  }

  sim::SyntheticSequence seq_;
  sim::CameraRenderer renderer_;
  StereoCalibration c_;
  StereoOdometryOptions o_;
  StereoMatcher matcher_;
};

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

TEST_F(StreetPair, DetectedCornersAreSpreadOverTheGridAndApart) {
  const Pair pair = Render(0);
  const FrameImages frame = matcher_.Prepare(pair.left, pair.right);
  const std::vector<cv::Point2f> existing = {{100.5f, 100.5f}, {300.0f, 200.0f}};
  const std::vector<cv::Point2f> fresh = matcher_.Detect(frame, existing);
  ASSERT_GT(fresh.size(), 100u);
  EXPECT_LE(fresh.size() + existing.size(), static_cast<size_t>(o_.max_features));
  const int per_cell = o_.max_features / (o_.grid_cols * o_.grid_rows);
  std::map<std::pair<int, int>, int> in_cell;  // grid cell (column, row) → features
  std::set<std::pair<int, int>> squares;       // spacing squares taken
  constexpr int kSpacing = StereoMatcher::kMinFeatureSpacingPx;
  for (const auto& p : existing) {
    ++in_cell[{static_cast<int>(p.x * o_.grid_cols / c_.width_px),
               static_cast<int>(p.y * o_.grid_rows / c_.height_px)}];
    squares.insert({static_cast<int>(p.x) / kSpacing, static_cast<int>(p.y) / kSpacing});
  }
  const float margin = static_cast<float>(o_.klt_window_px / 2);
  for (const auto& p : fresh) {
    EXPECT_TRUE(p.x >= margin && p.y >= margin && p.x < c_.width_px - margin && p.y < c_.height_px - margin);
    EXPECT_TRUE(squares.insert({static_cast<int>(p.x) / kSpacing, static_cast<int>(p.y) / kSpacing}).second)
        << "two features within one " << kSpacing << " px square at " << p;
    ++in_cell[{static_cast<int>(p.x * o_.grid_cols / c_.width_px),
               static_cast<int>(p.y * o_.grid_rows / c_.height_px)}];
  }
  for (const auto& [cell, n] : in_cell) EXPECT_LE(n, per_cell) << cell.first << ", " << cell.second;
}

TEST_F(StreetPair, StereoMatchesHaveTheDisparityOfTheTrueDepth) {
  const Pair pair = Render(0);
  const FrameImages frame = matcher_.Prepare(pair.left, pair.right);
  const StereoFeatures features = TopUpFeatures(matcher_, frame, {});
  ASSERT_GT(features.left.size(), 100u);
  std::vector<double> errors;
  for (size_t i = 0; i < features.left.size(); ++i) {
    const cv::Point2f& l = features.left[i];
    const cv::Point2f& r = features.right[i];
    EXPECT_LE(std::abs(l.y - r.y), o_.max_epipolar_error_px);
    EXPECT_GE(l.x - r.x, o_.min_disparity_px);
    const double z = SmoothDepthAt(pair.left_depth_m, l);
    if (z > 0.0) errors.push_back(std::abs((l.x - r.x) - c_.fx_px * c_.baseline_m / z));
  }
  // KLT finds the rendered texture (noise, blur, the right camera's exposure) to a fraction of a pixel; a
  // match started from the wrong disparity or paired with another feature would be off by pixels.
  ASSERT_GT(errors.size(), 100u);
  EXPECT_LT(Median(errors), 0.4);
  const auto within = std::count_if(errors.begin(), errors.end(), [](double e) { return e < 1.5; });
  EXPECT_GT(static_cast<double>(within), 0.85 * static_cast<double>(errors.size()));
}

TEST_F(StreetPair, TrackedFeaturesLandWhereTheKnownMotionMovesTheirPoints) {
  const Pair a = Render(0), b = Render(1);
  const FrameImages ref_frame = matcher_.Prepare(a.left, a.right);
  const FrameImages cur_frame = matcher_.Prepare(b.left, b.right);
  const StereoFeatures ref = TopUpFeatures(matcher_, ref_frame, {});
  const Pose3d motion = TrueMotion();
  ASSERT_GT(motion.translation().norm(), 0.5);  // the rig does move
  const std::vector<cv::Point2f> starts = PredictFeaturePositions(c_, ref, {}, motion);
  const TrackedFeatures tracked = TrackFeatures(matcher_, o_, ref_frame.left_pyramid, ref, cur_frame, starts);
  ASSERT_GT(tracked.left.size(), 0.8 * static_cast<double>(ref.left.size()));
  std::vector<double> errors;
  for (size_t k = 0; k < tracked.left.size(); ++k) {
    const cv::Point2f& p = ref.left[tracked.ref_index[k]];
    const double z = SmoothDepthAt(a.left_depth_m, p);
    if (z <= 0.0) continue;
    const Eigen::Vector2d truth = c_.Project(motion * c_.Unproject(p.x, p.y, z));
    errors.push_back((truth - Eigen::Vector2d(tracked.left[k].x, tracked.left[k].y)).norm());
  }
  // Half a pixel typically (the scale change of near surfaces over the ~1 m step adds to the noise of both
  // images); a track that lost its feature or took another's would be off by many.
  ASSERT_GT(errors.size(), 100u);
  EXPECT_LT(Median(errors), 0.75);
  const auto within = std::count_if(errors.begin(), errors.end(), [](double e) { return e < 2.0; });
  EXPECT_GT(static_cast<double>(within), 0.75 * static_cast<double>(errors.size()));
  // Most tracked features find their stereo match in the new frame, and each match is the refiner's.
  const auto matched = std::count(tracked.stereo_ok.begin(), tracked.stereo_ok.end(), true);
  EXPECT_GT(static_cast<double>(matched), 0.7 * static_cast<double>(tracked.left.size()));
  const std::vector<StereoMatch> matches = MakeStereoMatches(ref, tracked);
  ASSERT_EQ(matches.size(), tracked.left.size());
  for (size_t k = 0; k < matches.size(); ++k) {
    EXPECT_EQ(matches[k].ref_left_px.x(), ref.left[tracked.ref_index[k]].x);
    EXPECT_EQ(matches[k].cur_right_u_px, tracked.right[k].x);
    EXPECT_EQ(matches[k].has_current_right, tracked.stereo_ok[k]);
  }
}

TEST_F(StreetPair, TheStepsChainedRecoverTheKnownMotion) {
  const Pair a = Render(0), b = Render(1);
  const FrameImages ref_frame = matcher_.Prepare(a.left, a.right);
  const FrameImages cur_frame = matcher_.Prepare(b.left, b.right);
  const StereoFeatures ref = TopUpFeatures(matcher_, ref_frame, {});
  // KLT from standing still: the pyramid reaches the ~1 m step of the generated drive.
  const TrackedFeatures tracked = TrackFeatures(matcher_, o_, ref_frame.left_pyramid, ref, cur_frame,
                                                PredictFeaturePositions(c_, ref, {}, {}));
  const StartMotion start = EstimateStartMotion(c_, o_, ref, {}, tracked);
  ASSERT_TRUE(start.solved);
  RefinerOptions ro;
  ro.inlier_threshold_px = o_.inlier_threshold_px;
  const RefinedMotion refined =
      RefineStereoMotion(c_, MakeStereoMatches(ref, tracked), start.cur_from_ref, start.inliers, ro);
  const Pose3d error = TrueMotion().inverse() * refined.cur_from_ref;
  EXPECT_LT(error.translation().norm(), 0.05);
  EXPECT_LT(RotationAngleRad(error), 1e-3);
  EXPECT_EQ(MotionProblem(refined, static_cast<int>(tracked.left.size()), 0.1, o_), "");
}

// Features of random points with exact pixels.
cv::Point2f Pixel(const Eigen::Vector2d& uv) {
  return {static_cast<float>(uv.x()), static_cast<float>(uv.y())};
}

std::vector<Eigen::Vector3d> RandomPoints(int n, std::mt19937* rng) {
  std::uniform_real_distribution<double> x(-10.0, 10.0), y(-2.0, 1.5), z(5.0, 40.0);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < n; ++i) points.emplace_back(x(*rng), y(*rng), z(*rng));
  return points;
}

StereoFeatures Observe(const StereoCalibration& c, const std::vector<Eigen::Vector3d>& points) {
  StereoFeatures f;
  for (const auto& p : points) {
    f.left.push_back(Pixel(c.Project(p)));
    f.right.push_back(Pixel(c.Project(p - Eigen::Vector3d(c.baseline_m, 0.0, 0.0))));
  }
  return f;
}

Pose3d Motion() {
  Pose3d m = Pose3d::Identity();
  m.linear() = Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitY()).toRotationMatrix();
  m.translation() = Eigen::Vector3d(0.1, 0.0, -1.0);
  return m;
}

TEST(StereoTracking, PredictionsAreTheProjectionsOfTheMovedPoints) {
  const StereoCalibration c = test::KittiOdometryCalibration();
  std::mt19937 rng(1);
  std::vector<Eigen::Vector3d> points = RandomPoints(50, &rng);
  points.emplace_back(0.0, 0.0, 0.5);  // 0.5 m ahead: behind the camera after a 1 m step
  const StereoFeatures ref = Observe(c, points);
  const std::vector<cv::Point2f> starts = PredictFeaturePositions(c, ref, {}, Motion());
  ASSERT_EQ(starts.size(), points.size());
  for (size_t i = 0; i + 1 < points.size(); ++i) {
    const Eigen::Vector3d moved = Motion() * points[i];
    if (!c.InImage(c.Project(moved))) continue;
    // The triangulation runs on float pixels: a few thousandths of a pixel.
    EXPECT_NEAR(starts[i].x, c.Project(moved).x(), 0.02) << i;
    EXPECT_NEAR(starts[i].y, c.Project(moved).y(), 0.02) << i;
  }
  EXPECT_EQ(starts.back(), ref.left.back());  // behind the camera: it starts where it was
}

TEST(StereoTracking, P3pFindsTheMotionAndLeavesTheMistracksOut) {
  const StereoCalibration c = test::KittiOdometryCalibration();
  std::mt19937 rng(2);
  const std::vector<Eigen::Vector3d> points = RandomPoints(200, &rng);
  const StereoFeatures ref = Observe(c, points);
  TrackedFeatures tracked;
  std::vector<bool> mistracked;
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d moved = Motion() * points[i];
    cv::Point2f p = Pixel(c.Project(moved));
    mistracked.push_back(i % 5 == 0);
    if (mistracked.back()) p.x += 15.0f;
    tracked.ref_index.push_back(i);
    tracked.left.push_back(p);
    tracked.right.push_back(Pixel(c.Project(moved - Eigen::Vector3d(c.baseline_m, 0.0, 0.0))));
    tracked.stereo_ok.push_back(true);
  }
  const StartMotion start = EstimateStartMotion(c, StereoOdometryOptions(), ref, {}, tracked);
  ASSERT_TRUE(start.solved);
  const Pose3d error = Motion().inverse() * start.cur_from_ref;
  EXPECT_LT(error.translation().norm(), 0.01);
  EXPECT_LT(RotationAngleRad(error), 1e-3);
  int good_inliers = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    if (mistracked[i]) {
      EXPECT_FALSE(start.inliers[i]) << i;
    }
    good_inliers += !mistracked[i] && start.inliers[i];
  }
  EXPECT_EQ(start.num_inliers, good_inliers);
  EXPECT_GT(good_inliers, 150);  // of 160 exact tracks
}

TEST(StereoTracking, MotionProblemNamesWhatFails) {
  StereoOdometryOptions o;  // min_inliers 40, min_inlier_ratio 0.2, 50 m/s, 120 deg/s
  RefinedMotion r;
  r.num_inliers = 100;
  r.cur_from_ref.translation() = Eigen::Vector3d(0.0, 0.0, -1.0);
  EXPECT_EQ(MotionProblem(r, 300, 0.1, o), "");                                     // 10 m/s
  EXPECT_EQ(MotionProblem(r, 600, 0.1, o), "100 inliers of 600 tracked features");  // under a fifth
  r.num_inliers = 39;
  EXPECT_EQ(MotionProblem(r, 100, 0.1, o), "39 inliers of 100 tracked features");
  r.num_inliers = 100;
  r.cur_from_ref.translation() = Eigen::Vector3d(0.0, 0.0, -6.0);  // 60 m/s
  EXPECT_NE(MotionProblem(r, 300, 0.1, o).find("m/s > max_speed_mps"), std::string::npos);
  EXPECT_EQ(MotionProblem(r, 300, -0.2, o), "");  // a step back in time: 30 m/s
  r.cur_from_ref.translation().setZero();
  r.cur_from_ref.linear() =
      Eigen::AngleAxisd(0.25, Eigen::Vector3d::UnitY()).toRotationMatrix();  // 143 deg/s
  EXPECT_NE(MotionProblem(r, 300, 0.1, o).find("deg/s > max_rotation_rate_deg_s"), std::string::npos);
  EXPECT_DOUBLE_EQ(SpeedMps(Motion(), 0.0), Motion().translation().norm() / kMinTimeStepS);
}

TEST(StereoTracking, MotionGuessesLeaveOutRepeats) {
  const Pose3d still = Pose3d::Identity();
  // No motion seen yet: the prediction is standing still, the one guess.
  EXPECT_EQ(MotionGuesses(still, still, 0.0, 0.1).size(), 1u);
  // Moving at a constant velocity: the last moving motion scaled to the step is the prediction.
  const std::vector<Pose3d> two = MotionGuesses(Motion(), Motion(), 0.1, 0.1);
  ASSERT_EQ(two.size(), 2u);
  EXPECT_TRUE(two[0].isApprox(Motion()));
  EXPECT_TRUE(two[1].isApprox(still));
  // Stopped for a frame: the prediction, the moving motion over twice its step, standing still.
  const std::vector<Pose3d> three = MotionGuesses(ScaleMotion(Motion(), 0.5), Motion(), 0.1, 0.2);
  ASSERT_EQ(three.size(), 3u);
  EXPECT_NEAR((three[1].translation() - 2.0 * Motion().translation()).norm(), 0.0, 1e-12);
  EXPECT_NEAR(RotationAngleRad(three[1]), 0.04, 1e-12);
  EXPECT_NEAR(RotationAngleRad(three[0]), 0.01, 1e-12);
}

TEST(StereoTracking, MedianDisparityIsTheUpperMiddleOfTheDisparities) {
  StereoFeatures f;
  const std::vector<float> d = {4.0f, 1.5f, 9.0f, 2.0f};
  for (size_t i = 0; i < d.size(); ++i) {
    f.left.emplace_back(100.0f + i, 50.0f);
    f.right.emplace_back(100.0f + i - d[i], 50.0f);
  }
  std::vector<float> sorted = d;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_DOUBLE_EQ(MedianDisparityPx(f), sorted[2]);
  EXPECT_DOUBLE_EQ(MedianDisparityPx(StereoFeatures{}), 0.0);
}

RefinedMotion OffsetEstimate(double constant_px, double per_row_px, double sigma_px,
                             const Eigen::Matrix2d& info) {
  RefinedMotion e;
  e.disparity_offset = {constant_px, per_row_px};
  e.disparity_offset_sigma_px = sigma_px;
  e.offset_information = info;
  return e;
}

TEST(StereoTracking, OffsetVotesAverageByTheirInformation) {
  // The constant alone: Σ I_k x_k / Σ I_k, each I_k capped at 1 / 0.02² (2500 / px²).
  OffsetMean mean;
  const double xs[] = {0.30, 0.10, 0.20};
  const double sigmas[] = {0.1, 0.05, 0.01};  // the last is surer than the cap
  double sum_i = 0.0, sum_ix = 0.0;
  for (int k = 0; k < 3; ++k) {
    Eigen::Matrix2d info = Eigen::Matrix2d::Zero();
    info(0, 0) = 1.0 / (sigmas[k] * sigmas[k]);
    AddOffsetVote(OffsetEstimate(xs[k], 0.0, sigmas[k], info), 1, &mean);
    const double capped = std::min(info(0, 0), 2500.0);
    sum_i += capped;
    sum_ix += capped * xs[k];
  }
  EXPECT_NEAR(mean.offset.constant_px, sum_ix / sum_i, 1e-12);
  EXPECT_EQ(mean.offset.per_row_px, 0.0);
  // An exact estimate counts as the cap, on the constant alone.
  OffsetMean exact;
  AddOffsetVote(OffsetEstimate(0.4, 0.0, 0.0, Eigen::Matrix2d::Zero()), 1, &exact);
  EXPECT_DOUBLE_EQ(exact.information(0, 0), 2500.0);
  EXPECT_DOUBLE_EQ(exact.offset.constant_px, 0.4);
}

TEST(StereoTracking, TwoTermOffsetVotesSolveTheirSummedInformation) {
  OffsetMean mean;
  Eigen::Matrix2d a, b;
  a << 400.0, 50.0, 50.0, 100.0;
  b << 300.0, -80.0, -80.0, 200.0;
  AddOffsetVote(OffsetEstimate(0.2, 0.5, 0.06, a), 2, &mean);
  AddOffsetVote(OffsetEstimate(0.1, -0.3, 0.07, b), 2, &mean);
  // (A + B) m = A x_a + B x_b, by Cramer's rule.
  const Eigen::Vector2d rhs = a * Eigen::Vector2d(0.2, 0.5) + b * Eigen::Vector2d(0.1, -0.3);
  const Eigen::Matrix2d s = a + b;
  const double det = s(0, 0) * s(1, 1) - s(0, 1) * s(1, 0);
  EXPECT_NEAR(mean.offset.constant_px, (rhs(0) * s(1, 1) - s(0, 1) * rhs(1)) / det, 1e-12);
  EXPECT_NEAR(mean.offset.per_row_px, (s(0, 0) * rhs(1) - s(1, 0) * rhs(0)) / det, 1e-12);
}

TEST(StereoTracking, OnlySureAndPlausibleOffsetEstimatesVote) {
  const Eigen::Matrix2d info = Eigen::Matrix2d::Identity();
  EXPECT_TRUE(OffsetEstimateVotes(OffsetEstimate(0.3, 0.0, 0.25, info)));
  EXPECT_FALSE(OffsetEstimateVotes(OffsetEstimate(0.3, 0.0, 0.26, info)));          // unsure
  EXPECT_FALSE(OffsetEstimateVotes(OffsetEstimate(0.3, 0.0, std::nan(""), info)));  // no estimate
  EXPECT_FALSE(OffsetEstimateVotes(OffsetEstimate(5.5, 0.0, 0.1, info)));           // a wrong calibration
  EXPECT_FALSE(OffsetEstimateVotes(OffsetEstimate(0.3, -5.5, 0.1, info)));
}

TEST(StereoTracking, ScaleMotionScalesTheAngleAndTheTranslation) {
  const Pose3d half = ScaleMotion(Motion(), 0.5);
  EXPECT_NEAR(RotationAngleRad(half), 0.01, 1e-12);
  EXPECT_NEAR((half.translation() - 0.5 * Motion().translation()).norm(), 0.0, 1e-15);
  // The same axis: half the rotation twice is the whole one.
  EXPECT_TRUE((half.linear() * half.linear()).isApprox(Motion().linear(), 1e-12));
  EXPECT_TRUE(ScaleMotion(Motion(), 0.0).isApprox(Pose3d::Identity()));
}

}  // namespace
}  // namespace semap::odometry_internal
