// `semap table` run as a user would, on a tiny generated sequence.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "io/mesh/ply_off.h"
#include "tests/common/test_data.h"
#include "tests/engine/map/manifold_checker.h"
#include "tests/tools/cli_run.h"
#include "tests/tools/small_sequence.h"

namespace semap::tools {
namespace {

namespace fs = std::filesystem;
using test::CliRun;
using test::RunSemap;

TEST(SemapTable, RunsOAndPsAndWritesThePaperTable) {
  const fs::path seq = test::SmallGeneratedSequence(3);
  const fs::path out = test::TempDir() / "table";
  const CliRun r = RunSemap("table small=" + seq.string() + " --progress-interval 0 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string text = test::ReadFile(out / "table.md");
  EXPECT_NE(text.find("| small | O |"), std::string::npos) << text;
  EXPECT_NE(text.find("| small | PS |"), std::string::npos) << text;
  EXPECT_NE(text.find("| 95 | PS | 0.7173 | 1.5434 |"), std::string::npos) << text;
  EXPECT_TRUE(fs::exists(out / "small" / "O" / "mesh.ply"));
  EXPECT_TRUE(fs::exists(out / "small" / "PS" / "mesh.ply"));
  for (const char* method : {"O", "PS"}) {
    const test::ManifoldReport m =
        test::CheckManifold(io::ReadMeshPly(out / "small" / method / "mesh.ply"), true);
    EXPECT_TRUE(m.ok()) << method << "\n" << m.Summary();
  }

  const nlohmann::json rows = nlohmann::json::parse(std::ifstream(out / "table.json"));
  ASSERT_EQ(rows.size(), 2u);
  const auto& o = rows[0];
  const auto& ps = rows[1];
  EXPECT_EQ(o["method"], "O");
  EXPECT_EQ(ps["method"], "PS");
  for (const auto& row : rows) {
    EXPECT_EQ(row["frames"], 3);
    EXPECT_GT(row["fps"].get<double>(), 0.0);
    // The mapper alone is faster than the whole process, which also reads, computes depth and labels.
    EXPECT_GT(row["mapper_fps"].get<double>(), row["fps"].get<double>());
    EXPECT_GT(row["completeness"].get<double>(), 0.5);
    EXPECT_TRUE(std::isfinite(row["rmse_m"].get<double>()));
    EXPECT_GT(row["exact_depth_rmse_m"].get<double>(), 0.0);  // a generated sequence has exact depth
    // ... and a scene mesh: the by-area figures.
    ASSERT_TRUE(row.contains("scene_mesh")) << row.dump();
    EXPECT_GT(row["scene_mesh"]["area_m2"].get<double>(), 0.0);
    EXPECT_GT(row["scene_mesh"]["accuracy"].get<double>(), 0.0);
    EXPECT_LE(row["scene_mesh"]["accuracy"].get<double>(), 1.0);
    EXPECT_TRUE(fs::exists(out / "small" / row["method"].get<std::string>() / "top_view.png"));
    EXPECT_TRUE(fs::exists(out / "small" / row["method"].get<std::string>() / "top_view_error.png"));
  }
  EXPECT_NE(text.find("| area (m²) | area within τ | within 0.5 m | beyond 2 m | mean distance (m) |"),
            std::string::npos)
      << text;
  // PS keeps fewer points, so its mesh is smaller.
  EXPECT_LT(ps["mesh_mb"].get<double>(), o["mesh_mb"].get<double>());
}

TEST(SemapTable, MissingSequenceIsAClearFailure) {
  const CliRun r = RunSemap("table /nonexistent/sequence --out " + (test::TempDir() / "t").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_TRUE(r.Has("/nonexistent/sequence")) << r.output;
}

}  // namespace
}  // namespace semap::tools
