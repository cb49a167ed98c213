// A generated calibrated multi-view set with exact geometry, in the manner of EPFL fountain-P11: an ornate,
// textured object (a fountain: a basin with relief, pillars and a sculpted top) in front of a wall on a
// paved ground plane, seen by views on an arc around it, every view looking at it, the distance to it
// varying along the arc. Each view renders colour, exact depth and labels (engine/sim/camera_renderer.h).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "engine/core/calibration.h"
#include "engine/core/options.h"
#include "engine/sim/camera_renderer.h"
#include "engine/sim/scene.h"
#include "engine/sim/synth_options.h"

namespace semap::sim {

// The label of the object's surfaces: pole, a class the simplification keeps (Cityscapes' 20 classes have
// none for a monument). The ground is sidewalk, the wall building.
inline constexpr Label kMultiViewObjectLabel = label::kPole;

// The set's composition and cameras. The world frame is the scene frame: z up, the ground at z = 0, the
// object's foot at the origin, the wall behind it along +y.
struct MultiViewSetOptions {
  int num_views = 11;
  int image_width_px = 768;
  int image_height_px = 512;
  double fx_px = 690.0;
  double fy_px = 691.0;
  double cx_px = 383.5;
  double cy_px = 255.5;
  double min_distance_m = 4.0;
  double max_distance_m = 10.0;
  double arc_deg = 90.0;
  double camera_height_m = 1.6;
  double wall_distance_m = 3.0;

  // Each field's key, text and valid values, declared once here (engine/core/options.h); Check() tests the
  // values against them.
  template <typename Visitor>
  void Describe(Visitor& v) {
    v.Field("num_views", &num_views, "views of the set, on the arc", In(1, 1000));
    v.Field("image_width_px", &image_width_px, "image width (px)", In(16, 8192));
    v.Field("image_height_px", &image_height_px, "image height (px)", In(16, 8192));
    // fountain-P11's focal length scaled to the width (1379.74 px at 1536 px).
    v.Field("fx_px", &fx_px, "focal length x (px)", Above(0));
    v.Field("fy_px", &fy_px, "focal length y (px)", Above(0));
    v.Field("cx_px", &cx_px, "principal point x (px)");
    v.Field("cy_px", &cy_px, "principal point y (px)");
    v.Field("min_distance_m", &min_distance_m,
            "camera centre to the object's axis at the arc's ends, m (the object's half width and then some)",
            AtLeast(2.5));
    v.Field("max_distance_m", &max_distance_m,
            "camera centre to the object's axis at the middle of the arc, m; at least min_distance_m");
    v.Field("arc_deg", &arc_deg,
            "angle the arc spans around the object's axis, deg (the cameras stay in front of the wall)",
            In(0, 150));
    v.Field("camera_height_m", &camera_height_m,
            "camera height above the ground, m (each view varies it by up to ±0.15 m)", In(0.5, 5));
    v.Field("wall_distance_m", &wall_distance_m,
            "from the object's axis to the front of the wall, m (behind the object)", AtLeast(2));
  }

  // The same field of view at `factor` (> 0) times the image size: sizes and focal lengths scaled, the
  // principal point moved with the pixel centres (integer coordinates), c' = (c + 0.5) · factor − 0.5.
  void ScaleImage(double factor);

  // Throws InvalidOption naming the field (e.g. "num_views") when a value is out of range.
  void Check() const;
};

// One view: its intrinsics (a pinhole without skew) and its pose.
struct MultiViewCamera {
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  Pose3d world_from_cam = Pose3d::Identity();  // x right, y down, z forward
  StereoCalibration calibration;               // K as the renderer takes it (baseline unused, 1 m)
  double exposure_gain = 1.0;
};

// Owns the scene and its renderer. Deterministic for (synth, options): `synth` gives the seed and the
// photometric settings (noise, blur, vignetting, exposure variation, near plane), `options` the layout.
// Immutable after construction; Render() is const and thread-safe.
class MultiViewSet {
 public:
  // Throws InvalidOption when either options object is invalid.
  MultiViewSet(const SynthOptions& synth, const MultiViewSetOptions& options);
  ~MultiViewSet();
  MultiViewSet(const MultiViewSet&) = delete;
  MultiViewSet& operator=(const MultiViewSet&) = delete;

  const MultiViewSetOptions& options() const { return options_; }
  const Scene& scene() const { return *scene_; }
  int num_views() const { return static_cast<int>(cameras_.size()); }
  const MultiViewCamera& camera(int view) const;
  // The point on the object's axis the views look at (each at a point within 0.1 m of it).
  const Eigen::Vector3d& target() const { return target_; }

  // Colour, exact depth (camera z) and labels of a view.
  CameraImage Render(int view) const;

 private:
  SynthOptions synth_;
  MultiViewSetOptions options_;
  std::unique_ptr<Scene> scene_;
  std::unique_ptr<CameraRenderer> renderer_;
  std::vector<MultiViewCamera> cameras_;
  Eigen::Vector3d target_ = Eigen::Vector3d::Zero();
};

// The set's scene alone: ground, wall and object (labels above), deterministic in `seed`.
Scene BuildMultiViewScene(const MultiViewSetOptions& options, std::uint64_t seed);

}  // namespace semap::sim
