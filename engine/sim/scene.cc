// The grid city: streets along x = i * pitch and y = j * pitch, one block per cell, content by preset.
#include "engine/sim/scene.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "engine/core/check.h"
#include "engine/sim/internal/random.h"
#include "engine/sim/internal/scene_builder.h"
#include "engine/sim/trajectory.h"

namespace semap::sim {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;
using sim_internal::Rng;
using sim_internal::SceneBuilder;
using sim_internal::Surface;

// Side of the square cells used to group triangles for view-frustum culling.
constexpr double kChunkSizeM = 16.0;
// Longest side of a ground quad (keeps chunks local).
constexpr double kGroundTileM = 12.0;
// Spacing of path samples when deciding which blocks to build.
constexpr double kPathSampleM = 4.0;

// What lines the streets, per preset.
struct Mix {
  double building = 0.0, fence = 0.0;  // probabilities of a frontage segment's type; the rest is park
  double street_tree = 0.0;            // probability of a tree per sidewalk slot
  double car = 0.0;                    // probability of a parked car per slot
  double min_height_m = 0.0, max_height_m = 0.0;
  double max_setback_m = 0.0;  // front gardens
  int park_trees_per_10m = 0;
};

Mix MixOf(ScenePreset p) {
  switch (p) {
    case ScenePreset::kUrban:
      return {0.82, 0.08, 0.06, 0.30, 10.0, 24.0, 0.0, 1};
    case ScenePreset::kVegetated:
      return {0.12, 0.30, 0.80, 0.75, 6.0, 10.0, 6.0, 3};
    case ScenePreset::kMixed:
      return {0.45, 0.20, 0.40, 0.50, 8.0, 18.0, 3.0, 2};
  }
  return {};
}

struct Side {
  Vector3d a;  // lot corner where the side starts (z = curb height)
  Vector3d u;  // along the side
  Vector3d n;  // outwards, towards the street
  double length = 0.0;
};

class CityBuilder {
 public:
  CityBuilder(const SynthOptions& o, Scene* scene) : o_(o), mix_(MixOf(o.preset)), b_(scene) {}

  void GroundCell(int i, int j) {
    const double p = o_.block_pitch_m, hw = 0.5 * o_.road_width_m;
    const Surface road{label::kRoad, Material::kAsphalt, 0};
    GroundRect(i * p - hw, (i + 1) * p - hw, j * p - hw, j * p + hw, 0.0, road);
    GroundRect(i * p - hw, i * p + hw, j * p + hw, (j + 1) * p - hw, 0.0, road);
  }

  // Sidewalk ring, curbs and lot ground of block (i, j); `detailed` adds the frontage and street furniture.
  void Block(int i, int j, bool detailed) {
    Rng rng(sim_internal::HashCombine(
        sim_internal::HashCombine(o_.seed, 0x626c6f63ULL),
        sim_internal::HashCombine(static_cast<std::uint64_t>(i), static_cast<std::uint64_t>(j))));
    const double p = o_.block_pitch_m, hw = 0.5 * o_.road_width_m, sw = o_.sidewalk_width_m,
                 h = o_.curb_height_m;
    const double x0 = i * p + hw, x1 = (i + 1) * p - hw, y0 = j * p + hw, y1 = (j + 1) * p - hw;
    const Surface walk{label::kSidewalk, Material::kPaving, 0}, curb{label::kSidewalk, Material::kCurb, 0};
    GroundRect(x0, x1, y0, y0 + sw, h, walk);
    GroundRect(x0, x1, y1 - sw, y1, h, walk);
    GroundRect(x0, x0 + sw, y0 + sw, y1 - sw, h, walk);
    GroundRect(x1 - sw, x1, y0 + sw, y1 - sw, h, walk);
    GroundRect(x0 + sw, x1 - sw, y0 + sw, y1 - sw, h, {label::kTerrain, Material::kGrass, 0});
    if (h > 0.0) {
      CurbFace({x0, y0}, {x1, y0}, {0, -1}, curb);
      CurbFace({x1, y0}, {x1, y1}, {1, 0}, curb);
      CurbFace({x1, y1}, {x0, y1}, {0, 1}, curb);
      CurbFace({x0, y1}, {x0, y0}, {-1, 0}, curb);
    }
    const double lx0 = x0 + sw, lx1 = x1 - sw, ly0 = y0 + sw, ly1 = y1 - sw;
    const Side sides[4] = {{{lx0, ly0, h}, {1, 0, 0}, {0, -1, 0}, lx1 - lx0},
                           {{lx1, ly0, h}, {0, 1, 0}, {1, 0, 0}, ly1 - ly0},
                           {{lx1, ly1, h}, {-1, 0, 0}, {0, 1, 0}, lx1 - lx0},
                           {{lx0, ly1, h}, {0, -1, 0}, {-1, 0, 0}, ly1 - ly0}};
    for (const Side& s : sides) {
      if (detailed) {
        Frontage(s, rng);
        Furniture(s, rng);
      } else if (rng.Bernoulli(mix_.building)) {
        PlainBuilding(s, rng);
      }
    }
  }

