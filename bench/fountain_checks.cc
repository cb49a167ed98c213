// semap_fountain_checks: two checks of a calibrated multi-view set's meshes that need no laser truth.
// - Sparse truth: SIFT keypoints of every view, matched between every pair of views (ratio test, then the
//   epipolar line of the set's own cameras), joined into tracks of at least --min-views views (a track with
//   two keypoints of one view is left out), triangulated with the cameras (linear DLT, Gauss–Newton on the
//   reprojection error) and kept in front of every observing camera with every reprojection error below
//   --max-reprojection-px. Per --mesh: the distance of those points to the mesh (count, median, RMSE, share
//   within 1 cm and 5 cm).
// - Leave one out: the view --leave-out's own plane-sweep depth against its neighbour views among the other
//   views (as `semap run` sweeps it: input.neighbour_views, depth.half_resolution, plane_sweep.*; the sweep
//   without label directions, the set has no labels), and per mesh its depth rendered from that view's
//   camera: the share of the view's pixels the mesh covers, and |Δz| between the two on the pixels both
//   cover (median, RMSE, within 1 cm / 5 cm). --leave-out-mesh names the meshes mapped without that view
//   (the real check); the --mesh meshes, which saw it, are shown beside them.
//
// Usage: semap_fountain_checks SET --mesh NAME=PLY ... [--leave-out-mesh NAME=PLY ...] [--leave-out N]
//        [--config FILE] [--set key=value ...]
#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "app/config/config.h"
#include "bench/fountain_geometry.h"
#include "bench/stats.h"
#include "engine/depth/frame_sweep.h"
#include "engine/eval/depth_render.h"
#include "engine/eval/surface_metrics.h"
#include "io/frame_source.h"
#include "io/mesh/ply_off.h"
#include "io/sfm/strecha.h"

namespace {

using namespace semap;

struct SparseOptions {
  int max_features = 8000;  // SIFT keypoints per view
  double ratio = 0.8;       // Lowe's ratio test
  double max_epipolar_px = 1.0;
  int min_views = 3;
  double max_reprojection_px = 0.5;
};

struct ViewFeatures {
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
};

std::vector<ViewFeatures> DetectFeatures(const std::vector<io::StrechaView>& views, int max_features) {
  const cv::Ptr<cv::SIFT> sift = cv::SIFT::create(max_features);
  std::vector<ViewFeatures> features(views.size());
  for (size_t i = 0; i < views.size(); ++i) {
    const cv::Mat grey = cv::imread(views[i].image.string(), cv::IMREAD_GRAYSCALE);
    if (grey.empty()) throw std::runtime_error("cannot read " + views[i].image.string());
    sift->detectAndCompute(grey, cv::noArray(), features[i].keypoints, features[i].descriptors);
  }
  return features;
}

Eigen::Vector2d Pixel(const cv::KeyPoint& k) { return {k.pt.x, k.pt.y}; }

// Matches of views a and b that pass the ratio test and lie within max_epipolar_px of their epipolar line.
std::vector<bench::KeypointMatch> MatchPair(const std::vector<ViewFeatures>& features,
                                            const std::vector<bench::PinholeCamera>& cameras, int a, int b,
                                            const SparseOptions& options) {
  const ViewFeatures& fa = features[static_cast<size_t>(a)];
  const ViewFeatures& fb = features[static_cast<size_t>(b)];
  std::vector<bench::KeypointMatch> matches;
  if (fa.keypoints.size() < 2 || fb.keypoints.size() < 2) return matches;
  cv::FlannBasedMatcher matcher;
  std::vector<std::vector<cv::DMatch>> knn;
  matcher.knnMatch(fa.descriptors, fb.descriptors, knn, 2);
  const Eigen::Matrix3d F =
      bench::FundamentalMatrix(cameras[static_cast<size_t>(a)], cameras[static_cast<size_t>(b)]);
  for (const auto& m : knn) {
    if (m.size() < 2 || !(m[0].distance < options.ratio * m[1].distance)) continue;
    const Eigen::Vector2d xa = Pixel(fa.keypoints[static_cast<size_t>(m[0].queryIdx)]);
    const Eigen::Vector2d xb = Pixel(fb.keypoints[static_cast<size_t>(m[0].trainIdx)]);
    if (bench::EpipolarDistancePx(F, xa, xb) > options.max_epipolar_px) continue;
    matches.push_back({{a, m[0].queryIdx}, {b, m[0].trainIdx}});
  }
  return matches;
}

// A sparse point and the pixels of the views that see it.
struct SparsePoint {
  Eigen::Vector3d p_world = Eigen::Vector3d::Zero();
  std::vector<int> views;
  std::vector<Eigen::Vector2d> uv_px;
};

// The sparse points of the set, with what each step kept printed.
std::vector<SparsePoint> SparsePoints(const std::vector<io::StrechaView>& views,
                                      const SparseOptions& options) {
  std::vector<bench::PinholeCamera> cameras;
  for (const io::StrechaView& v : views) cameras.push_back({v.K, v.world_from_cam});
  const std::vector<ViewFeatures> features = DetectFeatures(views, options.max_features);
  long long keypoints = 0;
  for (const ViewFeatures& f : features) keypoints += static_cast<long long>(f.keypoints.size());
  std::vector<bench::KeypointMatch> matches;
  const int n = static_cast<int>(views.size());
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) {
      const auto pair = MatchPair(features, cameras, a, b, options);
      matches.insert(matches.end(), pair.begin(), pair.end());
    }
  }
  const auto tracks = bench::BuildTracks(matches, options.min_views);
  std::vector<SparsePoint> points;
  for (const auto& track : tracks) {
    std::vector<bench::Observation> observations;
    SparsePoint point;
    for (const bench::ViewKeypoint& k : track) {
      observations.push_back(
          {cameras[static_cast<size_t>(k.view)],
           Pixel(features[static_cast<size_t>(k.view)].keypoints[static_cast<size_t>(k.keypoint)])});
    }
    for (const bench::Observation& o : observations) point.uv_px.push_back(o.uv_px);
    for (const bench::ViewKeypoint& k : track) point.views.push_back(k.view);
    if (auto p = bench::TriangulateTrack(observations, options.max_reprojection_px)) {
      point.p_world = *p;
      points.push_back(std::move(point));
    }
  }
  std::printf(
      "Sparse truth: %d views, %lld SIFT keypoints, %zu matches (ratio %.2f, epipolar <= %.1f px), "
      "%zu tracks of >= %d views, %zu points kept (reprojection < %.2f px in every view)\n\n",
      n, keypoints, matches.size(), options.ratio, options.max_epipolar_px, tracks.size(), options.min_views,
      points.size(), options.max_reprojection_px);
  return points;
}

