#include "io/labels/label_images.h"

#include <algorithm>
#include <opencv2/imgcodecs.hpp>

#include "engine/core/check.h"

namespace semap::io {

cv::Mat ReadLabelImage(const std::filesystem::path& path, cv::Size expected_size) {
  if (!std::filesystem::is_regular_file(path)) throw FileError(path, "label image not found");
  cv::Mat m;
  try {
    m = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    throw FileError(path, std::string("cannot decode label image: ") + e.what());
  }
  if (m.empty()) throw FileError(path, "cannot decode label image (truncated or corrupt PNG)");
  if (m.type() != CV_8UC1) {
    throw FileError(path, "label image must be 8-bit single channel (ids), got " +
                              std::to_string(m.channels()) + " channel(s) of " +
                              std::to_string(m.elemSize1() * 8) + " bit");
  }
  if (!expected_size.empty() && m.size() != expected_size) {
    throw FileError(path, "label image is " + std::to_string(m.cols) + "x" + std::to_string(m.rows) +
                              " but the left image is " + std::to_string(expected_size.width) + "x" +
                              std::to_string(expected_size.height));
  }
  return m;
}

void LabelHistogram::Add(const cv::Mat& labels) {
  SEMAP_ASSERT(labels.type() == CV_8UC1, "label image type " << labels.type());
  for (int r = 0; r < labels.rows; ++r) {
    const auto* row = labels.ptr<std::uint8_t>(r);
    for (int c = 0; c < labels.cols; ++c) ++counts[row[c]];
  }
  total += static_cast<std::int64_t>(labels.total());
}

std::vector<CompositionRow> SummariseByRole(const LabelHistogram& h, const ClassMap& map) {
  const int vegetation = map.FindByName("vegetation");
  const int car = map.FindByName("car");
  std::int64_t ground = 0, wall = 0, veg = 0, cars = 0, other = 0;
  for (int id = 0; id < 256; ++id) {
    const std::int64_t n = h.counts[id];
    const ClassRole role = map.Role(static_cast<Label>(id));
    if (role == ClassRole::kGround) {
      ground += n;
    } else if (role == ClassRole::kWall) {
      wall += n;
    } else if (id == vegetation) {
      veg += n;
    } else if (id == car) {
      cars += n;
    } else {
      other += n;
    }
  }
  const double total = h.total > 0 ? static_cast<double>(h.total) : 1.0;
  return {{"ground", ground / total},
          {"wall", wall / total},
          {"vegetation", veg / total},
          {"car", cars / total},
          {"other", other / total}};
}

std::vector<CompositionRow> SummariseByClass(const LabelHistogram& h, const ClassMap& map) {
  std::vector<CompositionRow> rows;
  const double total = h.total > 0 ? static_cast<double>(h.total) : 1.0;
  for (int id = 0; id < 256; ++id) {
    if (h.counts[id] == 0) continue;
    const auto label = static_cast<Label>(id);
    rows.push_back(
        {map.Contains(label) ? map.Get(label).name : "id " + std::to_string(id), h.counts[id] / total});
  }
  std::stable_sort(rows.begin(), rows.end(), [](const auto& a, const auto& b) { return a.share > b.share; });
  return rows;
}

}  // namespace semap::io
