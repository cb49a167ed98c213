// `semap run --realtime [SPEED]` end to end on a small generated sequence: frames played at their time
// stamps, every frame accounted for (integrated in frames.csv, or dropped or failed in errors.jsonl), the
// latency figures written, and a bad speed refused by name.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "io/mesh/ply_off.h"
#include "tests/common/test_data.h"
#include "tests/tools/cli_run.h"

namespace semap::tools {
namespace {

namespace fs = std::filesystem;
using test::CliRun;

constexpr int kFrames = 12;

class RunRealtime : public ::testing::Test {
 protected:
  static fs::path Sequence() { return test::ProcessTempRoot() / "RunRealtime_sequence"; }
  static void SetUpTestSuite() {
    fs::remove_all(Sequence());
    const CliRun r = test::RunSemap("synth --preset urban --frames " + std::to_string(kFrames) +
                                    " --seed 3 --out " + Sequence().string() + test::kSmallSynth);
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  fs::path out_ = test::TempDir() / "run";
};

// At 4× the sensor's rate the engine may fall behind: whatever it drops is accounted for, frame by frame.
TEST_F(RunRealtime, EveryFrameIsIntegratedOrDroppedWithItsReasonAndTheLatencyIsWritten) {
  const CliRun r = test::RunSemap("run " + Sequence().string() + " --realtime 4 --out " + out_.string() +
                                  " --set pipeline.depth_workers=1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(r.Has("realtime mode at 4x the sensor's rate")) << r.output;
  const auto summary = nlohmann::json::parse(std::ifstream(out_ / "summary.json"));
  const int integrated = summary["frames_integrated"], dropped = summary["frames_dropped"];
  EXPECT_EQ(integrated + dropped + summary["frames_failed"].get<int>(), kFrames) << summary.dump();
  EXPECT_GT(integrated, 0);
  for (const char* step : {"depth", "labels", "map", "published"}) {
    const auto& l = summary["latency_ms"][step];
    EXPECT_LE(l["p50"].get<double>(), l["p95"].get<double>()) << step;
    EXPECT_LE(l["p95"].get<double>(), l["max"].get<double>()) << step;
    EXPECT_GT(l["max"].get<double>(), 0.0) << step;
  }
  EXPECT_LE(summary["latency_ms"]["map"]["max"].get<double>(),
            summary["latency_ms"]["published"]["max"].get<double>());
  // frames.csv: a row per integrated frame, with its latency; errors.jsonl: a line per dropped frame.
  const std::vector<std::string> rows = test::NonEmptyLines(out_ / "frames.csv");
  ASSERT_EQ(rows.size(), static_cast<std::size_t>(integrated + 1));
  const std::vector<std::string> names = test::CsvCells(rows[0]);
  std::map<std::string, std::size_t> column;
  for (std::size_t i = 0; i < names.size(); ++i) column[names[i]] = i;
  for (const char* name : {"latency_depth_ms", "latency_labels_ms", "latency_map_ms", "latency_published_ms",
                           "late_ms", "dropped_behind", "dropped_no_keyframe_labels"}) {
    ASSERT_TRUE(column.count(name)) << name << " in " << rows[0];
  }
  std::set<std::int64_t> seen;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const std::vector<std::string> cells = test::CsvCells(rows[i]);
    ASSERT_EQ(cells.size(), names.size()) << rows[i];
    EXPECT_TRUE(seen.insert(std::stoll(cells[column["frame_id"]])).second) << rows[i];
    EXPECT_GE(std::stod(cells[column["latency_published_ms"]]), std::stod(cells[column["latency_map_ms"]]));
    // In realtime mode the mesh is extracted after every frame (pipeline.realtime_mesh_every_frames): each
    // row counts a mesh that holds its frame (every 5 frames, the rows before the first extraction count 0).
    EXPECT_GT(std::stoll(cells[column["mesh_triangles"]]), 0) << rows[i];
  }
  int drops = 0;
  for (const std::string& line : test::NonEmptyLines(out_ / "errors.jsonl")) {
    const auto e = nlohmann::json::parse(line);
    EXPECT_TRUE(seen.insert(e["frame_id"].get<std::int64_t>()).second) << line;
    if (!e.contains("dropped")) continue;
    ++drops;
    EXPECT_TRUE(e["dropped"] == "behind" || e["dropped"] == "no_keyframe_labels") << line;
  }
  EXPECT_EQ(drops, dropped);
  EXPECT_EQ(seen.size(), static_cast<std::size_t>(kFrames));  // every frame once
  EXPECT_GT(io::ReadMeshPly(out_ / "mesh.ply").num_triangles(), 0u);
}

// `--realtime` alone plays the sensor's own rate; a speed that is not positive is refused, naming the key.
TEST_F(RunRealtime, NoSpeedIsTheSensorsRateAndABadSpeedIsRefusedByName) {
  const CliRun r =
      test::RunSemap("run " + Sequence().string() + " --realtime --frames 3 --out " + out_.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(r.Has("realtime mode at 1x the sensor's rate")) << r.output;
  const CliRun bad = test::RunSemap("run " + Sequence().string() + " --realtime 0 --out " + out_.string());
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_TRUE(bad.Has("realtime_speed")) << bad.output;
}

}  // namespace
}  // namespace semap::tools