// Median, 90th percentile, RMSE and the shares within 1 cm and 5 cm of absolute errors (m), as one table
// row's cells.
std::string ErrorCells(const std::vector<double>& errors_m) {
  double sq = 0.0;
  long long within_1cm = 0, within_5cm = 0;
  for (double e : errors_m) {
    sq += e * e;
    within_1cm += e <= 0.01;
    within_5cm += e <= 0.05;
  }
  const double n = std::max(static_cast<double>(errors_m.size()), 1.0);
  std::vector<double> sorted = errors_m;
  std::sort(sorted.begin(), sorted.end());
  const double p90_m = sorted.empty() ? std::nan("") : sorted[static_cast<size_t>(0.9 * (sorted.size() - 1))];
  char cells[160];
  std::snprintf(cells, sizeof cells, "%.1f | %.1f | %.1f | %.1f %% | %.1f %%",
                1000.0 * bench::Median(errors_m), 1000.0 * p90_m, 1000.0 * std::sqrt(sq / n),
                100.0 * within_1cm / n, 100.0 * within_5cm / n);
  return cells;
}

using NamedMesh = std::pair<std::string, Mesh>;

// The distance of every point to each mesh (m), a row per mesh.
std::vector<std::vector<double>> MeshDistances(const std::vector<SparsePoint>& points,
                                               const std::vector<NamedMesh>& meshes) {
  std::vector<std::vector<double>> d_m;
  for (const auto& named : meshes) {
    const SurfaceDistance distance(named.second);
    d_m.emplace_back();
    d_m.back().reserve(points.size());
    for (const SparsePoint& p : points) d_m.back().push_back(distance(p.p_world));
  }
  return d_m;
}