 private:
  void GroundRect(double x0, double x1, double y0, double y1, double z, const Surface& s) {
    const int nx = std::max(1, static_cast<int>(std::ceil((x1 - x0) / kGroundTileM)));
    const int ny = std::max(1, static_cast<int>(std::ceil((y1 - y0) / kGroundTileM)));
    for (int a = 0; a < nx; ++a) {
      for (int c = 0; c < ny; ++c) {
        const double xa = x0 + (x1 - x0) * a / nx, xb = x0 + (x1 - x0) * (a + 1) / nx;
        const double ya = y0 + (y1 - y0) * c / ny, yb = y0 + (y1 - y0) * (c + 1) / ny;
        b_.AddQuad({xa, ya, z}, {xb, ya, z}, {xb, yb, z}, {xa, yb, z}, Vector3d::UnitZ(), s);
      }
    }
  }

  void CurbFace(const Vector2d& a, const Vector2d& c, const Vector2d& n, const Surface& s) {
    const double h = o_.curb_height_m;
    b_.AddQuad({a.x(), a.y(), 0.0}, {c.x(), c.y(), 0.0}, {c.x(), c.y(), h}, {a.x(), a.y(), h},
               {n.x(), n.y(), 0}, s);
  }

  // Splits a side into segments of buildings, fences with gardens, and parks.
  void Frontage(const Side& s, Rng& rng) {
    double t = 0.0;
    while (t < s.length - 1.0) {
      const double r = rng.Uniform();
      double len = std::min(s.length - t, rng.Uniform(12.0, 30.0));
      if (s.length - t - len < 6.0) len = s.length - t;  // no slivers at the end
      if (r < mix_.building) {
        Building(s, t, t + len, rng);
      } else if (r < mix_.building + mix_.fence) {
        Fence(s, t, t + len, rng);
        Park(s, t, t + len, rng, /*behind_fence=*/true);
      } else {
        Park(s, t, t + len, rng, /*behind_fence=*/false);
      }
      t += len;
    }
  }

  Vector3d At(const Side& s, double along, double inward, double z) const {
    Vector3d p = s.a + along * s.u - inward * s.n;
    p.z() = z;
    return p;
  }

