#include "app/depth/depth_maps.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <opencv2/imgcodecs.hpp>

#include "app/depth/frame_at.h"
#include "engine/depth/stereo_depth.h"
#include "engine/pipeline/semap_stages.h"
#include "engine/semantics/labelling.h"
#include "engine/semantics/segmenter.h"
#include "io/atomic_file.h"
#include "io/image/image_files.h"
#include "io/mesh/ply_off.h"

namespace semap::app {
namespace {

std::string Fixed17(double value) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.17g", value);
  return buf;
}

std::string Stem(const char* what, std::int64_t id) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%s_%06lld", what, static_cast<long long>(id));
  return buf;
}

// Depth maps are written as 16-bit PNGs in millimetres (the convention of generated sequences' exact depth
// and of Open3D's depth_scale = 1000): up to 65.535 m.
constexpr double kDepthPngUnitsPerMetre = 1000.0;

// The depth map (camera-frame z, 16-bit mm, 0 = none) of the points of `cloud` seen from `world_from_cam`,
// each at its pixel (the nearest wins where two share one).
cv::Mat DepthMapOfCloud(const LabelledCloud& cloud, const Pose3d& world_from_cam, const cv::Size& size) {
  cv::Mat depth_mm(size, CV_16U, cv::Scalar(0));
  const Pose3d cam_from_world = world_from_cam.inverse();
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const int u = static_cast<int>(std::lround(cloud.pixels_px[i].x()));
    const int v = static_cast<int>(std::lround(cloud.pixels_px[i].y()));
    if (u < 0 || v < 0 || u >= size.width || v >= size.height) continue;
    const double z_mm = (cam_from_world * cloud.positions_world[i]).z() * kDepthPngUnitsPerMetre;
    if (!(z_mm >= 1.0 && z_mm <= std::numeric_limits<std::uint16_t>::max())) continue;
    std::uint16_t& d = depth_mm.at<std::uint16_t>(v, u);
    const auto z = static_cast<std::uint16_t>(std::lround(z_mm));
    if (d == 0 || z < d) d = z;
  }
  return depth_mm;
}

// `semap depth --all` (app/depth/depth_maps.h): every selected frame through the engine's depth stage (SGBM,
// point filters, labels and sky removal as `semap run` does), densely (depth.max_points_per_frame is not
// applied: fusion tools take whole depth maps). Writes DIR/depth/NNNNNN.png, DIR/poses.txt ("id" then
// world_from_cam as 3×4 row-major, one line per frame) and DIR/camera.txt ("width_px height_px fx_px fy_px
// cx_px cy_px").
}  // namespace

void WriteAllDepthMaps(const Config& config, const std::string& path, const std::filesystem::path& out) {
  io::FrameSourceOptions input = config.input;
  input.load_velodyne = false;
  input.load_labels =
      config.semantics.source == LabelSource::kAuto || config.semantics.source == LabelSource::kDisk;
  auto source = io::OpenFrameSource(path, input);
  DepthOptions dense = config.depth;
  dense.max_points_per_frame = 0;
  StereoLabelStage stage(dense, config.semantics, source->class_map());
  // The rows lined up as `semap run` lines them up (measured on the first frames, then every 100), so that
  // the depth maps are the ones the map is built from.
  std::unique_ptr<FrameReader> reader = std::move(source);
  if (config.depth.align_rows) reader = std::make_unique<RowAlignmentReader>(std::move(reader));
  std::filesystem::create_directories(out / "depth");
  io::AtomicFile poses(out / "poses.txt");
  poses.stream().precision(17);
  std::int64_t frames = 0, empty = 0;
  double stage_s = 0.0;
  std::optional<StereoCalibration> calibration;
  const auto start = std::chrono::steady_clock::now();
  while (auto frame = reader->Next()) {
    if (!frame->world_from_cam) {
      throw std::runtime_error("frame " + std::to_string(frame->id) + " of " + path +
                               " has no pose: --all needs a sequence with poses");
    }
    if (!calibration) calibration = frame->calibration;
    const auto t0 = std::chrono::steady_clock::now();
    LabelledCloud cloud;
    try {
      cloud = stage.Process(*frame, nullptr);
    } catch (const std::runtime_error& e) {
      spdlog::warn("{} (an empty depth map is written)", e.what());
      ++empty;
    }
    stage_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    char name[32];
    std::snprintf(name, sizeof(name), "%06lld.png", static_cast<long long>(frame->id));
    const auto depth_png = out / "depth" / name;
    if (!cv::imwrite(depth_png.string(),
                     DepthMapOfCloud(cloud, *frame->world_from_cam, frame->left.size()))) {
      throw io::FileError(depth_png, "cannot write the depth PNG");
    }
    const Eigen::Matrix<double, 3, 4> m = frame->world_from_cam->matrix().topRows<3>();
    poses.stream() << frame->id;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) poses.stream() << ' ' << m(r, c);
    }
    poses.stream() << '\n';
    ++frames;
  }
  poses.Commit();
  if (!calibration) throw std::runtime_error(path + ": no frame selected");
  io::WriteFileAtomically(out / "camera.txt",
                          std::to_string(calibration->width_px) + " " +
                              std::to_string(calibration->height_px) + " " + Fixed17(calibration->fx_px) +
                              " " + Fixed17(calibration->fy_px) + " " + Fixed17(calibration->cx_px) + " " +
                              Fixed17(calibration->cy_px) + "\n");
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf(
      "depth maps: %lld frames (%lld empty), depth stage %.3f s (%.2f f/s), %.3f s with reading and "
      "writing\n",
      static_cast<long long>(frames), static_cast<long long>(empty), stage_s,
      stage_s > 0.0 ? frames / stage_s : 0.0, wall_s);
  std::printf("wrote %s/depth/*.png (16-bit, mm), %s/poses.txt, %s/camera.txt\n", out.c_str(), out.c_str(),
              out.c_str());
}