// One line per point: x, y, z (m), the views that see it, its distance to each mesh (m).
void WritePointsCsv(const std::string& path, const std::vector<SparsePoint>& points,
                    const std::vector<NamedMesh>& meshes, const std::vector<std::vector<double>>& d_m) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw std::runtime_error("cannot write " + path);
  std::fprintf(f, "x_m,y_m,z_m,views");
  for (const auto& named : meshes) std::fprintf(f, ",%s_distance_m", named.first.c_str());
  std::fprintf(f, "\n");
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d& p = points[i].p_world;
    std::fprintf(f, "%.6f,%.6f,%.6f,", p.x(), p.y(), p.z());
    for (size_t k = 0; k < points[i].views.size(); ++k)
      std::fprintf(f, "%s%d", k ? " " : "", points[i].views[k]);
    for (const auto& row : d_m) std::fprintf(f, ",%.6f", row[i]);
    std::fprintf(f, "\n");
  }
  std::fclose(f);
}

void PrintSparseTable(const std::vector<NamedMesh>& meshes, const std::vector<std::vector<double>>& d_m) {
  std::printf(
      "| mesh | points | median mm | 90 %% mm | RMSE mm | within 1 cm | within 5 cm "
      "|\n|---|---|---|---|---|---|---|\n");
  for (size_t m = 0; m < meshes.size(); ++m) {
    std::printf("| %s | %zu | %s |\n", meshes[m].first.c_str(), d_m[m].size(), ErrorCells(d_m[m]).c_str());
  }
  std::printf("\n");
}

// The frame of view `view` of the set, with its neighbour views.
std::optional<Frame> ReadFrame(const std::string& set, const app::Config& config, std::int64_t view) {
  io::FrameSourceOptions input = config.input;
  input.layout = io::DatasetLayout::kStrecha;
  auto source = io::OpenFrameSource(set, input);
  while (auto frame = source->Next()) {
    if (frame->id == view) return frame;
  }
  return std::nullopt;
}

void PrintLeaveOneOutRow(const std::string& name, bool saw_view, const cv::Mat& sweep_m,
                         const cv::Mat& mesh_m) {
  std::vector<double> dz_m;
  long long covered = 0;
  for (int v = 0; v < sweep_m.rows; ++v) {
    for (int u = 0; u < sweep_m.cols; ++u) {
      const float m = mesh_m.at<float>(v, u), s = sweep_m.at<float>(v, u);
      if (!(m > 0.0f)) continue;
      ++covered;
      if (s > 0.0f) dz_m.push_back(std::abs(static_cast<double>(m) - s));
    }
  }
  const double pixels = static_cast<double>(sweep_m.total());
  std::printf("| %s | %s | %.1f %% | %.1f %% | %s |\n", name.c_str(), saw_view ? "yes" : "no",
              100.0 * covered / pixels, 100.0 * static_cast<double>(dz_m.size()) / pixels,
              ErrorCells(dz_m).c_str());
}

// The view's sweep depth against the sparse points it sees (their camera-frame z), at their pixels.
void PrintSweepAgainstPoints(const std::vector<SparsePoint>& points, const Frame& frame,
                             const cv::Mat& sweep_m) {
  std::vector<double> dz_m;
  long long seen = 0;
  const bench::PinholeCamera camera{FrameCamera(frame).K, *frame.world_from_cam};
  for (const SparsePoint& p : points) {
    for (size_t k = 0; k < p.views.size(); ++k) {
      if (p.views[k] != frame.id) continue;
      ++seen;
      const int u = static_cast<int>(std::lround(p.uv_px[k].x())),
                v = static_cast<int>(std::lround(p.uv_px[k].y()));
      if (u < 0 || v < 0 || u >= sweep_m.cols || v >= sweep_m.rows) continue;
      const float z = sweep_m.at<float>(v, u);
      if (z > 0.0f) dz_m.push_back(std::abs(z - bench::InCamera(camera, p.p_world).z()));
    }
  }
  std::printf(
      "The sweep's depth against the %lld sparse points the view sees, %zu of them with a depth "
      "(|dz| median mm | 90 %% mm | RMSE mm | within 1 cm | within 5 cm): %s\n\n",
      seen, dz_m.size(), ErrorCells(dz_m).c_str());
}

