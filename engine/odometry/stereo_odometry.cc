#include "engine/odometry/stereo_odometry.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <stdexcept>

#include "engine/core/check.h"
#include "engine/odometry/internal/stereo_pose_refiner.h"

namespace semap {

using odometry_internal::RefinedMotion;
using odometry_internal::RefinerOptions;
using odometry_internal::RefineStereoMotion;
using odometry_internal::StereoMatch;

namespace {

constexpr double kPi = 3.14159265358979323846;
// Features closer than this to each other are one: a new corner goes only where no feature is this close, px.
constexpr int kMinFeatureSpacingPx = 8;
// KLT stops after this many iterations or when the update is below this, px.
constexpr int kKltMaxIterations = 30;
constexpr double kKltEpsilonPx = 0.01;
// P3P RANSAC stops early once it is this sure of its best hypothesis.
constexpr double kRansacConfidence = 0.999;
// A tracked motion faster than this is "moving": KLT's second guess after a frame that stood still, m/s.
constexpr double kMovingSpeedMps = 0.5;
// Two guesses this close (Eigen isApprox precision) are one: the second is not tried.
constexpr double kSameGuess = 1e-3;
// A time step below this is taken as this when turning a motion into a speed (duplicated timestamps), s.
constexpr double kMinTimeStepS = 1e-3;
// A disparity offset (either term) beyond this is not a rectification error but a wrong calibration, px.
constexpr double kMaxDisparityOffsetPx = 5.0;
// A frame's offset estimate with a standard deviation below this counts as this (one frame must not
// dominate the running mean), px.
constexpr double kMinOffsetSigmaPx = 0.02;
// A frame whose estimate is less sure than this cannot tell the offset (standing still, turning on the
// spot: the depths do not change with the motion) and does not vote, px.
constexpr double kMaxOffsetSigmaPx = 0.25;
// Gauss-Newton steps of a frame's offset estimate: it starts from the refined motion, so a few suffice.
constexpr int kOffsetIterations = 4;

double ThreadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

// `motion` scaled to `fraction` of itself (rotation angle and translation), e.g. a velocity over another
// time step.
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

}  // namespace

void StereoOdometryOptions::Check() const {
  SEMAP_CHECK_OPTION(max_features >= 8, "max_features", max_features, "must be >= 8");
  SEMAP_CHECK_OPTION(grid_cols >= 1, "grid_cols", grid_cols, "must be >= 1");
  SEMAP_CHECK_OPTION(grid_rows >= 1, "grid_rows", grid_rows, "must be >= 1");
  SEMAP_CHECK_OPTION(fast_threshold >= 1 && fast_threshold <= 255, "fast_threshold", fast_threshold,
                     "must be in [1, 255]");
  SEMAP_CHECK_OPTION(klt_window_px >= 5 && klt_window_px % 2 == 1, "klt_window_px", klt_window_px,
                     "must be odd and >= 5");
  SEMAP_CHECK_OPTION(klt_levels >= 0 && klt_levels <= 8, "klt_levels", klt_levels, "must be in [0, 8]");
  SEMAP_CHECK_OPTION(stereo_levels >= 0 && stereo_levels <= 8, "stereo_levels", stereo_levels,
                     "must be in [0, 8]");
  SEMAP_CHECK_OPTION(std::isfinite(max_epipolar_error_px) && max_epipolar_error_px > 0.0,
                     "max_epipolar_error_px", max_epipolar_error_px, "must be finite and > 0");
  SEMAP_CHECK_OPTION(std::isfinite(max_stereo_check_px) && max_stereo_check_px > 0.0, "max_stereo_check_px",
                     max_stereo_check_px, "must be finite and > 0");
  SEMAP_CHECK_OPTION(std::isfinite(min_disparity_px) && min_disparity_px > 0.0, "min_disparity_px",
                     min_disparity_px, "must be finite and > 0");
  SEMAP_CHECK_OPTION(std::isfinite(ransac_threshold_px) && ransac_threshold_px > 0.0, "ransac_threshold_px",
                     ransac_threshold_px, "must be finite and > 0");
  SEMAP_CHECK_OPTION(ransac_iterations >= 1, "ransac_iterations", ransac_iterations, "must be >= 1");
  SEMAP_CHECK_OPTION(std::isfinite(inlier_threshold_px) && inlier_threshold_px > 0.0, "inlier_threshold_px",
                     inlier_threshold_px, "must be finite and > 0");
  SEMAP_CHECK_OPTION(min_inliers >= 6, "min_inliers", min_inliers, "must be >= 6");
  SEMAP_CHECK_OPTION(min_inlier_ratio >= 0.0 && min_inlier_ratio <= 1.0, "min_inlier_ratio", min_inlier_ratio,
                     "must be in [0, 1]");
  SEMAP_CHECK_OPTION(std::isfinite(max_speed_mps) && max_speed_mps > 0.0, "max_speed_mps", max_speed_mps,
                     "must be finite and > 0");
  SEMAP_CHECK_OPTION(std::isfinite(max_rotation_rate_deg_s) && max_rotation_rate_deg_s > 0.0,
                     "max_rotation_rate_deg_s", max_rotation_rate_deg_s, "must be finite and > 0");
  SEMAP_CHECK_OPTION(max_bridged_frames >= 0, "max_bridged_frames", max_bridged_frames, "must be >= 0");
  SEMAP_CHECK_OPTION(keyframe_max_frames >= 1, "keyframe_max_frames", keyframe_max_frames, "must be >= 1");
  SEMAP_CHECK_OPTION(keyframe_min_inlier_ratio >= 0.0 && keyframe_min_inlier_ratio <= 1.0,
                     "keyframe_min_inlier_ratio", keyframe_min_inlier_ratio, "must be in [0, 1]");
  SEMAP_CHECK_OPTION(
      std::isfinite(disparity_offset_px) && std::abs(disparity_offset_px) <= kMaxDisparityOffsetPx,
      "disparity_offset_px", disparity_offset_px, "must be finite and within ±5 px");
  SEMAP_CHECK_OPTION(std::isfinite(disparity_offset_per_row_px) &&
                         std::abs(disparity_offset_per_row_px) <= kMaxDisparityOffsetPx,
                     "disparity_offset_per_row_px", disparity_offset_per_row_px,
                     "must be finite and within ±5 px");
}

const char* OdometryStatusName(OdometryStatus status) {
  switch (status) {
    case OdometryStatus::kFirst:
      return "first";
    case OdometryStatus::kTracked:
      return "tracked";
    case OdometryStatus::kBridged:
      return "bridged";
    case OdometryStatus::kRestarted:
      return "restarted";
  }
  return "?";
}

// The reference frame: the last tracked one, with its features' stereo matches.
struct StereoOdometry::State {
  bool started = false;
  Pose3d first_world_from_cam = Pose3d::Identity();
  // Reference frame.
  std::vector<cv::Mat> ref_left_pyramid;
  std::vector<cv::Point2f> ref_left_px;
  std::vector<cv::Point2f> ref_right_px;
  Pose3d world_from_ref = Pose3d::Identity();
  double ref_timestamp_s = 0.0;
  // The last tracked motion (cur_from_ref) over its time step: the constant-velocity model.
  Pose3d velocity_motion = Pose3d::Identity();
  double velocity_dt_s = 0.0;  // 0: no motion seen yet (prediction: standing still)
  // The last tracked motion faster than kMovingSpeedMps, likewise.
  Pose3d moving_motion = Pose3d::Identity();
  double moving_dt_s = 0.0;
  int failed_in_a_row = 0;
  int tracked_from_ref = 0;  // frames tracked from the reference so far
  // The disparity offset: in use, and the information-weighted sums of the frames' estimates (constant,
  // per row).
  DisparityOffset offset;
  Eigen::Matrix2d offset_information = Eigen::Matrix2d::Zero();
  Eigen::Vector2d offset_weighted_sum = Eigen::Vector2d::Zero();
};

StereoOdometry::StereoOdometry(const StereoOdometryOptions& options, const StereoCalibration& calibration)
    : options_(options), calibration_(calibration), state_(std::make_unique<State>()) {
  options_.Check();
  state_->offset = {options_.disparity_offset_px, options_.disparity_offset_per_row_px};
  if (!calibration_.IsValid()) throw InvalidOption("calibration", "is not a valid stereo calibration");
}

StereoOdometry::~StereoOdometry() = default;

void StereoOdometry::SetFirstPose(const Pose3d& world_from_cam) {
  SEMAP_ASSERT(!state_->started, "SetFirstPose after the first frame");
  state_->first_world_from_cam = world_from_cam;
}

namespace {

// What one frame's images give: pyramids and the matching parameters.
struct FrameImages {
  cv::Mat left;
  std::vector<cv::Mat> left_pyramid;
  std::vector<cv::Mat> right_pyramid;
};

class Matcher {
 public:
  Matcher(const StereoOdometryOptions& o, const StereoCalibration& c) : o_(o), c_(c) {}

