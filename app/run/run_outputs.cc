#include "app/run/run_outputs.h"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "io/mesh/ply_off.h"

namespace semap::app {

RunOutputs::RunOutputs(const Config& config, Lcm lcm) : mesh_(config.output) {
  if (config.output.frame_stats) stats_ = std::make_unique<io::StatsFileSink>(config.output);
  if (lcm == Lcm::kAsConfigured && config.lcm.enabled) {
    lcm_ = std::make_unique<io::LcmSink>(std::make_unique<io::LcmPublisher>(config.lcm));
  }
}

std::vector<PipelineSink*> RunOutputs::sinks() {
  std::vector<PipelineSink*> all{&mesh_};
  if (stats_) all.push_back(stats_.get());
  if (lcm_) all.push_back(lcm_.get());
  return all;
}

Mesh RunOutputs::WrittenMesh() const {
  const auto& written = mesh_.written();
  const auto ply = std::find_if(written.begin(), written.end(),
                                [](const std::filesystem::path& f) { return f.filename() == "mesh.ply"; });
  return ply != written.end() ? io::ReadMeshPly(*ply) : io::AsStoredInPly(mesh_.mesh());
}

void RunOutputs::LogWritten() {
  if (!mesh_.spill_error().empty()) {
    spdlog::warn("{}; the finalised mesh was kept in memory from then on", mesh_.spill_error());
  }
  for (const auto& f : mesh_.written()) spdlog::info("wrote {}", f.string());
  if (lcm_) {
    const auto c = lcm_->publisher().counters();
    spdlog::info("LCM: {} mesh messages, {} other, {} send failures, {} dropped", c.mesh_messages,
                 c.other_messages, c.send_failures, c.dropped);
  }
}

}  // namespace semap::app
