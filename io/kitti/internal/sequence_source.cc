#include "io/kitti/internal/sequence_source.h"

#include <algorithm>
#include <array>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "io/kitti/calibration.h"
#include "io/kitti/velodyne.h"
#include "io/labels/class_map_yaml.h"
#include "io/labels/label_images.h"

namespace semap::io::kitti_internal {
namespace {

namespace fs = std::filesystem;

// Bytes of a PNG file up to the end of the IHDR width/height fields.
constexpr size_t kPngHeaderBytes = 24;

}  // namespace

cv::Mat ReadImage(const fs::path& path, int flags, const char* what) {
  if (!fs::is_regular_file(path)) throw FileError(path, std::string(what) + " not found");
  cv::Mat m;
  try {
    m = cv::imread(path.string(), flags);
  } catch (const cv::Exception& e) {
    throw FileError(path, std::string("cannot decode ") + what + ": " + e.what());
  }
  if (m.empty())
    throw FileError(path, std::string("cannot decode ") + what + " (truncated or corrupt image)");
  return m;
}

Frame ReadAsFrame(std::int64_t frame_id, const std::function<Frame()>& read) {
  try {
    return read();
  } catch (const FileError& e) {
    throw FrameError(frame_id, "frame " + std::to_string(frame_id) + ": " + e.what());
  } catch (const cv::Exception& e) {
    throw FrameError(frame_id, "frame " + std::to_string(frame_id) + ": OpenCV error: " + e.what());
  }
}

std::vector<FrameEntry> ListFrames(const fs::path& dir, const std::regex& pattern) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw FileError(dir, "image folder not found");
  std::vector<FrameEntry> out;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    std::smatch m;
    if (!std::regex_match(name, m, pattern)) continue;
    out.push_back({std::stoll(m[1].str()), entry.path().stem().string()});
  }
  if (ec) throw FileError(dir, "cannot list: " + ec.message());
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.id < b.id; });
  return out;
}

void SelectFrames(const FrameSourceOptions& options, SequenceScan* scan) {
  for (const auto& f : scan->all_frames) {
    if (f.id < options.first_frame) continue;
    if (options.max_frames > 0 && static_cast<int>(scan->frames.size()) >= options.max_frames) break;
    scan->frames.push_back(f);
  }
  if (scan->all_frames.empty()) throw FileError(scan->info.left_dir, "no frames (no left images found)");
  if (scan->frames.empty()) {
    throw FileError(scan->info.left_dir, "no frames from first_frame " + std::to_string(options.first_frame) +
                                             " on (last frame is " +
                                             std::to_string(scan->all_frames.back().id) + ")");
  }
}

void TimestampsFromFile(const std::vector<double>& times_s, const std::filesystem::path& path,
                        const std::string& noun, SequenceScan* scan) {
  const std::int64_t needed = scan->frames.back().id + 1;
  if (static_cast<std::int64_t>(times_s.size()) < needed) {
    throw FileError(path, "has " + std::to_string(times_s.size()) + " " + noun + " but frame " +
                              std::to_string(scan->frames.back().id) + " needs line " +
                              std::to_string(needed));
  }
  scan->timestamps_s.clear();
  const double t0 = times_s[scan->all_frames.front().id];
  for (const auto& f : scan->frames) scan->timestamps_s.push_back(times_s[f.id] - t0);
  scan->info.has_timestamps = true;
}

void NominalTimestamps(const FrameSourceOptions& options, SequenceScan* scan) {
  scan->timestamps_s.clear();
  const std::int64_t id0 = scan->all_frames.front().id;
  for (const auto& f : scan->frames) {
    scan->timestamps_s.push_back(static_cast<double>(f.id - id0) * options.default_frame_period_s);
  }
  scan->info.has_timestamps = false;
}

void AttachLabels(const FrameSourceOptions& options, const fs::path& default_dir, SequenceScan* scan) {
  SequenceInfo& info = scan->info;
  info.class_map = LoadClassMap(options.class_map);
  if (!options.load_labels) return;
  fs::path dir;
  if (!options.labels_dir.empty()) {
    dir = options.labels_dir;
    if (!fs::is_directory(dir)) throw FileError(dir, "labels folder not found");
  } else if (!default_dir.empty() && fs::is_directory(default_dir)) {
    dir = default_dir;
  }
  if (dir.empty()) return;
  scan->labels_dir = dir;
  info.has_labels = true;
  info.labels_dir = dir;
  for (const auto& f : scan->frames) {
    const fs::path p = dir / (f.stem + ".png");
    if (fs::exists(p)) info.label_files.push_back(p);
  }
  if (info.label_files.size() < scan->frames.size()) {
    info.notes.push_back(std::to_string(scan->frames.size() - info.label_files.size()) +
                         " selected frame(s) have no label image in " + dir.string());
  }
}

