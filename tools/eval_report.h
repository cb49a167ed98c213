// Printing and writing a mesh evaluation (io/eval), shared by `semap eval` and `semap run --eval`.
#pragma once

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "io/eval/mesh_evaluation.h"

namespace semap::tools {

nlohmann::json ToJson(const DepthAccuracy& accuracy);
// The whole evaluation (totals, and per frame when `per_frame`) as JSON.
nlohmann::json ToJson(const io::MeshEvaluation& evaluation, bool per_frame);
// Prints mesh size and the totals on stdout.
void PrintEvaluation(const io::MeshEvaluation& evaluation);
// One line per evaluated frame: frame_id, then RMSE / MAE / median / bias / completeness against Velodyne and
// against exact depth (empty where the frame has none). Written atomically; throws io::FileError naming the
// file.
void WritePerFrameCsv(const io::MeshEvaluation& evaluation, const std::filesystem::path& path);

}  // namespace semap::tools
