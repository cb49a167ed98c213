#include "app/dataset/dataset_info.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>

#include "io/frame_source.h"
#include "io/labels/label_images.h"

namespace semap::app {
namespace {

const char* YesNo(bool b) { return b ? "yes" : "no"; }

// Up to `n` evenly spaced entries of `files` (all when n <= 0 or there are fewer).
std::vector<std::filesystem::path> Sample(const std::vector<std::filesystem::path>& files, int n) {
  if (n <= 0 || static_cast<int>(files.size()) <= n) return files;
  std::vector<std::filesystem::path> out;
  for (int i = 0; i < n; ++i) out.push_back(files[files.size() * i / n]);
  return out;
}

void PrintComposition(const io::SequenceInfo& info, int sample_frames) {
  const auto files = Sample(info.label_files, sample_frames);
  io::LabelHistogram histogram;
  int read = 0;
  for (const auto& f : files) {
    try {
      histogram.Add(io::ReadLabelImage(f, {info.calibration.width_px, info.calibration.height_px}));
      ++read;
    } catch (const io::FileError& e) {
      spdlog::warn("skipping label image: {}", e.what());
    }
  }
  std::printf("class composition over %d of %zu label images (scheme %s):\n", read, info.label_files.size(),
              info.class_map.scheme().c_str());
  if (read == 0) return;
  for (const auto& row : io::SummariseByRole(histogram, info.class_map)) {
    std::printf("  %-12s %6.1f %%\n", row.name.c_str(), 100.0 * row.share);
  }
  std::printf("  by class:");
  for (const auto& row : io::SummariseByClass(histogram, info.class_map)) {
    std::printf(" %s %.1f%%", row.name.c_str(), 100.0 * row.share);
  }
  std::printf("\n");
}

}  // namespace

void PrintDatasetInfo(const Config& config, const std::string& path, int sample_frames) {
  const io::SequenceInfo info = io::DescribeDataset(path, config.input);
  const StereoCalibration& c = info.calibration;
  std::printf("dataset      %s\n", info.root.string().c_str());
  std::printf("layout       %s\n", io::DatasetLayoutName(info.layout));
  std::printf("frames       %lld (ids %lld..%lld; %lld left images on disk)\n",
              static_cast<long long>(info.num_frames), static_cast<long long>(info.first_frame_id),
              static_cast<long long>(info.last_frame_id), static_cast<long long>(info.num_frames_on_disk));
  std::printf("image size   %d x %d px, %s\n", c.width_px, c.height_px, info.color ? "colour" : "gray");
  std::printf("calibration  fx %.4f  fy %.4f  cx %.4f  cy %.4f px, baseline %.6f m\n", c.fx_px, c.fy_px,
              c.cx_px, c.cy_px, c.baseline_m);
  std::printf("poses        %s\n", info.layout == io::DatasetLayout::kKittiStereo2015
                                       ? "identity (every frame on its own)"
                                       : YesNo(info.has_poses));
  std::printf("timestamps   %s\n",
              info.has_timestamps ? "yes" : "no (frame id x input.default_frame_period_s)");
  std::printf("velodyne     %s\n", YesNo(info.has_velodyne));
  std::printf("labels       %s%s\n", YesNo(info.has_labels),
              info.has_labels ? (" (" + info.labels_dir.string() + ", " +
                                 std::to_string(info.label_files.size()) + " images)")
                                    .c_str()
                              : "");
  for (const auto& note : info.notes) std::printf("note         %s\n", note.c_str());
  if (!info.label_files.empty()) PrintComposition(info, sample_frames);
}

}  // namespace semap::app
