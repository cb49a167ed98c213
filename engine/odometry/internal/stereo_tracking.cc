#include "engine/odometry/internal/stereo_tracking.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

namespace semap::odometry_internal {

namespace {

constexpr double kPi = 3.14159265358979323846;
// KLT stops after this many iterations or when the update is below this, px.
constexpr int kKltMaxIterations = 30;
constexpr double kKltEpsilonPx = 0.01;
// P3P RANSAC stops early once it is this sure of its best hypothesis.
constexpr double kRansacConfidence = 0.999;
// Two guesses this close (Eigen isApprox precision) are one: the second is not tried.
constexpr double kSameGuess = 1e-3;
// A frame's offset estimate with a standard deviation below this counts as this (one frame must not
// dominate the running mean), px.
constexpr double kMinOffsetSigmaPx = 0.02;
// A frame whose estimate is less sure than this cannot tell the offset (standing still, turning on the
// spot: the depths do not change with the motion) and does not vote, px.
constexpr double kMaxOffsetSigmaPx = 0.25;
// Gauss-Newton steps of a frame's offset estimate: it starts from the refined motion, so a few suffice.
constexpr int kOffsetIterations = 4;

cv::TermCriteria KltTermination() {
  return cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, kKltMaxIterations, kKltEpsilonPx);
}

}  // namespace

Pose3d ScaleMotion(const Pose3d& motion, double fraction) {
  const Eigen::AngleAxisd aa(motion.linear());
  Pose3d out = Pose3d::Identity();
  out.linear() = Eigen::AngleAxisd(aa.angle() * fraction, aa.axis()).toRotationMatrix();
  out.translation() = motion.translation() * fraction;
  return out;
}

double RotationAngleRad(const Pose3d& motion) { return Eigen::AngleAxisd(motion.linear()).angle(); }

