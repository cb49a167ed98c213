// Printing and writing a mesh evaluation (app/eval/mesh_evaluation.h), shared by `semap eval` and
// `semap run --eval`.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/eval/mesh_evaluation.h"

namespace semap::app {

nlohmann::json ToJson(const DepthAccuracy& accuracy);
// The whole evaluation (totals, and per frame when `per_frame`) as JSON.
nlohmann::json ToJson(const MeshEvaluation& evaluation, bool per_frame);
// The breakdown's three tables as JSON (bins with their figures).
nlohmann::json ToJson(const ErrorBreakdown& breakdown);
// Prints mesh size and the totals on stdout: against Velodyne and exact depth in both protocols, strict first
// (the configured filters), then the paper's, each line saying its filters.

void PrintEvaluation(const MeshEvaluation& evaluation);
// The scene-mesh figures (by area, per vertex, completeness) as JSON.
nlohmann::json ToJson(const SurfaceMetrics& scene);
// Pictures of `mesh` from above for a report, along the evaluated cameras' up direction (+z when no frame had
// a pose), with the camera track: `dir`/top_view.png in the mesh's colours, and, when the evaluation had a
// scene mesh, `dir`/top_view_error.png coloured by distance to it (the bins of the by-area figures). Returns
// the files written; throws std::runtime_error naming a file that cannot be read or written.
std::vector<std::filesystem::path> WriteTopViews(const Mesh& mesh, const MeshEvaluation& evaluation,
                                                 const std::filesystem::path& dir);
// The evaluation as markdown for a report (eval.md): the totals in both protocols side by side (saying which
// is which), then where the errors come from: error by class, by reference distance and by the area of the
// mesh triangle hit, against Velodyne and against exact depth where the sequence has them.
std::string EvaluationMarkdown(const MeshEvaluation& evaluation);
// Writes the evaluation's error images to `dir` as error_lidar_NNNNNN.png / error_exact_depth_NNNNNN.png
// (created). Returns the files written; throws naming a file that cannot be written.
std::vector<std::filesystem::path> WriteErrorImages(const MeshEvaluation& evaluation,
                                                    const std::filesystem::path& dir);
// One line per evaluated frame: frame_id, then RMSE / MAE / median / bias / completeness against Velodyne and
// against exact depth (empty where the frame has none). Written atomically; throws io::FileError naming the
// file.
void WritePerFrameCsv(const MeshEvaluation& evaluation, const std::filesystem::path& path);

}  // namespace semap::app
