// The steps of RenderTopView (engine/eval/top_view.h), each on its own: the projection, the view's extent and
// size, the z-buffer rasterisation of each triangle, the base colours, the shading and the track. Not API.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <opencv2/core.hpp>
#include <vector>

#include "engine/core/mesh.h"
#include "engine/eval/top_view.h"

namespace semap::eval_internal {

// The view's axes: image right, image up and the viewing direction (into the scene), unit and orthogonal.
struct Projection {
  Eigen::Vector3d right, image_up, into;
};

// The axes of the view of `options` (elevation, azimuth) for the world's `up` (non-zero), as top_view.h says.
Projection MakeProjection(const Eigen::Vector3d& up, const TopViewOptions& options);

// The box of the projected triangles' vertices (and of `track`, when the mesh has a triangle): a along
// image right, b along image up, m; [0, 1] × [0, 1] for a mesh without triangles.
struct ViewExtent {
  double a_min = 0.0, a_max = 1.0, b_min = 0.0, b_max = 1.0;
};
ViewExtent ProjectedExtent(const Mesh& mesh, const Projection& projection,
                           const std::vector<Eigen::Vector3d>& track);

// The image's size: `extent` at the scale that fits it into the largest size within the margins (and above
// the legend strip), each side no larger than the content needs. Sets the view's projection fields
// (axes, scale, origin, margin).
struct ViewSize {
  int width = 0;
  int height = 0;  // the mesh's rows, above the legend strip
  int rows = 0;    // the image's rows: height and the legend strip
};
ViewSize FitView(const ViewExtent& extent, const Projection& projection, const TopViewOptions& options,
                 TopView* view);

// Per pixel, the depth along the viewing direction of the nearest surface so far (+∞: none), CV_64FC1, and
// its colour before shading (BGR, CV_32FC3; grey where the mesh has no vertex colours).
struct ZBuffer {
  cv::Mat depth;
  cv::Mat base;
};
// A view of `size` with nothing drawn: no triangle at any pixel, depth +∞, grey base.
ZBuffer EmptyRaster(const ViewSize& size, TopView* view);

// Draws triangle `ti` of `mesh` into the z-buffer and the view's triangle and points images: every pixel
// centre of the mesh's rows inside its projection (edge functions; a centre on an edge belongs to both
// triangles), where it is nearer along `into` than what the pixel holds. With vertex colours, the base
// colour is their barycentric mean. A triangle seen edge-on covers nothing.
void RasteriseTriangle(const Mesh& mesh, std::size_t ti, const Eigen::Vector3d& into, int height,
                       TopView* view, ZBuffer* z);

// The lowest and highest height along `up_unit` of the points the covered pixels see (+∞ and −∞ when none).
struct HeightRange {
  double low = 0.0, high = 0.0;
};
HeightRange CoveredHeights(const TopView& view, const Eigen::Vector3d& up_unit);

// Replaces the base colour of each covered pixel by its height's (kHeight: the range's blue to red) or its
// error bin's (kError: `distance` of its point); nothing for kMesh.
void ColourByHeightOrError(const TopView& view, const TopViewOptions& options,
                           const std::function<double(const Eigen::Vector3d&)>& distance,
                           const Eigen::Vector3d& up_unit, const HeightRange& heights, cv::Mat* base);

// The picture: white background, each covered pixel its base colour shaded flat (two-sided) by its
// triangle's normal against a light from behind the viewer, up and to the right, never brighter than 250.
cv::Mat ShadeImage(const Mesh& mesh, const Projection& projection, const TopView& view, const cv::Mat& base);

// Draws `track` (two points or more) on the view's image as a dark blue line.
void DrawTrack(const std::vector<Eigen::Vector3d>& track, TopView* view);

}  // namespace semap::eval_internal