cv::Mat Gray(const cv::Mat& image) {
  if (image.channels() == 1) return image;
  cv::Mat gray;
  cv::cvtColor(image, gray, image.channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
  return gray;
}

Eigen::Vector3d Triangulate(const StereoCalibration& c, const cv::Point2f& l, const cv::Point2f& r,
                            const DisparityOffset& offset) {
  return c.Unproject(l.x, l.y, c.DepthFromDisparity(l.x - r.x + offset.At(l.y, c)));
}

FrameImages StereoMatcher::Prepare(const cv::Mat& left, const cv::Mat& right) const {
  FrameImages f;
  f.left = Gray(left);
  const cv::Size win(o_.klt_window_px, o_.klt_window_px);
  const int levels = std::max(o_.klt_levels, o_.stereo_levels);
  cv::buildOpticalFlowPyramid(f.left, f.left_pyramid, win, levels, true);
  cv::buildOpticalFlowPyramid(Gray(right), f.right_pyramid, win, levels, true);
  return f;
}

bool StereoMatcher::Inside(const cv::Point2f& p) const {
  const float margin = static_cast<float>(o_.klt_window_px / 2);
  return p.x >= margin && p.y >= margin && p.x < static_cast<float>(c_.width_px) - margin &&
         p.y < static_cast<float>(c_.height_px) - margin;
}

void StereoMatcher::MatchStereo(const FrameImages& f, const std::vector<cv::Point2f>& left_px,
                                std::vector<cv::Point2f>* right_px, std::vector<bool>* ok) const {
  ok->assign(left_px.size(), false);
  if (left_px.empty()) return;
  const cv::Size win(o_.klt_window_px, o_.klt_window_px);
  const cv::TermCriteria term = KltTermination();
  std::vector<uchar> status, back_status;
  std::vector<float> err;
  cv::calcOpticalFlowPyrLK(f.left_pyramid, f.right_pyramid, left_px, *right_px, status, err, win,
                           o_.stereo_levels, term, cv::OPTFLOW_USE_INITIAL_FLOW);
  std::vector<cv::Point2f> back = left_px;
  cv::calcOpticalFlowPyrLK(f.right_pyramid, f.left_pyramid, *right_px, back, back_status, err, win, 1, term,
                           cv::OPTFLOW_USE_INITIAL_FLOW);
  for (size_t i = 0; i < left_px.size(); ++i) {
    const cv::Point2f& l = left_px[i];
    const cv::Point2f& r = (*right_px)[i];
    (*ok)[i] = status[i] && back_status[i] && Inside(r) && std::abs(r.y - l.y) <= o_.max_epipolar_error_px &&
               l.x - r.x >= o_.min_disparity_px && cv::norm(back[i] - l) <= o_.max_stereo_check_px;
  }
}

int StereoMatcher::CellOf(const cv::Point2f& p) const {
  const int cx = std::clamp(static_cast<int>(p.x * o_.grid_cols / c_.width_px), 0, o_.grid_cols - 1);
  const int cy = std::clamp(static_cast<int>(p.y * o_.grid_rows / c_.height_px), 0, o_.grid_rows - 1);
  return cy * o_.grid_cols + cx;
}

std::vector<cv::Point2f> StereoMatcher::Detect(const FrameImages& f,
                                               const std::vector<cv::Point2f>& existing) const {
  std::vector<cv::KeyPoint> corners;
  cv::FAST(f.left, corners, o_.fast_threshold, true);
  std::sort(corners.begin(), corners.end(),
            [](const cv::KeyPoint& a, const cv::KeyPoint& b) { return a.response > b.response; });
  const int cells = o_.grid_cols * o_.grid_rows;
  const int per_cell = std::max(1, o_.max_features / cells);
  std::vector<int> count(static_cast<size_t>(cells), 0);
  // One flag per kMinFeatureSpacingPx square: a feature there already.
  cv::Mat occupied = cv::Mat::zeros(c_.height_px / kMinFeatureSpacingPx + 1,
                                    c_.width_px / kMinFeatureSpacingPx + 1, CV_8UC1);
  const auto occupied_at = [&occupied](const cv::Point2f& p) -> uchar& {
    return occupied.at<uchar>(static_cast<int>(p.y) / kMinFeatureSpacingPx,
                              static_cast<int>(p.x) / kMinFeatureSpacingPx);
  };
  for (const auto& p : existing) {
    ++count[static_cast<size_t>(CellOf(p))];
    occupied_at(p) = 1;
  }
  std::vector<cv::Point2f> out;
  int total = static_cast<int>(existing.size());
  for (const auto& k : corners) {
    if (total >= o_.max_features) break;
    if (!Inside(k.pt)) continue;
    const int cell = CellOf(k.pt);
    if (count[static_cast<size_t>(cell)] >= per_cell) continue;
    if (occupied_at(k.pt)) continue;
    occupied_at(k.pt) = 1;
    ++count[static_cast<size_t>(cell)];
    ++total;
    out.push_back(k.pt);
  }
  return out;
}

double MedianDisparityPx(const StereoFeatures& features) {
  if (features.left.empty()) return 0.0;
  std::vector<float> d;
  for (size_t i = 0; i < features.left.size(); ++i) d.push_back(features.left[i].x - features.right[i].x);
  std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2), d.end());
  return d[d.size() / 2];
}

StereoFeatures TopUpFeatures(const StereoMatcher& matcher, const FrameImages& frame, StereoFeatures kept) {
  const std::vector<cv::Point2f> fresh = matcher.Detect(frame, kept.left);
  const double disparity_guess_px = MedianDisparityPx(kept);
  std::vector<cv::Point2f> fresh_right;
  for (const auto& p : fresh) fresh_right.emplace_back(p.x - static_cast<float>(disparity_guess_px), p.y);
  std::vector<bool> ok;
  matcher.MatchStereo(frame, fresh, &fresh_right, &ok);
  for (size_t i = 0; i < fresh.size(); ++i) {
    if (!ok[i]) continue;
    kept.left.push_back(fresh[i]);
    kept.right.push_back(fresh_right[i]);
  }
  return kept;
}

