#include "app/single/single_commands.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>

#include "app/depth/frame_at.h"
#include "engine/semantics/labelling.h"
#include "engine/semantics/segmenter.h"
#include "engine/simplify/simplify.h"
#include "io/image/image_files.h"
#include "io/labels/class_map_yaml.h"
#include "io/mesh/ply_off.h"

namespace semap::app {

void SimplifyCloudFile(const Config& config, const SimplifyCloudRequest& request) {
  const ClassMap class_map = io::LoadClassMap(config.input.class_map);  // empty = Cityscapes
  const LabelledCloud cloud = io::ReadCloudPly(request.cloud);
  const SimplifyResult result = Simplify(cloud, class_map, config.simplify);

  std::printf("%s: %zu points, method %s\n", request.cloud.c_str(), cloud.size(),
              SimplifyMethodName(config.simplify.method));
  std::printf("%-14s %-7s %10s %10s %10s %8s\n", "class", "role", "in", "kept", "removed", "kept%");
  for (const auto& s : result.per_class) {
    const bool known = class_map.Contains(s.label);
    const std::string name = known ? class_map.Get(s.label).name : "id " + std::to_string(s.label);
    std::printf("%-14s %-7s %10llu %10llu %10llu %7.1f%%\n", name.c_str(),
                ClassRoleName(class_map.Role(s.label)), static_cast<unsigned long long>(s.in),
                static_cast<unsigned long long>(s.kept), static_cast<unsigned long long>(s.removed),
                s.in > 0 ? 100.0 * static_cast<double>(s.kept) / static_cast<double>(s.in) : 100.0);
  }
  std::printf(
      "%-14s %-7s %10llu %10llu %10llu %7.1f%%\n", "total", "", static_cast<unsigned long long>(result.in),
      static_cast<unsigned long long>(result.kept()),
      static_cast<unsigned long long>(result.in - result.kept()),
      result.in > 0 ? 100.0 * static_cast<double>(result.kept()) / static_cast<double>(result.in) : 100.0);
  std::printf("time: %.3f s (%.0f points/s)\n", result.time_s,
              result.time_s > 0.0 ? static_cast<double>(result.in) / result.time_s : 0.0);
  if (!request.out.empty()) {
    io::WriteCloudPly(request.out, ApplySimplification(cloud, result),
                      request.ascii ? io::PlyEncoding::kAscii : io::PlyEncoding::kBinaryLittleEndian);
    spdlog::info("wrote {} points to {}", result.kept(), request.out);
  }
}

void SegmentFrame(const Config& config, const SegmentFrameRequest& request) {
  io::FrameSourceOptions input = config.input;
  input.load_velodyne = false;
  const FrameAt at = ReadFrameAt(request.dataset, request.frame, input);
  SemanticsOptions semantics = config.semantics;
  semantics.source = LabelSource::kEnet;  // this command always runs the built-in segmenter
  auto segmenter = MakeSegmenter(semantics);
  const auto t0 = std::chrono::steady_clock::now();
  const cv::Mat labels = segmenter->Segment(at.frame.left);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  const std::filesystem::path out(request.out);
  std::filesystem::create_directories(out);
  char stem[64];
  std::snprintf(stem, sizeof(stem), "%06lld", static_cast<long long>(at.frame.id));
  const auto labels_png = out / (std::string("labels_") + stem + ".png");
  const auto overlay_png = out / (std::string("overlay_") + stem + ".png");
  io::WritePng(labels_png, labels);
  io::WritePng(overlay_png, OverlayLabels(at.frame.left, labels, segmenter->class_map(), request.alpha));

  const ClassMap& classes = segmenter->class_map();
  std::printf("frame %lld: %s in %.3f s; classes:", static_cast<long long>(at.frame.id),
              segmenter->name().c_str(), seconds);
  for (const auto& c : classes.classes()) {
    const int n = cv::countNonZero(labels == c.id);
    if (n > 0) std::printf(" %s %.1f%%", c.name.c_str(), 100.0 * n / static_cast<double>(labels.total()));
  }
  std::printf("\nwrote %s\n      %s\n", labels_png.c_str(), overlay_png.c_str());
}

}  // namespace semap::app
