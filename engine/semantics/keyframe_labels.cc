#include "engine/semantics/keyframe_labels.h"

#include <Eigen/Geometry>
#include <cmath>

#include "engine/core/check.h"

namespace semap {

const char* LabelPropagationName(LabelPropagation propagation) {
  switch (propagation) {
    case LabelPropagation::kReproject:
      return "reproject";
    case LabelPropagation::kReuse:
      return "reuse";
  }
  return "?";
}

KeyframeSchedule::KeyframeSchedule(int every_frames) : every_frames_(every_frames) {
  SEMAP_ASSERT(every_frames >= 1, "keyframe interval " << every_frames);
}

bool KeyframeSchedule::IsDue(std::int64_t frame_id, bool has_pose) const {
  if (!last_id_ || !has_pose || !last_has_pose_) return true;
  return frame_id < *last_id_ || frame_id - *last_id_ >= every_frames_;
}

void KeyframeSchedule::SetEveryFrames(int every_frames) {
  SEMAP_ASSERT(every_frames >= 1, "keyframe interval " << every_frames);
  every_frames_ = every_frames;
}

void KeyframeSchedule::Record(std::int64_t frame_id, bool has_pose) {
  last_id_ = frame_id;
  last_has_pose_ = has_pose;
}

cv::Mat PropagateLabels(const KeyframeLabels& keyframe, const Pose3d& world_from_cam, const cv::Mat& depth_m,
                        const StereoCalibration& intrinsics, Label unlabelled_id, PropagationReport* report) {
  const cv::Size size(intrinsics.width_px, intrinsics.height_px);
  SEMAP_ASSERT(keyframe.world_from_cam.has_value(), "keyframe " << keyframe.frame_id << " has no pose");
  SEMAP_ASSERT(keyframe.labels.type() == CV_8UC1 && keyframe.labels.size() == size,
               "keyframe labels " << keyframe.labels.cols << "x" << keyframe.labels.rows << " for a "
                                  << size.width << "x" << size.height << " camera");
  SEMAP_ASSERT(depth_m.type() == CV_32FC1 && depth_m.size() == size, "depth map of another size or type");
  const Pose3d keyframe_from_cam = keyframe.world_from_cam->inverse() * world_from_cam;
  const Eigen::Matrix3d r = keyframe_from_cam.linear();
  const Eigen::Vector3d t = keyframe_from_cam.translation();
  PropagationReport counts;
  cv::Mat out(size, CV_8UC1);
  for (int v = 0; v < size.height; ++v) {
    const float* z_row = depth_m.ptr<float>(v);
    std::uint8_t* out_row = out.ptr<std::uint8_t>(v);
    const double y = (v - intrinsics.cy_px) / intrinsics.fy_px;
    for (int u = 0; u < size.width; ++u) {
      const Eigen::Vector3d ray((u - intrinsics.cx_px) / intrinsics.fx_px, y, 1.0);
      const double z = z_row[u];
      Eigen::Vector3d q;
      if (z > 0.0 && std::isfinite(z)) {
        q = r * (ray * z) + t;
        ++counts.with_depth;
      } else {
        q = r * ray;  // a point at infinity: the translation does not move it
        ++counts.at_infinity;
      }
      out_row[u] = unlabelled_id;
      if (q.z() <= 0.0) {
        ++counts.outside;
        continue;
      }
      const long ku = std::lround(intrinsics.fx_px * q.x() / q.z() + intrinsics.cx_px);
      const long kv = std::lround(intrinsics.fy_px * q.y() / q.z() + intrinsics.cy_px);
      if (ku < 0 || kv < 0 || ku >= size.width || kv >= size.height) {
        ++counts.outside;
        continue;
      }
      out_row[u] = keyframe.labels.at<std::uint8_t>(static_cast<int>(kv), static_cast<int>(ku));
    }
  }
  if (report != nullptr) *report = counts;
  return out;
}

}  // namespace semap
