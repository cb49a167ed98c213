#include "io/frame_source.h"

namespace semap::io {

const char* DatasetLayoutName(DatasetLayout layout) {
  switch (layout) {
    case DatasetLayout::kAuto:
      return "auto";
    case DatasetLayout::kKittiRaw:
      return "kitti_raw";
    case DatasetLayout::kKittiOdometry:
      return "kitti_odometry";
    case DatasetLayout::kKittiStereo2015:
      return "kitti_stereo2015";
    case DatasetLayout::kStrecha:
      return "strecha";
  }
  return "?";
}

}  // namespace semap::io
