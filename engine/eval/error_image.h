// A per-pixel picture of the depth error of one frame, for reports (where the large errors are,
// shown rather than guessed): at each reference pixel (engine/eval/depth_accuracy.h: reference depth in the
// options' range) the colour of |mesh depth − reference depth| on a fixed scale (turbo colour map, 0 = dark
// blue, at and beyond max_error_m = dark red); black where the reference has a depth and the mesh none (a
// hole); grey elsewhere (no reference: the frame's left image in dim grey, or plain grey without it). A band
// under the picture holds the colour bar with its ticks, the two other swatches and a title.
#pragma once

#include <opencv2/core.hpp>
#include <string>

#include "engine/eval/depth_accuracy.h"

namespace semap {

struct ErrorImageOptions {
  // |error| at the top of the colour scale (m); larger errors take its colour. The paper protocol's bound.
  double max_error_m = kPaperMaxAbsErrorM;
  // Sparse references (projected Velodyne, ~6 % of the pixels) are drawn as squares of side 2r + 1 px so that
  // they can be seen, the larger errors on top; 0 = one pixel each (dense references such as exact depth).
  int point_radius_px = 1;
  // Height of the legend band under the picture (px).
  int legend_height_px = 44;
  // Ticks of the colour bar: every this many metres.
  double tick_step_m = 0.5;
  void Check() const;
};

// `reference` and `mesh`: CV_32F depth maps of one size (0 = none); `background`: the frame's left image
// (CV_8UC1 or CV_8UC3, same size) or empty; `title` is written in the legend band. Returns CV_8UC3 (BGR),
// the image's size plus the legend band below. Throws InvalidOption on bad options.
cv::Mat RenderErrorImage(const cv::Mat& reference, const cv::Mat& mesh, const cv::Mat& background,
                         const DepthAccuracyOptions& filters, const ErrorImageOptions& options,
                         const std::string& title);

// The colour (BGR) of an absolute error on the scale of `options`.
cv::Vec3b ErrorColour(double abs_error_m, const ErrorImageOptions& options);

}  // namespace semap
