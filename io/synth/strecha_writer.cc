#include "io/synth/strecha_writer.h"

#include <atomic>
#include <cstdio>
#include <mutex>
#include <vector>

#include "engine/core/parallel.h"
#include "io/image/image_files.h"
#include "io/mesh/ply_off.h"
#include "io/sfm/strecha.h"
#include "io/synth/internal/synth_files.h"

namespace semap::io {

namespace fs = std::filesystem;
using synth_internal::CreateFolders;
using synth_internal::WriteText;

std::string StrechaViewStem(int view) {
  char name[16];
  std::snprintf(name, sizeof(name), "%04d", view);
  return name;
}

StrechaWriteSummary WriteSyntheticStrecha(const sim::MultiViewSet& set, const fs::path& root,
                                          const std::function<void(int, int)>& progress) {
  for (const char* folder : {"images", "gt_dense_cameras", "labels", "depth"}) CreateFolders(root / folder);
  const int n = set.num_views();
  const Eigen::Matrix3d& K = set.camera(0).K;
  char k_text[256];
  std::snprintf(k_text, sizeof(k_text), "%.17g %.17g %.17g\n%.17g %.17g %.17g\n%.17g %.17g %.17g\n", K(0, 0),
                K(0, 1), K(0, 2), K(1, 0), K(1, 1), K(1, 2), K(2, 0), K(2, 1), K(2, 2));
  WriteText(root / "images" / "K.txt", k_text);
  for (int i = 0; i < n; ++i) {
    const sim::MultiViewCamera& c = set.camera(i);
    WriteText(root / "gt_dense_cameras" / (StrechaViewStem(i) + ".png.camera"),
              FormatStrechaCamera(c.K, c.world_from_cam, c.calibration.width_px, c.calibration.height_px));
  }
  WriteMeshPly(root / "scene_mesh.ply", set.scene().ToMesh(Pose3d::Identity()),
               PlyEncoding::kBinaryLittleEndian,
               /*double_precision=*/true);

  std::vector<sim::LabelHistogram> histograms(static_cast<size_t>(n));
  std::atomic<int> done{0};
  std::mutex progress_mutex;
  ParallelFor(0, n, 1, [&](int first, int last) {
    for (int i = first; i != last; ++i) {
      const sim::CameraImage image = set.Render(i);
      const std::string png = StrechaViewStem(i) + ".png";
      WritePng(root / "images" / png, image.color);
      WritePng(root / "labels" / png, image.labels);
      WriteDepthPngMm(root / "depth" / png, image.depth_m);
      histograms[static_cast<size_t>(i)].Add(image.labels);
      const int k = ++done;
      if (progress) {
        std::lock_guard<std::mutex> lock(progress_mutex);
        progress(k, n);
      }
    }
  });
  StrechaWriteSummary summary;
  summary.num_views = n;
  for (const auto& h : histograms) summary.label_pixels.Merge(h);
  return summary;
}

}  // namespace semap::io
