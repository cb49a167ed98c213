#include "app/synth/generate.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <limits>

#include "engine/core/class_map.h"
#include "io/synth/kitti_raw_writer.h"
#include "io/synth/strecha_writer.h"

namespace semap::app {

void GenerateSequence(const sim::SynthOptions& o, const std::filesystem::path& out) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  spdlog::info("synth: preset {}, {} frames, seed {}, {:.1f} m/s, {} turns -> {}",
               sim::ScenePresetName(o.preset), o.num_frames, o.seed, o.speed_mps, o.num_turns, out.string());
  const sim::SyntheticSequence sequence(o);
  const double build_s = std::chrono::duration<double>(Clock::now() - t0).count();
  spdlog::info("scene: {} triangles, {} chunks, BVH {} nodes; drive {:.0f} m with {} turns ({:.2f} s)",
               sequence.scene().num_triangles(), sequence.scene().chunks.size(), sequence.bvh().num_nodes(),
               sequence.trajectory().length_m(), sequence.trajectory().num_turns(), build_s);

  auto last_report = Clock::now();
  const auto t1 = Clock::now();
  const io::SynthWriteSummary summary = io::WriteSyntheticKittiRaw(sequence, out, [&](int done, int total) {
    const auto now = Clock::now();
    if (done == total || now - last_report > std::chrono::seconds(2)) {
      last_report = now;
      const double s = std::chrono::duration<double>(now - t1).count();
      spdlog::info("frame {}/{} ({:.1f} frames/s)", done, total, done / std::max(s, 1e-9));
    }
  });
  const double write_s = std::chrono::duration<double>(Clock::now() - t1).count();
  const double total_s = std::chrono::duration<double>(Clock::now() - t0).count();
  spdlog::info("wrote {} frames to {} in {:.2f} s ({:.2f} frames/s rendering+writing, {:.2f} s total)",
               summary.num_frames, summary.layout.drive_dir.string(), write_s, summary.num_frames / write_s,
               total_s);
  spdlog::info("velodyne: {:.0f} points per scan on average",
               static_cast<double>(summary.lidar_points) / std::max(1, summary.num_frames));
  const ClassMap classes = ClassMap::Cityscapes();
  const auto& h = summary.label_pixels;
  spdlog::info(
      "class composition (pixels of image_02): ground {:.1f}%, wall {:.1f}%, vegetation {:.1f}%, "
      "car {:.1f}%, sky {:.1f}%",
      100.0 * h.RoleShare(classes, ClassRole::kGround), 100.0 * h.RoleShare(classes, ClassRole::kWall),
      100.0 * h.Share(sim::label::kVegetation), 100.0 * h.Share(sim::label::kCar),
      100.0 * h.Share(sim::label::kSky));
}

void GenerateMultiViewSet(const sim::SynthOptions& synth, const sim::MultiViewSetOptions& options,
                          const std::filesystem::path& out) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  spdlog::info(
      "synth: multi-view set (strecha layout), {} views of {}x{} px on a {:.0f} deg arc at {:.1f}-{:.1f} m, "
      "seed {} -> {}",
      options.num_views, options.image_width_px, options.image_height_px, options.arc_deg,
      options.min_distance_m, options.max_distance_m, synth.seed, out.string());
  const sim::MultiViewSet set(synth, options);
  double nearest = std::numeric_limits<double>::infinity(), farthest = 0.0;
  for (int i = 0; i < set.num_views(); ++i) {
    const Eigen::Vector3d c = set.camera(i).world_from_cam.translation();
    const double d = std::hypot(c.x() - set.target().x(), c.y() - set.target().y());
    nearest = std::min(nearest, d);
    farthest = std::max(farthest, d);
  }
  spdlog::info("scene: {} triangles; cameras {:.2f}-{:.2f} m from the object's axis",
               set.scene().num_triangles(), nearest, farthest);
  const io::StrechaWriteSummary summary = io::WriteSyntheticStrecha(set, out);
  const double total_s = std::chrono::duration<double>(Clock::now() - t0).count();
  spdlog::info("wrote {} views to {} in {:.2f} s", summary.num_views, out.string(), total_s);
  const ClassMap classes = ClassMap::Cityscapes();
  const auto& h = summary.label_pixels;
  spdlog::info(
      "class composition (pixels of the views): ground {:.1f}%, wall {:.1f}%, object {:.1f}%, sky {:.1f}%",
      100.0 * h.RoleShare(classes, ClassRole::kGround), 100.0 * h.RoleShare(classes, ClassRole::kWall),
      100.0 * h.Share(sim::kMultiViewObjectLabel), 100.0 * h.Share(sim::label::kSky));
}

}  // namespace semap::app