void LeaveOneOut(const std::string& set, const app::Config& config, std::int64_t view,
                 const std::vector<SparsePoint>& points, const std::vector<NamedMesh>& without,
                 const std::vector<NamedMesh>& with) {
  const std::optional<Frame> frame = ReadFrame(set, config, view);
  if (!frame) throw std::invalid_argument("the set has no view " + std::to_string(view));
  const PlaneSweepDepth sweep(config.plane_sweep);
  const auto t0 = std::chrono::steady_clock::now();
  const DisparityResult disparity = SweepFrameDisparity(*frame, sweep, config.depth.half_resolution);
  const double sweep_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const cv::Mat sweep_m = DepthMapFromDisparity(disparity.disparity_px, frame->calibration);
  std::printf("Leave one out: view %lld (%d x %d px), its sweep against views", static_cast<long long>(view),
              sweep_m.cols, sweep_m.rows);
  for (const CalibratedView& n : frame->neighbour_views)
    std::printf(" %lld", static_cast<long long>(n.frame_id));
  std::printf(" gives a depth at %.1f %% of its pixels (%.1f s)\n\n",
              100.0 * cv::countNonZero(sweep_m > 0.0f) / static_cast<double>(sweep_m.total()), sweep_s);
  PrintSweepAgainstPoints(points, *frame, sweep_m);
  std::printf(
      "| mesh | mapped with the view | pixels covered | covered with a sweep depth | median abs dz mm | "
      "90 %% mm | RMSE mm | within 1 cm | within 5 cm |\n|---|---|---|---|---|---|---|---|---|\n");
  for (const auto* meshes : {&without, &with}) {
    for (const auto& [name, mesh] : *meshes) {
      const cv::Mat mesh_m = RenderDepth(mesh, frame->calibration, *frame->world_from_cam);
      PrintLeaveOneOutRow(name, meshes == &with, sweep_m, mesh_m);
    }
  }
  std::printf("\n");
}

std::vector<NamedMesh> ReadMeshes(const std::vector<std::string>& specs) {
  std::vector<NamedMesh> meshes;
  for (const std::string& spec : specs) {
    const size_t eq = spec.find('=');
    if (eq == std::string::npos || eq == 0)
      throw std::invalid_argument("expected NAME=PLY, got '" + spec + "'");
    meshes.emplace_back(spec.substr(0, eq), io::ReadMeshPly(spec.substr(eq + 1)));
  }
  return meshes;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli("Sparse-truth and leave-one-out checks of a calibrated multi-view set's meshes");
  std::string set, config_path;
  std::vector<std::string> overrides, mesh_specs, leave_out_specs;
  std::int64_t leave_out = 5;
  std::string points_csv;
  SparseOptions sparse;
  cli.add_option("SET", set, "Strecha-layout set (images/, gt_dense_cameras/)")->required();
  cli.add_option("--mesh", mesh_specs, "NAME=PLY, a mesh of the whole set (repeatable)");
  cli.add_option("--leave-out-mesh", leave_out_specs, "NAME=PLY, a mesh of the set without --leave-out");
  cli.add_option("--leave-out", leave_out, "the view left out (its index in the whole set)");
  cli.add_option("--max-features", sparse.max_features, "SIFT keypoints per view");
  cli.add_option("--ratio", sparse.ratio, "ratio test's bound");
  cli.add_option("--max-epipolar-px", sparse.max_epipolar_px, "distance to the epipolar line (px)");
  cli.add_option("--min-views", sparse.min_views, "views a track must span");
  cli.add_option("--max-reprojection-px", sparse.max_reprojection_px, "reprojection error bound (px)");
  cli.add_option("--points-csv", points_csv, "write the sparse points and their distances to each mesh here");
  cli.add_option("--config", config_path, "YAML config file");
  cli.add_option("--set", overrides, "section.key=value override (repeatable)");
  CLI11_PARSE(cli, argc, argv);
  try {
    const app::Config config = app::LoadConfig(config_path, overrides);
    const std::vector<NamedMesh> meshes = ReadMeshes(mesh_specs);
    const std::vector<NamedMesh> without = ReadMeshes(leave_out_specs);
    const std::vector<SparsePoint> points = SparsePoints(io::ReadStrechaSet(set), sparse);
    std::vector<NamedMesh> all = meshes;
    all.insert(all.end(), without.begin(), without.end());
    const std::vector<std::vector<double>> d_m = MeshDistances(points, all);
    PrintSparseTable(all, d_m);
    if (!points_csv.empty()) WritePointsCsv(points_csv, points, all, d_m);
    LeaveOneOut(set, config, leave_out, points, without, meshes);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "semap_fountain_checks: %s\n", e.what());
    return 1;
  }
  return 0;
}
