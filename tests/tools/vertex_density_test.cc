// The map's vertex density on a stream (map.merge_radius_px): every pixel votes at any density, and the
// default's coarser vertices keep the street as the dense map has it. A generated urban street at the
// camera's full size, mapped with the defaults and with vertices three pixels apart; each mesh.ply as written
// is read back by `semap eval` against the exact depth and the scene mesh.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/common/test_data.h"
#include "tests/tools/cli_run.h"
#include "tests/tools/eval_json.h"

namespace semap::tools {
namespace {

namespace fs = std::filesystem;
using test::CliRun;
using test::RunSemap;

// The bounds the default density keeps against the dense map (docs/map.md, "Vertex density").
constexpr double kMaxVertexShare = 0.6;        // of the dense map's vertices, at most
constexpr double kMaxPaperRmseGrowth = 0.03;   // paper protocol, RMSE against the exact depth
constexpr double kMaxAreaWithinLoss = 0.01;    // share of the mesh's area within 0.2 m of the scene
constexpr double kMaxCompletenessLoss = 0.02;  // share of the scene within 0.2 m of the mesh

// `semap run` of `seq` with `args`, then `semap eval --json` of the mesh.ply it wrote (null when either
// failed).
nlohmann::json RunAndEvaluate(const fs::path& seq, const std::string& args, const fs::path& out) {
  const CliRun run = RunSemap("run " + seq.string() + " --method PS " + args + " --out " + out.string());
  EXPECT_EQ(run.exit_code, 0) << run.output;
  if (run.exit_code != 0) return {};
  return test::EvalJson(seq, out / "mesh.ply", out / "again.json");
}

TEST(VertexDensity, TheDefaultHalvesTheVerticesAndKeepsTheStreet) {
  const fs::path dir = test::TempDir();
  const fs::path seq = dir / "street";
  const CliRun synth = RunSemap("synth --preset urban --frames 12 --seed 95 --out " + seq.string());
  ASSERT_EQ(synth.exit_code, 0) << synth.output;
  const nlohmann::json coarse = RunAndEvaluate(seq, "", dir / "default");
  const nlohmann::json dense = RunAndEvaluate(seq, "--set map.merge_radius_px=3", dir / "dense");
  ASSERT_TRUE(coarse.contains("scene_mesh") && dense.contains("scene_mesh"));

  const double vertices = coarse["vertices"].get<double>(), dense_vertices = dense["vertices"].get<double>();
  const auto paper_rmse = [](const nlohmann::json& e) {
    return e["protocols"]["paper"]["exact_depth"]["rmse_m"].get<double>();
  };
  const auto scene = [](const nlohmann::json& e, const char* key) {
    return e["scene_mesh"][key].get<double>();
  };
  std::cout << "vertices " << vertices << " (dense " << dense_vertices << "), paper RMSE vs exact depth "
            << paper_rmse(coarse) << " m (" << paper_rmse(dense) << "), area within 0.2 m "
            << scene(coarse, "accuracy") << " (" << scene(dense, "accuracy") << "), completeness "
            << scene(coarse, "completeness") << " (" << scene(dense, "completeness") << ")\n";
  EXPECT_LE(vertices, kMaxVertexShare * dense_vertices);
  EXPECT_LE(paper_rmse(coarse), (1.0 + kMaxPaperRmseGrowth) * paper_rmse(dense));
  EXPECT_GE(scene(coarse, "accuracy"), scene(dense, "accuracy") - kMaxAreaWithinLoss);
  EXPECT_GE(scene(coarse, "completeness"), scene(dense, "completeness") - kMaxCompletenessLoss);
}

}  // namespace
}  // namespace semap::tools
