// Post-processing of a disparity map: fills small horizontal gaps and the unmatched left border.
#pragma once

#include <opencv2/core.hpp>

namespace semap::depth_internal {

// `disparity` (CV_32F, invalid ≤ 0) is filled in place; `confidence` is (re)allocated to its size:
// 1 for valid input pixels, `gap_confidence` for pixels filled in a gap, 0 for border-filled pixels and
// for pixels left invalid.
// - Gaps: a run of at most `max_gap_px` invalid pixels on a row with valid pixels on both ends takes the
//   smaller of the two end disparities (the background side, as KITTI's interpolation does). 0 = off.
// - Border: invalid pixels of a row left of its first valid pixel, within the first `border_px` columns,
//   take that pixel's disparity. 0 = off.
void FillDisparity(int max_gap_px, int border_px, float gap_confidence, cv::Mat* disparity,
                   cv::Mat* confidence);

}  // namespace semap::depth_internal
