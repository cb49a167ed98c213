// `semap compare` run as a user would, on a tiny generated sequence: both modes, the plot, bad methods.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "tests/common/test_data.h"
#include "tests/tools/cli_run.h"
#include "tests/tools/compare_csv.h"
#include "tests/tools/small_sequence.h"

namespace semap::tools {
namespace {

namespace fs = std::filesystem;
using test::CliRun;
using test::RunSemap;

// compare.csv as method → column → value.
std::map<std::string, std::map<std::string, double>> ReadCsv(const fs::path& path) {
  std::map<std::string, std::map<std::string, double>> rows;
  for (const auto& [method, cells] : test::CompareCsvCells(path)) {
    for (const auto& [column, text] : cells) rows[method][column] = std::stod(text);
  }
  return rows;
}

bool IsPng(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  return in && std::string(magic + 1, 3) == "PNG" && fs::file_size(path) > 1000;
}

void ExpectComparison(const fs::path& out) {
  const auto rows = ReadCsv(out / "compare.csv");
  ASSERT_EQ(rows.size(), 4u);
  for (const char* m : {"O", "PS", "voxel", "no ground/wall"}) ASSERT_TRUE(rows.count(m)) << m;
  EXPECT_EQ(rows.at("O").at("kept_ground"), 1.0);
  EXPECT_LT(rows.at("PS").at("kept_ground"), 1.0);
  EXPECT_EQ(rows.at("no ground/wall").at("kept_ground"), 0.0);
  EXPECT_EQ(rows.at("no ground/wall").at("kept_wall"), 0.0);
  EXPECT_LT(rows.at("PS").at("mesh_mb"), rows.at("O").at("mesh_mb"));
  EXPECT_LT(rows.at("no ground/wall").at("mesh_mb"), rows.at("PS").at("mesh_mb"));
  EXPECT_GT(rows.at("O").at("completeness"), 0.5);
  EXPECT_TRUE(IsPng(out / "compare.png"));
  EXPECT_TRUE(fs::exists(out / "compare.md"));
  // The plot's data: both protocols' RMSE as in compare.csv, and each method's kind (0 O, 1 non-semantic
  // baseline, 2 semantic), which colours its point; the line without ground and wall is not a point.
  std::ifstream dat(out / "compare_plot.dat");
  std::map<std::string, int> kind;
  for (std::string line; std::getline(dat, line);) {
    if (line.empty() || line[0] == '#') continue;
    const auto close = line.find('"', 1);
    const std::string method = line.substr(1, close - 1);
    std::stringstream values(line.substr(close + 1));
    double mesh_mb = 0.0, rmse_strict_m = 0.0, rmse_paper_m = 0.0;
    values >> mesh_mb >> rmse_strict_m >> rmse_paper_m >> kind[method];
    ASSERT_TRUE(values) << line;
    EXPECT_NEAR(rmse_strict_m, rows.at(method).at("rmse_m"), 1e-4) << method;
    EXPECT_NEAR(rmse_paper_m, rows.at(method).at("rmse_paper_m"), 1e-4) << method;
  }
  EXPECT_EQ(kind, (std::map<std::string, int>{{"O", 0}, {"PS", 2}, {"voxel", 1}}));
}

TEST(SemapCompare, IncrementalModeWritesTableCsvAndPlot) {
  const fs::path seq = test::SmallGeneratedSequence(3);
  const fs::path out = test::TempDir() / "cmp";
  const CliRun r = RunSemap("compare " + seq.string() + " --methods O PS voxel --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ExpectComparison(out);
  // Incremental runs of a generated sequence: the by-area figures and each method's picture from above.
  const auto rows = ReadCsv(out / "compare.csv");
  for (const char* m : {"O", "PS", "voxel"}) {
    EXPECT_GT(rows.at(m).at("area_m2"), 0.0) << m;
    EXPECT_GT(rows.at(m).at("area_accuracy"), 0.0) << m;
    EXPECT_LE(rows.at(m).at("area_beyond_far"), 1.0 - rows.at(m).at("area_accuracy")) << m;
    EXPECT_TRUE(IsPng(out / m / "top_view.png")) << m;
  }
}

TEST(SemapCompare, SingleFrameModeBuildsOneMapPerFrame) {
  const fs::path seq = test::SmallGeneratedSequence(3);
  const fs::path out = test::TempDir() / "cmp1";
  const CliRun r = RunSemap("compare " + seq.string() +
                            " --mode single-frame --frames 2 --methods O PS voxel --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(r.Has("compare: frame 1")) << r.output;
  ExpectComparison(out);
  EXPECT_TRUE(
      std::isnan(ReadCsv(out / "compare.csv").at("PS").at("area_accuracy")));  // batch maps: not measured
}

TEST(SemapCompare, UnknownMethodOrModeIsAUsageError) {
  const fs::path seq = test::SmallGeneratedSequence(3);
  const CliRun bad_method =
      RunSemap("compare " + seq.string() + " --methods O XYZ --out " + (test::TempDir() / "b").string());
  EXPECT_EQ(bad_method.exit_code, 2) << bad_method.output;
  EXPECT_TRUE(bad_method.Has("XYZ")) << bad_method.output;
  EXPECT_EQ(RunSemap("compare " + seq.string() + " --mode batch").exit_code, 2);
}

}  // namespace
}  // namespace semap::tools
