// Every accuracy figure that `semap table` and `semap compare` print and write for a run is the one `semap
// eval` gives for the mesh.ply that run wrote, to the digits printed: read from the commands' files and
// output alone, on one small generated street (test::SmallGeneratedSequence).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "tests/common/test_data.h"
#include "tests/tools/cli_run.h"
#include "tests/tools/compare_csv.h"
#include "tests/tools/eval_json.h"
#include "tests/tools/small_sequence.h"

namespace semap::tools {
namespace {

namespace fs = std::filesystem;
using test::CliRun;
using test::RunSemap;
using Json = nlohmann::json;

// `semap ARGS` with its standard output captured alone (its log is there too), so that nothing written to
// the standard error (a child's warning) can fall inside a printed table; the standard error goes to `err`.
CliRun RunSemapStdout(const std::string& args, const fs::path& err) {
  const std::string command = std::string(SEMAP_EXE) + " " + args + " 2>" + err.string();
  CliRun r = test::RunShell("(" + command + ")");
  r.output += "\n[stderr]\n" + test::ReadFile(err);
  return r;
}

// A markdown table's rows, each as header cell → cell: the first table of `text`, its first column naming the
// row (with the second column too when `key_columns` is 2, joined by a space).
std::map<std::string, std::map<std::string, std::string>> MarkdownRows(const std::string& text,
                                                                       int key_columns) {
  std::vector<std::vector<std::string>> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] != '|') {
      if (!lines.empty()) break;
      continue;
    }
    std::vector<std::string> cells;
    std::size_t from = 1;
    for (std::size_t bar; (bar = line.find('|', from)) != std::string::npos; from = bar + 1) {
      std::string cell = line.substr(from, bar - from);
      cell.erase(0, cell.find_first_not_of(' '));
      cell.erase(cell.find_last_not_of(' ') + 1);
      cells.push_back(cell);
    }
    lines.push_back(cells);
  }
  std::map<std::string, std::map<std::string, std::string>> rows;
  for (std::size_t i = 2; i < lines.size(); ++i) {  // after the header and its rule
    const std::string key = key_columns == 2 ? lines[i][0] + " " + lines[i][1] : lines[i][0];
    for (std::size_t c = 0; c < lines[i].size() && c < lines[0].size(); ++c)
      rows[key][lines[0][c]] = lines[i][c];
  }
  return rows;
}

std::string Printf(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof(text), format, value);
  return text;
}

// As an ostream writes a double by default (compare.csv, compare_plot.dat).
std::string Streamed(double value) {
  std::ostringstream s;
  s << value;
  return s.str();
}

double Number(const Json& j, const std::vector<std::string>& keys) {
  const Json* at = &j;
  for (const std::string& k : keys) {
    if (!at->contains(k)) {
      ADD_FAILURE() << "no " << k << " in " << at->dump();
      return 0.0;
    }
    at = &(*at)[k];
  }
  return at->get<double>();
}

// `semap eval` of the mesh.ply in `run_dir` (a run of `sequence`), as its --json.
Json EvalOf(const fs::path& sequence, const fs::path& run_dir) {
  const fs::path json = run_dir.parent_path() / (run_dir.filename().string() + "_eval.json");
  Json j = test::EvalJson(sequence, run_dir / "mesh.ply", json);
  if (j.is_null()) return Json::object();
  // Figures of something: pixels compared against Velodyne in both protocols, exact depth and the scene mesh,
  // so that equal figures are not two empty ones.
  EXPECT_GT(Number(j, {"lidar", "compared_pixels"}), 0.0) << run_dir;
  EXPECT_GT(Number(j, {"protocols", "paper", "lidar", "compared_pixels"}), 0.0) << run_dir;
  EXPECT_TRUE(j.contains("exact_depth")) << run_dir;
  EXPECT_TRUE(j.contains("scene_mesh")) << run_dir;
  EXPECT_GT(Number(j, {"triangles"}), 0.0) << run_dir;
  return j;
}

// The by-area cells both commands print, from `semap eval`'s scene_mesh.
void ExpectSceneCells(const std::map<std::string, std::string>& row, const Json& eval,
                      const std::string& what) {
  EXPECT_EQ(row.at("area (m²)"), Printf("%.0f", Number(eval, {"scene_mesh", "area_m2"}))) << what;
  EXPECT_EQ(row.at("area within τ"), Printf("%.1f %%", 100.0 * Number(eval, {"scene_mesh", "accuracy"})))
      << what;
  EXPECT_EQ(row.at("within 0.5 m"),
            Printf("%.1f %%", 100.0 * Number(eval, {"scene_mesh", "area_within_near"})))
      << what;
  EXPECT_EQ(row.at("beyond 2 m"), Printf("%.1f %%", 100.0 * Number(eval, {"scene_mesh", "area_beyond_far"})))
      << what;
  EXPECT_EQ(row.at("mean distance (m)"), Printf("%.2f", Number(eval, {"scene_mesh", "mean_distance_m"})))
      << what;
}

