#include "engine/sim/multi_view_set.h"

#include <algorithm>
#include <cmath>

#include "engine/core/check.h"
#include "engine/sim/internal/random.h"
#include "engine/sim/internal/scene_builder.h"

namespace semap::sim {
namespace {

using Eigen::Vector3d;
using sim_internal::HashCombine;
using sim_internal::Rng;
using sim_internal::SceneBuilder;
using sim_internal::Surface;

// Extent of the ground and the wall to either side of the object, and how far the ground reaches towards
// and behind the cameras (the farthest camera stands at max_distance_m).
constexpr double kHalfWidthM = 20.0;
constexpr double kGroundBeyondCamerasM = 8.0;
constexpr double kGroundTileM = 4.0;
constexpr double kWallHeightM = 9.0;
constexpr double kWallThicknessM = 0.4;
constexpr double kPilasterPitchM = 4.0;
// Culling cells of the renderer.
constexpr double kChunkSizeM = 4.0;
// Independent random streams of a set.
enum Stream : std::uint64_t { kSceneStream = 11, kCameraStream = 12, kNoiseStream = 13 };

void AddGround(const MultiViewSetOptions& o, SceneBuilder* b) {
  const Surface paving{label::kSidewalk, Material::kPaving, 0};
  const double y0 = -(o.max_distance_m + kGroundBeyondCamerasM), y1 = o.wall_distance_m;
  for (double x = -kHalfWidthM; x < kHalfWidthM; x += kGroundTileM) {
    for (double y = y0; y < y1; y += kGroundTileM) {
      const double xe = std::min(x + kGroundTileM, kHalfWidthM), ye = std::min(y + kGroundTileM, y1);
      b->AddQuad({x, y, 0.0}, {xe, y, 0.0}, {xe, ye, 0.0}, {x, ye, 0.0}, Vector3d::UnitZ(), paving);
    }
  }
}

// A brick wall whose front is the plane y = wall_distance_m, with stone pilasters and a cornice.
void AddWall(const MultiViewSetOptions& o, SceneBuilder* b) {
  const double front = o.wall_distance_m;
  const Surface brick{label::kBuilding, Material::kBrick, b->NewObjectId()};
  b->AddBox({0.0, front + 0.5 * kWallThicknessM, 0.5 * kWallHeightM},
            {kHalfWidthM, 0.5 * kWallThicknessM, 0.5 * kWallHeightM}, 0.0, brick);
  const Surface stone{label::kBuilding, Material::kCurb, b->NewObjectId()};
  for (double x = -kHalfWidthM + 0.5 * kPilasterPitchM; x < kHalfWidthM; x += kPilasterPitchM) {
    b->AddBox({x, front - 0.12, 0.5 * kWallHeightM - 0.5}, {0.3, 0.12, 0.5 * kWallHeightM - 0.5}, 0.0, stone);
  }
  b->AddBox({0.0, front - 0.2, kWallHeightM - 1.2}, {kHalfWidthM, 0.2, 0.15}, 0.0, stone);
  b->AddBox({0.0, front - 0.1, 0.25}, {kHalfWidthM, 0.1, 0.25}, 0.0, stone);
}

// The fountain: a plinth, a rounded basin with medallions on its faces, four pillars with finials at its
// corners, a ringed column, an upper dish and a sculpted top.
void AddFountain(std::uint64_t seed, SceneBuilder* b) {
  Rng rng(seed);
  const Label kObject = kMultiViewObjectLabel;
  const Surface stone{kObject, Material::kCurb, b->NewObjectId()};
  const Surface carved{kObject, Material::kBrick, b->NewObjectId()};
  const Surface bronze{kObject, Material::kBark, b->NewObjectId()};
  const double basin_x = rng.Uniform(1.45, 1.75), basin_y = rng.Uniform(0.95, 1.15);
  const double basin_h = rng.Uniform(0.32, 0.4);
  b->AddBox({0.0, 0.0, 0.1}, {basin_x + 0.3, basin_y + 0.3, 0.1}, 0.0, stone);
  b->AddRoundedBox({0.0, 0.0, 0.2 + basin_h}, {basin_x, basin_y, basin_h}, 0.0, 4.0, 4, carved);
  // Medallions along the front and back faces and on the sides, proud of the basin by a few cm.
  const int medallions = rng.UniformInt(4, 6);
  for (int k = 0; k < medallions; ++k) {
    const double x = basin_x * (-0.75 + 1.5 * (k + 0.5) / medallions);
    for (const double side : {-1.0, 1.0}) {
      b->AddRoundedBox({x, side * (basin_y - 0.02), 0.2 + basin_h}, {0.13, 0.07, 0.16}, 0.0, 2.5, 2, stone);
    }
  }
  for (const double side : {-1.0, 1.0}) {
    b->AddBlob({side * (basin_x - 0.01), 0.0, 0.2 + basin_h}, {0.09, 0.22, 0.2}, 2, 0.2, rng.NextU64(),
               bronze);
  }
  // Pillars at the plinth's corners.
  for (const double sx : {-1.0, 1.0}) {
    for (const double sy : {-1.0, 1.0}) {
      const double height = rng.Uniform(1.3, 1.7);
      const Vector3d base(sx * (basin_x + 0.15), sy * (basin_y + 0.15), 0.2);
      b->AddCylinder(base, Vector3d::UnitZ(), 0.13, height, 14, stone);
      b->AddBox(base + Vector3d(0.0, 0.0, height + 0.05), {0.18, 0.18, 0.05}, 0.0, stone);
      b->AddBlob(base + Vector3d(0.0, 0.0, height + 0.28), {0.16, 0.16, 0.2}, 2, 0.25, rng.NextU64(), bronze);
    }
  }
  // The column, its rings, the upper dish and the sculpture on top.
  const double column_top = 0.2 + 2.0 * basin_h + rng.Uniform(1.1, 1.4);
  b->AddCylinder({0.0, 0.0, 0.2}, Vector3d::UnitZ(), 0.26, column_top - 0.2, 20, carved);
  for (const double t : {0.35, 0.65, 0.95}) {
    b->AddCylinder({0.0, 0.0, 0.2 + t * (column_top - 0.2)}, Vector3d::UnitZ(), 0.34, 0.08, 20, stone);
  }
  b->AddRoundedBox({0.0, 0.0, column_top + 0.1}, {0.75, 0.75, 0.12}, 0.0, 2.5, 3, stone);
  b->AddBlob({0.0, 0.0, column_top + 0.65}, {0.32, 0.28, 0.5}, 3, 0.3, rng.NextU64(), bronze);
}

}  // namespace

void MultiViewSetOptions::ScaleImage(double factor) {
  SEMAP_ASSERT(factor > 0.0, "factor " << factor);
  image_width_px = static_cast<int>(std::lround(image_width_px * factor));
  image_height_px = static_cast<int>(std::lround(image_height_px * factor));
  fx_px *= factor;
  fy_px *= factor;
  cx_px = (cx_px + 0.5) * factor - 0.5;
  cy_px = (cy_px + 0.5) * factor - 0.5;
}

void MultiViewSetOptions::Check() const {
  CheckDeclaredRanges(*this);
  if (max_distance_m < min_distance_m) {
    throw OptionError(*this, max_distance_m, "must be >= " + KeyOf(*this, min_distance_m));
  }
}

Scene BuildMultiViewScene(const MultiViewSetOptions& options, std::uint64_t seed) {
  options.Check();
  Scene scene;
  SceneBuilder builder(&scene);
  AddGround(options, &builder);
  AddWall(options, &builder);
  AddFountain(HashCombine(seed, kSceneStream), &builder);
  sim_internal::SortIntoChunks(&scene, kChunkSizeM);
  return scene;
}

MultiViewSet::MultiViewSet(const SynthOptions& synth, const MultiViewSetOptions& options)
    : synth_(synth), options_(options) {
  synth_.Check();
  options_.Check();
  scene_ = std::make_unique<Scene>(BuildMultiViewScene(options_, synth_.seed));
  renderer_ = std::make_unique<CameraRenderer>(*scene_, synth_);
  target_ = Vector3d(0.0, 0.0, 1.4);
  Rng rng(HashCombine(synth_.seed, kCameraStream));
  const int n = options_.num_views;
  const double arc_rad = options_.arc_deg * M_PI / 180.0;
  const double step_rad = n > 1 ? arc_rad / (n - 1) : 0.0;
  for (int k = 0; k < n; ++k) {
    // Along the arc t in [0, 1]: nearest at its ends, farthest in its middle.
    const double t = n > 1 ? static_cast<double>(k) / (n - 1) : 0.5;
    const double angle = -0.5 * arc_rad + k * step_rad + rng.Uniform(-0.15, 0.15) * step_rad;
    const double span = options_.max_distance_m - options_.min_distance_m;
    const double distance =
        std::clamp(options_.min_distance_m + span * std::sin(M_PI * t) + rng.Uniform(-0.05, 0.05) * span,
                   options_.min_distance_m, options_.max_distance_m);
    const Vector3d centre(distance * std::sin(angle), -distance * std::cos(angle),
                          options_.camera_height_m + rng.Uniform(-0.15, 0.15));
    const Vector3d look_at = target_ + Vector3d(rng.Uniform(-0.1, 0.1), 0.0, rng.Uniform(-0.1, 0.1));
    const Vector3d z = (look_at - centre).normalized();
    const Vector3d x = z.cross(Vector3d::UnitZ()).normalized();
    const Vector3d y = z.cross(x);
    MultiViewCamera c;
    c.world_from_cam.linear().col(0) = x;
    c.world_from_cam.linear().col(1) = y;
    c.world_from_cam.linear().col(2) = z;
    c.world_from_cam.translation() = centre;
    c.K << options_.fx_px, 0.0, options_.cx_px, 0.0, options_.fy_px, options_.cy_px, 0.0, 0.0, 1.0;
    c.calibration.fx_px = options_.fx_px;
    c.calibration.fy_px = options_.fy_px;
    c.calibration.cx_px = options_.cx_px;
    c.calibration.cy_px = options_.cy_px;
    c.calibration.width_px = options_.image_width_px;
    c.calibration.height_px = options_.image_height_px;
    c.calibration.baseline_m = 1.0;
    c.exposure_gain = 1.0 + synth_.exposure_variation * rng.Uniform(-1.0, 1.0);
    cameras_.push_back(c);
  }
}

MultiViewSet::~MultiViewSet() = default;

const MultiViewCamera& MultiViewSet::camera(int view) const {
  SEMAP_ASSERT(view >= 0 && view < num_views(), "view " << view);
  return cameras_[static_cast<size_t>(view)];
}

CameraImage MultiViewSet::Render(int view) const {
  const MultiViewCamera& c = camera(view);
  const std::uint64_t noise =
      HashCombine(HashCombine(synth_.seed, kNoiseStream), static_cast<std::uint64_t>(view));
  return renderer_->Render(c.calibration, c.world_from_cam, {c.exposure_gain, noise});
}

}  // namespace semap::sim