  FrameImages Prepare(const cv::Mat& left, const cv::Mat& right) const {
    FrameImages f;
    f.left = Gray(left);
    const cv::Size win(o_.klt_window_px, o_.klt_window_px);
    const int levels = std::max(o_.klt_levels, o_.stereo_levels);
    cv::buildOpticalFlowPyramid(f.left, f.left_pyramid, win, levels, true);
    cv::buildOpticalFlowPyramid(Gray(right), f.right_pyramid, win, levels, true);
    return f;
  }

  bool Inside(const cv::Point2f& p) const {
    const float margin = static_cast<float>(o_.klt_window_px / 2);
    return p.x >= margin && p.y >= margin && p.x < static_cast<float>(c_.width_px) - margin &&
           p.y < static_cast<float>(c_.height_px) - margin;
  }

  // Right-image positions of `left_px` (starting from `right_px`, filled in place); ok[i] says whether
  // point i has a stereo match (on its row, positive disparity, consistent back to the left image).
  void MatchStereo(const FrameImages& f, const std::vector<cv::Point2f>& left_px,
                   std::vector<cv::Point2f>* right_px, std::vector<bool>* ok) const {
    ok->assign(left_px.size(), false);
    if (left_px.empty()) return;
    const cv::Size win(o_.klt_window_px, o_.klt_window_px);
    const cv::TermCriteria term(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, kKltMaxIterations,
                                kKltEpsilonPx);
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
      (*ok)[i] = status[i] && back_status[i] && Inside(r) &&
                 std::abs(r.y - l.y) <= o_.max_epipolar_error_px && l.x - r.x >= o_.min_disparity_px &&
                 cv::norm(back[i] - l) <= o_.max_stereo_check_px;
    }
  }