cv::Size PngSize(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(path, fs::exists(path) ? "cannot open for reading" : "image not found");
  std::array<unsigned char, kPngHeaderBytes> h{};
  in.read(reinterpret_cast<char*>(h.data()), h.size());
  static constexpr std::array<unsigned char, 8> kSignature = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (in.gcount() != static_cast<std::streamsize>(h.size()) ||
      !std::equal(kSignature.begin(), kSignature.end(), h.begin()) ||
      std::string(h.begin() + 12, h.begin() + 16) != "IHDR") {
    throw FileError(path, "not a PNG image (bad or truncated header)");
  }
  auto be32 = [&](size_t o) {
    return (int(h[o]) << 24) | (int(h[o + 1]) << 16) | (int(h[o + 2]) << 8) | int(h[o + 3]);
  };
  const cv::Size size(be32(16), be32(20));
  if (size.width <= 0 || size.height <= 0) throw FileError(path, "PNG header has an invalid image size");
  return size;
}

void FinishInfo(SequenceScan* scan) {
  SequenceInfo& info = scan->info;
  info.num_frames = static_cast<std::int64_t>(scan->frames.size());
  info.num_frames_on_disk = static_cast<std::int64_t>(scan->all_frames.size());
  info.first_frame_id = scan->frames.front().id;
  info.last_frame_id = scan->frames.back().id;
  info.color = scan->imread_flags == cv::IMREAD_COLOR;
  const cv::Size size = PngSize(info.left_dir / (scan->frames.front().stem + ".png"));
  info.calibration.width_px = size.width;
  info.calibration.height_px = size.height;
  CheckIntrinsicsFitImage(info.calibration, scan->calibration_file, scan->calibration_key);
}

SequenceSource::SequenceSource(SequenceScan scan) : scan_(std::move(scan)) {}

std::optional<Frame> SequenceSource::Next() {
  if (next_ >= scan_.frames.size()) return std::nullopt;
  const size_t index = next_++;  // advance first: a bad frame is skipped, the next call reads the next one
  return ReadAsFrame(scan_.frames[index].id, [&] { return ReadFrame(index); });
}

Frame SequenceSource::ReadFrame(size_t index) {
  const FrameEntry& entry = scan_.frames[index];
  const std::string png = entry.stem + ".png";
  Frame f;
  f.id = entry.id;
  f.timestamp_s = scan_.timestamps_s[index];
  f.left = ReadImage(scan_.info.left_dir / png, scan_.imread_flags, "left image");
  const fs::path right_path = scan_.right_dir / png;
  f.right = ReadImage(right_path, scan_.imread_flags, "right image");
  if (f.right.size() != f.left.size()) {
    throw FileError(right_path, "right image is " + std::to_string(f.right.cols) + "x" +
                                    std::to_string(f.right.rows) + " but the left image is " +
                                    std::to_string(f.left.cols) + "x" + std::to_string(f.left.rows));
  }
  // The calibration holds for the size of the sequence's first image: a frame of another size would be
  // mapped with the wrong intrinsics (and may be far larger than what the run was sized for).
  if (f.left.cols != scan_.info.calibration.width_px || f.left.rows != scan_.info.calibration.height_px) {
    throw FileError(scan_.info.left_dir / png,
                    "left image is " + std::to_string(f.left.cols) + "x" + std::to_string(f.left.rows) +
                        " but the calibration is for " + std::to_string(scan_.info.calibration.width_px) +
                        "x" + std::to_string(scan_.info.calibration.height_px) +
                        " (the size of the first image)");
  }
  f.calibration = scan_.info.calibration;
  f.world_from_cam = PoseAt(index);
  if (!scan_.velodyne_dir.empty()) {
    VelodyneScan v;
    const fs::path scan_path = scan_.velodyne_dir / (entry.stem + ".bin");
    v.points_velo = ReadVelodyneBin(scan_path);
    // A valid file, but not a frame with Velodyne: treated as a missing scan (the frame is not evaluated
    // against an empty reference).
    if (v.points_velo.empty()) throw FileError(scan_path, "Velodyne scan is empty (0 points)");
    v.cam_from_velo = *scan_.info.cam_from_velo;
    f.velodyne = std::move(v);
  }
  // Any size: the label stage resizes it or refuses it as semantics.size_mismatch says.
  if (!scan_.labels_dir.empty()) f.labels = ReadLabelImage(scan_.labels_dir / png, cv::Size());
  return f;
}

}  // namespace semap::io::kitti_internal