TEST(WrittenMeshFigures, TableFiguresAreSemapEvalOfEachRunsMeshPly) {
  const fs::path seq = test::SmallGeneratedSequence(3);
  const fs::path root = test::TempDir();
  const fs::path out = root / "table";
  const CliRun r = RunSemapStdout(
      "table street=" + seq.string() + " --progress-interval 0 --out " + out.string(), root / "table.err");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string md = test::ReadFile(out / "table.md");
  ASSERT_FALSE(md.empty());
  EXPECT_TRUE(r.Has(md)) << "the printed table is table.md\n" << r.output;
  const auto rows = MarkdownRows(md, 2);
  const Json json_rows = Json::parse(std::ifstream(out / "table.json"));
  ASSERT_EQ(json_rows.size(), 2u);
  for (const Json& row_json : json_rows) {
    const std::string method = row_json["method"].get<std::string>();
    SCOPED_TRACE(method);
    const Json eval = EvalOf(seq, out / "street" / method);
    const double rmse = Number(eval, {"lidar", "rmse_m"});
    const double rmse_paper = Number(eval, {"protocols", "paper", "lidar", "rmse_m"});
    const double completeness = Number(eval, {"lidar", "completeness"});
    const double mesh_mb = Number(eval, {"off_bytes"}) / 1e6;
    const double exact = Number(eval, {"exact_depth", "rmse_m"});
    const double exact_paper = Number(eval, {"protocols", "paper", "exact_depth", "rmse_m"});

    // table.json: the figures themselves.
    EXPECT_EQ(row_json["rmse_m"].get<double>(), rmse);
    EXPECT_EQ(row_json["rmse_paper_m"].get<double>(), rmse_paper);
    EXPECT_EQ(row_json["completeness"].get<double>(), completeness);
    EXPECT_EQ(row_json["mesh_mb"].get<double>(), mesh_mb);
    EXPECT_EQ(row_json["triangles"], eval["triangles"]);
    EXPECT_EQ(row_json["exact_depth_rmse_m"].get<double>(), exact);
    EXPECT_EQ(row_json["exact_depth_rmse_paper_m"].get<double>(), exact_paper);
    EXPECT_EQ(row_json["scene_mesh"], eval["scene_mesh"]);

    // table.md (and the printed table): to its digits.
    ASSERT_TRUE(rows.count("street " + method)) << md;
    const auto& row = rows.at("street " + method);
    EXPECT_EQ(row.at("RMSE strict (m)"), Printf("%.4f", rmse));
    EXPECT_EQ(row.at("RMSE paper (m)"), Printf("%.4f", rmse_paper));
    EXPECT_EQ(row.at("completeness"), Printf("%.1f %%", 100.0 * completeness));
    EXPECT_EQ(row.at("mesh (MB, OFF)"), Printf("%.2f", mesh_mb));
    EXPECT_EQ(row.at("triangles"), eval["triangles"].dump());
    EXPECT_EQ(row.at("RMSE vs exact depth, strict (m)"), Printf("%.4f", exact));
    EXPECT_EQ(row.at("RMSE vs exact depth, paper (m)"), Printf("%.4f", exact_paper));
    ExpectSceneCells(row, eval, "table " + method);

    // The run's log line.
    EXPECT_TRUE(r.Has("table: street " + method + ": RMSE " + Printf("%.4f", rmse) + " m strict, " +
                      Printf("%.4f", rmse_paper) + " m paper, "))
        << r.output;
    EXPECT_TRUE(r.Has("completeness " + Printf("%.1f", 100.0 * completeness) + " %, " +
                      Printf("%.2f", mesh_mb) + " MB"))
        << r.output;
  }
}

