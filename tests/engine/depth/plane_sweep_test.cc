#include "engine/depth/plane_sweep.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <iostream>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <string>
#include <utility>
#include <vector>

#include "engine/core/check.h"
#include "tests/engine/depth/sweep_scene.h"

namespace semap {
namespace {

using namespace sweep_scene;

// The depth step between neighbouring fronto-parallel planes at depth z (num_planes uniform in 1/z).
double PlaneStepM(double z, const DepthRange& r, int num_planes) {
  return z * z * (1.0 / r.min_depth_m - 1.0 / r.max_depth_m) / (num_planes - 1);
}

struct Score {
  double valid_share = 0.0;     // of the pixels with a true depth in the range (and inside `region`)
  double median_error_m = 0.0;  // |depth − truth| over the valid ones
  double p95_error_m = 0.0;
  double accurate_share = 0.0;  // valid and within `tolerance` of the truth (relative to the truth's depth)
};

// The result against the true depth, over the pixels where `region` (CV_8UC1; empty: all) is set.
Score Evaluate(const PlaneSweepResult& r, const cv::Mat& truth_m, double relative_tolerance,
               const cv::Mat& region = cv::Mat()) {
  std::vector<double> errors;
  int considered = 0, accurate = 0;
  for (int v = 0; v < kHeight; ++v) {
    for (int u = 0; u < kWidth; ++u) {
      if (!region.empty() && !region.at<std::uint8_t>(v, u)) continue;
      const double truth = truth_m.at<float>(v, u);
      if (!(truth >= r.range.min_depth_m && truth <= r.range.max_depth_m)) continue;
      ++considered;
      if (!r.valid.at<std::uint8_t>(v, u)) continue;
      const double error = std::abs(r.depth_m.at<float>(v, u) - truth);
      errors.push_back(error);
      if (error <= relative_tolerance * truth) ++accurate;
    }
  }
  Score s;
  if (considered == 0) return s;
  s.valid_share = double(errors.size()) / considered;
  s.accurate_share = double(accurate) / considered;
  if (errors.empty()) return s;
  std::sort(errors.begin(), errors.end());
  s.median_error_m = errors[errors.size() / 2];
  s.p95_error_m = errors[std::min(errors.size() - 1, size_t(0.95 * double(errors.size())))];
  return s;
}

std::ostream& operator<<(std::ostream& os, const Score& s) {
  return os << "valid " << s.valid_share << ", median error " << s.median_error_m << " m, p95 "
            << s.p95_error_m << " m, accurate " << s.accurate_share;
}

TEST(PlaneSweepOptions, DefaultsAreValid) { EXPECT_NO_THROW(PlaneSweepOptions{}.Check()); }

TEST(PlaneSweepOptions, RejectsBadValuesNamingTheKey) {
  auto expect_key = [](PlaneSweepOptions o, const std::string& key) {
    try {
      o.Check();
      ADD_FAILURE() << "accepted a bad " << key;
    } catch (const InvalidOption& e) {
      EXPECT_EQ(e.field(), key);
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  PlaneSweepOptions o;
  auto with = [&](auto change) {
    PlaneSweepOptions changed = o;
    change(changed);
    return changed;
  };
  expect_key(with([](auto& x) { x.num_planes = 2; }), "num_planes");
  expect_key(with([](auto& x) {
               x.min_depth_m = -1.0;
               x.max_depth_m = 10.0;
             }),
             "min_depth_m");
  expect_key(with([](auto& x) {
               x.min_depth_m = 5.0;
               x.max_depth_m = 4.0;
             }),
             "max_depth_m");
  expect_key(with([](auto& x) {
               x.min_depth_m = 0.0;
               x.max_depth_m = 4.0;
             }),
             "min_depth_m");
  expect_key(with([](auto& x) { x.camera_range_factor = 1.0; }), "camera_range_factor");
  expect_key(with([](auto& x) { x.window_px = 6; }), "window_px");
  expect_key(with([](auto& x) { x.window_px = 1; }), "window_px");
  expect_key(with([](auto& x) { x.min_window_stddev = 0.0; }), "min_window_stddev");
  expect_key(with([](auto& x) { x.best_views = -1; }), "best_views");
  expect_key(with([](auto& x) { x.min_views = 0; }), "min_views");
  expect_key(with([](auto& x) { x.max_cost = 2.5; }), "max_cost");
  expect_key(with([](auto& x) { x.min_confidence = std::nan(""); }), "min_confidence");
  expect_key(with([](auto& x) { x.min_agreeing_views = -1; }), "min_agreeing_views");
  expect_key(with([](auto& x) { x.agreement_planes = -1; }), "agreement_planes");
  expect_key(with([](auto& x) { x.agreement_max_cost = 0.0; }), "agreement_max_cost");
  EXPECT_THROW(PlaneSweepDepth{with([](auto& x) { x.num_planes = 0; })}, InvalidOption);
}

TEST(PlaneSweep, RejectsBadViews) {
  const PlaneSweepDepth sweep(PlaneSweepOptions{});
  PlaneSweepView good;
  good.image = cv::Mat(20, 20, CV_8UC1, cv::Scalar(0));
  good.K = TestK();
  EXPECT_THROW(sweep.Compute(good, {}), std::invalid_argument);
  PlaneSweepView colour = good;
  colour.image = cv::Mat(20, 20, CV_8UC3);
  EXPECT_THROW(sweep.Compute(good, {colour}), std::invalid_argument);
  PlaneSweepView skewed = good;
  skewed.K(2, 0) = 0.1;
  EXPECT_THROW(sweep.Compute(skewed, {good}), std::invalid_argument);
}

TEST(PlaneSweep, DepthRangeFromCamerasIsWhereTheAxesMeet) {
  const Eigen::Vector3d target(0.3, -0.2, 6.0);
  PlaneSweepView reference, left, right;
  reference.world_from_cam = LookAt(Eigen::Vector3d::Zero(), target);
  left.world_from_cam = LookAt(Eigen::Vector3d(-1.0, 0.0, 0.5), target);
  right.world_from_cam = LookAt(Eigen::Vector3d(1.0, 0.1, 0.0), target);
  const auto range = DepthRangeFromCameras(reference, {left, right}, 2.0);
  ASSERT_TRUE(range.has_value());
  EXPECT_NEAR(range->min_depth_m, target.norm() / 2.0, 1e-6);
  EXPECT_NEAR(range->max_depth_m, target.norm() * 2.0, 1e-6);
  // Parallel axes (a stereo rig) meet nowhere.
  PlaneSweepView beside;
  beside.world_from_cam.translation() = Eigen::Vector3d(0.5, 0.0, 0.0);
  EXPECT_FALSE(DepthRangeFromCameras(PlaneSweepView{}, {beside}, 2.0).has_value());
}

// The same orientation as `world_from_cam`, moved by `offset_cam` in its own frame.
Pose3d Moved(const Pose3d& world_from_cam, const Eigen::Vector3d& offset_cam) {
  Pose3d moved = world_from_cam;
  moved.translation() += world_from_cam.linear() * offset_cam;
  return moved;
}

TEST(PlaneSweep, FrontoParallelPlaneWithinAQuarterPlaneStep) {
  constexpr double kDepthM = 5.07;  // between two swept planes
  const std::vector<TexturedPlane> scene{Wall(kDepthM, 1)};
  cv::Mat truth_m;
  const PlaneSweepView reference = Render(scene, Pose3d::Identity(), &truth_m);
  const Eigen::Vector3d target(0.0, 0.0, kDepthM);
  std::vector<PlaneSweepView> neighbours;
  for (const Eigen::Vector3d& c : {Eigen::Vector3d(-0.4, 0.0, 0.0), Eigen::Vector3d(0.4, 0.05, 0.1),
                                   Eigen::Vector3d(0.0, -0.3, -0.2), Eigen::Vector3d(0.1, 0.3, 0.0)})
    neighbours.push_back(Render(scene, LookAt(c, target)));
  PlaneSweepOptions o;
  o.num_planes = 64;
  o.min_depth_m = 2.0;
  o.max_depth_m = 20.0;
  const PlaneSweepResult r = PlaneSweepDepth(o).Compute(reference, neighbours);
  const double step_m = PlaneStepM(kDepthM, r.range, o.num_planes);
  const Score s = Evaluate(r, truth_m, 0.25 * step_m / kDepthM);
  std::cout << "[ measured ] fronto-parallel wall, plane step " << step_m << " m: " << s << "\n";
  EXPECT_GE(s.valid_share, 0.9);
  EXPECT_LE(s.p95_error_m, 0.25 * step_m);
  EXPECT_GE(s.accurate_share, 0.85);
  for (int v = 0; v < kHeight; ++v)
    for (int u = 0; u < kWidth; ++u)
      if (r.valid.at<std::uint8_t>(v, u)) {
        ASSERT_EQ(r.family.at<std::uint8_t>(v, u), 0);
      }
}

TEST(PlaneSweep, GrazingGroundNeedsItsOwnSweepDirection) {
  // The ground, 1 m below a camera pitched down by 10°, seen at a grazing angle from views up to 1 m apart:
  // its disparity changes by about a pixel per row, several pixels across one window.
  constexpr double kHeightM = 1.0;
  const std::vector<TexturedPlane> scene{Ground(kHeightM, 2)};
  const Pose3d world_from_reference = PitchedDown();
  cv::Mat truth_m;
  const PlaneSweepView reference = Render(scene, world_from_reference, &truth_m);
  std::vector<PlaneSweepView> neighbours;
  for (const Eigen::Vector3d& c : {Eigen::Vector3d(-1.0, 0.0, 0.0), Eigen::Vector3d(1.0, 0.0, 0.0),
                                   Eigen::Vector3d(0.0, -0.6, 0.0), Eigen::Vector3d(0.3, 0.0, 1.0)})
    neighbours.push_back(Render(scene, Moved(world_from_reference, c)));
  PlaneSweepOptions o;
  o.num_planes = 96;
  o.min_depth_m = 2.0;
  o.max_depth_m = 20.0;
  const PlaneSweepDepth sweep(o);
  const PlaneSweepResult fronto = sweep.Compute(reference, neighbours);
  // The ground's direction with its offset known to ±20 % (as a plane fitted to sparse points would give).
  const SweepDirection ground_direction{Eigen::Vector3d::UnitY(), 0.8 * kHeightM, 1.2 * kHeightM};
  const PlaneSweepResult with_ground = sweep.Compute(reference, neighbours, {ground_direction});
  constexpr double kTolerance = 0.02;  // of the true depth
  const Score f = Evaluate(fronto, truth_m, kTolerance), g = Evaluate(with_ground, truth_m, kTolerance);
  std::cout << "[ measured ] ground, fronto-parallel only: " << f << "\n"
            << "[ measured ] ground, with its normal and offsets: " << g << "\n";
  EXPECT_GE(g.accurate_share, 0.9);
  EXPECT_GE(g.accurate_share, f.accurate_share + 0.2);
  EXPECT_LE(g.median_error_m, 0.1 * f.median_error_m);
  EXPECT_LE(g.p95_error_m, 0.1 * f.p95_error_m);
  // The ground's pixels were won by the ground's planes.
  EXPECT_GT(cv::countNonZero(with_ground.family == 1), 4 * cv::countNonZero(with_ground.family == 0));
}

TEST(PlaneSweep, OccluderInOneNeighbourIsIgnoredByTheBestViews) {
  constexpr double kDepthM = 6.13;
  const std::vector<TexturedPlane> scene{Wall(kDepthM, 3)};
  cv::Mat truth_m;
  const PlaneSweepView reference = Render(scene, Pose3d::Identity(), &truth_m);
  const Eigen::Vector3d target(0.0, 0.0, kDepthM);
  std::vector<PlaneSweepView> neighbours;
  for (const Eigen::Vector3d& c :
       {Eigen::Vector3d(-0.5, 0.0, 0.0), Eigen::Vector3d(0.5, 0.1, 0.0), Eigen::Vector3d(0.0, -0.4, 0.1)})
    neighbours.push_back(Render(scene, LookAt(c, target)));
  // Something in front of neighbour 0 only: a patch of another texture over part of its image.
  const cv::Rect occluder(90, 50, 120, 110);
  cv::Mat patch;
  RandomTexture(256, 4)(cv::Rect(0, 0, occluder.width, occluder.height)).convertTo(patch, CV_8UC1);
  patch.copyTo(neighbours[0].image(occluder));
  // The reference pixels whose surface point neighbour 0 sees through the occluder (the test's projection).
  cv::Mat hidden = cv::Mat::zeros(kHeight, kWidth, CV_8UC1);
  const Pose3d cam0_from_world = neighbours[0].world_from_cam.inverse(Eigen::Isometry);
  for (int v = 0; v < kHeight; ++v) {
    for (int u = 0; u < kWidth; ++u) {
      const Eigen::Vector3d x_world =
          TestK().inverse() * Eigen::Vector3d(u, v, 1.0) * truth_m.at<float>(v, u);
      const Eigen::Vector3d x = TestK() * (cam0_from_world * x_world);
      if (occluder.contains(cv::Point(int(std::floor(x.x() / x.z())), int(std::floor(x.y() / x.z())))))
        hidden.at<std::uint8_t>(v, u) = 1;
    }
  }
  ASSERT_GT(cv::countNonZero(hidden), 5000);
  PlaneSweepOptions o;
  o.num_planes = 64;
  o.min_depth_m = 2.0;
  o.max_depth_m = 20.0;
  o.best_views = 2;
  const PlaneSweepResult robust = PlaneSweepDepth(o).Compute(reference, neighbours);
  o.best_views = 0;
  const PlaneSweepResult plain = PlaneSweepDepth(o).Compute(reference, neighbours);
  // Neighbour 0 is the only one left of the reference: the right subset's mean is free of the occluder.
  o.left_right_subsets = true;
  const PlaneSweepResult sides = PlaneSweepDepth(o).Compute(reference, neighbours);
  const double step_m = PlaneStepM(kDepthM, robust.range, o.num_planes);
  const double tolerance = 0.25 * step_m / kDepthM;
  const Score r = Evaluate(robust, truth_m, tolerance, hidden),
              p = Evaluate(plain, truth_m, tolerance, hidden),
              l = Evaluate(sides, truth_m, tolerance, hidden);
  std::cout << "[ measured ] behind the occluder, best 2 of 3 views: " << r << "\n"
            << "[ measured ] behind the occluder, mean of all 3 views: " << p << "\n"
            << "[ measured ] behind the occluder, lower of the left and right means: " << l << "\n";
  EXPECT_GE(r.accurate_share, 0.95);
  EXPECT_LE(r.p95_error_m, 0.25 * step_m);
  EXPECT_LE(p.accurate_share, 0.85);
  EXPECT_GE(p.median_error_m, 2.0 * r.median_error_m);
  EXPECT_GE(l.accurate_share, 0.95);
}

// A wall seen by four neighbours, two of which see another texture over part of their image: per reference
// pixel and neighbour, whether the neighbour sees the wall there, sees the pasted texture, or neither
// clearly (near a patch's or the image's edge, within the window's reach).
struct PatchedWall {
  static constexpr double kDepthM = 6.13;
  static constexpr int kNeighbours = 4;
  cv::Mat truth_m;
  PlaneSweepView reference;
  std::vector<PlaneSweepView> neighbours;
  cv::Mat clean_views;  // CV_8UC1: the neighbours that clearly see the wall at the pixel
  cv::Mat unclear;      // CV_8UC1: 1 where some neighbour sees neither clearly

  explicit PatchedWall(int window_px) {
    const std::vector<TexturedPlane> scene{Wall(kDepthM, 3)};
    reference = Render(scene, Pose3d::Identity(), &truth_m);
    const Eigen::Vector3d target(0.0, 0.0, kDepthM);
    for (const Eigen::Vector3d& c : {Eigen::Vector3d(-0.5, 0.0, 0.0), Eigen::Vector3d(0.5, 0.1, 0.0),
                                     Eigen::Vector3d(0.0, -0.4, 0.1), Eigen::Vector3d(-0.1, 0.4, -0.1)})
      neighbours.push_back(Render(scene, LookAt(c, target)));
    // Neighbours 0 and 1 see other surfaces (two unrelated textures) over overlapping parts of their images.
    const cv::Rect patches[] = {cv::Rect(70, 50, 130, 110), cv::Rect(130, 80, 130, 110)};
    for (int j = 0; j < 2; ++j) {
      cv::Mat patch;
      RandomTexture(256, 4 + j)(cv::Rect(0, 0, patches[j].width, patches[j].height))
          .convertTo(patch, CV_8UC1);
      patch.copyTo(neighbours[size_t(j)].image(patches[j]));
    }
    // A neighbour's view of a pixel is clear when the projection of its true point lies farther than the
    // window's half-side and two pixels from every edge of the image and of the patch.
    const double margin_px = window_px / 2 + 2.0;
    clean_views = cv::Mat::zeros(kHeight, kWidth, CV_8UC1);
    unclear = cv::Mat::zeros(kHeight, kWidth, CV_8UC1);
    for (int j = 0; j < kNeighbours; ++j) {
      const Pose3d cam_from_world = neighbours[size_t(j)].world_from_cam.inverse(Eigen::Isometry);
      for (int v = 0; v < kHeight; ++v) {
        for (int u = 0; u < kWidth; ++u) {
          const Eigen::Vector3d x_world =
              TestK().inverse() * Eigen::Vector3d(u, v, 1.0) * truth_m.at<float>(v, u);
          const Eigen::Vector3d x = TestK() * (cam_from_world * x_world);
          const double px = x.x() / x.z(), py = x.y() / x.z();
          // Signed distance to a rectangle's edges: positive inside.
          const auto inside_by = [&](double left, double top, double right, double bottom) {
            return std::min({px - left, right - px, py - top, bottom - py});
          };
          const double in_image = inside_by(0, 0, kWidth - 1, kHeight - 1);
          double in_patch = -margin_px - 1.0;
          if (j < 2) {
            const cv::Rect& p = patches[j];
            in_patch = inside_by(p.x, p.y, p.x + p.width - 1, p.y + p.height - 1);
          }
          if (in_image > margin_px && in_patch < -margin_px) {
            ++clean_views.at<std::uint8_t>(v, u);
          } else if (!(in_image > margin_px && in_patch > margin_px)) {
            unclear.at<std::uint8_t>(v, u) = 1;
          }
        }
      }
    }
  }
};

// Options for the wall: 64 planes over 2–20 m, the best two views' mean (which ignores one or two hidden
// views), agreement off.
PlaneSweepOptions WallOptions() {
  PlaneSweepOptions o;
  o.num_planes = 64;
  o.min_depth_m = 2.0;
  o.max_depth_m = 20.0;
  o.best_views = 2;
  o.min_agreeing_views = 0;
  return o;
}

TEST(PlaneSweep, AgreementDropsThePixelsTooFewNeighboursSeeAlike) {
  PlaneSweepOptions o = WallOptions();
  const PatchedWall wall(o.window_px);
  const PlaneSweepResult off = PlaneSweepDepth(o).Compute(wall.reference, wall.neighbours);
  // Three of the four must agree: the pixels both patched neighbours hide have two. The views of the wall
  // score its plane far below the cost bound; a looser bound lets a patch of blurred random texture agree
  // by chance over small blobs, where it happens to correlate with the reference.
  o.min_agreeing_views = 3;
  o.agreement_planes = 1;
  o.agreement_max_cost = 0.15;
  const PlaneSweepResult on = PlaneSweepDepth(o).Compute(wall.reference, wall.neighbours);
  const double step_m = PlaneStepM(PatchedWall::kDepthM, off.range, o.num_planes);
  // Over the pixels every neighbour sees clearly (the wall or a patch), among those the sweep without the
  // test gives a depth: with at least 3 neighbours on the wall the depth is kept as it was, with 2 it is
  // dropped.
  int enough = 0, enough_kept = 0, too_few = 0, too_few_kept = 0, too_few_accurate = 0;
  for (int v = 0; v < kHeight; ++v) {
    for (int u = 0; u < kWidth; ++u) {
      if (wall.unclear.at<std::uint8_t>(v, u) || !off.valid.at<std::uint8_t>(v, u)) continue;
      const bool kept = on.valid.at<std::uint8_t>(v, u) != 0;
      if (kept) {
        ASSERT_EQ(on.depth_m.at<float>(v, u), off.depth_m.at<float>(v, u)) << "at " << u << ", " << v;
      }
      if (wall.clean_views.at<std::uint8_t>(v, u) >= 3) {
        ++enough;
        enough_kept += kept;
      } else {
        ASSERT_EQ(wall.clean_views.at<std::uint8_t>(v, u), 2);
        ++too_few;
        too_few_kept += kept;
        too_few_accurate +=
            std::abs(off.depth_m.at<float>(v, u) - wall.truth_m.at<float>(v, u)) <= 0.25 * step_m;
      }
    }
  }
  std::cout << "[ measured ] agreement of 3 views: kept " << enough_kept << " of " << enough
            << " pixels seen alike by 3 or 4 neighbours, " << too_few_kept << " of " << too_few
            << " seen alike by 2\n";
  ASSERT_GT(enough, 20000);
  ASSERT_GT(too_few, 2000);
  // The best two views' mean alone gets the hidden pixels right: what the test drops there is no error.
  EXPECT_GE(too_few_accurate, 0.95 * too_few);
  EXPECT_GE(enough_kept, 0.99 * enough);
  EXPECT_LE(too_few_kept, 0.01 * too_few);
}

TEST(PlaneSweep, AgreementOffIsTheSweepWithoutIt) {
  // Agreement off, and an agreement every neighbour that sees the pixel at some plane passes: the same
  // result, bit for bit, on the patched wall with a second direction of planes (its ground normal meets the
  // wall at a grazing angle, so both families score pixels).
  PlaneSweepOptions o = WallOptions();
  const PatchedWall wall(o.window_px);
  const std::vector<SweepDirection> directions{{Eigen::Vector3d(0.0, 1.0, -0.3), 0.0, 0.0}};
  const PlaneSweepResult off = PlaneSweepDepth(o).Compute(wall.reference, wall.neighbours, directions);
  o.min_agreeing_views = 1;
  o.agreement_planes = o.num_planes;
  o.agreement_max_cost = 2.0;
  const PlaneSweepResult all = PlaneSweepDepth(o).Compute(wall.reference, wall.neighbours, directions);
  ASSERT_GT(cv::countNonZero(off.valid), kWidth * kHeight / 2);
  ASSERT_GT(cv::countNonZero(off.family == 1), 0);
  for (const auto& [a, b] :
       {std::pair{off.depth_m, all.depth_m}, std::pair{off.confidence, all.confidence},
        std::pair{off.cost, all.cost}, std::pair{off.valid, all.valid}, std::pair{off.family, all.family}}) {
    ASSERT_EQ(a.type(), b.type());
    // memcmp: NaN-free maps, but equal bits is the claim.
    for (int v = 0; v < kHeight; ++v)
      ASSERT_EQ(std::memcmp(a.ptr(v), b.ptr(v), a.cols * a.elemSize()), 0) << "row " << v;
  }
  // The default is off.
  EXPECT_EQ(PlaneSweepOptions{}.min_agreeing_views, 0);
}

}  // namespace
}  // namespace semap
