// The steps of StereoOdometry::Track (engine/odometry/README.md, "The scheme"), each on its own: features and
// their stereo matches, tracking into a new frame, the P3P start of the motion, the checks a refined motion
// must pass, and the running mean of the disparity offset. Not API.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "engine/core/calibration.h"
#include "engine/odometry/internal/stereo_pose_refiner.h"
#include "engine/odometry/stereo_odometry.h"

namespace semap::odometry_internal {

// A tracked motion faster than this is "moving": KLT's second guess after a frame that stood still, m/s.
constexpr double kMovingSpeedMps = 0.5;
// A time step below this is taken as this when turning a motion into a speed (duplicated timestamps), s.
constexpr double kMinTimeStepS = 1e-3;
// A disparity offset (either term) beyond this is not a rectification error but a wrong calibration, px:
// the bound of the options' offsets too.
constexpr double kMaxDisparityOffsetPx = StereoOdometryOptions::kMaxDisparityOffsetPx;

// `motion` scaled to `fraction` of itself (rotation angle and translation), e.g. a velocity over another
// time step.
Pose3d ScaleMotion(const Pose3d& motion, double fraction);

// The angle of the motion's rotation, rad.
double RotationAngleRad(const Pose3d& motion);

// The image as one 8-bit channel (itself when it is one already; BGR or BGRA converted).
cv::Mat Gray(const cv::Mat& image);

// The point that left pixel `l` and right pixel `r` see, in the left camera's frame, with `offset` added to
// their disparity.
Eigen::Vector3d Triangulate(const StereoCalibration& c, const cv::Point2f& l, const cv::Point2f& r,
                            const DisparityOffset& offset);

// One frame's grey left image and the KLT pyramids of both images.
struct FrameImages {
  cv::Mat left;
  std::vector<cv::Mat> left_pyramid;
  std::vector<cv::Mat> right_pyramid;
};

// Features with their stereo matches: left[i] and right[i] are one feature's pixels.
struct StereoFeatures {
  std::vector<cv::Point2f> left;
  std::vector<cv::Point2f> right;
};

// Feature detection and stereo matching as the options say, on images of the calibration's size. Holds
// references to both: they must outlive it.
class StereoMatcher {
 public:
  StereoMatcher(const StereoOdometryOptions& o, const StereoCalibration& c) : o_(o), c_(c) {}

  // The grey left image and the pyramids (max(klt_levels, stereo_levels) levels) of a pair.
  FrameImages Prepare(const cv::Mat& left, const cv::Mat& right) const;

  // True when `p` is at least half a KLT window inside the image.
  bool Inside(const cv::Point2f& p) const;

  // Right-image positions of `left_px` (starting from `right_px`, filled in place); ok[i] says whether
  // point i has a stereo match (on its row, positive disparity, consistent back to the left image).
  void MatchStereo(const FrameImages& f, const std::vector<cv::Point2f>& left_px,
                   std::vector<cv::Point2f>* right_px, std::vector<bool>* ok) const;

  // New FAST corners of the left image where `existing` leaves room: strongest first, at most
  // max_features / cells per grid cell (counting the existing ones), none within kMinFeatureSpacingPx of
  // another feature.
  std::vector<cv::Point2f> Detect(const FrameImages& f, const std::vector<cv::Point2f>& existing) const;

  // The grid cell (row-major index) of pixel `p`.
  int CellOf(const cv::Point2f& p) const;

  // Features closer than this to each other are one: a new corner goes only where no feature is this
  // close, px.
  static constexpr int kMinFeatureSpacingPx = 8;