std::vector<cv::Point2f> PredictFeaturePositions(const StereoCalibration& c, const StereoFeatures& ref,
                                                 const DisparityOffset& offset, const Pose3d& cur_from_ref) {
  std::vector<cv::Point2f> starts(ref.left.size());
  for (size_t i = 0; i < ref.left.size(); ++i) {
    const Eigen::Vector3d p = cur_from_ref * Triangulate(c, ref.left[i], ref.right[i], offset);
    starts[i] = ref.left[i];
    if (p.z() > 0.0) {
      const Eigen::Vector2d uv = c.Project(p);
      if (c.InImage(uv)) starts[i] = cv::Point2f(static_cast<float>(uv.x()), static_cast<float>(uv.y()));
    }
  }
  return starts;
}

TrackedFeatures TrackFeatures(const StereoMatcher& matcher, const StereoOdometryOptions& options,
                              const std::vector<cv::Mat>& ref_left_pyramid, const StereoFeatures& ref,
                              const FrameImages& frame, const std::vector<cv::Point2f>& starts) {
  std::vector<cv::Point2f> cur_left = starts;
  const cv::Size win(options.klt_window_px, options.klt_window_px);
  std::vector<uchar> status;
  std::vector<float> err;
  cv::calcOpticalFlowPyrLK(ref_left_pyramid, frame.left_pyramid, ref.left, cur_left, status, err, win,
                           options.klt_levels, KltTermination(), cv::OPTFLOW_USE_INITIAL_FLOW);
  TrackedFeatures tracked;
  for (size_t i = 0; i < cur_left.size(); ++i) {
    if (!status[i] || !matcher.Inside(cur_left[i])) continue;
    tracked.ref_index.push_back(i);
    tracked.left.push_back(cur_left[i]);
    const float ref_disparity = ref.left[i].x - ref.right[i].x;
    tracked.right.emplace_back(cur_left[i].x - ref_disparity, cur_left[i].y);
  }
  matcher.MatchStereo(frame, tracked.left, &tracked.right, &tracked.stereo_ok);
  return tracked;
}

std::vector<StereoMatch> MakeStereoMatches(const StereoFeatures& ref, const TrackedFeatures& tracked) {
  std::vector<StereoMatch> matches(tracked.ref_index.size());
  for (size_t k = 0; k < tracked.ref_index.size(); ++k) {
    const size_t i = tracked.ref_index[k];
    StereoMatch& m = matches[k];
    m.ref_left_px = {ref.left[i].x, ref.left[i].y};
    m.ref_right_u_px = ref.right[i].x;
    m.cur_left_px = {tracked.left[k].x, tracked.left[k].y};
    m.has_current_right = tracked.stereo_ok[k];
    m.cur_right_u_px = tracked.right[k].x;
  }
  return matches;
}

StartMotion EstimateStartMotion(const StereoCalibration& c, const StereoOdometryOptions& options,
                                const StereoFeatures& ref, const DisparityOffset& offset,
                                const TrackedFeatures& tracked) {
  std::vector<cv::Point3f> object_points;
  for (const size_t i : tracked.ref_index) {
    const Eigen::Vector3d x = Triangulate(c, ref.left[i], ref.right[i], offset);
    object_points.emplace_back(static_cast<float>(x.x()), static_cast<float>(x.y()),
                               static_cast<float>(x.z()));
  }
  const cv::Matx33d k(c.fx_px, 0.0, c.cx_px, 0.0, c.fy_px, c.cy_px, 0.0, 0.0, 1.0);
  cv::Mat rvec, tvec;
  std::vector<int> ransac_inliers;
  StartMotion start;
  start.solved = cv::solvePnPRansac(
      object_points, tracked.left, k, cv::noArray(), rvec, tvec, false, options.ransac_iterations,
      static_cast<float>(options.ransac_threshold_px), kRansacConfidence, ransac_inliers, cv::SOLVEPNP_AP3P);
  start.num_inliers = static_cast<int>(ransac_inliers.size());
  start.inliers.assign(tracked.ref_index.size(), false);
  for (int i : ransac_inliers) start.inliers[static_cast<size_t>(i)] = true;
  if (!start.solved) return start;
  cv::Matx33d r;
  cv::Rodrigues(rvec, r);
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) start.cur_from_ref.linear()(a, b) = r(a, b);
    start.cur_from_ref.translation()(a) = tvec.at<double>(a);
  }
  return start;
}

