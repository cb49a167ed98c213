#include "engine/odometry/stereo_odometry.h"

#include <ctime>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "engine/core/check.h"
#include "engine/odometry/internal/stereo_pose_refiner.h"
#include "engine/odometry/internal/stereo_tracking.h"

namespace semap {

using namespace odometry_internal;  // the steps of tracking (internal/stereo_tracking.h)

namespace {

double ThreadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

// Throws std::invalid_argument unless the pair is two 8-bit images of the calibration's size and one type.
void CheckImages(const cv::Mat& left, const cv::Mat& right, const StereoCalibration& calibration) {
  const cv::Size size(calibration.width_px, calibration.height_px);
  if (left.empty() || right.empty() || left.size() != size || right.size() != size ||
      left.type() != right.type() || left.depth() != CV_8U) {
    throw std::invalid_argument("stereo odometry: the images (" + std::to_string(left.cols) + "x" +
                                std::to_string(left.rows) + ", " + std::to_string(right.cols) + "x" +
                                std::to_string(right.rows) + ") do not fit the calibration (" +
                                std::to_string(size.width) + "x" + std::to_string(size.height) + ", 8-bit)");
  }
}

// One try at tracking the reference into a frame from a guessed motion.
struct TrackAttempt {
  TrackedFeatures tracked;
  std::vector<StereoMatch> matches;      // of `tracked`
  RefinerOptions refiner;                // what the motion was refined with
  std::optional<RefinedMotion> refined;  // when P3P found a start to refine
  std::string problem;                   // why the frame is not tracked; empty: it is
};

// The reference frame (a keyframe: the last tracked frame that became one), with its features' stereo
// matches.
struct Reference {
  std::vector<cv::Mat> left_pyramid;
  StereoFeatures features;
  Pose3d world_from_ref = Pose3d::Identity();
  double timestamp_s = 0.0;
  int tracked_from_ref = 0;  // frames tracked from it so far
};

}  // namespace

void StereoOdometryOptions::Check() const { CheckDeclaredRanges(*this); }

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

// What the odometry keeps between frames, and the steps of Track that change it.
struct StereoOdometry::State {
  State(const StereoOdometryOptions& o, const StereoCalibration& c) : options(o), calibration(c) {}

  // Makes `frame` the reference: `kept` features plus new corners with a stereo match.
  void MakeReference(const StereoMatcher& matcher, const FrameImages& frame, StereoFeatures kept,
                     const Pose3d& world_from_cam, double timestamp_s, OdometryResult* result);
  // Tracks the reference into `frame` from the motion `guess` (cur_from_ref); changes nothing.
  TrackAttempt Attempt(const StereoMatcher& matcher, const FrameImages& frame, const Pose3d& guess,
                       double dt_s) const;
  // The frame is tracked by `attempt`: its pose, the offset's vote, the velocity, and the next reference.
  void Accept(const TrackAttempt& attempt, const StereoMatcher& matcher, const FrameImages& frame,
              double dt_s, double timestamp_s, OdometryResult* result);
  // Tracking failed: the constant-velocity pose `predicted` from the reference; after max_bridged_frames such
  // frames in a row, or with a reference too poor to track from, tracking restarts on this frame when it has
  // enough features.
  void Bridge(const StereoMatcher& matcher, const FrameImages& frame, const Pose3d& predicted,
              double timestamp_s, OdometryResult* result);

