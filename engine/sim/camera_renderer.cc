#include "engine/sim/camera_renderer.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "engine/core/check.h"
#include "engine/sim/internal/materials.h"
#include "engine/sim/internal/random.h"

namespace semap::sim {
namespace {

using Eigen::Vector3d;
using Eigen::Vector3f;

// Lighting: a sun (direction in the scene frame, z up) plus sky ambient.
const Vector3d kSunDirection = Vector3d(0.45, 0.30, 0.84).normalized();
constexpr float kAmbient = 0.55f;
constexpr float kSunStrength = 0.55f;
// Grazing surfaces: the pixel footprint grows as 1 / cos(incidence) along the viewing direction only; the
// texture LOD uses an isotropic footprint, so the stretch is capped low to keep the horizontal detail stereo
// needs (vertical aliasing is the same in both rectified images).
constexpr double kMaxFootprintStretch = 1.5;

// Clips a polygon against z >= near (Sutherland-Hodgman, one plane).
int ClipNear(const Vector3d in[3], double near, Vector3d out[4]) {
  int n = 0;
  for (int k = 0; k < 3; ++k) {
    const Vector3d& a = in[k];
    const Vector3d& b = in[(k + 1) % 3];
    const bool ia = a.z() >= near, ib = b.z() >= near;
    if (ia) out[n++] = a;
    if (ia != ib) {
      const double t = (near - a.z()) / (b.z() - a.z());
      out[n++] = a + t * (b - a);
    }
  }
  return n;
}

}  // namespace

CameraRenderer::CameraRenderer(const Scene& scene, const SynthOptions& options)
    : scene_(scene), options_(options) {
  options_.Check();
}

cv::Mat CameraRenderer::Rasterize(const StereoCalibration& cal, const Pose3d& scene_from_cam) const {
  SEMAP_ASSERT(cal.IsValid());
  const int w = cal.width_px, h = cal.height_px;
  cv::Mat ids(h, w, CV_32SC1, cv::Scalar(-1));
  cv::Mat inv_z(h, w, CV_64FC1, cv::Scalar(0.0));
  const Pose3d cam_from_scene = scene_from_cam.inverse();
  const double near = options_.near_m;
  // Frustum side planes through the optical centre (normals pointing inwards), with a one-pixel margin.
  const double ul = (-1.0 - cal.cx_px) / cal.fx_px, ur = (w - cal.cx_px) / cal.fx_px;
  const double vt = (-1.0 - cal.cy_px) / cal.fy_px, vb = (h - cal.cy_px) / cal.fy_px;
  const Vector3d planes[4] = {{1, 0, -ul}, {-1, 0, ur}, {0, 1, -vt}, {0, -1, vb}};

  for (const SceneChunk& chunk : scene_.chunks) {
    // Cull the chunk when its box is entirely behind the near plane or outside one side plane.
    Vector3d corners[8];
    for (int c = 0; c < 8; ++c) {
      corners[c] = cam_from_scene * Vector3d((c & 1) ? chunk.box.max().x() : chunk.box.min().x(),
                                             (c & 2) ? chunk.box.max().y() : chunk.box.min().y(),
                                             (c & 4) ? chunk.box.max().z() : chunk.box.min().z());
    }
    bool culled = std::all_of(corners, corners + 8, [&](const Vector3d& p) { return p.z() < near; });
    for (int k = 0; k < 4 && !culled; ++k) {
      culled = std::all_of(corners, corners + 8, [&](const Vector3d& p) { return planes[k].dot(p) < 0.0; });
    }
    if (culled) continue;
    for (std::uint32_t t = chunk.first; t < chunk.first + chunk.count; ++t) {
      const auto& tri = scene_.triangles[t];
      Vector3d v[3];
      for (int k = 0; k < 3; ++k) v[k] = cam_from_scene * scene_.vertices[tri[k]];
      if (v[0].z() < near && v[1].z() < near && v[2].z() < near) continue;
      Vector3d poly[4];
      const int n = ClipNear(v, near, poly);
      if (n < 3) continue;
      // Screen-space vertices (u, v, 1/z).
      double su[4], sv[4], sz[4];
      for (int k = 0; k < n; ++k) {
        sz[k] = 1.0 / poly[k].z();
        su[k] = cal.fx_px * poly[k].x() * sz[k] + cal.cx_px;
        sv[k] = cal.fy_px * poly[k].y() * sz[k] + cal.cy_px;
      }
      // Fan triangulation of the clipped polygon.
      for (int f = 1; f + 1 < n; ++f) {
        const int a = 0, b = f, c = f + 1;
        const double area = (su[b] - su[a]) * (sv[c] - sv[a]) - (su[c] - su[a]) * (sv[b] - sv[a]);
        if (std::abs(area) < 1e-12) continue;
        const int x0 = std::max(0, static_cast<int>(std::ceil(std::min({su[a], su[b], su[c]}))));
        const int x1 = std::min(w - 1, static_cast<int>(std::floor(std::max({su[a], su[b], su[c]}))));
        const int y0 = std::max(0, static_cast<int>(std::ceil(std::min({sv[a], sv[b], sv[c]}))));
        const int y1 = std::min(h - 1, static_cast<int>(std::floor(std::max({sv[a], sv[b], sv[c]}))));
        if (x0 > x1 || y0 > y1) continue;
        // Barycentric weights as affine functions of the pixel centre (x, y); inclusive edges (no cracks).
        const double inv_area = 1.0 / area;
        const double aa = -(sv[c] - sv[b]) * inv_area, ba = (su[c] - su[b]) * inv_area;
        const double ca = (su[b] * sv[c] - su[c] * sv[b]) * inv_area;
        const double ab = -(sv[a] - sv[c]) * inv_area, bb = (su[a] - su[c]) * inv_area;
        const double cb = (su[c] * sv[a] - su[a] * sv[c]) * inv_area;
        for (int y = y0; y <= y1; ++y) {
          auto* id_row = ids.ptr<std::int32_t>(y);
          auto* z_row = inv_z.ptr<double>(y);
          const double ra = ba * y + ca, rb = bb * y + cb;
          for (int x = x0; x <= x1; ++x) {
            const double wa = ra + aa * x, wb = rb + ab * x;
            const double wc = 1.0 - wa - wb;
            if (wa < 0.0 || wb < 0.0 || wc < 0.0) continue;
            const double iz = wa * sz[a] + wb * sz[b] + wc * sz[c];
            if (iz > z_row[x]) {
              z_row[x] = iz;
              id_row[x] = static_cast<std::int32_t>(t);
            }
          }
        }
      }
    }
  }
  return ids;
}

CameraImage CameraRenderer::RenderGeometry(const StereoCalibration& cal, const Pose3d& scene_from_cam) const {
  const cv::Mat ids = Rasterize(cal, scene_from_cam);
  CameraImage out;
  out.depth_m = cv::Mat(cal.height_px, cal.width_px, CV_32FC1, cv::Scalar(0.0f));
  out.labels = cv::Mat(cal.height_px, cal.width_px, CV_8UC1, cv::Scalar(label::kSky));
  const Eigen::Matrix3d r = scene_from_cam.linear();
  const Vector3d c = scene_from_cam.translation();
  for (int y = 0; y < cal.height_px; ++y) {
    const auto* id_row = ids.ptr<std::int32_t>(y);
    auto* d_row = out.depth_m.ptr<float>(y);
    auto* l_row = out.labels.ptr<std::uint8_t>(y);
    for (int x = 0; x < cal.width_px; ++x) {
      const int t = id_row[x];
      if (t < 0) continue;
      const auto& tri = scene_.triangles[t];
      const Vector3d& v0 = scene_.vertices[tri[0]];
      const Vector3d n = (scene_.vertices[tri[1]] - v0).cross(scene_.vertices[tri[2]] - v0);
      const Vector3d d = r * Vector3d((x - cal.cx_px) / cal.fx_px, (y - cal.cy_px) / cal.fy_px, 1.0);
      const double denom = n.dot(d);
      const double z = std::abs(denom) > 0.0 ? n.dot(v0 - c) / denom : 0.0;
      d_row[x] = z > 0.0 ? static_cast<float>(z) : 0.0f;
      l_row[x] = scene_.labels[t];
    }
  }
  return out;
}

CameraImage CameraRenderer::Render(const StereoCalibration& cal, const Pose3d& scene_from_cam,
                                   const Exposure& exposure) const {
  const cv::Mat ids = Rasterize(cal, scene_from_cam);
  const int w = cal.width_px, h = cal.height_px;
  CameraImage out;
  out.depth_m = cv::Mat(h, w, CV_32FC1, cv::Scalar(0.0f));
  out.labels = cv::Mat(h, w, CV_8UC1, cv::Scalar(label::kSky));
  cv::Mat radiance(h, w, CV_32FC3, cv::Scalar::all(0.0));
  const Eigen::Matrix3d r = scene_from_cam.linear();
  const Vector3d c = scene_from_cam.translation();
  const sim_internal::TextureContext ctx(options_);
  const double r_max2 =
      (std::pow(std::max(cal.cx_px, w - cal.cx_px), 2) + std::pow(std::max(cal.cy_px, h - cal.cy_px), 2));
  for (int y = 0; y < h; ++y) {
    const auto* id_row = ids.ptr<std::int32_t>(y);
    auto* d_row = out.depth_m.ptr<float>(y);
    auto* l_row = out.labels.ptr<std::uint8_t>(y);
    auto* c_row = radiance.ptr<cv::Vec3f>(y);
    for (int x = 0; x < w; ++x) {
      const Vector3d ray_cam((x - cal.cx_px) / cal.fx_px, (y - cal.cy_px) / cal.fy_px, 1.0);
      const Vector3d d = r * ray_cam;
      const double rr = ((x - cal.cx_px) * (x - cal.cx_px) + (y - cal.cy_px) * (y - cal.cy_px)) / r_max2;
      const float vignette = static_cast<float>((1.0 - options_.vignetting * rr) * exposure.gain);
      const int t = id_row[x];
      Vector3f rgb;
      if (t < 0) {
        rgb = sim_internal::SkyColor(ctx, d.normalized());
      } else {
        const auto& tri = scene_.triangles[t];
        const Vector3d& v0 = scene_.vertices[tri[0]];
        const Vector3d n = (scene_.vertices[tri[1]] - v0).cross(scene_.vertices[tri[2]] - v0);
        const double denom = n.dot(d);
        const double z = std::abs(denom) > 0.0 ? n.dot(v0 - c) / denom : 0.0;
        if (z <= 0.0) continue;  // numerically degenerate: leave black and without depth
        d_row[x] = static_cast<float>(z);
        l_row[x] = scene_.labels[t];
        const Vector3d p = c + z * d;
        Vector3f nf = scene_.normals[t];
        const double cos_inc = std::abs(nf.cast<double>().dot(d.normalized()));
        if (nf.cast<double>().dot(d) > 0.0) nf = -nf;  // two-sided: face the camera
        const double footprint =
            z * ray_cam.norm() / cal.fx_px * std::min(kMaxFootprintStretch, 1.0 / std::max(cos_inc, 1e-6));
        const Vector3f albedo =
            sim_internal::Albedo(ctx, scene_.materials[t], scene_.object_ids[t], p, nf, footprint);
        float light = kAmbient * (0.85f + 0.15f * nf.z()) +
                      kSunStrength * std::max(0.0f, nf.dot(kSunDirection.cast<float>()));
        // Contact darkening at the foot of walls and objects.
        if (std::abs(nf.z()) < 0.5f)
          light *= 1.0f - 0.3f * static_cast<float>(std::exp(-std::max(0.0, p.z()) / 0.5));
        rgb = albedo * light;
      }
      rgb *= vignette;
      c_row[x] = cv::Vec3f(rgb.z(), rgb.y(), rgb.x());  // BGR
    }
  }
  if (options_.blur_sigma_px > 0.0) {
    cv::GaussianBlur(radiance, radiance, cv::Size(0, 0), options_.blur_sigma_px, options_.blur_sigma_px,
                     cv::BORDER_REFLECT);
  }
  out.color = cv::Mat(h, w, CV_8UC3);
  const float sigma = static_cast<float>(options_.image_noise_sigma);
  for (int y = 0; y < h; ++y) {
    sim_internal::Rng rng(sim_internal::HashCombine(exposure.noise_seed, static_cast<std::uint64_t>(y)));
    const auto* src = radiance.ptr<cv::Vec3f>(y);
    auto* dst = out.color.ptr<cv::Vec3b>(y);
    for (int x = 0; x < w; ++x) {
      for (int k = 0; k < 3; ++k) {
        const float v = 255.0f * src[x][k] + (sigma > 0.0f ? sigma * rng.FastNormal() : 0.0f);
        dst[x][k] = static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
      }
    }
  }
  return out;
}

}  // namespace semap::sim