double SpeedMps(const Pose3d& cur_from_ref, double dt_s) {
  return cur_from_ref.translation().norm() / std::max(std::abs(dt_s), kMinTimeStepS);
}

std::string MotionProblem(const RefinedMotion& refined, int features, double dt_s,
                          const StereoOdometryOptions& options) {
  const double step_s = std::max(std::abs(dt_s), kMinTimeStepS);
  const double speed_mps = SpeedMps(refined.cur_from_ref, dt_s);
  const double turn_deg_s = RotationAngleRad(refined.cur_from_ref) * 180.0 / kPi / step_s;
  if (refined.num_inliers < options.min_inliers ||
      refined.num_inliers < options.min_inlier_ratio * features) {
    return std::to_string(refined.num_inliers) + " inliers of " + std::to_string(features) +
           " tracked features";
  }
  if (!refined.cur_from_ref.matrix().allFinite() || speed_mps > options.max_speed_mps) {
    return "the motion jumps (" + std::to_string(speed_mps) + " m/s > max_speed_mps)";
  }
  if (turn_deg_s > options.max_rotation_rate_deg_s) {
    return "the motion jumps (" + std::to_string(turn_deg_s) + " deg/s > max_rotation_rate_deg_s)";
  }
  return "";
}

std::vector<Pose3d> MotionGuesses(const Pose3d& predicted, const Pose3d& moving_motion, double moving_dt_s,
                                  double dt_s) {
  std::vector<Pose3d> candidates = {predicted};
  if (moving_dt_s > 0.0) candidates.push_back(ScaleMotion(moving_motion, dt_s / moving_dt_s));
  candidates.push_back(Pose3d::Identity());
  std::vector<Pose3d> guesses;
  for (size_t g = 0; g < candidates.size(); ++g) {
    bool tried = false;
    for (size_t h = 0; h < g; ++h) tried = tried || candidates[h].isApprox(candidates[g], kSameGuess);
    if (!tried) guesses.push_back(candidates[g]);
  }
  return guesses;
}

RefinedMotion EstimateFrameOffset(const StereoCalibration& c, const std::vector<StereoMatch>& matches,
                                  const RefinedMotion& refined, const RefinerOptions& refiner, int terms) {
  RefinerOptions eo = refiner;
  eo.estimate_offset_terms = terms;
  eo.rounds = 1;
  eo.iterations = kOffsetIterations;
  return RefineStereoMotion(c, matches, refined.cur_from_ref, refined.inliers, eo);
}

bool OffsetEstimateVotes(const RefinedMotion& estimate) {
  // A NaN standard deviation does not vote; a NaN term is not beyond the bound.
  return estimate.disparity_offset_sigma_px <= kMaxOffsetSigmaPx &&
         !(std::abs(estimate.disparity_offset.constant_px) > kMaxDisparityOffsetPx) &&
         !(std::abs(estimate.disparity_offset.per_row_px) > kMaxDisparityOffsetPx);
}

void AddOffsetVote(const RefinedMotion& estimate, int terms, OffsetMean* mean) {
  const double sigma = estimate.disparity_offset_sigma_px;
  Eigen::Matrix2d info = Eigen::Matrix2d::Zero();
  if (sigma > 0.0) {
    const double scale =
        sigma < kMinOffsetSigmaPx ? (sigma * sigma) / (kMinOffsetSigmaPx * kMinOffsetSigmaPx) : 1.0;
    info = scale * estimate.offset_information;
  } else {
    info(0, 0) = 1.0 / (kMinOffsetSigmaPx * kMinOffsetSigmaPx);
  }
  const Eigen::Vector2d x(estimate.disparity_offset.constant_px, estimate.disparity_offset.per_row_px);
  mean->information += info;
  mean->weighted_sum += info * x;
  if (terms == 2 && mean->information(1, 1) > 0.0 && mean->information.determinant() > 0.0) {
    const Eigen::Vector2d m = mean->information.ldlt().solve(mean->weighted_sum);
    mean->offset = {m(0), m(1)};
  } else {
    mean->offset.constant_px = mean->weighted_sum(0) / mean->information(0, 0);
  }
}

}  // namespace semap::odometry_internal
