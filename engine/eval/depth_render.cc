#include "engine/eval/depth_render.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "engine/core/check.h"

namespace semap {

void DepthRenderOptions::Check() const { SEMAP_CHECK_OPTION(near_m > 0.0, "near_m", near_m, "must be > 0"); }

namespace {

// Keeps the part of polygon `in` (camera frame) with z >= near (Sutherland–Hodgman on one plane).
std::vector<Eigen::Vector3d> ClipNear(const std::array<Eigen::Vector3d, 3>& in, double near) {
  std::vector<Eigen::Vector3d> out;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d& a = in[i];
    const Eigen::Vector3d& b = in[(i + 1) % 3];
    const bool a_in = a.z() >= near;
    const bool b_in = b.z() >= near;
    if (a_in) out.push_back(a);
    if (a_in != b_in) {
      const double t = (near - a.z()) / (b.z() - a.z());
      out.push_back(a + t * (b - a));
    }
  }
  return out;
}

// Rasterises one camera-frame triangle (all z >= near) into `depth`: pixel centres inside the projected
// triangle get the interpolated z when nearer, and `index` in `triangle` (when given).
void RasteriseTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                       const StereoCalibration& cal, int index, cv::Mat* depth, cv::Mat* triangle) {
  // OpenCV/KITTI convention: the centre of pixel column x is at u = x.
  const Eigen::Vector2d pa = cal.Project(a), pb = cal.Project(b), pc = cal.Project(c);
  const double area = (pb.x() - pa.x()) * (pc.y() - pa.y()) - (pb.y() - pa.y()) * (pc.x() - pa.x());
  if (std::abs(area) < 1e-12) return;  // degenerate or edge-on
  const int x0 = std::max(0, static_cast<int>(std::ceil(std::min({pa.x(), pb.x(), pc.x()}))));
  const int x1 = std::min(cal.width_px - 1, static_cast<int>(std::floor(std::max({pa.x(), pb.x(), pc.x()}))));
  const int y0 = std::max(0, static_cast<int>(std::ceil(std::min({pa.y(), pb.y(), pc.y()}))));
  const int y1 =
      std::min(cal.height_px - 1, static_cast<int>(std::floor(std::max({pa.y(), pb.y(), pc.y()}))));
  const double inv_za = 1.0 / a.z(), inv_zb = 1.0 / b.z(), inv_zc = 1.0 / c.z();
  for (int y = y0; y <= y1; ++y) {
    float* row = depth->ptr<float>(y);
    int* ids = triangle ? triangle->ptr<int>(y) : nullptr;
    for (int x = x0; x <= x1; ++x) {
      // Barycentric coordinates of the pixel centre in screen space.
      const double wa = ((pb.x() - x) * (pc.y() - y) - (pb.y() - y) * (pc.x() - x)) / area;
      const double wb = ((pc.x() - x) * (pa.y() - y) - (pc.y() - y) * (pa.x() - x)) / area;
      const double wc = 1.0 - wa - wb;
      constexpr double kEdgeEps = -1e-9;  // pixel centres exactly on a shared edge belong to both triangles
      if (wa < kEdgeEps || wb < kEdgeEps || wc < kEdgeEps) continue;
      const double z = 1.0 / (wa * inv_za + wb * inv_zb + wc * inv_zc);  // 1/z is affine in screen space
      float& d = row[x];
      if (d == 0.0f || z < d) {
        d = static_cast<float>(z);
        if (ids) ids[x] = index;
      }
    }
  }
}

// Renders into `depth` and, when given, `triangle` (both allocated by the caller).
void Render(const Mesh& mesh, const StereoCalibration& calibration, const Pose3d& world_from_cam,
            const DepthRenderOptions& options, cv::Mat* depth, cv::Mat* triangle) {
  options.Check();
  SEMAP_ASSERT(calibration.IsValid());
  SEMAP_ASSERT(mesh.IsConsistent());
  const Pose3d cam_from_world = world_from_cam.inverse();
  std::vector<Eigen::Vector3d> cam_vertices(mesh.vertices.size());
  for (size_t i = 0; i < mesh.vertices.size(); ++i) cam_vertices[i] = cam_from_world * mesh.vertices[i];
  for (size_t i = 0; i < mesh.triangles.size(); ++i) {
    const auto& t = mesh.triangles[i];
    const std::array<Eigen::Vector3d, 3> tri = {cam_vertices[t[0]], cam_vertices[t[1]], cam_vertices[t[2]]};
    if (tri[0].z() < options.near_m && tri[1].z() < options.near_m && tri[2].z() < options.near_m) continue;
    const auto poly = ClipNear(tri, options.near_m);
    for (size_t k = 1; k + 1 < poly.size(); ++k) {
      RasteriseTriangle(poly[0], poly[k], poly[k + 1], calibration, static_cast<int>(i), depth, triangle);
    }
  }
}

}  // namespace

cv::Mat RenderDepth(const Mesh& mesh, const StereoCalibration& calibration, const Pose3d& world_from_cam,
                    const DepthRenderOptions& options) {
  cv::Mat depth(calibration.height_px, calibration.width_px, CV_32F, cv::Scalar(0.0f));
  Render(mesh, calibration, world_from_cam, options, &depth, nullptr);
  return depth;
}

DepthAndTriangles RenderDepthAndTriangles(const Mesh& mesh, const StereoCalibration& calibration,
                                          const Pose3d& world_from_cam, const DepthRenderOptions& options) {
  DepthAndTriangles r;
  r.depth = cv::Mat(calibration.height_px, calibration.width_px, CV_32F, cv::Scalar(0.0f));
  r.triangle = cv::Mat(calibration.height_px, calibration.width_px, CV_32S, cv::Scalar(-1));
  Render(mesh, calibration, world_from_cam, options, &r.depth, &r.triangle);
  return r;
}

}  // namespace semap