  // New FAST corners of the left image where `existing` leaves room: strongest first, at most
  // max_features / cells per grid cell (counting the existing ones), none within kMinFeatureSpacingPx of
  // another feature.
  std::vector<cv::Point2f> Detect(const FrameImages& f, const std::vector<cv::Point2f>& existing) const {
    std::vector<cv::KeyPoint> corners;
    cv::FAST(f.left, corners, o_.fast_threshold, true);
    std::sort(corners.begin(), corners.end(),
              [](const cv::KeyPoint& a, const cv::KeyPoint& b) { return a.response > b.response; });
    const int cells = o_.grid_cols * o_.grid_rows;
    const int per_cell = std::max(1, o_.max_features / cells);
    std::vector<int> count(static_cast<size_t>(cells), 0);
    auto cell_of = [&](const cv::Point2f& p) {
      const int cx = std::clamp(static_cast<int>(p.x * o_.grid_cols / c_.width_px), 0, o_.grid_cols - 1);
      const int cy = std::clamp(static_cast<int>(p.y * o_.grid_rows / c_.height_px), 0, o_.grid_rows - 1);
      return cy * o_.grid_cols + cx;
    };
    cv::Mat occupied = cv::Mat::zeros(c_.height_px / kMinFeatureSpacingPx + 1,
                                      c_.width_px / kMinFeatureSpacingPx + 1, CV_8UC1);
    auto occupy = [&](const cv::Point2f& p) {
      occupied.at<uchar>(static_cast<int>(p.y) / kMinFeatureSpacingPx,
                         static_cast<int>(p.x) / kMinFeatureSpacingPx) = 1;
    };
    for (const auto& p : existing) {
      ++count[static_cast<size_t>(cell_of(p))];
      occupy(p);
    }
    std::vector<cv::Point2f> out;
    int total = static_cast<int>(existing.size());
    for (const auto& k : corners) {
      if (total >= o_.max_features) break;
      if (!Inside(k.pt)) continue;
      const int cell = cell_of(k.pt);
      if (count[static_cast<size_t>(cell)] >= per_cell) continue;
      if (occupied.at<uchar>(static_cast<int>(k.pt.y) / kMinFeatureSpacingPx,
                             static_cast<int>(k.pt.x) / kMinFeatureSpacingPx)) {
        continue;
      }
      occupy(k.pt);
      ++count[static_cast<size_t>(cell)];
      ++total;
      out.push_back(k.pt);
    }
    return out;
  }

