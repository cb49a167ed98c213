#include "app/eval/eval_run.h"

#include <spdlog/spdlog.h>

#include <memory>
#include <nlohmann/json.hpp>

#include "app/eval/eval_report.h"
#include "io/atomic_file.h"
#include "io/mesh/ply_off.h"

namespace semap::app {

MeshEvaluation EvaluateAsConfigured(const Mesh& mesh, const std::filesystem::path& dataset,
                                    const Config& config, MeshEvaluationOptions options) {
  const std::unique_ptr<Segmenter> segmenter = EvaluationSegmenter(config.semantics);
  options.segmenter = segmenter.get();
  return EvaluateMesh(mesh, dataset, config.input, config.eval, options);
}

bool EvaluateMeshFile(const Config& config, const EvalRequest& request) {
  const Mesh mesh = io::ReadMesh(request.mesh);
  // A mesh without faces has no surface to measure: an RMSE of 0 would read as perfect.
  if (mesh.num_triangles() == 0) throw io::FileError(request.mesh, "mesh has no faces: nothing to evaluate");
  MeshEvaluationOptions options;
  if (!request.out.empty()) {
    options.error_images = request.error_images;
    options.error_image_frames = request.error_frames;
  }
  const MeshEvaluation e = EvaluateAsConfigured(mesh, request.dataset, config, options);
  PrintEvaluation(e);
  // The figures with every frame's, for --json and the report folder alike.
  std::string json;
  if (!request.json.empty() || !request.out.empty()) {
    nlohmann::json j = ToJson(e, /*per_frame=*/true);
    j["mesh"] = request.mesh.string();
    json = j.dump(2) + "\n";
  }
  if (!request.json.empty()) io::WriteFileAtomically(request.json, json);
  if (!request.pictures.empty()) {
    std::filesystem::create_directories(request.pictures);
    for (const auto& f : WriteTopViews(mesh, e, request.pictures)) spdlog::info("wrote {}", f.string());
  }
  if (!request.out.empty()) {
    const std::filesystem::path out(request.out);
    std::filesystem::create_directories(out);
    io::WriteFileAtomically(out / "eval.json", json);
    io::WriteFileAtomically(out / "eval.md", EvaluationMarkdown(e));
    std::vector<std::filesystem::path> written = WriteErrorImages(e, out);
    for (const auto& f : WriteTopViews(mesh, e, out)) written.push_back(f);
    spdlog::info("wrote {} and {} ({} pictures)", (out / "eval.json").string(), (out / "eval.md").string(),
                 written.size());
    if (!request.error_frames.empty() && e.error_images.empty()) {
      spdlog::warn("--error-frames: none of the named frames was evaluated (ids as on disk, with a pose)");
    }
  }
  if (e.frames_with_lidar == 0 && !e.exact_depth) {
    spdlog::error("{}: no frame with a pose and Velodyne or exact depth to compare with",
                  request.dataset.string());
    return false;
  }
  return true;
}

}  // namespace semap::app
