#include "app/run/progress_sink.h"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cstdio>
#include <string>

namespace semap::app {

ProgressSink::ProgressSink(std::int64_t total_frames, double interval_s)
    : total_frames_(total_frames), interval_s_(interval_s), tty_(::isatty(STDERR_FILENO) != 0) {}

void ProgressSink::Print(const FrameStats& s, bool final) {
  std::string stages;
  for (const auto& st : s.stages) {
    if (st.name == "read" || IsStageStep(st.name)) continue;  // steps: in the CSV
    char buf[64];
    std::snprintf(buf, sizeof(buf), " %s %.0fms", st.name.c_str(), st.mean_ms);
    stages += buf;
  }
  char line[512];
  std::snprintf(
      line, sizeof(line),
      "frame %lld/%lld | %.2f fps | latency %.0f ms |%s | points %lld→%lld | mesh %lld tris | dropped "
      "%lld failed %lld | %.0f MB",
      static_cast<long long>(s.frames_processed), static_cast<long long>(total_frames_), s.fps,
      s.latency.published_ms, stages.c_str(), static_cast<long long>(s.points_in),
      static_cast<long long>(s.points_kept), static_cast<long long>(s.mesh_triangles),
      static_cast<long long>(s.frames_dropped), static_cast<long long>(s.frames_failed), s.rss_mb);
  if (tty_) {
    std::fprintf(stderr, "\r\033[K%s%s", line, final ? "\n" : "");
  } else {
    std::fprintf(stderr, "%s\n", line);
  }
  std::fflush(stderr);
}

void ProgressSink::OnFrame(const FrameStats& stats, const MeshDelta&, const std::optional<Pose3d>&) {
  const auto now = std::chrono::steady_clock::now();
  if (std::chrono::duration<double>(now - last_print_).count() < interval_s_) return;
  last_print_ = now;
  Print(stats, false);
}

void ProgressSink::OnFrameError(std::int64_t frame_id, const std::string& stage, const std::string& what) {
  if (tty_) std::fprintf(stderr, "\r\033[K");
  spdlog::warn("frame {} skipped: {} failed: {}", frame_id, stage, what);
}

void ProgressSink::OnFinish(const FrameStats& stats, const MeshDelta&) { Print(stats, true); }

}  // namespace semap::app