  void Building(const Side& s, double t0, double t1, Rng& rng) {
    const double setback = rng.Uniform(0.0, mix_.max_setback_m);
    const double depth = rng.Uniform(9.0, 15.0);
    const double height = rng.Uniform(mix_.min_height_m, mix_.max_height_m);
    const double z0 = o_.curb_height_m, z1 = z0 + height;
    const bool brick = rng.Bernoulli(0.5);
    const Surface wall{label::kBuilding, brick ? Material::kBrick : Material::kPlaster, b_.NewObjectId()};
    // Side, back walls and roof.
    const Vector3d f0 = At(s, t0, setback, z0), f1 = At(s, t1, setback, z0);
    const Vector3d b0 = At(s, t0, setback + depth, z0), b1 = At(s, t1, setback + depth, z0);
    const Vector3d up(0, 0, height);
    b_.AddQuad(f0, b0, b0 + up, f0 + up, -s.u, wall);
    b_.AddQuad(f1, b1, b1 + up, f1 + up, s.u, wall);
    b_.AddQuad(b0, b1, b1 + up, b0 + up, -s.n, wall);
    b_.AddQuad(f0 + up, f1 + up, b1 + up, b0 + up, Vector3d::UnitZ(),
               {label::kBuilding, Material::kRoof, wall.object_id});
    Facade(s, t0, t1, setback, z0, z1, wall, rng);
    if (setback > 1.5) Hedge(s, t0, t1, rng);
  }

  // The street façade: a grid of floors x bays, each bay a recessed window (or a door on the ground floor).
  void Facade(const Side& s, double t0, double t1, double inward, double z0, double z1, const Surface& wall,
              Rng& rng) {
    const double floor_h = rng.Uniform(2.9, 3.6), bay_w = rng.Uniform(2.4, 3.4);
    const double win_w = bay_w * rng.Uniform(0.4, 0.6), win_h = floor_h * rng.Uniform(0.4, 0.55);
    const double sill = floor_h * 0.3, recess = rng.Uniform(0.10, 0.25);
    const int floors = std::max(1, static_cast<int>((z1 - z0) / floor_h));
    const int bays = std::max(1, static_cast<int>((t1 - t0) / bay_w));
    const double bw = (t1 - t0) / bays, fh = (z1 - z0) / floors;
    const Surface glass{label::kBuilding, Material::kGlass, wall.object_id};
    const Surface door{label::kBuilding, Material::kWood, wall.object_id};
    auto q = [&](double a0, double a1, double h0, double h1, double in, const Surface& sf) {
      b_.AddQuad(At(s, a0, in, h0), At(s, a1, in, h0), At(s, a1, in, h1), At(s, a0, in, h1), s.n, sf);
    };
    // Reveal faces of an opening (a0..a1) x (h0..h1), from the wall plane back to the recess.
    auto reveal = [&](double a0, double a1, double h0, double h1) {
      const double w0 = inward, w1 = inward + recess;
      b_.AddQuad(At(s, a0, w0, h0), At(s, a0, w1, h0), At(s, a0, w1, h1), At(s, a0, w0, h1), s.u, wall);
      b_.AddQuad(At(s, a1, w0, h0), At(s, a1, w1, h0), At(s, a1, w1, h1), At(s, a1, w0, h1), -s.u, wall);
      b_.AddQuad(At(s, a0, w0, h1), At(s, a1, w0, h1), At(s, a1, w1, h1), At(s, a0, w1, h1),
                 -Vector3d::UnitZ(), wall);
      b_.AddQuad(At(s, a0, w0, h0), At(s, a1, w0, h0), At(s, a1, w1, h0), At(s, a0, w1, h0),
                 Vector3d::UnitZ(), wall);
    };
    for (int f = 0; f < floors; ++f) {
      for (int k = 0; k < bays; ++k) {
        const double a0 = t0 + k * bw, a1 = a0 + bw, c0 = z0 + f * fh, c1 = c0 + fh;
        const bool is_door = f == 0 && rng.Bernoulli(0.25);
        const double ow = is_door ? std::min(1.2, 0.8 * bw) : win_w;
        const double oa0 = 0.5 * (a0 + a1) - 0.5 * ow, oa1 = oa0 + ow;
        const double oh0 = is_door ? c0 : c0 + sill,
                     oh1 = is_door ? c0 + std::min(2.3, 0.85 * fh) : oh0 + win_h;
        if (rng.Bernoulli(0.06) && !is_door) {  // a blank bay
          q(a0, a1, c0, c1, inward, wall);
          continue;
        }
        if (oh0 > c0) q(a0, a1, c0, oh0, inward, wall);
        q(a0, a1, oh1, c1, inward, wall);
        q(a0, oa0, oh0, oh1, inward, wall);
        q(oa1, a1, oh0, oh1, inward, wall);
        reveal(oa0, oa1, oh0, oh1);
        q(oa0, oa1, oh0, oh1, inward + recess, is_door ? door : glass);
      }
    }
  }

