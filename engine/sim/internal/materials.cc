#include "engine/sim/internal/materials.h"

#include <algorithm>
#include <cmath>

#include "engine/sim/internal/random.h"

namespace semap::sim::sim_internal {
namespace {

using Eigen::Vector3d;
using Eigen::Vector3f;

float Hash01(std::uint64_t a, std::uint64_t b) {
  return static_cast<float>(HashCombine(a, b) >> 40) / 16777216.0f;
}

// Blends a sharp pattern value towards its mean as the pixel footprint approaches the pattern's feature size.
float Fade(float value, float mean, double feature_m, double footprint_m) {
  const double r = feature_m / (2.0 * footprint_m);
  if (r >= 1.0) return value;
  if (r <= 0.5) return mean;
  const float w = static_cast<float>(2.0 * r - 1.0);
  return w * value + (1.0f - w) * mean;
}

// Coordinates on a wall: along the wall (horizontal) and up.
void WallCoords(const Vector3d& p, const Vector3f& n, double* along, double* up) {
  if (std::abs(n.z()) > 0.7f) {
    *along = p.x();
    *up = p.y();
  } else {
    *along = std::abs(n.x()) > std::abs(n.y()) ? p.y() : p.x();
    *up = p.z();
  }
}

Vector3f ObjectTint(std::uint64_t seed, std::uint32_t id, float amount) {
  return Vector3f(1.0f + amount * (Hash01(seed + 1, id) - 0.5f),
                  1.0f + amount * (Hash01(seed + 2, id) - 0.5f),
                  1.0f + amount * (Hash01(seed + 3, id) - 0.5f));
}

float Asphalt(const TextureContext& c, const Vector3d& p, double fp) {
  const float coarse = Fbm(p.x(), p.y(), 0.0, 6.0, 2, fp, c.seed + 11);
  const float grain = Fbm(p.x(), p.y(), 0.0, 0.25, 4, fp, c.seed + 12);
  float v = 0.30f + 0.16f * (coarse - 0.5f) + 0.40f * (grain - 0.5f);
  // Dashed centre lines: 3 m dash, 3 m gap, 12 cm wide, not inside intersections.
  const double pitch = c.block_pitch_m, hw = 0.5 * c.road_width_m;
  auto off_grid = [&](double x) { return std::abs(x - pitch * std::round(x / pitch)); };
  const double dx = off_grid(p.x()), dy = off_grid(p.y());
  const bool on_x_line = dy < 0.06 && dx > hw && std::fmod(std::abs(p.x()), 6.0) < 3.0;
  const bool on_y_line = dx < 0.06 && dy > hw && std::fmod(std::abs(p.y()), 6.0) < 3.0;
  if (on_x_line || on_y_line) v = Fade(0.8f + 0.1f * (grain - 0.5f), v, 0.12, fp);
  return v;
}

Vector3f Paving(const TextureContext& c, const Vector3d& p, double fp) {
  const double tile = 0.3;
  const double fx = p.x() / tile, fy = p.y() / tile;
  const auto ix = static_cast<std::int64_t>(std::floor(fx)), iy = static_cast<std::int64_t>(std::floor(fy));
  const double gx = std::min(fx - ix, 1.0 + ix - fx), gy = std::min(fy - iy, 1.0 + iy - fy);
  const float tile_v = 0.50f + 0.14f * (LatticeValue(ix, iy, 0, c.seed + 21) - 0.5f);
  const float grain = Fbm(p.x(), p.y(), 0.0, 0.15, 3, fp, c.seed + 22);
  float v = tile_v + 0.35f * (grain - 0.5f);
  const bool grout = std::min(gx, gy) * tile < 0.008;
  v = Fade(grout ? 0.30f : v, 0.48f, 0.03, fp);
  const float stain = Fbm(p.x(), p.y(), 0.0, 3.0, 2, fp, c.seed + 23);
  v *= 0.85f + 0.3f * stain;
  return Vector3f(v, v * 0.98f, v * 0.95f);
}

Vector3f Brick(const TextureContext& c, std::uint32_t id, const Vector3d& p, const Vector3f& n, double fp) {
  double along, up;
  WallCoords(p, n, &along, &up);
  const double bw = 0.25, bh = 0.08, mortar = 0.012;
  const auto row = static_cast<std::int64_t>(std::floor(up / bh));
  const double shifted = along / bw + (row % 2 ? 0.5 : 0.0);
  const auto col = static_cast<std::int64_t>(std::floor(shifted));
  const double ua = (shifted - col) * bw, va = up - row * bh;
  const bool is_mortar = ua < mortar || va < mortar;
  const Vector3f base = Vector3f(0.55f, 0.30f, 0.22f).cwiseProduct(ObjectTint(c.seed, id, 0.35f));
  const float brick_v = 0.8f + 0.4f * LatticeValue(row, col, id, c.seed + 31);
  const float grain = Fbm(p.x(), p.y(), p.z(), 0.05, 2, fp, c.seed + 32);
  const Vector3f brick = base * (brick_v * (0.85f + 0.3f * grain));
  const Vector3f mortar_c(0.62f, 0.60f, 0.55f);
  const Vector3f mean = 0.8f * base + 0.2f * mortar_c;
  const Vector3f sharp = is_mortar ? mortar_c : brick;
  const float w = Fade(1.0f, 0.0f, bh, fp);
  const float dirt = Fbm(p.x(), p.y(), p.z(), 4.0, 2, fp, c.seed + 33);
  return (w * sharp + (1.0f - w) * mean) * (0.8f + 0.35f * dirt);
}

Vector3f Plaster(const TextureContext& c, std::uint32_t id, const Vector3d& p, double fp) {
  // Deliberately weak texture: plain rendered walls are hard for stereo, as in real streets.
  const Vector3f base = Vector3f(0.78f, 0.74f, 0.66f).cwiseProduct(ObjectTint(c.seed + 5, id, 0.3f));
  const float low = Fbm(p.x(), p.y(), p.z(), 3.0, 2, fp, c.seed + 41);
  const float fine = Fbm(p.x(), p.y(), p.z(), 0.3, 4, fp, c.seed + 42);
  return base * (0.88f + 0.18f * low + 0.26f * (fine - 0.5f));
}

Vector3f Leaves(const TextureContext& c, std::uint32_t id, const Vector3d& p, double fp) {
  const Vector3f base = Vector3f(0.20f, 0.34f, 0.12f).cwiseProduct(ObjectTint(c.seed + 7, id, 0.4f));
  const float clumps = Fbm(p.x(), p.y(), p.z(), 0.6, 2, fp, c.seed + 51);
  const float leaves = Fbm(p.x(), p.y(), p.z(), 0.07, 3, fp, c.seed + 52);
  const float v = 0.45f + 0.9f * (clumps - 0.5f) + 1.3f * (leaves - 0.5f);
  return base * std::max(0.15f, 0.6f + v);
}

}  // namespace

Vector3f Albedo(const TextureContext& c, Material m, std::uint32_t id, const Vector3d& p, const Vector3f& n,
                double fp) {
  switch (m) {
    case Material::kAsphalt: {
      const float v = Asphalt(c, p, fp);
      return {v, v, v * 1.03f};
    }
    case Material::kPaving:
      return Paving(c, p, fp);
    case Material::kCurb: {
      const float v = 0.58f + 0.2f * (Fbm(p.x(), p.y(), p.z(), 0.05, 3, fp, c.seed + 61) - 0.5f);
      return {v, v, v};
    }
    case Material::kBrick:
      return Brick(c, id, p, n, fp);
    case Material::kPlaster:
      return Plaster(c, id, p, fp);
    case Material::kGlass: {
      // Reflections of the street: smooth blotches with some detail.
      const float refl = Fbm(p.x(), p.y(), p.z(), 1.5, 4, fp, c.seed + 71);
      const float v = 0.08f + 0.22f * refl;
      return {v * 0.9f, v, v * 1.2f};
    }
    case Material::kWood: {
      double along, up;
      WallCoords(p, n, &along, &up);
      const float grain = Fbm(along * 8.0, up * 0.5, 0.0, 0.12, 3, fp, c.seed + 81);
      const Vector3f base = Vector3f(0.45f, 0.30f, 0.18f).cwiseProduct(ObjectTint(c.seed + 9, id, 0.5f));
      return base * (0.7f + 0.6f * grain);
    }
    case Material::kRoof: {
      const float v = 0.25f + 0.1f * Fbm(p.x(), p.y(), p.z(), 0.3, 3, fp, c.seed + 91);
      return {v * 1.2f, v * 0.9f, v * 0.8f};
    }
    case Material::kLeaves:
      return Leaves(c, id, p, fp);
    case Material::kBark: {
      const float v = 0.22f + 0.15f * Fbm(p.x(), p.y(), p.z() * 0.3, 0.08, 3, fp, c.seed + 101);
      return {v * 1.1f, v * 0.9f, v * 0.7f};
    }
    case Material::kGrass: {
      const float patch = Fbm(p.x(), p.y(), 0.0, 2.0, 2, fp, c.seed + 111);
      const float blades = Fbm(p.x(), p.y(), 0.0, 0.05, 3, fp, c.seed + 112);
      const float v = 0.8f + 0.4f * (patch - 0.5f) + 0.6f * (blades - 0.5f);
      return Vector3f(0.30f, 0.40f, 0.15f) * v;
    }
    case Material::kCarPaint: {
      static constexpr float kPalette[6][3] = {{0.85f, 0.85f, 0.85f}, {0.08f, 0.08f, 0.09f},
                                               {0.55f, 0.56f, 0.58f}, {0.55f, 0.08f, 0.06f},
                                               {0.10f, 0.18f, 0.45f}, {0.30f, 0.30f, 0.32f}};
      const int k = static_cast<int>(Hash01(c.seed + 121, id) * 6.0f) % 6;
      const float v = 0.85f + 0.3f * Fbm(p.x(), p.y(), p.z(), 0.4, 4, fp, c.seed + 122);
      return Vector3f(kPalette[k][0], kPalette[k][1], kPalette[k][2]) * v;
    }
    case Material::kTyre:
      return {0.07f, 0.07f, 0.07f};
    case Material::kMetal: {
      const float v = 0.45f + 0.15f * Fbm(p.x(), p.y(), p.z(), 0.2, 2, fp, c.seed + 131);
      return {v, v, v * 1.05f};
    }
    case Material::kSign: {
      const bool blue = Hash01(c.seed + 141, id) < 0.5f;
      return blue ? Vector3f(0.08f, 0.20f, 0.60f) : Vector3f(0.70f, 0.08f, 0.06f);
    }
    case Material::kCount:
      break;
  }
  return {1.0f, 0.0f, 1.0f};
}

Vector3f SkyColor(const TextureContext& c, const Vector3d& d) {
  const double elev = std::clamp(d.z(), 0.0, 1.0);
  const Vector3f horizon(0.86f, 0.88f, 0.90f), zenith(0.50f, 0.66f, 0.88f);
  const float t = static_cast<float>(std::sqrt(elev));
  const Vector3f sky = (1.0f - t) * horizon + t * zenith;
  const float cloud = Fbm(d.x() * 4.0, d.y() * 4.0, d.z() * 4.0, 1.0, 3, 0.0, c.seed + 151);
  const float amount = std::clamp((cloud - 0.5f) * 3.0f, 0.0f, 1.0f);
  return (1.0f - amount) * sky + amount * Vector3f(0.93f, 0.93f, 0.94f);
}

float LidarReflectance(Material m) {
  switch (m) {
    case Material::kAsphalt:
      return 0.18f;
    case Material::kPaving:
      return 0.30f;
    case Material::kCurb:
      return 0.35f;
    case Material::kBrick:
      return 0.32f;
    case Material::kPlaster:
      return 0.45f;
    case Material::kGlass:
      return 0.05f;
    case Material::kWood:
      return 0.30f;
    case Material::kRoof:
      return 0.20f;
    case Material::kLeaves:
      return 0.38f;
    case Material::kBark:
      return 0.25f;
    case Material::kGrass:
      return 0.40f;
    case Material::kCarPaint:
      return 0.50f;
    case Material::kTyre:
      return 0.04f;
    case Material::kMetal:
      return 0.55f;
    case Material::kSign:
      return 0.95f;
    case Material::kCount:
      break;
  }
  return 0.0f;
}

}  // namespace semap::sim::sim_internal
