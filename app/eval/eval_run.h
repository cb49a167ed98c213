// `semap eval`: a mesh file against the sequence it was built from, printed and optionally written as a
// report.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "app/config/config.h"
#include "app/eval/mesh_evaluation.h"
#include "engine/core/mesh.h"

namespace semap::app {

struct EvalRequest {
  std::filesystem::path dataset;   // the sequence the mesh was built from
  std::filesystem::path mesh;      // .ply or .off
  std::filesystem::path json;      // when not empty: the figures (per frame too) as JSON
  std::filesystem::path pictures;  // when not empty: top_view.png (and top_view_error.png) in this folder
  // When not empty: the report folder (eval.json, eval.md, error images, pictures from above).
  std::filesystem::path out;
  int error_images = 3;                    // with `out`: error images of this many frames, spread out
  std::vector<std::int64_t> error_frames;  // with `out`: of these frames (ids on disk) instead
};

// `mesh` against `dataset` as `semap eval` measures it: the frames config.input selects, config.eval's
// filters, and, with semantics.source: enet, ENet labelling the frames that have no label images (the static
// scene, the by-class breakdown), as the run labelled them. `options` adds the error images; its segmenter is
// set here. Throws what EvaluateMesh throws.
MeshEvaluation EvaluateAsConfigured(const Mesh& mesh, const std::filesystem::path& dataset,
                                    const Config& config, MeshEvaluationOptions options = {});

// Reads the mesh (io::FileError for a mesh without faces: nothing to measure), evaluates it with
// config.input and config.eval, prints the totals and writes what `request` asks for. Returns false when no
// frame had a pose with Velodyne or exact depth to compare with (logged).
bool EvaluateMeshFile(const Config& config, const EvalRequest& request);

}  // namespace semap::app