  void PlainBuilding(const Side& s, Rng& rng) {
    const double height = rng.Uniform(mix_.min_height_m, mix_.max_height_m);
    const double depth = rng.Uniform(9.0, 15.0);
    const Vector3d c = At(s, 0.5 * s.length, 0.5 * depth, o_.curb_height_m + 0.5 * height);
    const Vector3d half(0.5 * s.length * std::abs(s.u.x()) + 0.5 * depth * std::abs(s.n.x()),
                        0.5 * s.length * std::abs(s.u.y()) + 0.5 * depth * std::abs(s.n.y()), 0.5 * height);
    b_.AddBox(c, half, 0.0, {label::kBuilding, Material::kPlaster, b_.NewObjectId()});
  }

  void Fence(const Side& s, double t0, double t1, Rng& rng) {
    const double in = 0.2, height = rng.Uniform(1.0, 1.8), z0 = o_.curb_height_m;
    const Surface post{label::kFence, Material::kWood, b_.NewObjectId()};
    const bool boards = rng.Bernoulli(0.6);
    for (double t = t0 + 0.3; t < t1 - 0.2; t += 2.0) {
      b_.AddBox(At(s, t, in, z0 + 0.5 * height + 0.05), {0.05, 0.05, 0.5 * height + 0.05}, 0.0, post);
    }
    // Two rails, then boards (wooden fence) or thin vertical bars (metal fence) with gaps.
    for (double rz : {0.2 * height, 0.85 * height}) {
      const Vector3d a = At(s, t0 + 0.3, in + 0.06, z0 + rz), c = At(s, t1 - 0.3, in + 0.06, z0 + rz);
      b_.AddQuad(a, c, c + Vector3d(0, 0, 0.08), a + Vector3d(0, 0, 0.08), s.n, post);
    }
    const double step = boards ? 0.15 : 0.12, width = boards ? 0.10 : 0.025;
    const Surface bar{label::kFence, boards ? Material::kWood : Material::kMetal, post.object_id};
    for (double t = t0 + 0.35; t + width < t1 - 0.3; t += step) {
      const Vector3d a = At(s, t, in - 0.02, z0 + 0.05), c = At(s, t + width, in - 0.02, z0 + 0.05);
      const Vector3d up(0, 0, height - 0.05);
      b_.AddQuad(a, c, c + up, a + up, s.n, bar);
      b_.AddQuad(a, c, c + up, a + up, -s.n, bar);
    }
  }

  void Hedge(const Side& s, double t0, double t1, Rng& rng) {
    for (double t = t0 + 1.0; t < t1 - 0.5; t += rng.Uniform(1.5, 3.0))
      Bush(At(s, t, 0.8, o_.curb_height_m), rng);
  }

  void Park(const Side& s, double t0, double t1, Rng& rng, bool behind_fence) {
    const double len = t1 - t0;
    const int trees =
        static_cast<int>(std::round(mix_.park_trees_per_10m * len / 10.0 * rng.Uniform(0.6, 1.4)));
    for (int k = 0; k < trees; ++k)
      Tree(At(s, rng.Uniform(t0 + 1.0, t1 - 1.0), rng.Uniform(2.5, 14.0), 0), rng);
    const int bushes = static_cast<int>(len / (behind_fence ? 2.5 : 5.0));
    for (int k = 0; k < bushes; ++k)
      Bush(At(s, rng.Uniform(t0 + 0.5, t1 - 0.5), rng.Uniform(1.0, 6.0), 0), rng);
  }

