// Semantic label images: one 8-bit single-channel PNG per frame holding the class id of each pixel of the
// left image (the id scheme of a ClassMap), and the class composition of a set of them.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "engine/core/class_map.h"
#include "io/file_error.h"

namespace semap::io {

// Reads a label PNG as CV_8UC1. Throws FileError naming the file when it is missing, cannot be decoded
// (truncated or corrupt), is not 8-bit single channel, or its size differs from `expected_size` (when that
// is not empty). Ids unknown to the class map are kept as they are (they count as "keep" classes).
cv::Mat ReadLabelImage(const std::filesystem::path& path, cv::Size expected_size = {});

// Pixel counts per label id over any number of label images.
struct LabelHistogram {
  std::array<std::int64_t, 256> counts{};
  std::int64_t total = 0;

  void Add(const cv::Mat& labels);  // requires CV_8UC1
};

// One row of a composition summary: a group of classes and its share of the counted pixels.
struct CompositionRow {
  std::string name;  // "ground", "wall", "vegetation", "car", "other" or a class name
  double share = 0.0;
};

// Shares of ground (role ground), wall (role wall), vegetation and car (classes of these names, when the
// map has them and they are not targets) and other (everything else, unlabelled and unknown ids included).
std::vector<CompositionRow> SummariseByRole(const LabelHistogram& histogram, const ClassMap& map);

// Share of every id present (class name, or "id N" for ids unknown to the map), largest first.
std::vector<CompositionRow> SummariseByClass(const LabelHistogram& histogram, const ClassMap& map);

}  // namespace semap::io