  const StereoOdometryOptions& options;
  const StereoCalibration& calibration;
  bool started = false;
  Pose3d first_world_from_cam = Pose3d::Identity();
  Reference ref;
  // The last tracked motion (cur_from_ref) over its time step: the constant-velocity model.
  Pose3d velocity_motion = Pose3d::Identity();
  double velocity_dt_s = 0.0;  // 0: no motion seen yet (prediction: standing still)
  // The last tracked motion faster than kMovingSpeedMps, likewise.
  Pose3d moving_motion = Pose3d::Identity();
  double moving_dt_s = 0.0;
  int failed_in_a_row = 0;
  // The disparity offset in use, and the information-weighted sums of the frames' estimates.
  OffsetMean offset;
};

void StereoOdometry::State::MakeReference(const StereoMatcher& matcher, const FrameImages& frame,
                                          StereoFeatures kept, const Pose3d& world_from_cam,
                                          double timestamp_s, OdometryResult* result) {
  ref.features = TopUpFeatures(matcher, frame, std::move(kept));
  ref.left_pyramid = frame.left_pyramid;
  ref.world_from_ref = world_from_cam;
  ref.timestamp_s = timestamp_s;
  ref.tracked_from_ref = 0;
  result->stereo_features = static_cast<int>(ref.features.left.size());
  result->keyframe = true;
}

TrackAttempt StereoOdometry::State::Attempt(const StereoMatcher& matcher, const FrameImages& frame,
                                            const Pose3d& guess, double dt_s) const {
  TrackAttempt a;
  const std::vector<cv::Point2f> starts =
      PredictFeaturePositions(calibration, ref.features, offset.offset, guess);
  a.tracked = TrackFeatures(matcher, options, ref.left_pyramid, ref.features, frame, starts);
  a.matches = MakeStereoMatches(ref.features, a.tracked);
  const int features = static_cast<int>(a.tracked.left.size());
  if (features < options.min_inliers) {
    a.problem =
        std::to_string(features) + " of " + std::to_string(ref.features.left.size()) + " features tracked";
    return a;
  }
  const StartMotion start = EstimateStartMotion(calibration, options, ref.features, offset.offset, a.tracked);
  if (!start.solved || start.num_inliers < options.min_inliers) {
    a.problem = "no motion fits the tracks (" + std::to_string(start.num_inliers) + " RANSAC inliers of " +
                std::to_string(features) + ")";
    return a;
  }
  a.refiner.inlier_threshold_px = options.inlier_threshold_px;
  a.refiner.min_disparity_px = options.min_disparity_px;
  a.refiner.disparity_offset = offset.offset;
  a.refined = RefineStereoMotion(calibration, a.matches, start.cur_from_ref, start.inliers, a.refiner);
  a.problem = MotionProblem(*a.refined, features, dt_s, options);
  return a;
}

void StereoOdometry::State::Accept(const TrackAttempt& attempt, const StereoMatcher& matcher,
                                   const FrameImages& frame, double dt_s, double timestamp_s,
                                   OdometryResult* result) {
  const RefinedMotion& refined = *attempt.refined;
  result->status = OdometryStatus::kTracked;
  result->world_from_cam = ref.world_from_ref * refined.cur_from_ref.inverse();
  if (options.estimate_disparity_offset != OffsetEstimate::kOff) {
    // The frame's own estimate joins the mean that the next frames use; this frame's motion keeps the offset
    // it was refined with: one frame's estimate is too noisy to move it.
    const int terms = options.estimate_disparity_offset == OffsetEstimate::kPerRow ? 2 : 1;
    const RefinedMotion e =
        EstimateFrameOffset(calibration, attempt.matches, refined, attempt.refiner, terms);
    if (OffsetEstimateVotes(e)) {
      AddOffsetVote(e, terms, &offset);
      result->frame_offset = e.disparity_offset;
      result->frame_offset_sigma_px = e.disparity_offset_sigma_px;
    }
  }
  if (dt_s > 0.0) {
    velocity_motion = refined.cur_from_ref;
    velocity_dt_s = dt_s;
    if (SpeedMps(refined.cur_from_ref, dt_s) > kMovingSpeedMps) {
      moving_motion = refined.cur_from_ref;
      moving_dt_s = dt_s;
    }
  }
  failed_in_a_row = 0;
  // The reference stays for up to keyframe_max_frames tracked frames while most of its features still fit:
  // each frame's pose then comes from one estimate against the keyframe instead of a chain of frame-to-frame
  // ones, whose errors (a bias of a few thousandths of a degree in each rotation on exact generated frames)
  // add up.
  const int ref_count = static_cast<int>(ref.features.left.size());
  ++ref.tracked_from_ref;
  if (ref.tracked_from_ref < options.keyframe_max_frames &&
      refined.num_inliers >= options.keyframe_min_inlier_ratio * ref_count) {
    result->stereo_features = ref_count;
    return;
  }
  // The frame becomes the reference, its inlier tracks kept with their stereo matches.
  StereoFeatures kept;
  for (size_t k = 0; k < attempt.matches.size(); ++k) {
    if (!refined.inliers[k] || !attempt.tracked.stereo_ok[k]) continue;
    kept.left.push_back(attempt.tracked.left[k]);
    kept.right.push_back(attempt.tracked.right[k]);
  }
  MakeReference(matcher, frame, std::move(kept), result->world_from_cam, timestamp_s, result);
}

void StereoOdometry::State::Bridge(const StereoMatcher& matcher, const FrameImages& frame,
                                   const Pose3d& predicted, double timestamp_s, OdometryResult* result) {
  result->world_from_cam = ref.world_from_ref * predicted.inverse();
  ++failed_in_a_row;
  result->status = OdometryStatus::kBridged;
  const bool reference_unusable = static_cast<int>(ref.features.left.size()) < options.min_inliers;
  if (!reference_unusable && failed_in_a_row <= options.max_bridged_frames) return;
  // Restart on this frame when it has enough features; otherwise keep bridging from the old reference.
  Reference old = ref;
  MakeReference(matcher, frame, {}, result->world_from_cam, timestamp_s, result);
  if (result->stereo_features >= options.min_inliers) {
    result->status = OdometryStatus::kRestarted;
    failed_in_a_row = 0;
    return;
  }
  if (!reference_unusable) {  // keep the usable old reference
    ref = std::move(old);
    result->stereo_features = 0;  // this frame did not become the reference
    result->keyframe = false;
  }
}

StereoOdometry::StereoOdometry(const StereoOdometryOptions& options, const StereoCalibration& calibration)
    : options_(options), calibration_(calibration), state_(std::make_unique<State>(options_, calibration_)) {
  options_.Check();
  state_->offset.offset = {options_.disparity_offset_px, options_.disparity_offset_per_row_px};
  if (!calibration_.IsValid()) throw InvalidOption("calibration", "is not a valid stereo calibration");
}

StereoOdometry::~StereoOdometry() = default;

void StereoOdometry::SetFirstPose(const Pose3d& world_from_cam) {
  SEMAP_ASSERT(!state_->started, "SetFirstPose after the first frame");
  state_->first_world_from_cam = world_from_cam;
}

OdometryResult StereoOdometry::Track(const cv::Mat& left, const cv::Mat& right, double timestamp_s) {
  const double cpu0_ms = ThreadCpuMs();
  CheckImages(left, right, calibration_);
  State& s = *state_;
  const StereoMatcher matcher(options_, calibration_);
  const FrameImages frame = matcher.Prepare(left, right);
  OdometryResult result;
  result.disparity_offset = s.offset.offset;
  if (!s.started) {
    s.started = true;
    result.status = OdometryStatus::kFirst;
    result.world_from_cam = s.first_world_from_cam;
    s.MakeReference(matcher, frame, {}, s.first_world_from_cam, timestamp_s, &result);
    result.cpu_ms = ThreadCpuMs() - cpu0_ms;
    return result;
  }
  const double dt_s = timestamp_s - s.ref.timestamp_s;
  const Pose3d predicted = s.velocity_dt_s > 0.0 ? ScaleMotion(s.velocity_motion, dt_s / s.velocity_dt_s)
                                                 : Pose3d::Identity();  // cur_from_ref
  const int ref_count = static_cast<int>(s.ref.features.left.size());
  std::string problem;  // the first try's
  if (ref_count < options_.min_inliers) {
    problem = "the reference frame has " + std::to_string(ref_count) +
              " features with a stereo match (fewer than " + std::to_string(options_.min_inliers) + ")";
  } else {
    // The constant-velocity prediction first; then the last motion that moved (a duplicated frame stops the
    // velocity for one frame), then standing still (a swapped frame reverses it).
    for (const Pose3d& guess : MotionGuesses(predicted, s.moving_motion, s.moving_dt_s, dt_s)) {
      const TrackAttempt attempt = s.Attempt(matcher, frame, guess, dt_s);
      result.features = static_cast<int>(attempt.tracked.left.size());
      if (attempt.refined) result.inliers = attempt.refined->num_inliers;
      if (attempt.problem.empty()) {
        s.Accept(attempt, matcher, frame, dt_s, timestamp_s, &result);
        break;
      }
      if (problem.empty()) problem = attempt.problem;
    }
  }
  if (result.status != OdometryStatus::kTracked) {
    result.problem = problem;
    s.Bridge(matcher, frame, predicted, timestamp_s, &result);
  }
  if (result.status == OdometryStatus::kTracked) ++frames_tracked_;
  if (result.status == OdometryStatus::kBridged) ++frames_bridged_;
  if (result.status == OdometryStatus::kRestarted) ++restarts_;
  result.cpu_ms = ThreadCpuMs() - cpu0_ms;
  return result;
}

}  // namespace semap