  void Tree(Vector3d base, Rng& rng) {
    base.z() = o_.curb_height_m;
    const std::uint32_t id = b_.NewObjectId();
    const double trunk_h = rng.Uniform(1.8, 3.5), trunk_r = rng.Uniform(0.10, 0.22);
    const double crown_r = rng.Uniform(1.6, 3.6);
    b_.AddCylinder(base, Vector3d::UnitZ(), trunk_r, trunk_h + 0.5 * crown_r, 8,
                   {label::kVegetation, Material::kBark, id});
    const Surface leaves{label::kVegetation, Material::kLeaves, id};
    const int blobs = rng.UniformInt(1, 3);
    for (int k = 0; k < blobs; ++k) {
      const double r = crown_r * (k == 0 ? 1.0 : rng.Uniform(0.5, 0.8));
      const Vector3d off = k == 0
                               ? Vector3d(0, 0, 0)
                               : Vector3d(rng.Uniform(-0.6, 0.6) * crown_r, rng.Uniform(-0.6, 0.6) * crown_r,
                                          rng.Uniform(-0.2, 0.5) * crown_r);
      b_.AddBlob(base + Vector3d(0, 0, trunk_h + crown_r * 0.8) + off,
                 Vector3d(r, r, r * rng.Uniform(0.8, 1.2)), 2, 0.35, rng.NextU64(), leaves);
    }
  }

  void Bush(Vector3d base, Rng& rng) {
    base.z() = o_.curb_height_m;
    const double r = rng.Uniform(0.5, 1.3);
    b_.AddBlob(base + Vector3d(0, 0, 0.5 * r), Vector3d(r * rng.Uniform(1.0, 1.6), r, 0.8 * r), 2, 0.4,
               rng.NextU64(), {label::kVegetation, Material::kLeaves, b_.NewObjectId()});
  }

  // Poles, signs and street trees on the sidewalk, parked cars on the road along the curb.
  void Furniture(const Side& s, Rng& rng) {
    const double sw = o_.sidewalk_width_m, z0 = o_.curb_height_m;
    for (double t = rng.Uniform(2.0, 10.0); t < s.length - 1.0; t += rng.Uniform(18.0, 32.0)) {
      const Vector3d base = At(s, t, -(sw - 0.45), z0);
      const double h = rng.Uniform(4.5, 8.0);
      const std::uint32_t id = b_.NewObjectId();
      b_.AddCylinder(base, Vector3d::UnitZ(), 0.07, h, 8, {label::kPole, Material::kMetal, id});
      if (rng.Bernoulli(0.4)) {
        const Vector3d c = base + Vector3d(0, 0, rng.Uniform(2.2, 2.9)) + 0.09 * s.n;
        const double yaw = std::atan2(s.n.y(), s.n.x()) + M_PI / 2 + rng.Uniform(-0.3, 0.3);
        b_.AddBox(c, {0.35, 0.015, 0.35}, yaw, {label::kTrafficSign, Material::kSign, b_.NewObjectId()});
      }
    }
    for (double t = 4.0; t < s.length - 2.0; t += rng.Uniform(7.0, 11.0)) {
      if (rng.Bernoulli(mix_.street_tree)) Tree(At(s, t, -0.5 * sw, z0), rng);
    }
    // Cars: slots along the curb line, clear of the intersections.
    const double margin = o_.turn_radius_m + 1.0;
    for (double t = -sw + margin; t < s.length + sw - margin - 4.5; t += rng.Uniform(5.5, 7.0)) {
      if (!rng.Bernoulli(mix_.car)) continue;
      Car(At(s, t + 2.2, -(sw + 1.05), 0.0), std::atan2(s.u.y(), s.u.x()) + (rng.Bernoulli(0.5) ? 0.0 : M_PI),
          rng);
    }
  }

