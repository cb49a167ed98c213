// semap_rectification_check: is a stereo sequence rectified? In a rectified pair a point of the left image
// lies on the same row of the right one. The stereo matches the depth stage's row alignment fits
// (semap::MatchRows: the strongest FAST corners of each left image, pyramidal KLT into the right image and
// back); the match's vertical offset (right row − left row) is averaged per cell of a grid
// over the image and printed as a table, with a fit of the offset to the terms a small error of the
// rectification gives: a constant (pitch between the cameras), one growing with the column (roll) and one
// with column × row (a keystone: yaw, or a projective term of the rectifying homographies). A rectified pair
// shows offsets of a few hundredths of a pixel everywhere; SGBM matches along rows, and the odometry's stereo
// matches are refused beyond odometry.max_epipolar_error_px.
//
// Usage: semap_rectification_check SEQUENCE [--frames N] [--every K] [--grid COLSxROWS] [--config FILE]
// [--set ...]
#include <CLI/CLI.hpp>
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bench/sequence_args.h"
#include "bench/stats.h"
#include "engine/depth/row_alignment.h"

namespace {

// The fit's robust rounds: residuals beyond this many MADs are dropped before the next round.
constexpr int kFitRounds = 3;
constexpr double kFitTrimMads = 3.0;
constexpr double kMadToSigma = 1.4826;

struct Match {
  double u_px, v_px, dy_px;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"vertical offsets of stereo matches over the image: is a sequence rectified?"};
  semap::bench::SequenceArgs args;
  args.AddTo(app, "sequence folder");
  int every = 2;
  std::string grid_text = "8x4";
  app.add_option("--every", every, "use every K-th frame")->check(CLI::PositiveNumber);
  app.add_option("--grid", grid_text, "cells of the table, COLSxROWS");
  CLI11_PARSE(app, argc, argv);
  int grid_cols = 0, grid_rows = 0;
  if (std::sscanf(grid_text.c_str(), "%dx%d", &grid_cols, &grid_rows) != 2 || grid_cols < 1 ||
      grid_rows < 1) {
    std::fprintf(stderr, "--grid %s: expected COLSxROWS, e.g. 8x4\n", grid_text.c_str());
    return 2;
  }
  try {
    const semap::app::Config config = args.LoadConfig();
    auto source = semap::io::OpenFrameSource(args.sequence, args.Input(config, false));
    std::vector<Match> matches;
    semap::StereoCalibration calibration;
    cv::Size size;
    int frames = 0, index = 0;
    while (auto frame = source->Next()) {
      if (index++ % every != 0) continue;
      ++frames;
      calibration = frame->calibration;
      size = frame->left.size();
      // The matches the depth stage's row alignment fits (engine/depth/row_alignment.h).
      for (const semap::RowMatch& m : semap::MatchRows(frame->left, frame->right)) {
        matches.push_back({m.left_px.x, m.left_px.y, m.right_px.y - m.left_px.y});
      }
    }
    if (matches.empty()) {
      std::fprintf(stderr, "%s: no stereo matches in %d frames\n", args.sequence.c_str(), frames);
      return 1;
    }
    // The table: mean vertical offset per cell (and its match count).
    std::vector<std::vector<double>> cells(static_cast<size_t>(grid_cols * grid_rows));
    for (const Match& m : matches) {
      const int c = std::min(grid_cols - 1, static_cast<int>(m.u_px * grid_cols / size.width));
      const int r = std::min(grid_rows - 1, static_cast<int>(m.v_px * grid_rows / size.height));
      cells[static_cast<size_t>(r * grid_cols + c)].push_back(m.dy_px);
    }
    std::printf(
        "%s: %d frames, %zu stereo matches; mean vertical offset (right row - left row, px) per cell,\n"
        "columns left to right, rows top to bottom (matches in brackets):\n\n|",
        args.sequence.c_str(), frames, matches.size());
    for (int c = 0; c < grid_cols; ++c) std::printf(" col %d |", c + 1);
    std::printf("\n|");
    for (int c = 0; c < grid_cols; ++c) std::printf("---:|");
    std::printf("\n");
    for (int r = 0; r < grid_rows; ++r) {
      std::printf("|");
      for (int c = 0; c < grid_cols; ++c) {
        const auto& v = cells[static_cast<size_t>(r * grid_cols + c)];
        if (v.empty()) {
          std::printf(" – |");
        } else {
          std::printf(" %+.2f (%zu) |", semap::bench::Mean(v), v.size());
        }
      }
      std::printf("\n");
    }
    // The fit, in normalised image coordinates x = (u - cx)/fx, y = (v - cy)/fy: dy/fy = a + b x + c x y.
    const semap::StereoCalibration& k = calibration;
    std::vector<bool> keep(matches.size(), true);
    Eigen::Vector3d w = Eigen::Vector3d::Zero();
    double mad_px = 0.0;
    for (int round = 0; round < kFitRounds; ++round) {
      Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
      Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
      for (size_t i = 0; i < matches.size(); ++i) {
        if (!keep[i]) continue;
        const double x = (matches[i].u_px - k.cx_px) / k.fx_px, y = (matches[i].v_px - k.cy_px) / k.fy_px;
        const Eigen::Vector3d a(1.0, x, x * y);
        normal += a * a.transpose();
        rhs += a * (matches[i].dy_px / k.fy_px);
      }
      w = normal.ldlt().solve(rhs);
      std::vector<double> residuals(matches.size());
      for (size_t i = 0; i < matches.size(); ++i) {
        const double x = (matches[i].u_px - k.cx_px) / k.fx_px, y = (matches[i].v_px - k.cy_px) / k.fy_px;
        residuals[i] = std::abs(matches[i].dy_px - k.fy_px * (w[0] + w[1] * x + w[2] * x * y));
      }
      mad_px = semap::bench::Median(residuals);
      for (size_t i = 0; i < matches.size(); ++i)
        keep[i] = residuals[i] <= kFitTrimMads * kMadToSigma * mad_px;
    }
    // What each term gives at the image's corners, px.
    const double x_edge = std::max(k.cx_px, size.width - k.cx_px) / k.fx_px;
    const double y_edge = std::max(k.cy_px, size.height - k.cy_px) / k.fy_px;
    std::printf(
        "\nfit dy = a + b x + c x y (x, y normalised): a %+.3f px (pitch %.4f deg), b x at the left/right "
        "edge %+.2f px (roll %.4f deg), c x y at the corners %+.2f px; median |residual| %.3f px\n",
        k.fy_px * w[0], w[0] * 180.0 / M_PI, k.fy_px * w[1] * x_edge, w[1] * 180.0 / M_PI,
        k.fy_px * w[2] * x_edge * y_edge, mad_px);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "semap_rectification_check: %s\n", e.what());
    return 1;
  }
  return 0;
}
