#include "tools/view/view_sources.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>

#include "engine/eval/surface_metrics.h"
#include "io/file_error.h"
#include "io/frame_source.h"
#include "io/lcm/lcm_publisher.h"
#include "io/lcm/mesh_blocks.h"
#include "io/mesh/ply_off.h"
#include "semap_lcm/camera_pose_t.hpp"
#include "semap_lcm/frame_stats_t.hpp"

namespace semap::tools::view {
namespace {

// frames.jsonl of a run folder: one StatsPoint per line; a line that does not parse ends the reading (a run
// killed mid-line), with a warning.
std::vector<StatsPoint> ReadFrameStats(const std::filesystem::path& path) {
  std::vector<StatsPoint> out;
  std::ifstream in(path);
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const auto j = nlohmann::json::parse(line, nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded() || !j.is_object()) {
      spdlog::warn("{}: line {} is not a JSON object; statistics read up to it", path.string(), line_no);
      break;
    }
    StatsPoint s;
    s.frame_id = j.value("frame_id", std::int64_t{0});
    s.elapsed_s = j.value("elapsed_s", 0.0);
    s.fps = j.value("fps", 0.0);
    s.triangles = j.value("mesh_triangles", std::int64_t{0});
    s.vertices = j.value("map_vertices", std::int64_t{0});
    out.push_back(s);
  }
  return out;
}

// The left camera of every frame of the sequence that has a pose (reads the frames: about a second for KITTI
// odometry 04's 51 frames).
std::vector<PosePoint> ReadTrajectory(const std::filesystem::path& sequence) {
  std::vector<PosePoint> out;
  auto source = io::OpenFrameSource(sequence, io::FrameSourceOptions{});
  while (true) {
    std::optional<Frame> frame;
    try {
      frame = source->Next();
    } catch (const io::FrameError& e) {
      spdlog::warn("{}: frame {} skipped for the trajectory: {}", sequence.string(), e.frame_id(), e.what());
      continue;
    }
    if (!frame) break;
    if (!frame->world_from_cam) continue;
    PosePoint p;
    p.frame_id = frame->id;
    p.position_m = frame->world_from_cam->translation();
    p.world_from_cam = Eigen::Quaterniond(frame->world_from_cam->rotation());
    out.push_back(p);
  }
  return out;
}

}  // namespace

std::unique_ptr<ViewModel> LoadFinished(const std::filesystem::path& path,
                                        const FinishedViewOptions& options) {
  SourceInfo info;
  info.up = options.up;
  std::filesystem::path mesh_path = path;
  std::vector<StatsPoint> stats;
  if (std::filesystem::is_directory(path)) {
    info.kind = "run";
    mesh_path = path / "mesh.ply";
    if (!std::filesystem::exists(mesh_path)) mesh_path = path / "mesh.off";
    if (!std::filesystem::exists(mesh_path)) {
      throw io::FileError(path,
                          "holds neither mesh.ply nor mesh.off: not a `semap run` output folder (give the "
                          "folder of --out, or a mesh file)");
    }
    if (std::filesystem::exists(path / "frames.jsonl")) stats = ReadFrameStats(path / "frames.jsonl");
  } else if (std::filesystem::is_regular_file(path)) {
    info.kind = "mesh";
    if (path.extension() != ".ply" && path.extension() != ".off") {
      throw io::FileError(path, "is neither a .ply nor an .off mesh, nor a run folder");
    }
  } else {
    throw io::FileError(path, "no such run folder or mesh file");
  }
  info.name = path.string();
  const Mesh mesh = io::ReadMesh(mesh_path);

  ClassMap class_map = ClassMap::Cityscapes();
  std::vector<PosePoint> poses;
  std::string truth = options.truth;
  if (!options.sequence.empty()) {
    const io::SequenceInfo seq = io::DescribeDataset(options.sequence, io::FrameSourceOptions{});
    class_map = seq.class_map;
    if (seq.has_poses) poses = ReadTrajectory(options.sequence);
    if (truth.empty() && std::filesystem::is_regular_file(seq.root / "scene_mesh.ply")) {
      truth = (seq.root / "scene_mesh.ply").string();
    }
  }
  std::vector<float> error_m;
  if (!truth.empty()) {
    const Mesh truth_mesh = io::ReadMesh(truth);
    if (truth_mesh.num_triangles() == 0) throw io::FileError(truth, "the true surface has no triangle");
    const SurfaceDistance distance(truth_mesh);
    error_m.reserve(mesh.num_vertices());
    for (const Eigen::Vector3d& v : mesh.vertices) error_m.push_back(static_cast<float>(distance(v)));
    info.has_error = true;
    info.error_source = truth;
  }
  auto model = std::make_unique<ViewModel>(info, class_map);
  const std::int64_t last_frame = stats.empty() ? -1 : stats.back().frame_id;
  model->SetMesh(std::make_shared<const std::string>(
                     EncodeMeshMessage(mesh, last_frame, error_m.empty() ? nullptr : &error_m)),
                 static_cast<std::int64_t>(mesh.num_triangles()),
                 static_cast<std::int64_t>(mesh.num_vertices()));
  for (const StatsPoint& s : stats) model->AddStats(s);
  for (const PosePoint& p : poses) model->AddPose(p);
  model->SetStatus(mesh_path.string() + ": " + std::to_string(mesh.num_triangles()) + " triangles, " +
                   std::to_string(mesh.num_vertices()) + " vertices" +
                   (poses.empty() ? "" : ", " + std::to_string(poses.size()) + " camera poses"));
  return model;
}

