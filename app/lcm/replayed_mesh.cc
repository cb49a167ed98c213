#include "app/lcm/replayed_mesh.h"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "io/mesh/ply_off.h"

namespace semap::app {
namespace {

constexpr size_t kMaxListed = 20;

std::string RunState(const io::MeshReplay& r) {
  if (r.blocks.run_ended) return "run ended";
  if (r.blocks.closing_seen && r.index_complete) return "run closing, every block of its index held";
  return "run not seen to end";
}

}  // namespace

bool WriteReplayedMesh(const std::string& source, const io::MeshReplay& r, const std::filesystem::path& out,
                       bool ascii) {
  if (!r.log_problem.empty()) {
    spdlog::warn("{}: {} ({} bytes skipped)", source, r.log_problem, r.damaged_bytes);
  }
  if (r.skipped > 0) {
    spdlog::warn("{}: {} mesh messages skipped as invalid, e.g.:", source, r.skipped);
    for (const auto& why : r.skipped_reasons) spdlog::warn("  {}", why);
  }
  if (r.mesh.num_triangles() == 0) {
    spdlog::error("{}: no triangle rebuilt ({} events, {} mesh messages, {} blocks lacking); nothing written",
                  source, r.events, r.mesh_events, r.missing.size());
    return false;
  }
  if (out.extension() == ".off") {
    io::WriteMeshOff(out, r.mesh);
  } else {
    io::WriteMeshPly(out, r.mesh, ascii ? io::PlyEncoding::kAscii : io::PlyEncoding::kBinaryLittleEndian);
  }
  spdlog::info(
      "{}: {} events over {:.1f} s, {} mesh messages ({} bytes, largest event {} bytes), {} duplicates, "
      "{} deltas without their base, {} → {} vertices, {} triangles → {}",
      source, r.events, r.duration_s, r.mesh_events, r.mesh_bytes, r.largest_message, r.blocks.duplicates,
      r.blocks.deltas_without_base, RunState(r), r.mesh.num_vertices(), r.mesh.num_triangles(), out.string());
  if (r.converged_after_s >= 0)
    spdlog::info("late subscriber converged {:.2f} s after joining", r.converged_after_s);
  if (r.blocks.runs > 1)
    spdlog::warn("{}: {} runs in the log; the mesh is the last run's", source, r.blocks.runs);
  if (r.missing.empty()) return true;
  spdlog::error("{}: the mesh is incomplete: {} blocks lacking:", source, r.missing.size());
  for (size_t i = 0; i < std::min(kMaxListed, r.missing.size()); ++i) spdlog::error("  {}", r.missing[i]);
  if (r.missing.size() > kMaxListed) spdlog::error("  ... and {} more", r.missing.size() - kMaxListed);
  return false;
}

}  // namespace semap::app