 private:
  const StereoOdometryOptions& o_;
  const StereoCalibration& c_;
};

// The median of left[i].x − right[i].x (the upper one of an even count); 0 when there are none.
double MedianDisparityPx(const StereoFeatures& features);

// `kept` topped up with the frame's new corners (StereoMatcher::Detect) that have a stereo match, each
// matched from the median disparity of `kept`.
StereoFeatures TopUpFeatures(const StereoMatcher& matcher, const FrameImages& frame, StereoFeatures kept);

// Where the motion `cur_from_ref` puts the reference's features in the current left image: KLT's starts.
// A feature whose point falls behind the camera or out of the image starts where it was.
std::vector<cv::Point2f> PredictFeaturePositions(const StereoCalibration& c, const StereoFeatures& ref,
                                                 const DisparityOffset& offset, const Pose3d& cur_from_ref);

// The reference's features tracked into a frame: the indices of those KLT kept inside the image, their
// left pixels, their right pixels and whether each has a stereo match there.
struct TrackedFeatures {
  std::vector<size_t> ref_index;
  std::vector<cv::Point2f> left;
  std::vector<cv::Point2f> right;
  std::vector<bool> stereo_ok;
};

// Tracks `ref` from the reference's left pyramid into `frame`'s left image with pyramidal KLT (klt_levels)
// from `starts`, then matches the tracked ones into its right image, each from the disparity it had.
TrackedFeatures TrackFeatures(const StereoMatcher& matcher, const StereoOdometryOptions& options,
                              const std::vector<cv::Mat>& ref_left_pyramid, const StereoFeatures& ref,
                              const FrameImages& frame, const std::vector<cv::Point2f>& starts);

// The refiner's matches of the tracked features, in the order of `tracked`.
std::vector<StereoMatch> MakeStereoMatches(const StereoFeatures& ref, const TrackedFeatures& tracked);

// The motion P3P RANSAC finds from the reference's triangulated features to their tracked left pixels.
struct StartMotion {
  bool solved = false;
  Pose3d cur_from_ref = Pose3d::Identity();
  std::vector<bool> inliers;  // per tracked feature
  int num_inliers = 0;
};
StartMotion EstimateStartMotion(const StereoCalibration& c, const StereoOdometryOptions& options,
                                const StereoFeatures& ref, const DisparityOffset& offset,
                                const TrackedFeatures& tracked);

// The speed of `cur_from_ref` over `dt_s`, the time from the reference (its absolute value, at least
// kMinTimeStepS), m/s.
double SpeedMps(const Pose3d& cur_from_ref, double dt_s);

// Why the refined motion of `features` tracked features over `dt_s` (as SpeedMps takes it) is not accepted:
// too few inliers (min_inliers, min_inlier_ratio), faster than max_speed_mps or not finite, or turning faster
// than max_rotation_rate_deg_s; empty when it is accepted.
std::string MotionProblem(const RefinedMotion& refined, int features, double dt_s,
                          const StereoOdometryOptions& options);

// The motions KLT starts from, in order: the constant-velocity prediction, the last motion that moved
// scaled to this step dt_s (when moving_dt_s > 0), standing still; a guess within Eigen's isApprox
// precision kSameGuess of an earlier candidate (whether that one was kept or not) is left out.
std::vector<Pose3d> MotionGuesses(const Pose3d& predicted, const Pose3d& moving_motion, double moving_dt_s,
                                  double dt_s);

// The disparity offset as the information-weighted mean of the frames' estimates of it.
struct OffsetMean {
  DisparityOffset offset;  // in use
  Eigen::Matrix2d information = Eigen::Matrix2d::Zero();
  Eigen::Vector2d weighted_sum = Eigen::Vector2d::Zero();
};

// One frame's estimate of the offset (its terms unknowns beside the pose, `terms` of them: 1 or 2) from
// the refined motion and inliers, with `refiner` otherwise as the motion was refined.
RefinedMotion EstimateFrameOffset(const StereoCalibration& c, const std::vector<StereoMatch>& matches,
                                  const RefinedMotion& refined, const RefinerOptions& refiner, int terms);

// True when `estimate` may vote: its constant's standard deviation is at most kMaxOffsetSigmaPx and both
// terms are within kMaxDisparityOffsetPx.
bool OffsetEstimateVotes(const RefinedMotion& estimate);

// Adds the vote of `estimate` to `mean` and updates the offset in use: the information of the estimate,
// capped at that of a kMinOffsetSigmaPx standard deviation of the constant (an exact estimate counts as
// that on the constant alone); with two terms the mean of both when their information is full rank, else
// the constant's alone.
void AddOffsetVote(const RefinedMotion& estimate, int terms, OffsetMean* mean);

}  // namespace semap::odometry_internal