std::unique_ptr<ViewModel> LiveSource::MakeModel(const LiveViewOptions& options) {
  SourceInfo info;
  info.kind = "live";
  info.name = options.url + " (channels " + options.channel_prefix + "*)";
  info.up = options.up;
  auto model = std::make_unique<ViewModel>(info, ClassMap::Cityscapes());
  model->SetStatus("waiting for a run on " + options.url);
  return model;
}

LiveSource::LiveSource(const LiveViewOptions& options, ViewModel* model)
    : options_(options), model_(model), lcm_(std::make_unique<lcm::LCM>(options.url)) {
  if (!lcm_->good()) throw io::LcmError("cannot open LCM URL '" + options.url + "'");
  thread_ = std::thread([this] { Loop(); });
}

LiveSource::~LiveSource() {
  stop_ = true;
  thread_.join();
}

void LiveSource::Loop() {
  // Everything below lives on this thread: the subscriptions' handlers run inside handleTimeout.
  struct State {
    LiveSource* self = nullptr;
    io::MeshBlockAssembler assembler;
    std::int64_t run_id = 0;
    bool have_run = false;
    std::int64_t frame_id = -1;
    bool mesh_changed = false;
    std::int64_t invalid = 0;
    // A message of a new run: the page starts over.
    void SeeRun(std::int64_t id) {
      if (have_run && id == run_id) return;
      if (have_run) self->model_->Reset();
      have_run = true;
      run_id = id;
      frame_id = -1;
    }
  };
  State state;
  state.self = this;
  const std::string& prefix = options_.channel_prefix;
  lcm_->subscribeFunction<State*>(
      prefix + "MESH_BLOCK",
      [](const lcm::ReceiveBuffer* rbuf, const std::string& channel, State* s) {
        std::string error;
        const auto msg = io::DecodeMeshBlock(rbuf->data, rbuf->data_size, &error);
        if (!msg) {
          if (s->invalid++ < 5) spdlog::warn("{}: invalid mesh block skipped: {}", channel, error);
          return;
        }
        s->SeeRun(msg->run_id);
        s->frame_id = std::max(s->frame_id, msg->frame_id);
        s->assembler.Add(*msg);
        s->mesh_changed = true;
      },
      &state);
  lcm_->subscribeFunction<State*>(
      prefix + "MESH_END",
      [](const lcm::ReceiveBuffer* rbuf, const std::string& channel, State* s) {
        std::string error;
        const auto msg = io::DecodeMeshEnd(rbuf->data, rbuf->data_size, &error);
        if (!msg) {
          if (s->invalid++ < 5) spdlog::warn("{}: invalid mesh index skipped: {}", channel, error);
          return;
        }
        s->SeeRun(msg->run_id);
        s->assembler.Add(*msg);
        s->mesh_changed = true;
      },
      &state);
  lcm_->subscribeFunction<State*>(
      prefix + "FRAME_STATS",
      [](const lcm::ReceiveBuffer* rbuf, const std::string&, State* s) {
        semap_lcm::frame_stats_t msg;
        if (msg.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) < 0) return;
        s->self->model_->AddStats({msg.frame_id, 0.0, msg.fps, msg.mesh_triangles, msg.map_vertices});
      },
      &state);
  lcm_->subscribeFunction<State*>(
      prefix + "CAMERA_POSE",
      [](const lcm::ReceiveBuffer* rbuf, const std::string&, State* s) {
        semap_lcm::camera_pose_t msg;
        if (msg.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) < 0) return;
        PosePoint p;
        p.frame_id = msg.frame_id;
        p.position_m = Eigen::Vector3d(msg.position[0], msg.position[1], msg.position[2]);
        p.world_from_cam = Eigen::Quaterniond(msg.orientation[0], msg.orientation[1], msg.orientation[2],
                                              msg.orientation[3]);
        s->self->model_->AddPose(p);
      },
      &state);

  using Clock = std::chrono::steady_clock;
  const auto interval = std::chrono::duration<double>(options_.mesh_interval_s);
  auto last_sent = Clock::now() - std::chrono::hours(1);
  const auto start = Clock::now();
  while (!stop_) {
    if (lcm_->handleTimeout(50) < 0) {
      model_->SetStatus("LCM receive failed on " + options_.url + "; the view is frozen");
      break;
    }
    const auto& c = state.assembler.counters();
    if (state.mesh_changed && (Clock::now() - last_sent >= interval || c.run_ended)) {
      const Mesh mesh = state.assembler.ToMesh();
      model_->SetMesh(std::make_shared<const std::string>(EncodeMeshMessage(mesh, state.frame_id, nullptr)),
                      static_cast<std::int64_t>(mesh.num_triangles()),
                      static_cast<std::int64_t>(mesh.num_vertices()));
      state.mesh_changed = false;
      last_sent = Clock::now();
      const std::string run = "run " + std::to_string(state.run_id) + ": ";
      if (c.run_ended) {
        const auto missing = state.assembler.Missing();
        model_->SetStatus(
            run + "ended, " + std::to_string(mesh.num_triangles()) + " triangles" +
            (missing.empty() ? "" : " (" + std::to_string(missing.size()) + " blocks lacking)"));
      } else {
        model_->SetStatus(run + "frame " + std::to_string(state.frame_id) + ", " +
                          std::to_string(mesh.num_triangles()) + " triangles");
      }
    } else if (!state.have_run) {
      const double waited_s = std::chrono::duration<double>(Clock::now() - start).count();
      if (waited_s > 5.0) {
        model_->SetStatus("no run seen on " + options_.url + " for " +
                          std::to_string(static_cast<int>(waited_s)) +
                          " s (is `semap run --lcm-url` publishing there, with the same channel prefix?)");
      }
    }
  }
}

}  // namespace semap::tools::view
