// What a run writes and publishes, as its configuration says: shared by `semap run`, `semap map-sfm` and the
// in-process runs of `semap table` / `semap compare`.
#pragma once

#include <memory>
#include <vector>

#include "app/config/config.h"
#include "engine/core/mesh.h"
#include "engine/pipeline/stages.h"
#include "io/output/output_sinks.h"

namespace semap::app {

// The mesh files (always), the per-frame stats (output.frame_stats) and LCM (lcm.enabled, unless left out).
// Made before any work, so that an unusable output folder or LCM URL is reported first. The sinks are called
// from one thread at a time (the pipeline's output thread, or the caller's).
class RunOutputs {
 public:
  enum class Lcm { kAsConfigured, kOff };
  explicit RunOutputs(const Config& config, Lcm lcm = Lcm::kAsConfigured);

  // The sinks, in the order each frame reaches them: mesh files, stats, LCM.
  std::vector<PipelineSink*> sinks();
  // Adds `source`'s figures to each frame's line of the per-frame stats (when they are written).
  void SetFigureSource(io::FrameFigureSource source) {
    if (stats_) stats_->SetFigureSource(std::move(source));
  }
  // The whole mesh, once the run has finished (empty before).
  const Mesh& mesh() const { return mesh_.mesh(); }
  // The whole mesh as the run wrote it, once the run has finished (empty before): mesh.ply read back, or,
  // when the run wrote none (output.mesh_ply off, or its writing failed), the mesh with its coordinates
  // rounded as mesh.ply stores them. Throws io::FileError when mesh.ply cannot be read back.
  Mesh WrittenMesh() const;
  // Logs the files written and, with LCM, the publisher's counters.
  void LogWritten();

 private:
  io::MeshFileSink mesh_;
  std::unique_ptr<io::StatsFileSink> stats_;
  std::unique_ptr<io::LcmSink> lcm_;
};

}  // namespace semap::app