 private:
  const StereoOdometryOptions& o_;
  const StereoCalibration& c_;
};

Eigen::Vector3d Triangulate(const StereoCalibration& c, const cv::Point2f& l, const cv::Point2f& r,
                            const DisparityOffset& offset) {
  return c.Unproject(l.x, l.y, c.DepthFromDisparity(l.x - r.x + offset.At(l.y, c)));
}

}  // namespace

OdometryResult StereoOdometry::Track(const cv::Mat& left, const cv::Mat& right, double timestamp_s) {
  const double cpu0_ms = ThreadCpuMs();
  const cv::Size size(calibration_.width_px, calibration_.height_px);
  if (left.empty() || right.empty() || left.size() != size || right.size() != size ||
      left.type() != right.type() || left.depth() != CV_8U) {
    throw std::invalid_argument("stereo odometry: the images (" + std::to_string(left.cols) + "x" +
                                std::to_string(left.rows) + ", " + std::to_string(right.cols) + "x" +
                                std::to_string(right.rows) + ") do not fit the calibration (" +
                                std::to_string(size.width) + "x" + std::to_string(size.height) + ", 8-bit)");
  }
  State& s = *state_;
  const Matcher matcher(options_, calibration_);
  const FrameImages frame = matcher.Prepare(left, right);
  OdometryResult result;
  result.disparity_offset = s.offset;

  // Makes this frame the reference: `kept` features (left, right) plus new corners with a stereo match.
  auto make_reference = [&](std::vector<cv::Point2f> kept_left, std::vector<cv::Point2f> kept_right,
                            const Pose3d& world_from_cam) {
    std::vector<cv::Point2f> fresh = matcher.Detect(frame, kept_left);
    double disparity_guess_px = 0.0;  // the median disparity of the kept features, else zero
    if (!kept_left.empty()) {
      std::vector<float> d;
      for (size_t i = 0; i < kept_left.size(); ++i) d.push_back(kept_left[i].x - kept_right[i].x);
      std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2), d.end());
      disparity_guess_px = d[d.size() / 2];
    }
    std::vector<cv::Point2f> fresh_right;
    for (const auto& p : fresh) fresh_right.emplace_back(p.x - static_cast<float>(disparity_guess_px), p.y);
    std::vector<bool> ok;
    matcher.MatchStereo(frame, fresh, &fresh_right, &ok);
    for (size_t i = 0; i < fresh.size(); ++i) {
      if (!ok[i]) continue;
      kept_left.push_back(fresh[i]);
      kept_right.push_back(fresh_right[i]);
    }
    s.ref_left_pyramid = frame.left_pyramid;
    s.ref_left_px = std::move(kept_left);
    s.ref_right_px = std::move(kept_right);
    s.world_from_ref = world_from_cam;
    s.ref_timestamp_s = timestamp_s;
    s.tracked_from_ref = 0;
    result.stereo_features = static_cast<int>(s.ref_left_px.size());
    result.keyframe = true;
  };
  auto finish = [&]() {
    result.cpu_ms = ThreadCpuMs() - cpu0_ms;
    return result;
  };

  if (!s.started) {
    s.started = true;
    result.status = OdometryStatus::kFirst;
    result.world_from_cam = s.first_world_from_cam;
    make_reference({}, {}, s.first_world_from_cam);
    return finish();
  }

  const double dt_s = timestamp_s - s.ref_timestamp_s;
  const Pose3d predicted = s.velocity_dt_s > 0.0 ? ScaleMotion(s.velocity_motion, dt_s / s.velocity_dt_s)
                                                 : Pose3d::Identity();  // cur_from_ref
  // The frame's own estimate of the offset (its terms unknowns beside the pose, from the refined motion and
  // inliers) joins the information-weighted mean that the next frames use. The motion keeps the offset it was
  // refined with: one frame's estimate is too noisy to move it.
  auto UpdateOffset = [&](const std::vector<StereoMatch>& matches, const RefinedMotion& refined,
                          const RefinerOptions& ro) {
    RefinerOptions eo = ro;
    eo.estimate_offset_terms = options_.estimate_disparity_offset == OffsetEstimate::kPerRow ? 2 : 1;
    eo.rounds = 1;
    eo.iterations = kOffsetIterations;
    const RefinedMotion e =
        RefineStereoMotion(calibration_, matches, refined.cur_from_ref, refined.inliers, eo);
    if (!(e.disparity_offset_sigma_px <= kMaxOffsetSigmaPx) ||
        std::abs(e.disparity_offset.constant_px) > kMaxDisparityOffsetPx ||
        std::abs(e.disparity_offset.per_row_px) > kMaxDisparityOffsetPx) {
      return;
    }
    // No frame counts for more than a standard deviation of kMinOffsetSigmaPx on the constant; exact matches
    // (a standard deviation of 0) count for that much on the constant alone.
    const double sigma = e.disparity_offset_sigma_px;
    Eigen::Matrix2d info = Eigen::Matrix2d::Zero();
    if (sigma > 0.0) {
      const double scale =
          sigma < kMinOffsetSigmaPx ? (sigma * sigma) / (kMinOffsetSigmaPx * kMinOffsetSigmaPx) : 1.0;
      info = scale * e.offset_information;
    } else {
      info(0, 0) = 1.0 / (kMinOffsetSigmaPx * kMinOffsetSigmaPx);
    }
    const Eigen::Vector2d x(e.disparity_offset.constant_px, e.disparity_offset.per_row_px);
    s.offset_information += info;
    s.offset_weighted_sum += info * x;
    if (eo.estimate_offset_terms == 2 && s.offset_information(1, 1) > 0.0 &&
        s.offset_information.determinant() > 0.0) {
      const Eigen::Vector2d mean = s.offset_information.ldlt().solve(s.offset_weighted_sum);
      s.offset = {mean(0), mean(1)};
    } else {
      s.offset.constant_px = s.offset_weighted_sum(0) / s.offset_information(0, 0);
    }
    result.frame_offset = e.disparity_offset;
    result.frame_offset_sigma_px = sigma;
  };
  std::string problem;
  const int ref_count = static_cast<int>(s.ref_left_px.size());
  // One try at tracking from the reference with the motion `guess` (cur_from_ref) as KLT's start: true when
  // the frame is tracked (result and reference updated), else `problem` says why (the first try's is kept).
  auto try_track = [&](const Pose3d& guess) -> bool {
    std::string why;
    // Track the reference features into the left image, from where the guessed motion puts them.
    std::vector<cv::Point2f> cur_left(s.ref_left_px.size());
    for (size_t i = 0; i < s.ref_left_px.size(); ++i) {
      const Eigen::Vector3d p =
          guess * Triangulate(calibration_, s.ref_left_px[i], s.ref_right_px[i], s.offset);
      cur_left[i] = s.ref_left_px[i];
      if (p.z() > 0.0) {
        const Eigen::Vector2d uv = calibration_.Project(p);
        if (calibration_.InImage(uv))
          cur_left[i] = cv::Point2f(static_cast<float>(uv.x()), static_cast<float>(uv.y()));
      }
    }
    const cv::Size win(options_.klt_window_px, options_.klt_window_px);
    const cv::TermCriteria term(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, kKltMaxIterations,
                                kKltEpsilonPx);
    std::vector<uchar> status;
    std::vector<float> err;
    cv::calcOpticalFlowPyrLK(s.ref_left_pyramid, frame.left_pyramid, s.ref_left_px, cur_left, status, err,
                             win, options_.klt_levels, term, cv::OPTFLOW_USE_INITIAL_FLOW);
    std::vector<size_t> tracked;  // reference feature indices
    std::vector<cv::Point2f> tracked_left, tracked_right;
    for (size_t i = 0; i < cur_left.size(); ++i) {
      if (!status[i] || !matcher.Inside(cur_left[i])) continue;
      tracked.push_back(i);
      tracked_left.push_back(cur_left[i]);
      const float ref_disparity = s.ref_left_px[i].x - s.ref_right_px[i].x;
      tracked_right.emplace_back(cur_left[i].x - ref_disparity, cur_left[i].y);
    }
    std::vector<bool> stereo_ok;
    matcher.MatchStereo(frame, tracked_left, &tracked_right, &stereo_ok);
    result.features = static_cast<int>(tracked.size());

    std::vector<StereoMatch> matches(tracked.size());
    std::vector<cv::Point3f> object_points;
    std::vector<cv::Point2f> image_points;
    for (size_t k = 0; k < tracked.size(); ++k) {
      const size_t i = tracked[k];
      StereoMatch& m = matches[k];
      m.ref_left_px = {s.ref_left_px[i].x, s.ref_left_px[i].y};
      m.ref_right_u_px = s.ref_right_px[i].x;
      m.cur_left_px = {tracked_left[k].x, tracked_left[k].y};
      m.has_current_right = stereo_ok[k];
      m.cur_right_u_px = tracked_right[k].x;
      const Eigen::Vector3d x = Triangulate(calibration_, s.ref_left_px[i], s.ref_right_px[i], s.offset);
      object_points.emplace_back(static_cast<float>(x.x()), static_cast<float>(x.y()),
                                 static_cast<float>(x.z()));
      image_points.push_back(tracked_left[k]);
    }
    if (result.features < options_.min_inliers) {
      why = std::to_string(result.features) + " of " + std::to_string(ref_count) + " features tracked";
    } else {
      const cv::Matx33d k(calibration_.fx_px, 0.0, calibration_.cx_px, 0.0, calibration_.fy_px,
                          calibration_.cy_px, 0.0, 0.0, 1.0);
      cv::Mat rvec, tvec;
      std::vector<int> ransac_inliers;
      const bool solved =
          cv::solvePnPRansac(object_points, image_points, k, cv::noArray(), rvec, tvec, false,
                             options_.ransac_iterations, static_cast<float>(options_.ransac_threshold_px),
                             kRansacConfidence, ransac_inliers, cv::SOLVEPNP_AP3P);
      if (!solved || static_cast<int>(ransac_inliers.size()) < options_.min_inliers) {
        why = "no motion fits the tracks (" + std::to_string(ransac_inliers.size()) + " RANSAC inliers of " +
              std::to_string(result.features) + ")";
      } else {
        cv::Matx33d r;
        cv::Rodrigues(rvec, r);
        Pose3d start = Pose3d::Identity();
        for (int a = 0; a < 3; ++a) {
          for (int b = 0; b < 3; ++b) start.linear()(a, b) = r(a, b);
          start.translation()(a) = tvec.at<double>(a);
        }
        std::vector<bool> start_inliers(matches.size(), false);
        for (int i : ransac_inliers) start_inliers[static_cast<size_t>(i)] = true;
        RefinerOptions ro;
        ro.inlier_threshold_px = options_.inlier_threshold_px;
        ro.min_disparity_px = options_.min_disparity_px;
        ro.disparity_offset = s.offset;
        const RefinedMotion refined = RefineStereoMotion(calibration_, matches, start, start_inliers, ro);
        result.inliers = refined.num_inliers;
        const double step_s = std::max(std::abs(dt_s), kMinTimeStepS);
        const double speed_mps = refined.cur_from_ref.translation().norm() / step_s;
        const double turn_deg_s = RotationAngleRad(refined.cur_from_ref) * 180.0 / kPi / step_s;
        if (refined.num_inliers < options_.min_inliers ||
            refined.num_inliers < options_.min_inlier_ratio * result.features) {
          why = std::to_string(refined.num_inliers) + " inliers of " + std::to_string(result.features) +
                " tracked features";
        } else if (!refined.cur_from_ref.matrix().allFinite() || speed_mps > options_.max_speed_mps) {
          why = "the motion jumps (" + std::to_string(speed_mps) + " m/s > max_speed_mps)";
        } else if (turn_deg_s > options_.max_rotation_rate_deg_s) {
          why = "the motion jumps (" + std::to_string(turn_deg_s) + " deg/s > max_rotation_rate_deg_s)";
        } else {
          // Tracked: the frame becomes the reference, its inlier tracks kept with their stereo matches.
          result.status = OdometryStatus::kTracked;
          result.world_from_cam = s.world_from_ref * refined.cur_from_ref.inverse();
          if (options_.estimate_disparity_offset != OffsetEstimate::kOff) UpdateOffset(matches, refined, ro);
          if (dt_s > 0.0) {
            s.velocity_motion = refined.cur_from_ref;
            s.velocity_dt_s = dt_s;
            if (speed_mps > kMovingSpeedMps) {
              s.moving_motion = refined.cur_from_ref;
              s.moving_dt_s = dt_s;
            }
          }
          s.failed_in_a_row = 0;
          ++frames_tracked_;
          // The reference stays for up to keyframe_max_frames tracked frames while most of its features
          // still fit: each frame's pose then comes from one estimate against the keyframe instead of a
          // chain of frame-to-frame ones, whose errors (a bias of a few thousandths of a degree in each
          // rotation on exact generated frames) add up.
          ++s.tracked_from_ref;
          if (s.tracked_from_ref < options_.keyframe_max_frames &&
              refined.num_inliers >= options_.keyframe_min_inlier_ratio * ref_count) {
            result.stereo_features = ref_count;
            return true;
          }
          std::vector<cv::Point2f> kept_left, kept_right;
          for (size_t k = 0; k < matches.size(); ++k) {
            if (!refined.inliers[k] || !stereo_ok[k]) continue;
            kept_left.push_back(tracked_left[k]);
            kept_right.push_back(tracked_right[k]);
          }
          make_reference(std::move(kept_left), std::move(kept_right), result.world_from_cam);
          return true;
        }
      }
    }
    if (problem.empty()) problem = why;
    return false;
  };
  if (ref_count < options_.min_inliers) {
    problem = "the reference frame has " + std::to_string(ref_count) +
              " features with a stereo match (fewer than " + std::to_string(options_.min_inliers) + ")";
  } else {
    // The constant-velocity prediction first; then the last motion that moved (a duplicated frame stops the
    // velocity for one frame), then standing still (a swapped frame reverses it).
    std::vector<Pose3d> guesses = {predicted};
    if (s.moving_dt_s > 0.0) guesses.push_back(ScaleMotion(s.moving_motion, dt_s / s.moving_dt_s));
    guesses.push_back(Pose3d::Identity());
    for (size_t g = 0; g < guesses.size(); ++g) {
      bool tried = false;
      for (size_t h = 0; h < g; ++h) tried = tried || guesses[h].isApprox(guesses[g], kSameGuess);
      if (tried) continue;
      if (try_track(guesses[g])) return finish();
    }
  }

  // Tracking failed: bridge with the constant-velocity guess from the reference frame.
  result.problem = problem;
  result.world_from_cam = s.world_from_ref * predicted.inverse();
  ++s.failed_in_a_row;
  const bool reference_unusable = ref_count < options_.min_inliers;
  if (reference_unusable || s.failed_in_a_row > options_.max_bridged_frames) {
    // Restart on this frame when it has enough features; otherwise keep bridging from the old reference.
    const Pose3d old_ref = s.world_from_ref;
    const double old_t = s.ref_timestamp_s;
    const int old_tracked = s.tracked_from_ref;
    std::vector<cv::Mat> old_pyramid = s.ref_left_pyramid;
    std::vector<cv::Point2f> old_left = s.ref_left_px, old_right = s.ref_right_px;
    make_reference({}, {}, result.world_from_cam);
    if (result.stereo_features >= options_.min_inliers) {
      result.status = OdometryStatus::kRestarted;
      s.failed_in_a_row = 0;
      ++restarts_;
      return finish();
    }
    if (!reference_unusable) {  // keep the usable old reference
      s.world_from_ref = old_ref;
      s.ref_timestamp_s = old_t;
      s.ref_left_pyramid = std::move(old_pyramid);
      s.ref_left_px = std::move(old_left);
      s.ref_right_px = std::move(old_right);
      s.tracked_from_ref = old_tracked;
      result.stereo_features = 0;  // this frame did not become the reference
      result.keyframe = false;
    }
  }
  result.status = OdometryStatus::kBridged;
  ++frames_bridged_;
  return finish();
}

}  // namespace semap
