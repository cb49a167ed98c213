#include "engine/map/internal/depth_votes.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>

#include "engine/core/check.h"
#include "engine/map/internal/vote_weights.h"

namespace semap::map_internal {
namespace {

constexpr int kSamplesPerCell = 5;
// 1 − Φ(6) = 1e-9 is below a quarter of a fixed-point vote unit (kVoteScale = 2^24): a sample this many σ
// before its point is free with weight 1.
constexpr double kFreeSaturationSigmas = 6.0;
// A cell with a vertex this close to the camera plane (or behind it) may contain the camera: its footprint
// is taken as the whole image.
constexpr double kNearPlaneM = 0.05;
// CellsInView's margin around the image (px of the view): a sample reads the pixel it falls in and a facet
// centroid the nearest, so whatever reads the view's depth map lies within half a pixel of the image.
constexpr double kFrustumMarginPx = 1.0;

double TriangleArea2(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  return std::abs((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
}

// Area of the convex hull of four points: each hull point is in two of the four triangles and an inner point
// in none, so the four triangles cover the hull exactly twice (either shape): hull = Σ / 2 (Σ of doubled
// areas / 4).
double HullArea(const std::array<Eigen::Vector2d, 4>& p) {
  return 0.25 * (TriangleArea2(p[0], p[1], p[2]) + TriangleArea2(p[0], p[1], p[3]) +
                 TriangleArea2(p[0], p[2], p[3]) + TriangleArea2(p[1], p[2], p[3]));
}

// Whether the origin lies inside the tetrahedron (the same side of each face as the opposite vertex).
bool ContainsOrigin(const std::array<Eigen::Vector3d, 4>& t) {
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3d& a = t[(i + 1) % 4];
    const Eigen::Vector3d n = (t[(i + 2) % 4] - a).cross(t[(i + 3) % 4] - a);
    if (n.dot(t[i] - a) * n.dot(-a) < 0.0) return false;
  }
  return true;
}

}  // namespace

PixelQuad QuadAround(const DepthView& v, const Eigen::Vector2d& uv) {
  PixelQuad quad;
  const int u0 = int(std::floor(uv.x())), v0 = int(std::floor(uv.y()));
  if (!(u0 >= 0 && v0 >= 0 && u0 + 1 < v.depth_m.cols && v0 + 1 < v.depth_m.rows)) return quad;
  quad.inside = true;
  quad.depth_m = {v.depth_m.at<float>(v0, u0), v.depth_m.at<float>(v0, u0 + 1),
                  v.depth_m.at<float>(v0 + 1, u0), v.depth_m.at<float>(v0 + 1, u0 + 1)};
  quad.a = uv.x() - u0;
  quad.b = uv.y() - v0;
  return quad;
}

double PixelQuad::InterpolatedDepth() const {
  const double inverse =
      (1 - b) * ((1 - a) / depth_m[0] + a / depth_m[1]) + b * ((1 - a) / depth_m[2] + a / depth_m[3]);
  return 1.0 / inverse;
}

VotingView::VotingView(std::shared_ptr<const DepthView> v) : view(std::move(v)) {
  SEMAP_ASSERT(view && !view->empty(), "a voting view needs a depth map");
  const Pose3d cam_from_world = view->world_from_cam.inverse();
  cam_from_world_rotation = cam_from_world.linear();
  cam_from_world_translation = cam_from_world.translation();
  image_area_px = double(view->depth_m.cols) * double(view->depth_m.rows);
  focal_baseline_m_px =
      view->intrinsics.fx_px * std::sqrt(view->rays_per_pixel) * view->intrinsics.baseline_m;
}

VoteIncrement VoteCell(const std::array<Eigen::Vector3d, 4>& vertices_world, const VotingView& view,
                       const DepthVoteGeometry& geometry) {
  const DepthView& v = *view.view;
  const StereoCalibration& k = v.intrinsics;
  std::array<Eigen::Vector3d, 4> cam;
  bool near = false;
  double max_z = -1.0;
  for (int i = 0; i < 4; ++i) {
    cam[i] = view.ToCamera(vertices_world[i]);
    near = near || cam[i].z() < kNearPlaneM;
    max_z = std::max(max_z, cam[i].z());
  }
  if (max_z <= 0.0) return {};  // wholly behind the camera
  if (near && ContainsOrigin(cam)) {
    // Every ray of the view starts in this cell, far before its point: one full free vote per ray (the
    // view's valid pixels, counted as the whole image).
    return {QuantiseWeight(view.image_area_px * v.rays_per_pixel), 0, true};
  }
  double footprint_px = view.image_area_px;
  if (!near) {
    std::array<Eigen::Vector2d, 4> uv;
    Eigen::Vector2d lo(1e300, 1e300), hi(-1e300, -1e300);
    for (int i = 0; i < 4; ++i) {
      uv[i] = k.Project(cam[i]);
      lo = lo.cwiseMin(uv[i]);
      hi = hi.cwiseMax(uv[i]);
    }
    if (hi.x() < 0.0 || hi.y() < 0.0 || lo.x() >= k.width_px || lo.y() >= k.height_px) return {};
    footprint_px = std::min(HullArea(uv), view.image_area_px);
  }
  const Eigen::Vector3d centroid = 0.25 * (cam[0] + cam[1] + cam[2] + cam[3]);
  // The samples' depths are read first, all five before any is used: the reads miss the cache more often
  // than not, and issued together they wait for memory once instead of five times in a row (200 urban
  // frames, PS, half resolution: bench/results/frame-rate.md, "What changed (200 urban frames, PS, half
  // resolution unless said)").
  std::array<Eigen::Vector3d, kSamplesPerCell> samples;
  std::array<float, kSamplesPerCell> depths;
  for (int s = 0; s < kSamplesPerCell; ++s) {
    const Eigen::Vector3d& x = samples[s] =
        s == 0 ? centroid : Eigen::Vector3d(0.5 * (centroid + cam[s - 1]));
    if (x.z() <= 0.0) {
      depths[s] = 0.0f;
      continue;
    }
    const Eigen::Vector2d uv = k.Project(x);
    depths[s] = v.At(uv.x(), uv.y());
  }
  double free = 0.0, matter = 0.0;
  for (int s = 0; s < kSamplesPerCell; ++s) {
    const Eigen::Vector3d& x = samples[s];
    const float depth = depths[s];
    if (depth == 0.0f) continue;
    const double range = x.norm();
    if (depth == kFreeToFarRange) {
      if (x.z() >= v.max_depth_m) continue;  // beyond the far range: unknown
      free += GaussianComplement(range * (v.max_depth_m / x.z() - 1.0), geometry.ray.sigma_free_m);
      continue;
    }
    const double depth_m = depth;
    const double d = range * (depth_m / x.z() - 1.0);  // the sample is d before the pixel's point
    if (geometry.disparity_sigma_px == 0.0) {          // exact points: the paper's weights
      if (d > geometry.free_saturation_m) {
        free += 1.0;  // the Gaussian term is below a quarter of a fixed-point unit
      } else if (d > 0.0) {
        free += GaussianComplement(d, geometry.ray.sigma_free_m);
      } else if (-d <= geometry.ray.extension_m) {
        matter += GaussianComplement(-d, geometry.ray.sigma_matter_m);
      }
      continue;
    }
    // The pixel's point is uncertain along the ray by its own σ (see the header): the sample is free with the
    // probability that the true surface lies beyond it, Φ(d/σ), matter otherwise, out to the extension plus
    // matter_behind_sigmas σ behind the point.
    // hypot of two positive lengths in metres, without std::hypot's care for overflow (3 % of a run's CPU).
    const double sigma_along_m = view.DepthSigma(depth_m, geometry.disparity_sigma_px) * range / x.z();
    const double sigma_m =
        std::sqrt(sigma_along_m * sigma_along_m + geometry.ray.sigma_free_m * geometry.ray.sigma_free_m);
    if (d > kFreeSaturationSigmas * sigma_m) {
      free += 1.0;  // 1 − Φ is below a quarter of a fixed-point unit
    } else if (d >= -(geometry.ray.extension_m + geometry.matter_behind_sigmas * sigma_m)) {
      const double p_free = StandardNormalCdf(d / sigma_m);
      free += p_free;
      matter += 1.0 - p_free;
    }
  }
  const double rays_per_sample = footprint_px * v.rays_per_pixel / kSamplesPerCell;
  return {QuantiseWeight(free * rays_per_sample), QuantiseWeight(matter * rays_per_sample), true};
}

namespace {

// The depth the view's map gives at continuous pixel coordinates `uv` (pixel centres at integers): 1/z
// interpolated bilinearly where the four pixels around have depth (1/z is linear in the image over a plane,
// so a plane's depth comes back exactly), else the nearest pixel's. 0 or kFreeToFarRange as the map says.
double DepthAt(const DepthView& v, const Eigen::Vector2d& uv) {
  const PixelQuad quad = QuadAround(v, uv);
  if (quad.AllValid()) return quad.InterpolatedDepth();
  return v.At(std::round(uv.x()), std::round(uv.y()));
}

// Whether the points the view saw through the points halfway from a facet's centroid to its corners (camera
// frame) lie within the tolerance of its plane, where the view has depth there
// (map.seen_halfway_min_radius_m).
bool SeenHalfway(const DepthView& v, const VotingView& view, const DepthVoteGeometry& geometry,
                 const Eigen::Vector3d& centroid, std::initializer_list<const Eigen::Vector3d*> corners,
                 const Eigen::Vector3d& unit_normal) {
  const Eigen::Vector3d& on_plane = **corners.begin();
  for (const Eigen::Vector3d* corner : corners) {
    const Eigen::Vector3d halfway = 0.5 * (centroid + *corner);
    if (halfway.z() <= 0.0) continue;
    const double depth_m = DepthAt(v, v.intrinsics.Project(halfway));
    if (depth_m == 0.0 || depth_m == kFreeToFarRange) continue;
    const Eigen::Vector3d seen_point = halfway * (depth_m / halfway.z());
    const double tolerance_m =
        geometry.ray.extension_m +
        geometry.seen_noise_sigmas * view.DepthSigma(depth_m, geometry.disparity_sigma_px);
    if (std::abs(unit_normal.dot(seen_point - on_plane)) > tolerance_m) return false;
  }
  return true;
}

}  // namespace

std::uint8_t SeenFacets(const std::array<Eigen::Vector3d, 4>& vertices_world, std::uint8_t candidates,
                        const VotingView& view, const DepthVoteGeometry& geometry) {
  const DepthView& v = *view.view;
  std::array<Eigen::Vector3d, 4> cam;
  for (int i = 0; i < 4; ++i) cam[i] = view.ToCamera(vertices_world[i]);
  std::uint8_t seen = 0;
  for (int i = 0; i < 4; ++i) {
    if (!((candidates >> i) & 1)) continue;
    const Eigen::Vector3d& a = cam[(i + 1) % 4];
    const Eigen::Vector3d& b = cam[(i + 2) % 4];
    const Eigen::Vector3d& c = cam[(i + 3) % 4];
    // The point the view saw along the centroid's ray, against the facet: near its plane (measured across the
    // plane, so that a facet seen at a grazing angle is not judged by the steep depth change along it) and
    // near the facet itself. The centroid only: a facet spanning from a seen surface to a guess is seen near
    // its seen end (halfway samples let 3.7 % of the area lie beyond 2 m of the truth instead of 1.7 %).
    const Eigen::Vector3d centroid = (a + b + c) / 3.0;
    if (centroid.z() <= 0.0) continue;
    const double depth_m = DepthAt(v, v.intrinsics.Project(centroid));
    if (depth_m == 0.0 || depth_m == kFreeToFarRange) continue;
    const Eigen::Vector3d normal = (b - a).cross(c - a);
    if (normal.squaredNorm() == 0.0) continue;
    const Eigen::Vector3d unit_normal = normal.normalized();
    const double radius_m = std::sqrt(
        std::max({(a - centroid).squaredNorm(), (b - centroid).squaredNorm(), (c - centroid).squaredNorm()}));
    const Eigen::Vector3d seen_point = centroid * (depth_m / centroid.z());
    const double noise_m = view.DepthSigma(depth_m, geometry.disparity_sigma_px);
    const double tolerance_m = geometry.ray.extension_m + geometry.seen_noise_sigmas * noise_m;
    if (std::abs(unit_normal.dot(seen_point - a)) <= tolerance_m &&
        (seen_point - centroid).norm() <= radius_m + tolerance_m &&
        (geometry.seen_halfway_min_radius_m <= 0.0 || radius_m <= geometry.seen_halfway_min_radius_m ||
         SeenHalfway(v, view, geometry, centroid, {&a, &b, &c}, unit_normal))) {
      seen |= std::uint8_t(1u << i);
    }
  }
  return seen;
}

bool CellsInView(const Delaunay& dt, const VotingView& view, std::uint32_t visit_mark,
                 std::vector<CellHandle>* cells) {
  cells->clear();
  if (dt.dimension() < 3) return false;
  const CellHandle start = dt.locate(ToPoint(view.view->world_from_cam.translation()));
  if (dt.is_infinite(start)) return false;
  // The frustum widened by kFrustumMarginPx: the cone of the points in front of the camera that project
  // inside the image. Each side is a half-space through the camera centre (u ≥ −margin is
  // fx·x + (cx + margin)·z ≥ 0), so a cell whose four vertices all lie beyond one of them (or behind the
  // camera) is wholly outside.
  const StereoCalibration& k = view.view->intrinsics;
  const double margin = kFrustumMarginPx;
  const double width = view.view->depth_m.cols, height = view.view->depth_m.rows;
  const auto outcode = [&](const Point& p) {
    const Eigen::Vector3d x = view.ToCamera(ToEigen(p));
    unsigned code = x.z() <= 0.0 ? 1u : 0u;
    if (k.fx_px * x.x() + (k.cx_px + margin) * x.z() < 0.0) code |= 2u;
    if (k.fx_px * x.x() + (k.cx_px - width - margin) * x.z() > 0.0) code |= 4u;
    if (k.fy_px * x.y() + (k.cy_px + margin) * x.z() < 0.0) code |= 8u;
    if (k.fy_px * x.y() + (k.cy_px - height - margin) * x.z() > 0.0) code |= 16u;
    return code;
  };
  const auto outside = [&](CellHandle c) {
    unsigned all = 31u;
    for (int i = 0; i < 4 && all != 0; ++i) all &= outcode(c->vertex(i)->point());
    return all != 0;
  };
  cells->push_back(start);
  start->info().stamp = visit_mark;
  for (std::size_t q = 0; q < cells->size(); ++q) {
    const CellHandle c = (*cells)[q];
    for (int i = 0; i < 4; ++i) {
      const CellHandle n = c->neighbor(i);
      if (n->info().stamp == visit_mark) continue;
      n->info().stamp = visit_mark;
      if (!dt.is_infinite(n) && !outside(n)) cells->push_back(n);
    }
  }
  return true;
}

}  // namespace semap::map_internal
