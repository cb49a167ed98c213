// The residual vertical misalignment of a rectified stereo pair (RowOffsets, engine/core/calibration.h),
// measured on the pair itself and removed before matching. In a rectified pair a scene point lies on the
// same row of both images, and SGBM compares blocks along that row only. KITTI's real pairs are off by up to
// 0.7 px at the corners (odometry 04's colour pair) and 1.6 px (the grey pair of kitti_odometry_turn;
// bench/rectification_check.cc); there SGBM compares blocks a pixel apart in height, and its depth is
// noisier and biased.
//
// FitRowOffsets: sparse stereo matches (FAST corners of the left image, pyramidal KLT into the right one,
// checked back into the left) give the right row − left row at several hundred points; the quadratic of
// RowOffsets (the offsets of a pitch, a roll, a keystone from a yaw or a projective term of the rectifying
// homographies, lens residuals to second order) is fitted to them, robustly. AlignRows moves the right
// image's rows by it, with no horizontal change: disparities keep whatever horizontal error the rig has
// (not observable from a pair), only the rows line up. Both are pure functions, safe on any thread.
#pragma once

#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "engine/core/calibration.h"

namespace semap {

// One stereo match of a left-image corner: where it lies in each image (right row − left row is the rows'
// misalignment there).
struct RowMatch {
  cv::Point2f left_px, right_px;
};

// The matches FitRowOffsets fits, on a pair of 8-bit grey or BGR images of one size and type (BGR is matched
// in grey): the strongest FAST corners of the left image, tracked into the right one by pyramidal KLT and
// back, kept when the round trip closes, the row offset is plausible and the disparity positive (the rules
// and their constants in row_alignment.cc). Empty for a blank image. Throws std::invalid_argument on other
// images.
std::vector<RowMatch> MatchRows(const cv::Mat& left, const cv::Mat& right);

// The fit on MatchRows's matches of a pair; nothing when too few are found (a blank, texture-less or smooth
// generated frame). Throws std::invalid_argument on other images. ~30 ms on one core for a KITTI pair.
std::optional<RowOffsets> FitRowOffsets(const cv::Mat& left, const cv::Mat& right);

// `right` (any type cv::remap takes) with each pixel taken from the row the offsets say: the right image as
// a camera whose rows line up with the left one's would have seen it; bilinear between rows. Where the
// quadratic, extrapolated beyond the matches, exceeds the largest offset FitRowOffsets accepts from a match,
// it is held at that. Requires offsets.image_size == right.size().
cv::Mat AlignRows(const cv::Mat& right, const RowOffsets& offsets);

}  // namespace semap
