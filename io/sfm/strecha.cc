#include "io/sfm/strecha.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <string_view>

#include "io/sfm/internal/sfm_checks.h"

namespace semap::io {

using namespace sfm_internal;

namespace {

// Lines of a .camera file: K (3), distortion (1), R (3), C (1), size (1).
constexpr int kCameraLines = 9;
constexpr int kFirstRotationLine = 5;
constexpr int kCentreLine = 8;
constexpr int kSizeLine = 9;
// K's lower-left entries must be 0 and K(2, 2) 1 within this (files print 6 digits and more).
constexpr double kIntrinsicsTolerance = 1e-6;

EntryRef Line(const std::filesystem::path& file, int line) { return {file, "line " + std::to_string(line)}; }

// The numbers of one line, exactly `count` of them.
std::vector<double> Numbers(const EntryRef& at, const std::string& field, const std::string& text,
                            int count) {
  std::vector<double> values;
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
    const std::size_t start = i;
    while (i < text.size() && !std::isspace(static_cast<unsigned char>(text[i]))) ++i;
    if (i == start) break;
    const std::string_view token(text.data() + start, i - start);
    double value = 0.0;
    const auto r = std::from_chars(token.data(), token.data() + token.size(), value);
    if (r.ec != std::errc() || r.ptr != token.data() + token.size()) {
      std::string problem = "'";
      problem.append(token).append("' is not a number");
      at.Fail(field, problem);
    }
    values.push_back(value);
  }
  if (static_cast<int>(values.size()) != count) {
    at.Fail(field, "expects " + std::to_string(count) + " numbers, got " + std::to_string(values.size()));
  }
  CheckFinite(at, field, values.data(), count);
  return values;
}

std::vector<std::string> ReadLines(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw FileError(file, "cannot be read");
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  // Trailing blank lines are not entries.
  while (!lines.empty() && lines.back().find_first_not_of(" \t\r") == std::string::npos) lines.pop_back();
  if (static_cast<int>(lines.size()) < kCameraLines) {
    Line(file, static_cast<int>(lines.size()) + 1)
        .Fail("", "missing: a camera file has " + std::to_string(kCameraLines) + " lines, this one " +
                      std::to_string(lines.size()));
  }
  if (static_cast<int>(lines.size()) > kCameraLines)
    Line(file, kCameraLines + 1)
        .Fail("", "unexpected: a camera file has " + std::to_string(kCameraLines) + " lines");
  return lines;
}

Eigen::Matrix3d ReadMatrix(const std::filesystem::path& file, const std::vector<std::string>& lines,
                           int first_line, const std::string& name) {
  Eigen::Matrix3d m;
  for (int row = 0; row < 3; ++row) {
    const int line = first_line + row;
    const auto values = Numbers(Line(file, line), name + " row " + std::to_string(row + 1),
                                lines[static_cast<size_t>(line - 1)], 3);
    for (int col = 0; col < 3; ++col) m(row, col) = values[static_cast<size_t>(col)];
  }
  return m;
}

void CheckIntrinsics(const std::filesystem::path& file, const Eigen::Matrix3d& K) {
  const EntryRef at{file, "lines 1-3"};
  const bool triangular =
      std::abs(K(1, 0)) <= kIntrinsicsTolerance && std::abs(K(2, 0)) <= kIntrinsicsTolerance &&
      std::abs(K(2, 1)) <= kIntrinsicsTolerance && std::abs(K(2, 2) - 1.0) <= kIntrinsicsTolerance;
  if (!triangular) at.Fail("K", "not a pinhole matrix: rows 2 and 3 must start 0 and 0 0 1");
  if (!(K(0, 0) > 0.0) || !(K(1, 1) > 0.0))
    at.Fail("K", "focal lengths must be > 0 (got " + NumberText(K(0, 0)) + ", " + NumberText(K(1, 1)) + ")");
}

}  // namespace

