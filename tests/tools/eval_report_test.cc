// `semap run --eval` and `semap eval --json` (app/eval/eval_report): per-frame accuracy files a user can
// plot.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

#include "engine/core/class_map.h"
#include "io/mesh/ply_off.h"
#include "tests/common/test_data.h"
#include "tests/tools/cli_run.h"
#include "tests/tools/eval_json.h"
#include "tests/tools/small_sequence.h"

namespace semap::tools {
namespace {

namespace fs = std::filesystem;
using test::CliRun;
using test::RunSemap;

// `semap eval` of the mesh.ply a run wrote to `out`, as its --json (empty when the command failed).
nlohmann::json EvalOfWrittenMesh(const fs::path& seq, const fs::path& out) {
  return test::EvalJson(seq, out / "mesh.ply", out / "again.json");
}

// The same agreement on a mesh with vertices at weighted means (map.confirm_beyond_m), whose float32 rounding
// the in-process evaluation once skipped for two vertices: one Velodyne pixel of difference.
TEST(SemapRunEval, InProcessEvaluationRoundsEveryVertexAsThePlyStoresIt) {
  const fs::path seq = test::SmallGeneratedSequence(3);
  const fs::path out = test::TempDir() / "run";
  const CliRun run = RunSemap("run " + seq.string() +
                              " --method PS --set map.confirm_beyond_m=20 --eval --out " + out.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto a = nlohmann::json::parse(std::ifstream(out / "eval.json"));
  const auto b = EvalOfWrittenMesh(seq, out);
  ASSERT_TRUE(b.contains("lidar"));
  EXPECT_EQ(a["lidar"]["rmse_m"].get<double>(), b["lidar"]["rmse_m"].get<double>());
  EXPECT_EQ(a["lidar"]["compared_pixels"].get<std::int64_t>(),
            b["lidar"]["compared_pixels"].get<std::int64_t>());
}

TEST(SemapRunEval, WritesPerFrameAccuracyThatAgreesWithSemapEval) {
  const fs::path seq = test::SmallGeneratedSequence(3);
  const fs::path out = test::TempDir() / "run";
  const CliRun run =
      RunSemap("run " + seq.string() + " --method PS --eval --progress-interval 100 --out " + out.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(run.Has("vs Velodyne")) << run.output;
  std::ifstream csv(out / "eval_frames.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line.rfind("frame_id,lidar_rmse_m", 0), 0u) << line;
  int frames = 0;
  while (std::getline(csv, line)) {
    EXPECT_EQ(std::stoi(line.substr(0, line.find(','))), frames) << line;
    const double rmse = std::stod(line.substr(line.find(',') + 1));
    EXPECT_GT(rmse, 0.0);
    ++frames;
  }
  EXPECT_EQ(frames, 3);

  // The same mesh read back by `semap eval` gives the same totals: `semap run --eval` evaluates the mesh as
  // written (float32 coordinates; a vertex moved by 1e-6 m flips pixels at silhouettes, errors of metres).
  const auto a = nlohmann::json::parse(std::ifstream(out / "eval.json"));
  const auto b = EvalOfWrittenMesh(seq, out);
  ASSERT_TRUE(b.contains("lidar"));
  const double rmse_a = a["lidar"]["rmse_m"].get<double>(), rmse_b = b["lidar"]["rmse_m"].get<double>();
  EXPECT_NEAR(rmse_a, rmse_b, 1e-9 * rmse_a);
  EXPECT_EQ(a["lidar"]["compared_pixels"].get<std::int64_t>(),
            b["lidar"]["compared_pixels"].get<std::int64_t>());
  ASSERT_EQ(b["per_frame"].size(), 3u);
  EXPECT_TRUE(b["per_frame"][2].contains("exact_depth"));

  // The by-area figures against the scene mesh, and the per-vertex one under its own name.
  const auto& scene = a["scene_mesh"];
  EXPECT_EQ(scene["area_samples"].get<int>(), 100000);
  EXPECT_GT(scene["area_m2"].get<double>(), 10.0);
  for (const char* share :
       {"accuracy", "area_within_near", "area_beyond_near", "area_beyond_far", "vertex_accuracy"}) {
    EXPECT_GE(scene[share].get<double>(), 0.0) << share;
    EXPECT_LE(scene[share].get<double>(), 1.0) << share;
  }
  EXPECT_LE(scene["accuracy"].get<double>(), scene["area_within_near"].get<double>());
  EXPECT_NEAR(scene["area_within_near"].get<double>() + scene["area_beyond_near"].get<double>(), 1.0, 1e-12);
  EXPECT_LE(scene["area_beyond_far"].get<double>(), scene["area_beyond_near"].get<double>());
  EXPECT_TRUE(run.Has("of the area within tau")) << run.output;
  // Its pictures from above.
  for (const char* png : {"top_view.png", "top_view_error.png"}) {
    const cv::Mat image = cv::imread((out / png).string());
    ASSERT_FALSE(image.empty()) << png;
    cv::Mat grey;
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
    EXPECT_GT(cv::countNonZero(grey < 250), image.total() / 20) << png;  // the mesh covers a good part of it
  }
}

TEST(SemapEval, TheExactSceneMeshIsAccurateAndComplete) {
  const fs::path seq = test::SmallGeneratedSequence(3);
  const fs::path json = test::TempDir() / "scene.json";
  const fs::path scene = seq / "2026_01_01" / "2026_01_01_drive_0001_sync" / "scene_mesh.ply";
  const fs::path pictures = test::TempDir() / "pictures";
  const CliRun eval = RunSemap("eval " + seq.string() + " --mesh " + scene.string() + " --json " +
                               json.string() + " --pictures " + pictures.string());
  ASSERT_EQ(eval.exit_code, 0) << eval.output;
  EXPECT_TRUE(eval.Has("vs scene mesh accuracy 100.0 %")) << eval.output;
  const auto j = nlohmann::json::parse(std::ifstream(json));
  EXPECT_DOUBLE_EQ(j["scene_mesh"]["accuracy"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(j["scene_mesh"]["vertex_accuracy"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(j["scene_mesh"]["area_beyond_far"].get<double>(), 0.0);
  EXPECT_LT(j["scene_mesh"]["mean_distance_m"].get<double>(), 1e-6);
  // Its area, summed here from the file.
  const Mesh truth = io::ReadMeshPly(scene);
  double area = 0.0;
  for (const auto& t : truth.triangles) {
    const Eigen::Vector3d a = truth.vertices[t[0]];
    area += 0.5 * (truth.vertices[t[1]] - a).cross(truth.vertices[t[2]] - a).norm();
  }
  EXPECT_NEAR(j["scene_mesh"]["area_m2"].get<double>(), area, 1e-9 * area);
  // The truth against itself, seen from above: every covered pixel in the green bin (G above R and B).
  const cv::Mat error = cv::imread((pictures / "top_view_error.png").string());
  ASSERT_FALSE(error.empty());
  int covered = 0, green = 0;
  for (int y = 0; y < error.rows - 30; ++y) {
    for (int x = 0; x < error.cols; ++x) {
      const cv::Vec3b c = error.at<cv::Vec3b>(y, x);
      if (c == cv::Vec3b(255, 255, 255) || (c[0] == c[1] && c[1] == c[2])) continue;  // background, track
      ++covered;
      green += c[1] > c[2] && c[1] > c[0] ? 1 : 0;
    }
  }
  EXPECT_GT(covered, 10000);
  EXPECT_GT(green, 0.99 * covered);
  // Truth samples come from the 16-bit millimetre depth PNGs: within a millimetre of the true surface.
  EXPECT_GT(j["scene_mesh"]["completeness"].get<double>(), 0.999);
  EXPECT_LT(j["scene_mesh"]["mean_completeness_m"].get<double>(), 1e-3);
  EXPECT_GT(j["scene_mesh"]["truth_samples"].get<int>(), 1000);
  EXPECT_LT(j["exact_depth"]["rmse_m"].get<double>(), 0.01);
}

// Sum of a breakdown's compared pixels.
std::int64_t Compared(const nlohmann::json& bins) {
  std::int64_t n = 0;
  for (const auto& b : bins) n += b["compared_pixels"].get<std::int64_t>();
  return n;
}

// Pixels of the picture part (above the legend band) that are coloured (neither grey, no reference, nor
// black, a hole), and those that are black.
struct ErrorImagePixels {
  int coloured = 0;
  int holes = 0;
};
ErrorImagePixels CountPixels(const cv::Mat& image, int picture_rows) {
  ErrorImagePixels n;
  for (int y = 0; y < picture_rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      const cv::Vec3b c = image.at<cv::Vec3b>(y, x);
      n.coloured += (c[0] != c[1] || c[1] != c[2]) ? 1 : 0;
      n.holes += (c[0] == 0 && c[1] == 0 && c[2] == 0) ? 1 : 0;
    }
  }
  return n;
}

TEST(SemapEval, ReportFolderHasBothProtocolsTheBreakdownAndErrorImages) {
  // 5 frames: enough compared pixels for every bin of the breakdown now that the mesh is open where no view
  // saw a surface (3 frames gave 985 lidar pixels).
  const fs::path seq = test::SmallGeneratedSequence(5);
  const fs::path tmp = test::TempDir();  // emptied on each call: called once
  const fs::path run_dir = tmp / "run";
  const CliRun run =
      RunSemap("run " + seq.string() + " --method PS --progress-interval 100 --out " + run_dir.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const fs::path out = tmp / "report";
  const CliRun eval = RunSemap("eval " + seq.string() + " --mesh " + (run_dir / "mesh.ply").string() +
                               " --out " + out.string() + " --error-images 2");
  ASSERT_EQ(eval.exit_code, 0) << eval.output;
  EXPECT_TRUE(eval.Has("[strict: reference depth 1-40 m, every error]")) << eval.output;
  EXPECT_TRUE(eval.Has("[paper: reference depth 1-15 m, |error| <= 2 m;")) << eval.output;
  EXPECT_TRUE(
      eval.Has("[static: reference depth 1-40 m, every error, movable classes left out (the frames' own "
               "labels, 5 frames)]"))
      << eval.output;

  // eval.json: both protocols, and breakdowns whose bins add up to the strict totals.
  const auto j = nlohmann::json::parse(std::ifstream(out / "eval.json"));
  const auto& strict = j["protocols"]["strict"];
  const auto& paper = j["protocols"]["paper"];
  EXPECT_EQ(strict["lidar"]["rmse_m"], j["lidar"]["rmse_m"]);
  EXPECT_LE(paper["lidar"]["rmse_m"].get<double>(), strict["lidar"]["rmse_m"].get<double>() + 1e-9);
  EXPECT_LE(paper["lidar"]["reference_pixels"].get<std::int64_t>(),
            strict["lidar"]["reference_pixels"].get<std::int64_t>());
  EXPECT_EQ(j["breakdown"]["class_source"], "label images");  // a generated sequence has label images
  const auto& static_scene = j["protocols"]["static"];
  EXPECT_EQ(static_scene["frames_with_labels"], 5);
  for (const char* reference : {"lidar", "exact_depth"}) {
    SCOPED_TRACE(reference);
    const auto& b = j["breakdown"][reference];
    // The static scene is the strict one less the pixels of the movable classes, as the by-class breakdown
    // (the frames' label images) counts them (these five small frames show no car: the same figures).
    std::int64_t movable_reference = 0, movable_compared = 0;
    for (const auto& bin : b["by_class"]) {
      const std::string name = bin["name"];
      for (const char* movable :
           {"Person", "Rider", "Car", "Truck", "Bus", "Train", "Motorcycle", "Bicycle"}) {
        if (name != movable) continue;
        movable_reference += bin["reference_pixels"].get<std::int64_t>();
        movable_compared += bin["compared_pixels"].get<std::int64_t>();
      }
    }
    EXPECT_EQ(static_scene[reference]["reference_pixels"].get<std::int64_t>(),
              strict[reference]["reference_pixels"].get<std::int64_t>() - movable_reference);
    EXPECT_EQ(static_scene[reference]["compared_pixels"].get<std::int64_t>(),
              strict[reference]["compared_pixels"].get<std::int64_t>() - movable_compared);
    const std::int64_t compared = strict[reference]["compared_pixels"].get<std::int64_t>();
    ASSERT_GT(compared, 1000);
    EXPECT_EQ(Compared(b["by_class"]), compared);
    EXPECT_EQ(Compared(b["by_distance"]), compared);
    EXPECT_EQ(Compared(b["by_triangle_area"]), compared);  // every compared pixel hit a triangle
    EXPECT_GE(b["by_class"].size(), 3u);                   // a street has road, building, ... pixels
    ASSERT_EQ(b["by_distance"].size(), 7u);
    EXPECT_EQ(b["by_distance"][1]["name"], "5-10 m");
    std::int64_t reference_pixels = 0;
    for (const auto& bin : b["by_distance"]) reference_pixels += bin["reference_pixels"].get<std::int64_t>();
    EXPECT_EQ(reference_pixels, strict[reference]["reference_pixels"].get<std::int64_t>());
  }

  // eval.md: the two protocols named, the three tables.
  const std::string md = test::ReadFile(out / "eval.md");
  for (const char* text :
       {"| strict | Velodyne | reference depth 1-40 m, every error |",
        "| paper | Velodyne | reference depth 1-15 m, |error| <= 2 m |", "| strict | exact depth |",
        "| static | Velodyne | reference depth 1-40 m, every error, movable classes left out",
        "By class of the pixel (classes from: label images)", "| 5-10 m |", "By area of the mesh triangle",
        "| 0.01-0.1 m2 |", "error_lidar_000000.png"}) {
    EXPECT_NE(md.find(text), std::string::npos) << text << "\n" << md;
  }

  // Error images of frames 0 and 4 (two spread over five), against Velodyne and exact depth, non-trivial,
  // with a legend band.
  for (const char* name : {"error_lidar_000000.png", "error_lidar_000004.png", "error_exact_depth_000000.png",
                           "error_exact_depth_000004.png"}) {
    const cv::Mat image = cv::imread((out / name).string());
    ASSERT_FALSE(image.empty()) << name;
    EXPECT_EQ(image.cols, 480) << name;
    ASSERT_GT(image.rows, 144 + 29) << name;
    // Velodyne (512 azimuth steps here) has a reference in about 5 % of the picture, exact depth in most of
    // it (the sky has none); the mesh covers most of those pixels (it is open where no view saw a surface:
    // the holes are black).
    const int share = std::string(name).find("lidar") != std::string::npos ? 40 : 3;
    const ErrorImagePixels n = CountPixels(image, 144);
    std::cout << name << ": " << n.coloured << " coloured, " << n.holes << " holes\n";
    EXPECT_GT(n.coloured + n.holes, 480 * 144 / share) << name;
    // Measured 64–67 % covered on these 5 small frames (480 px wide: noisier depth, which opens more holes
    // with map.seen_noise_sigmas 0).
    EXPECT_GT(n.coloured, n.holes) << name;
  }
  EXPECT_FALSE(fs::exists(out / "error_lidar_000002.png"));
  EXPECT_TRUE(fs::exists(out / "top_view.png"));

  // Named frames instead.
  const fs::path named = tmp / "named";
  const CliRun one = RunSemap("eval " + seq.string() + " --mesh " + (run_dir / "mesh.ply").string() +
                              " --out " + named.string() + " --error-frames 1");
  ASSERT_EQ(one.exit_code, 0) << one.output;
  EXPECT_TRUE(fs::exists(named / "error_lidar_000001.png"));
  EXPECT_FALSE(fs::exists(named / "error_lidar_000000.png"));
}

TEST(SemapEval, TheStaticSceneLeavesOutThePixelsOfMovableClassesByTheFramesLabels) {
  const fs::path seq = test::SmallGeneratedSequence(5);
  const fs::path tmp = test::TempDir();  // emptied on each call: called once
  const CliRun run = RunSemap("run " + seq.string() + " --method PS --progress-interval 100 --out " +
                              (tmp / "run").string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  // The sequence's own labels with the left half of every frame painted "car" (these frames show no car).
  const int car = ClassMap::Cityscapes().FindByName("car");
  ASSERT_GE(car, 0);
  const fs::path labels = tmp / "labels";
  fs::create_directories(labels);
  int painted = 0;
  for (const auto& entry : fs::recursive_directory_iterator(seq)) {
    const fs::path& path = entry.path();
    if (path.extension() != ".png" || path.parent_path().filename() != "data" ||
        path.parent_path().parent_path().filename() != "semantic") {
      continue;
    }
    cv::Mat label = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(label.type(), CV_8UC1) << path;
    label.colRange(0, label.cols / 2).setTo(car);
    ASSERT_TRUE(cv::imwrite((labels / path.filename()).string(), label));
    ++painted;
  }
  ASSERT_EQ(painted, 5);
  const fs::path json = tmp / "eval.json";
  const CliRun eval = RunSemap("eval " + seq.string() + " --mesh " + (tmp / "run" / "mesh.ply").string() +
                               " --set input.labels_dir=" + labels.string() + " --json " + json.string());
  ASSERT_EQ(eval.exit_code, 0) << eval.output;
  const auto j = nlohmann::json::parse(std::ifstream(json));
  const auto& strict = j["protocols"]["strict"];
  const auto& static_scene = j["protocols"]["static"];
  EXPECT_EQ(static_scene["frames_with_labels"], 5);
  for (const char* reference : {"lidar", "exact_depth"}) {
    SCOPED_TRACE(reference);
    // An independent count: the by-class breakdown's "Car" bin (the same labels, counted by other code).
    std::int64_t car_reference = -1, car_compared = -1;
    for (const auto& bin : j["breakdown"][reference]["by_class"]) {
      if (bin["name"] != "Car") continue;
      car_reference = bin["reference_pixels"].get<std::int64_t>();
      car_compared = bin["compared_pixels"].get<std::int64_t>();
    }
    // About half of the reference pixels are the car's now; the static scene is the rest.
    const std::int64_t all = strict[reference]["reference_pixels"].get<std::int64_t>();
    ASSERT_GT(car_reference, all / 5);
    ASSERT_LT(car_reference, all - all / 5);
    EXPECT_EQ(static_scene[reference]["reference_pixels"].get<std::int64_t>(), all - car_reference);
    EXPECT_EQ(static_scene[reference]["compared_pixels"].get<std::int64_t>(),
              strict[reference]["compared_pixels"].get<std::int64_t>() - car_compared);
  }
}

}  // namespace
}  // namespace semap::tools
