// Where `semap view` takes what it shows from: a finished run folder or a mesh file (loaded once), or a live
// run's LCM messages (mesh blocks rebuilt by io/lcm's MeshBlockAssembler, frame statistics, camera poses).
#pragma once

#include <atomic>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>

#include "tools/view/view_model.h"

namespace lcm {
class LCM;
}

namespace semap::tools::view {

struct FinishedViewOptions {
  // Dataset the run read (optional): the camera trajectory is taken from its poses, its class map gives the
  // palette, and a generated sequence's scene_mesh.ply the per-vertex error.
  std::string sequence;
  // True surface to colour the error against (overrides the sequence's scene_mesh.ply).
  std::string truth;
  // World up axis passed to the page: auto, x, -x, y, -y, z, -z.
  std::string up = "auto";
};

// A run folder (mesh.ply or mesh.off, frames.jsonl) or a mesh file (.ply / .off), loaded into a model.
// Throws io::FileError naming the file when there is no mesh to show or a file is malformed.
std::unique_ptr<ViewModel> LoadFinished(const std::filesystem::path& path,
                                        const FinishedViewOptions& options);

struct LiveViewOptions {
  // LCM URL the run publishes to (`semap run --lcm-url`).
  std::string url = "udpm://239.255.76.67:7667?ttl=0";
  // Channels <prefix>MESH_BLOCK, MESH_END, FRAME_STATS, CAMERA_POSE.
  std::string channel_prefix = "SEMAP_";
  // The mesh is rebuilt and sent to the pages at most this often while blocks arrive, seconds.
  double mesh_interval_s = 0.25;
  // World up axis passed to the page.
  std::string up = "auto";
};

// Subscribes in its own thread until destroyed; writes into the model (thread-safe). A new run on the same
// channels (another run id) starts the mesh, trajectory and statistics over.
class LiveSource {
 public:
  // Throws io::LcmError naming the URL when it cannot be opened.
  LiveSource(const LiveViewOptions& options, ViewModel* model);
  ~LiveSource();
  LiveSource(const LiveSource&) = delete;
  LiveSource& operator=(const LiveSource&) = delete;

  // The model of a live view before any message: Cityscapes palette, no error.
  static std::unique_ptr<ViewModel> MakeModel(const LiveViewOptions& options);

 private:
  void Loop();

  LiveViewOptions options_;
  ViewModel* model_;
  std::unique_ptr<lcm::LCM> lcm_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace semap::tools::view