StrechaView ReadStrechaCamera(const std::filesystem::path& camera_file) {
  const std::vector<std::string> lines = ReadLines(camera_file);
  StrechaView view;
  view.camera_file = camera_file;
  view.K = ReadMatrix(camera_file, lines, 1, "K");
  CheckIntrinsics(camera_file, view.K);
  const auto distortion = Numbers(Line(camera_file, 4), "distortion", lines[3], 3);
  if (std::any_of(distortion.begin(), distortion.end(), [](double k) { return k != 0.0; }))
    Line(camera_file, 4).Fail("distortion", "must be 0 0 0 (semap reads undistorted images only)");
  const Eigen::Matrix3d R = ReadMatrix(camera_file, lines, kFirstRotationLine, "R");
  CheckRotation({camera_file, "lines 5-7"}, "R", R);
  const auto c = Numbers(Line(camera_file, kCentreLine), "C", lines[kCentreLine - 1], 3);
  view.world_from_cam = PoseFromRotationAndCenter(R.transpose(), Eigen::Vector3d(c[0], c[1], c[2]));
  const EntryRef size_at = Line(camera_file, kSizeLine);
  const auto size = Numbers(size_at, "width height", lines[kSizeLine - 1], 2);
  for (double s : size) {
    if (!(s >= 1.0) || s != std::floor(s) || s > INT32_MAX)
      size_at.Fail("width height", "must be positive integers (got " + NumberText(s) + ")");
  }
  view.width_px = static_cast<int>(size[0]);
  view.height_px = static_cast<int>(size[1]);
  return view;
}

std::string FormatStrechaCamera(const Eigen::Matrix3d& K, const Pose3d& world_from_cam, int width_px,
                                int height_px) {
  std::string text;
  const auto row = [&](double a, double b, double c) {
    char line[96];
    std::snprintf(line, sizeof(line), "%.17g %.17g %.17g\n", a, b, c);
    text += line;
  };
  for (int r = 0; r < 3; ++r) row(K(r, 0), K(r, 1), K(r, 2));
  text += "0 0 0\n";
  const Eigen::Matrix3d R = world_from_cam.linear();
  for (int r = 0; r < 3; ++r) row(R(r, 0), R(r, 1), R(r, 2));
  const Eigen::Vector3d& c = world_from_cam.translation();
  row(c.x(), c.y(), c.z());
  text += std::to_string(width_px) + " " + std::to_string(height_px) + "\n";
  return text;
}

std::vector<std::filesystem::path> StrechaImageFiles(const std::filesystem::path& root) {
  const std::filesystem::path images = root / "images";
  if (!std::filesystem::is_directory(images)) throw FileError(images, "missing: not a folder");
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(images)) {
    std::string ext = entry.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return std::tolower(ch); });
    if (entry.is_regular_file() && (ext == ".jpg" || ext == ".jpeg" || ext == ".png"))
      files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::vector<StrechaView> ReadStrechaSet(const std::filesystem::path& root) {
  const std::filesystem::path images = root / "images", cameras = root / "gt_dense_cameras";
  for (const auto& folder : {images, cameras}) {
    if (!std::filesystem::is_directory(folder)) throw FileError(folder, "missing: not a folder");
  }
  const std::vector<std::filesystem::path> files = StrechaImageFiles(root);
  if (files.empty()) throw FileError(images, "no images (.jpg, .jpeg, .png)");
  std::vector<StrechaView> views;
  for (const auto& image : files) {
    const auto camera_file = cameras / (image.filename().string() + ".camera");
    if (!std::filesystem::exists(camera_file))
      throw FileError(camera_file, "missing: the camera of image " + image.string());
    StrechaView view = ReadStrechaCamera(camera_file);
    view.image = image;
    const cv::Mat pixels = cv::imread(image.string(), cv::IMREAD_GRAYSCALE);
    if (pixels.empty()) throw FileError(image, "cannot be read as an image");
    if (pixels.cols != view.width_px || pixels.rows != view.height_px) {
      Line(camera_file, kSizeLine)
          .Fail("width height", "says " + std::to_string(view.width_px) + "x" +
                                    std::to_string(view.height_px) + ", but " + image.filename().string() +
                                    " is " + std::to_string(pixels.cols) + "x" + std::to_string(pixels.rows));
    }
    views.push_back(std::move(view));
  }
  return views;
}

}  // namespace semap::io