TEST(WrittenMeshFigures, CompareFiguresAreSemapEvalOfEachRunsMeshPly) {
  const fs::path seq = test::SmallGeneratedSequence(3);
  const fs::path root = test::TempDir();
  const fs::path out = root / "compare";
  const CliRun r = RunSemapStdout("compare " + seq.string() + " --methods O PS --out " + out.string(),
                                  root / "compare.err");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string md = test::ReadFile(out / "compare.md");
  ASSERT_FALSE(md.empty());
  EXPECT_TRUE(r.Has(md)) << "the printed table is compare.md\n" << r.output;
  const auto md_rows = MarkdownRows(md, 1);
  const auto csv_rows = test::CompareCsvCells(out / "compare.csv");
  // compare_plot.dat: method → its mesh size and both protocols' RMSE, as written.
  std::map<std::string, std::vector<std::string>> plot;
  std::ifstream dat(out / "compare_plot.dat");
  for (std::string line; std::getline(dat, line);) {
    if (line.empty() || line[0] == '#') continue;
    const auto close = line.find('"', 1);
    std::istringstream values(line.substr(close + 1));
    std::vector<std::string>& cells = plot[line.substr(1, close - 1)];
    for (std::string v; values >> v;) cells.push_back(v);
  }
  ASSERT_EQ(csv_rows.size(), 3u);
  ASSERT_EQ(plot.size(), 2u);
  for (const auto& [method, folder] :
       std::map<std::string, std::string>{{"O", "O"}, {"PS", "PS"}, {"no ground/wall", "no_ground_wall"}}) {
    SCOPED_TRACE(method);
    const Json eval = EvalOf(seq, out / folder);
    const double mesh_mb = Number(eval, {"off_bytes"}) / 1e6;
    const std::string triangles = eval["triangles"].dump();
    const double rmse = Number(eval, {"lidar", "rmse_m"});
    const double mae = Number(eval, {"lidar", "mae_m"});
    const double completeness = Number(eval, {"lidar", "completeness"});
    const double rmse_paper = Number(eval, {"protocols", "paper", "lidar", "rmse_m"});
    const double mae_paper = Number(eval, {"protocols", "paper", "lidar", "mae_m"});

    ASSERT_TRUE(md_rows.count(method)) << md;
    const auto& row = md_rows.at(method);
    EXPECT_EQ(row.at("mesh (MB, OFF)"), Printf("%.2f", mesh_mb));
    EXPECT_EQ(row.at("triangles"), triangles);
    EXPECT_EQ(row.at("RMSE strict (m)"), Printf("%.4f", rmse));
    EXPECT_EQ(row.at("RMSE paper (m)"), Printf("%.4f", rmse_paper));
    EXPECT_EQ(row.at("MAE strict (m)"), Printf("%.4f", mae));
    EXPECT_EQ(row.at("completeness"), Printf("%.1f %%", 100.0 * completeness));
    ExpectSceneCells(row, eval, "compare.md " + method);

    ASSERT_TRUE(csv_rows.count(method));
    const auto& csv = csv_rows.at(method);
    EXPECT_EQ(csv.at("mesh_mb"), Streamed(mesh_mb));
    EXPECT_EQ(csv.at("triangles"), triangles);
    EXPECT_EQ(csv.at("rmse_m"), Streamed(rmse));
    EXPECT_EQ(csv.at("mae_m"), Streamed(mae));
    EXPECT_EQ(csv.at("completeness"), Streamed(completeness));
    EXPECT_EQ(csv.at("rmse_paper_m"), Streamed(rmse_paper));
    EXPECT_EQ(csv.at("mae_paper_m"), Streamed(mae_paper));
    EXPECT_EQ(csv.at("area_m2"), Streamed(Number(eval, {"scene_mesh", "area_m2"})));
    EXPECT_EQ(csv.at("area_accuracy"), Streamed(Number(eval, {"scene_mesh", "accuracy"})));
    EXPECT_EQ(csv.at("area_within_near"), Streamed(Number(eval, {"scene_mesh", "area_within_near"})));
    EXPECT_EQ(csv.at("area_beyond_far"), Streamed(Number(eval, {"scene_mesh", "area_beyond_far"})));
    EXPECT_EQ(csv.at("mean_distance_m"), Streamed(Number(eval, {"scene_mesh", "mean_distance_m"})));

    if (method == "no ground/wall") continue;  // the plot's line, not one of its points
    ASSERT_TRUE(plot.count(method));
    ASSERT_GE(plot.at(method).size(), 3u);
    EXPECT_EQ(plot.at(method)[0], Streamed(mesh_mb));
    EXPECT_EQ(plot.at(method)[1], Streamed(rmse));
    EXPECT_EQ(plot.at(method)[2], Streamed(rmse_paper));
  }
}

}  // namespace
}  // namespace semap::tools