  void Car(const Vector3d& ground, double yaw, Rng& rng) {
    const std::uint32_t id = b_.NewObjectId();
    const Surface paint{label::kCar, Material::kCarPaint, id}, tyre{label::kCar, Material::kTyre, id},
        glass{label::kCar, Material::kGlass, id};
    const double len = rng.Uniform(3.8, 4.7), wid = rng.Uniform(1.65, 1.85), body_h = rng.Uniform(0.65, 0.8);
    const Eigen::Matrix3d r = Eigen::AngleAxisd(yaw, Vector3d::UnitZ()).toRotationMatrix();
    b_.AddRoundedBox(ground + Vector3d(0, 0, 0.3 + 0.5 * body_h), {0.5 * len, 0.5 * wid, 0.5 * body_h}, yaw,
                     6.0, 2, paint);
    const double cab_len = len * rng.Uniform(0.45, 0.55);
    b_.AddRoundedBox(ground + r * Vector3d(-0.08 * len, 0, 0) + Vector3d(0, 0, 0.3 + body_h + 0.2),
                     {0.5 * cab_len, 0.46 * wid, 0.32}, yaw, 4.0, 2, glass);
    for (int k = 0; k < 4; ++k) {
      const double ax = (k & 1 ? 0.33 : -0.33) * len, ay = (k & 2 ? 0.5 : -0.5) * wid;
      const Vector3d c = ground + r * Vector3d(ax, ay - (ay > 0 ? 0.12 : -0.12), 0.32);
      b_.AddCylinder(c, r * Vector3d(0, ay > 0 ? 1 : -1, 0), 0.32, 0.22, 10, tyre);
    }
  }

  const SynthOptions& o_;
  Mix mix_;
  SceneBuilder b_;
};

double DistanceToRect(const Vector2d& p, double x0, double x1, double y0, double y1) {
  const double dx = std::max({x0 - p.x(), 0.0, p.x() - x1}), dy = std::max({y0 - p.y(), 0.0, p.y() - y1});
  return std::hypot(dx, dy);
}

}  // namespace

Mesh Scene::ToMesh(const Pose3d& out_from_scene) const {
  Mesh m;
  m.vertices.reserve(vertices.size());
  for (const auto& v : vertices) m.vertices.push_back(out_from_scene * v);
  m.triangles = triangles;
  m.labels.assign(vertices.size(), label::kUnlabelled);
  for (size_t t = 0; t < triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) m.labels[triangles[t][k]] = labels[t];
  }
  return m;
}

Scene BuildScene(const SynthOptions& o, const Trajectory& trajectory) {
  o.Check();
  Scene scene;
  CityBuilder city(o, &scene);
  const double p = o.block_pitch_m, hw = 0.5 * o.road_width_m;
  const auto samples = trajectory.Sample(kPathSampleM);
  SEMAP_ASSERT(!samples.empty());
  // Cells near the path: ground everywhere within content distance + one pitch, content closer.
  double min_x = 1e300, max_x = -1e300, min_y = 1e300, max_y = -1e300;
  for (const auto& s : samples) {
    min_x = std::min(min_x, s.x()), max_x = std::max(max_x, s.x());
    min_y = std::min(min_y, s.y()), max_y = std::max(max_y, s.y());
  }
  const double reach = o.content_distance_m + p;
  const int i0 = static_cast<int>(std::floor((min_x - reach) / p)),
            i1 = static_cast<int>(std::ceil((max_x + reach) / p));
  const int j0 = static_cast<int>(std::floor((min_y - reach) / p)),
            j1 = static_cast<int>(std::ceil((max_y + reach) / p));
  for (int i = i0; i <= i1; ++i) {
    for (int j = j0; j <= j1; ++j) {
      const double x0 = i * p + hw, x1 = (i + 1) * p - hw, y0 = j * p + hw, y1 = (j + 1) * p - hw;
      double d = 1e300;
      for (const auto& s : samples) d = std::min(d, DistanceToRect(s, x0, x1, y0, y1));
      if (d > reach) continue;
      city.GroundCell(i, j);
      city.Block(i, j, d <= o.content_distance_m);
    }
  }
  sim_internal::SortIntoChunks(&scene, kChunkSizeM);
  return scene;
}

}  // namespace semap::sim
