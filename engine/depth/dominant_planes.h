// The scene's dominant plane directions for the plane sweep, found from the labels: the ground and the walls
// each fitted with a RANSAC plane through the view's points of that role (as the paper fits a plane per
// class), so that the sweep adds planes parallel to them around where they lie (Gallup et al. 2007).
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "engine/core/class_map.h"
#include "engine/depth/plane_sweep.h"

namespace semap {

struct DominantPlaneOptions {
  double inlier_m = 0.1;          // RANSAC inlier distance to the plane (larger: noisier depth still fits)
  int min_points = 200;           // a role with fewer points with a depth gives no direction
  int iterations = 200;           // RANSAC hypotheses at most
  int max_points = 4000;          // points each hypothesis is counted on at most
  double offset_fraction = 0.2;   // the swept offsets: the fitted plane ± this share of its distance from
                                  // the camera (larger: finds the plane when the first depth was far off,
                                  // with coarser steps; < 1 keeps the camera outside the range)
  double min_inlier_share = 0.5;  // a fit explaining fewer of the role's points gives no direction
};

// One direction per role (ground first, then wall) whose labelled pixels with a depth (depth_m > 0 and
// finite, at view.K's resolution; `labels` CV_8UC1 of any size, read at the pixel's centre scaled to it) fit
// a plane: its world normal and offsets, the plane ± offset_fraction of its distance from view's camera.
// Deterministic (a fixed seed). Empty labels or depth: none.
std::vector<SweepDirection> DominantDirections(const cv::Mat& depth_m, const cv::Mat& labels,
                                               const PlaneSweepView& view, const ClassMap& classes,
                                               const DominantPlaneOptions& options = {});

}  // namespace semap
