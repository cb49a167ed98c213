#include "engine/eval/error_image.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <tuple>
#include <vector>

#include "engine/core/check.h"

namespace semap {
namespace {

const cv::Vec3b kNoReference(128, 128, 128);  // plain grey, when there is no background image
const cv::Vec3b kHole(0, 0, 0);
const cv::Scalar kInk(30, 30, 30);
const cv::Scalar kBand(235, 235, 235);
// The background image is dimmed into a narrow grey band around mid grey so that colours stand out.
constexpr double kBackgroundContrast = 0.35;
constexpr double kBackgroundOffset = 0.5 * (1.0 - kBackgroundContrast) * 255.0;
constexpr int kBackgroundLevelStep = 8;
constexpr double kFontScale = 0.45;

std::string Metres(double m) {
  char text[32];
  std::snprintf(text, sizeof(text), "%g", m);
  return text;
}

}  // namespace

void ErrorImageOptions::Check() const {
  SEMAP_CHECK_OPTION(max_error_m > 0.0, "max_error_m", max_error_m, "must be > 0");
  SEMAP_CHECK_OPTION(point_radius_px >= 0 && point_radius_px <= 10, "point_radius_px", point_radius_px,
                     "must be in 0..10");
  SEMAP_CHECK_OPTION(legend_height_px >= 30, "legend_height_px", legend_height_px, "must be >= 30");
  SEMAP_CHECK_OPTION(tick_step_m > 0.0 && max_error_m / tick_step_m <= 20.0, "tick_step_m", tick_step_m,
                     "must be > 0 and give at most 20 ticks up to max_error_m");
}

namespace {

// The 256 colours of the scale, index = round(255 · |error| / max_error_m) clamped.
cv::Mat ColourScale() {
  cv::Mat ramp(1, 256, CV_8UC1);
  for (int i = 0; i < 256; ++i) ramp.at<std::uint8_t>(0, i) = static_cast<std::uint8_t>(i);
  cv::Mat colours;
  cv::applyColorMap(ramp, colours, cv::COLORMAP_TURBO);
  return colours;
}

cv::Vec3b ScaleColour(const cv::Mat& scale, double abs_error_m, const ErrorImageOptions& options) {
  const double t = std::clamp(abs_error_m / options.max_error_m, 0.0, 1.0);
  return scale.at<cv::Vec3b>(0, static_cast<int>(std::lround(255.0 * t)));
}

}  // namespace

cv::Vec3b ErrorColour(double abs_error_m, const ErrorImageOptions& options) {
  return ScaleColour(ColourScale(), abs_error_m, options);
}

cv::Mat RenderErrorImage(const cv::Mat& reference, const cv::Mat& mesh, const cv::Mat& background,
                         const DepthAccuracyOptions& filters, const ErrorImageOptions& options,
                         const std::string& title) {
  filters.Check();
  options.Check();
  SEMAP_ASSERT(reference.type() == CV_32F && mesh.type() == CV_32F && reference.size() == mesh.size());
  SEMAP_ASSERT(background.empty() || background.size() == reference.size());
  const int rows = reference.rows, cols = reference.cols;
  cv::Mat image(rows + options.legend_height_px, cols, CV_8UC3, cv::Scalar(kBand));
  cv::Mat picture = image.rowRange(0, rows);
  if (background.empty()) {
    picture.setTo(cv::Scalar(kNoReference));
  } else {
    cv::Mat grey = background;
    if (background.channels() == 3) cv::cvtColor(background, grey, cv::COLOR_BGR2GRAY);
    cv::Mat dimmed;  // a buffer of its own: a grey background is the caller's image
    grey.convertTo(dimmed, CV_8U, kBackgroundContrast, kBackgroundOffset);
    // A few grey levels are enough to recognise the scene and keep the PNG small (a third of the size). A
    // plain table loop rather than cv::LUT, which hands a frame-sized image to OpenCV's threads (a hand-over
    // TSan cannot see, as cv::Mat::forEach's was): a frame takes well under a millisecond on one thread.
    std::array<std::uint8_t, 256> level{};
    for (int g = 0; g < 256; ++g) {
      const int step_start = g / kBackgroundLevelStep * kBackgroundLevelStep;
      level[g] = static_cast<std::uint8_t>(step_start + kBackgroundLevelStep / 2);
    }
    for (int y = 0; y < dimmed.rows; ++y) {
      std::uint8_t* row = dimmed.ptr<std::uint8_t>(y);
      for (int x = 0; x < dimmed.cols; ++x) row[x] = level[row[x]];
    }
    cv::cvtColor(dimmed, picture, cv::COLOR_GRAY2BGR);
  }
  // Reference pixels: holes first, then errors from small to large, so that the large ones stay visible.
  std::vector<std::tuple<double, int, int>> errors;  // |error|, x, y
  std::vector<cv::Point> holes;
  for (int y = 0; y < rows; ++y) {
    const float* r = reference.ptr<float>(y);
    const float* m = mesh.ptr<float>(y);
    for (int x = 0; x < cols; ++x) {
      if (!(r[x] >= filters.min_depth_m && r[x] <= filters.max_depth_m)) continue;
      if (!(m[x] > 0.0f) || !std::isfinite(m[x])) {
        holes.emplace_back(x, y);
      } else {
        errors.emplace_back(std::abs(static_cast<double>(m[x]) - static_cast<double>(r[x])), x, y);
      }
    }
  }
  std::sort(errors.begin(), errors.end());
  const cv::Mat scale = ColourScale();
  const int r = options.point_radius_px;
  const auto paint = [&](int x, int y, const cv::Vec3b& colour) {
    for (int v = std::max(0, y - r); v <= std::min(rows - 1, y + r); ++v) {
      for (int u = std::max(0, x - r); u <= std::min(cols - 1, x + r); ++u)
        picture.at<cv::Vec3b>(v, u) = colour;
    }
  };
  for (const cv::Point& p : holes) paint(p.x, p.y, kHole);
  for (const auto& [e, x, y] : errors) paint(x, y, ScaleColour(scale, e, options));

  // The legend band: colour bar with ticks, hole and no-reference swatches, title.
  const int band_top = rows;
  const int bar_x = 10, bar_w = std::min(300, std::max(60, cols / 4)), bar_y = band_top + 6, bar_h = 12;
  for (int i = 0; i < bar_w; ++i) {
    const cv::Vec3b c = ScaleColour(scale, options.max_error_m * i / (bar_w - 1), options);
    cv::line(image, {bar_x + i, bar_y}, {bar_x + i, bar_y + bar_h}, cv::Scalar(c[0], c[1], c[2]), 1);
  }
  cv::rectangle(image, cv::Rect(bar_x, bar_y, bar_w, bar_h + 1), kInk, 1);
  const int ticks = static_cast<int>(std::floor(options.max_error_m / options.tick_step_m + 1e-9));
  for (int k = 0; k <= ticks; ++k) {
    const double m = k * options.tick_step_m;
    const int x = bar_x + static_cast<int>(std::lround(m / options.max_error_m * (bar_w - 1)));
    cv::line(image, {x, bar_y + bar_h}, {x, bar_y + bar_h + 4}, kInk, 1);
    const std::string text = (k == ticks && m >= options.max_error_m - 1e-9 ? ">=" : "") + Metres(m);
    cv::putText(image, text, {x - 6, bar_y + bar_h + 17}, cv::FONT_HERSHEY_SIMPLEX, 0.38, kInk, 1,
                cv::LINE_AA);
  }
  int x = bar_x + bar_w + 24;
  const int text_y = bar_y + bar_h - 1;
  cv::putText(image, "|error| (m)", {x, text_y}, cv::FONT_HERSHEY_SIMPLEX, kFontScale, kInk, 1, cv::LINE_AA);
  x += 100;
  cv::rectangle(image, cv::Rect(x, bar_y, 12, 12), cv::Scalar(kHole), cv::FILLED);
  cv::putText(image, "hole (no mesh)", {x + 16, text_y}, cv::FONT_HERSHEY_SIMPLEX, kFontScale, kInk, 1,
              cv::LINE_AA);
  x += 130;
  cv::rectangle(image, cv::Rect(x, bar_y, 12, 12), cv::Scalar(kNoReference), cv::FILLED);
  cv::putText(image, "no reference", {x + 16, text_y}, cv::FONT_HERSHEY_SIMPLEX, kFontScale, kInk, 1,
              cv::LINE_AA);
  cv::putText(image, title, {x + 130, text_y}, cv::FONT_HERSHEY_SIMPLEX, kFontScale, kInk, 1, cv::LINE_AA);
  return image;
}

}  // namespace semap
