// One frame as it enters the pipeline: a rectified stereo pair, or one view of a calibrated multi-view set
// with the neighbouring views its depth is swept against.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "engine/core/calibration.h"

namespace semap {

// A Velodyne scan in its own frame: x, y, z in metres and reflectance, as in KITTI's .bin files.
struct VelodyneScan {
  std::vector<Eigen::Vector4f> points_velo;
  Pose3d cam_from_velo = Pose3d::Identity();  // velodyne → rectified left camera (KITTI: R_rect_00 · Tr)
};

// Another calibrated camera's image that a frame's depth is computed against (plane sweep): a multi-view
// set's neighbouring views. The pinhole model has no distortion.
struct CalibratedView {
  std::int64_t frame_id = 0;                        // the view's frame id in its sequence
  cv::Mat image;                                    // CV_8UC1 grey
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();  // [fx s cx; 0 fy cy; 0 0 1], pixels
  Pose3d world_from_cam = Pose3d::Identity();
};

// A frame's depth-stage result computed elsewhere (a depth node of a split run): what the depth stage would
// compute from the images, handed over so that only the cloud is built from it.
struct FrameDepth {
  cv::Mat disparity_px;  // CV_32F, the left image's size, in full-resolution px; 0 = no disparity
  cv::Mat confidence;    // CV_32F in [0, 1], as DisparityResult::confidence
  cv::Mat labels;        // CV_8UC1 label ids (ClassMap scheme) of the left image; empty = none
};

struct Frame {
  std::int64_t id = 0;       // index in the sequence (as on disk)
  double timestamp_s = 0.0;  // seconds since the first frame of the sequence
  cv::Mat left;              // rectified left image, CV_8UC3 (BGR) or CV_8UC1
  cv::Mat right;             // rectified right image, same size and type as left; empty: no stereo pair
  StereoCalibration calibration;
  std::optional<Pose3d> world_from_cam;  // left camera pose, when the sequence has poses
  std::optional<VelodyneScan> velodyne;
  // The views whose images the left image's depth is swept against when there is no right image (a
  // multi-view set); calibration.baseline_m is then the distance to the nearest of them (the baseline the
  // depth's uncertainty follows, as a stereo pair's does).
  std::vector<CalibratedView> neighbour_views;
  cv::Mat labels;  // CV_8UC1 label ids of the left image (ClassMap scheme); empty = none
  // Added to every disparity measured on the pair before it becomes depth (true = measured + offset at the
  // pixel's row): the rig's rectification offset as known when the frame was read (the visual odometry's).
  DisparityOffset disparity_offset;
  // The rig's residual vertical misalignment as measured when the frame was read (depth.align_rows; the
  // pipeline's RowAlignmentReader; all-zero coefficients: measured, nothing to correct). Absent: not
  // measured, and the depth stage measures it on the pair itself.
  std::optional<RowOffsets> row_offsets;
  // Set when the frame's depth and labels were computed elsewhere (a split run's map node): the depth stage
  // builds the frame's cloud from them and needs no right image, neighbour views or segmenter.
  std::shared_ptr<const FrameDepth> depth;
  // When the sensor delivered the frame, seconds since the Unix epoch, as the host that read it measured
  // (0: not known; the pipeline sets it when it reads the frame). A frame read on another host keeps its
  // sensing time, so that latencies count from there.
  double sensed_unix_s = 0.0;
};

}  // namespace semap