void WriteFrameDepth(const Config& config, const FrameDepthRequest& request) {
  io::FrameSourceOptions input = config.input;
  input.load_velodyne = false;
  const FrameAt at = ReadFrameAt(request.dataset, request.frame, input);
  const Frame& frame = at.frame;

  const auto t0 = std::chrono::steady_clock::now();
  const StereoDepth depth(config.depth);
  const DisparityResult disparity = depth.Compute(frame.left, frame.right);
  LabelledCloud cloud = depth.ToCloud(frame, disparity.disparity_px, disparity.confidence);
  const double depth_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  auto segmenter = MakeSegmenter(config.semantics);
  const cv::Mat labels = FrameLabels(frame, config.semantics, segmenter.get());
  const ClassMap& classes = segmenter ? segmenter->class_map() : at.class_map;
  const LabellingReport report = ApplyFirstCameraLabels(
      cloud, frame.id, labels, frame.left.size(), classes.unlabelled_id(), config.semantics.size_mismatch);
  if (report.resized) {
    spdlog::warn("frame {}: label image {}x{} resized (nearest neighbour) to the image size {}x{}", frame.id,
                 labels.cols, labels.rows, frame.left.cols, frame.left.rows);
  }
  if (request.label_colours) {
    for (size_t i = 0; i < cloud.size(); ++i) cloud.colors_rgb[i] = classes.Color(cloud.labels[i]);
  }

  const std::filesystem::path out(request.out);
  std::filesystem::create_directories(out);
  const auto disp_png = out / (Stem("disparity", frame.id) + ".png");
  const auto colour_png = out / (Stem("disparity_colour", frame.id) + ".png");
  const auto cloud_ply = out / (Stem("cloud", frame.id) + ".ply");
  io::WriteKittiDisparityPng(disp_png, disparity.disparity_px);
  io::WritePng(colour_png, io::FalseColourDisparity(disparity.disparity_px,
                                                    static_cast<float>(config.depth.num_disparities)));
  io::WriteCloudPly(cloud_ply, cloud,
                    request.ascii ? io::PlyEncoding::kAscii : io::PlyEncoding::kBinaryLittleEndian);

  const int valid = cv::countNonZero(disparity.disparity_px > 0.0f);
  std::printf(
      "frame %lld: %dx%d, disparity on %.1f %% of the pixels, %zu points in [%.1f, %.1f] m, "
      "depth stage %.3f s\n",
      static_cast<long long>(frame.id), frame.left.cols, frame.left.rows,
      100.0 * valid / static_cast<double>(frame.left.total()), cloud.size(), config.depth.min_depth_m,
      config.depth.max_depth_m, depth_s);
  std::printf("labels: %s (%zu points labelled, %zu outside the label image)\n",
              labels.empty() ? "none (all points unlabelled)" : LabelSourceName(config.semantics.source),
              report.labelled, report.outside_image);
  std::printf("wrote %s\n      %s\n      %s\n", disp_png.c_str(), colour_png.c_str(), cloud_ply.c_str());
}

}  // namespace semap::app
