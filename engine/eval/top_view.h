// Pictures of a mesh as a user sees it in a viewer, for reports: an orthographic software rendering
// (z-buffer, flat shading, no GPU) seen from above along the world frame's up axis, or obliquely. Surfaces
// that no camera saw straight on (lids over the street, a ceiling of sky) show in them as they do in MeshLab,
// which the camera-side depth metrics cannot.
//
// The view: `up` is the world frame's up direction (for semap's sequences the cameras' −y: +z in KITTI raw's
// IMU world frame, −y in KITTI odometry's first-camera frame). Image right is the horizontal axis e1 (the
// world axis least aligned with up, projected and turned by azimuth_deg about up), image up is e2 = up × e1
// when seen from straight above, so the picture is never mirrored. With elevation_deg < 90 the view tilts
// towards e2 (looking from −e2's side). The scale fits the mesh's projection into the image size.
#pragma once

#include <Eigen/Core>
#include <array>
#include <functional>
#include <opencv2/core.hpp>
#include <vector>

#include "engine/core/mesh.h"

namespace semap {

enum class TopViewColour {
  kMesh,    // the vertex colours (grey when the mesh has none), shaded
  kHeight,  // height along up, from blue (low) to red (high) over the visible heights, shaded
  kError,   // distance to the true surface in the bins of error_bins_m, shaded (needs a distance function)
};

const char* TopViewColourName(TopViewColour colour);

struct TopViewOptions {
  // Largest image size in px: the mesh's projection is fitted into it (the other side shrinks to the
  // content).
  int max_width_px = 1400;
  int max_height_px = 1000;
  // Border around the mesh in px.
  int margin_px = 12;
  // Angle of the view above the horizontal (90 = straight down, orthographic from above).
  double elevation_deg = 90.0;
  // Turn of the view about the up axis (degrees, counter-clockwise seen from above).
  double azimuth_deg = 0.0;
  TopViewColour colour = TopViewColour::kMesh;
  // kError: upper bounds (m) of the green, yellow and orange bins; red beyond the last. The defaults are the
  // bins of the by-area accuracy (engine/eval/surface_metrics.h): τ, near and far.
  std::array<double, 3> error_bins_m{0.2, 0.5, 2.0};
  // Draw a scale bar and (kError, kHeight) a legend in the bottom-left corner.
  bool legend = true;
  void Check() const;
};

struct TopView {
  cv::Mat image;     // CV_8UC3 BGR; white background
  cv::Mat triangle;  // CV_32SC1: index of the triangle seen at each pixel centre, −1 = background
  cv::Mat points;    // CV_64FC3: the world point seen at each pixel centre (undefined on background)
  double metres_per_px = 0.0;
  // Pixel of a world point (sub-pixel), for drawing on the image.
  Eigen::Vector2d ToPixel(const Eigen::Vector3d& p) const;

  // The projection (filled by RenderTopView).
  Eigen::Vector3d right = Eigen::Vector3d::UnitX();
  Eigen::Vector3d image_up = Eigen::Vector3d::UnitY();
  double right_min = 0.0, up_max = 0.0;
  int margin_px = 0;
};

// Renders `mesh` (programmer error if inconsistent) as `options` says; `up` need not be unit (non-zero).
// `distance` (world point → distance to the true surface, thread-safe) is required for kError and unused
// otherwise. An empty mesh gives a small white image with no covered pixel. `track` (e.g. the camera centres)
// is drawn as a dark blue line over the mesh (the view widened to hold it). Throws InvalidOption on bad
// options or a zero up.
TopView RenderTopView(const Mesh& mesh, const Eigen::Vector3d& up, const TopViewOptions& options,
                      const std::function<double(const Eigen::Vector3d&)>& distance = {},
                      const std::vector<Eigen::Vector3d>& track = {});

}  // namespace semap
