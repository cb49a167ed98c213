// StereoLabelStage with keyframe labels (a pipeline with a segment stage) and with the sweep beside SGBM,
// SegmenterStage, the RowAlignmentReader and the StereoNeighbourReader. The frame-label path without
// keyframes is tested with the labelling rule (tests/engine/semantics/labelling_test.cc), the row fit itself
// in tests/engine/depth/row_alignment_test.cc.
#include "engine/pipeline/semap_stages.h"

#include <gtest/gtest.h>

#include <deque>
#include <iostream>
#include <opencv2/imgproc.hpp>
#include <set>

#include "engine/core/mesh_delta.h"
#include "tests/common/frames_reader.h"
#include "tests/engine/depth/sweep_scene.h"
#include "tests/engine/map/street_scene.h"

namespace semap {
namespace {

constexpr Label kRoad = 7;  // Cityscapes ids (none of them sky)
constexpr Label kBuilding = 3;
constexpr Label kUnlabelled = 0;  // Cityscapes' unlabelled id

// A textured fronto-parallel plane at disparity 16 px: depth fx·B/16 = 300·0.5/16 = 9.375 m. The frame's
// own label image (which keyframe labels must override) is all 1.
Frame Plane(std::int64_t id, const Pose3d& world_from_cam) {
  cv::RNG rng(3);
  cv::Mat noise(120, 216, CV_8UC1);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 255);
  cv::GaussianBlur(noise, noise, cv::Size(3, 3), 0.8);
  Frame f;
  f.id = id;
  f.left = noise(cv::Rect(0, 0, 200, 120)).clone();
  f.right = noise(cv::Rect(16, 0, 200, 120)).clone();
  f.calibration = {300.0, 300.0, 100.0, 60.0, 0.5, 200, 120};
  f.world_from_cam = world_from_cam;
  f.labels = cv::Mat(120, 200, CV_8UC1, cv::Scalar(1));
  return f;
}

// Keyframe 10 at the origin: columns u < 100 building, u >= 100 road.
KeyframeLabels SplitKeyframe() {
  KeyframeLabels k;
  k.frame_id = 10;
  k.world_from_cam = Pose3d::Identity();
  k.labels = cv::Mat(120, 200, CV_8UC1, cv::Scalar(kBuilding));
  k.labels.colRange(100, 200).setTo(kRoad);
  return k;
}

DepthOptions SmallDepth() {
  DepthOptions depth;
  depth.num_disparities = 32;
  depth.max_points_per_frame = 0;
  return depth;
}

SemanticsOptions Enet(LabelPropagation propagation) {
  SemanticsOptions s;
  s.source = LabelSource::kEnet;
  s.enet_model_path = "/nonexistent/enet-model.net";  // never loaded with keyframe labels
  s.enet_propagation = propagation;
  return s;
}

// On the keyframe itself, its labels are the frame's, whatever the frame's own label image.
TEST(StereoLabelStageKeyframes, AKeyframeTakesItsOwnLabels) {
  StereoLabelStage stage(SmallDepth(), Enet(LabelPropagation::kReproject), ClassMap::Cityscapes(), true);
  const KeyframeLabels keyframe = SplitKeyframe();
  const LabelledCloud cloud = stage.Process(Plane(10, Pose3d::Identity()), &keyframe);
  ASSERT_GT(cloud.size(), 1000u);
  for (size_t i = 0; i < cloud.size(); ++i) {
    EXPECT_EQ(cloud.labels[i], cloud.pixels_px[i].x() < 99.5 ? kBuilding : kRoad) << cloud.pixels_px[i].x();
  }
}

// The frame 0.25 m to the right of the keyframe: a point of the plane (9.375 m) at column u of the frame is
// at u + 300·0.25/9.375 = u + 8 in the keyframe: building up to u = 91, road from 92, unlabelled beyond 191.
// Reused labels keep the keyframe's columns.
TEST(StereoLabelStageKeyframes, AFrameBetweenKeyframesTakesTheReprojectedOrReusedLabels) {
  const Frame frame = Plane(12, Pose3d(Eigen::Translation3d(0.25, 0.0, 0.0)));
  const KeyframeLabels keyframe = SplitKeyframe();
  const LabelledCloud reprojected =
      StereoLabelStage(SmallDepth(), Enet(LabelPropagation::kReproject), ClassMap::Cityscapes(), true)
          .Process(frame, &keyframe);
  const LabelledCloud reused =
      StereoLabelStage(SmallDepth(), Enet(LabelPropagation::kReuse), ClassMap::Cityscapes(), true)
          .Process(frame, &keyframe);
  ASSERT_GT(reprojected.size(), 1000u);
  ASSERT_EQ(reused.size(), reprojected.size());
  size_t moved = 0;
  for (size_t i = 0; i < reprojected.size(); ++i) {
    const double u = reprojected.pixels_px[i].x();
    if (u < 91.0) {
      EXPECT_EQ(reprojected.labels[i], kBuilding) << u;
    }
    if (u > 93.0 && u < 191.0) {
      EXPECT_EQ(reprojected.labels[i], kRoad) << u;
    }
    if (u > 193.0) {
      EXPECT_EQ(reprojected.labels[i], kUnlabelled) << u;
    }
    if (u > 93.0 && u < 99.0) ++moved;
    EXPECT_EQ(reused.labels[i], u < 99.5 ? kBuilding : kRoad) << u;
  }
  EXPECT_GT(moved, 100u);  // the band that reprojection relabels exists
}

// The depth workers of a pipeline with a segment stage load no model: a wrong path is no error there; the
// segment stage loads it and names the file.
TEST(SegmenterStage, LoadsTheModelAtConstruction) {
  EXPECT_NO_THROW(
      StereoLabelStage(SmallDepth(), Enet(LabelPropagation::kReproject), ClassMap::Cityscapes(), true));
  try {
    SegmenterStage stage(Enet(LabelPropagation::kReproject));
    FAIL() << "no error for a missing model";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/enet-model.net"), std::string::npos) << e.what();
  }
  EXPECT_THROW(
      StereoLabelStage(SmallDepth(), Enet(LabelPropagation::kReproject), ClassMap::Cityscapes(), false),
      std::runtime_error);
}

// The map stage at a mesh cadence: 13 frames of the analytic street with finalisation, meshed every frame
// and every 4 frames. Snapshots, hence deltas, come only on every 4th frame and at the end, and the mesh a
// subscriber rebuilds from them at the end is the same, triangle for triangle.
TEST(IncrementalMapStage, MeshEveryNFramesPublishesLessOftenAndEndsWithTheSameMesh) {
  const test::StreetScene scene;
  MapOptions options;
  options.finalise_age_frames = 5;
  options.finalise_every_frames = 3;
  options.disparity_sigma_px = 0.0;  // exact depth
  IncrementalMapStage every_frame(options, 1), every_fourth(options, 4);
  MeshPublisher publisher_1, publisher_4;  // as the pipeline's output thread publishes
  MeshAccumulator mesh_1, mesh_4;
  std::vector<std::int64_t> frames_with_change;
  std::size_t finalised_4 = 0;
  constexpr int kFrames = 13;
  for (int f = 0; f < kFrames; ++f) {
    LabelledCloud frame = test::StreetDepthFrame(scene, 1.0 * f, 2);
    frame.camera_frame_ids = {f};
    const MapUpdate u1 = every_frame.Process(frame, Pose3d::Identity());
    const MapUpdate u4 = every_fourth.Process(frame, Pose3d::Identity());
    EXPECT_TRUE(u1.mesh.has_value()) << "frame " << f;
    EXPECT_EQ(u4.mesh.has_value(), f % 4 == 3) << "frame " << f;
    EXPECT_EQ(u4.frame_id, f);
    const MeshDelta d1 = publisher_1.Publish(u1), d4 = publisher_4.Publish(u4);
    EXPECT_FALSE(d1.empty()) << "frame " << f;
    EXPECT_EQ(d4.frame_id, f);
    EXPECT_EQ(u1.vertices, u4.vertices) << "frame " << f << ": the map itself does not depend on the cadence";
    EXPECT_EQ(u1.cells, u4.cells) << "frame " << f;
    mesh_1.Apply(d1);
    mesh_4.Apply(d4);
    if (!d4.empty()) frames_with_change.push_back(f);
    finalised_4 += d4.finalised_triangle_ids.size();
  }
  EXPECT_GT(finalised_4, 0u) << "the drive finalises regions between mesh frames";
  EXPECT_EQ(frames_with_change, (std::vector<std::int64_t>{3, 7, 11}));
  mesh_1.Apply(publisher_1.Publish(every_frame.Finish()));
  mesh_4.Apply(publisher_4.Publish(every_fourth.Finish()));
  EXPECT_EQ(publisher_1.published_triangles(), publisher_4.published_triangles());
  EXPECT_EQ(mesh_1.num_triangles(), mesh_4.num_triangles());
  const Mesh a = mesh_1.ToMesh(), b = mesh_4.ToMesh();
  ASSERT_GT(a.num_triangles(), 100u);
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.labels, b.labels);
  // Triangles as a set, each rotated to start at its smallest index (orientation kept): the rebuilt mesh
  // lists them in the order its hash table holds them.
  const auto canonical = [](const Mesh& m) {
    std::set<std::array<std::uint32_t, 3>> out;
    for (auto t : m.triangles) {
      while (t[0] > t[1] || t[0] > t[2]) t = {t[1], t[2], t[0]};
      out.insert(t);
    }
    return out;
  };
  EXPECT_EQ(canonical(a), canonical(b));
}

// A textured pair whose right image lies `dy_px` rows below the left one (and 12 px to the left): a rig whose
// rows are off by a constant.
Frame MisalignedPair(std::int64_t id, double dy_px) {
  cv::Mat noise(240, 640, CV_8UC1);
  cv::RNG rng(5);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 256);
  cv::Mat left;
  cv::GaussianBlur(noise, left, cv::Size(0, 0), 1.5);
  cv::normalize(left, left, 0, 255, cv::NORM_MINMAX);
  const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, -12, 0, 1, dy_px);
  Frame f;
  f.id = id;
  f.left = left;
  cv::warpAffine(left, f.right, shift, left.size(), cv::INTER_CUBIC, cv::BORDER_REFLECT);
  return f;
}

Frame BlankPair(std::int64_t id) {
  Frame f;
  f.id = id;
  f.left = cv::Mat(240, 640, CV_8UC1, cv::Scalar(128));
  f.right = f.left.clone();
  return f;
}

// The documented cadence, written out: frames 0-2 blank (no fit: "measured, nothing to correct"), frame 3
// fits (+0.8 px), frames after it hold that fit although their rows are off by −0.6 px, until the frame
// kRemeasureEveryFrames after the fit measures again.
TEST(RowAlignmentReader, MeasuresUntilAFitThenHoldsItForItsInterval) {
  constexpr double kFirstDyPx = 0.8, kLaterDyPx = -0.6;
  const int remeasure_at = 3 + RowAlignmentReader::kRemeasureEveryFrames;
  std::deque<Frame> frames;
  for (int i = 0; i <= remeasure_at; ++i) {
    if (i < 3) {
      frames.push_back(BlankPair(i));
    } else if (i == 3) {
      frames.push_back(MisalignedPair(i, kFirstDyPx));
    } else {
      // Between the two measurements a blank pair: a measurement there would find nothing, keep the fit,
      // and move the next measurement off frame remeasure_at.
      frames.push_back(i == remeasure_at ? MisalignedPair(i, kLaterDyPx) : BlankPair(i));
    }
  }
  RowAlignmentReader reader(std::make_unique<test::FramesReader>(std::move(frames)));
  std::vector<RowOffsets> seen;
  while (auto f = reader.Next()) {
    ASSERT_TRUE(f->row_offsets.has_value()) << "frame " << f->id;
    EXPECT_EQ(f->row_offsets->image_size, cv::Size(640, 240)) << "frame " << f->id;
    seen.push_back(*f->row_offsets);
  }
  ASSERT_EQ(seen.size(), static_cast<std::size_t>(remeasure_at + 1));
  const auto at_centre = [](const RowOffsets& r) { return r.At(320.0, 120.0); };
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(seen[i].matches, 0) << "frame " << i;
    EXPECT_EQ(seen[i].max_abs_px, 0.0) << "frame " << i;
  }
  EXPECT_NEAR(at_centre(seen[3]), kFirstDyPx, 0.1);
  EXPECT_GT(seen[3].matches, 0);
  for (int i = 4; i < remeasure_at; ++i) {
    EXPECT_EQ(seen[i].coefficients_px, seen[3].coefficients_px) << "frame " << i << " was measured again";
  }
  EXPECT_NEAR(at_centre(seen[remeasure_at]), kLaterDyPx, 0.1) << "not measured again at its interval";
}

// A stream that never fits stops trying after the first frames and tries again at the interval.
TEST(RowAlignmentReader, AStreamWithoutTextureIsMeasuredOnlyAtTheStartAndAtTheInterval) {
  const int first_tries = RowAlignmentReader::kFirstAttemptFrames;
  std::deque<Frame> frames;
  // A textured misaligned pair right after the first tries: not measured (its offsets stay zero) until the
  // interval since the last try has passed.
  const int last_try = first_tries - 1, next_try = last_try + RowAlignmentReader::kRemeasureEveryFrames;
  for (int i = 0; i <= next_try; ++i) {
    frames.push_back(i == first_tries || i == next_try ? MisalignedPair(i, 0.8) : BlankPair(i));
  }
  RowAlignmentReader reader(std::make_unique<test::FramesReader>(std::move(frames)));
  std::vector<RowOffsets> seen;
  while (auto f = reader.Next()) seen.push_back(*f->row_offsets);
  ASSERT_EQ(seen.size(), static_cast<std::size_t>(next_try + 1));
  EXPECT_EQ(seen[first_tries].matches, 0) << "measured after the first tries";
  EXPECT_NEAR(seen[next_try].At(320.0, 120.0), 0.8, 0.1) << "not measured at the interval";
}

}  // namespace
}  // namespace semap

namespace semap {
namespace {

// A multi-view frame (no right image) of the ground 1 m below a camera pitched down by 10°, seen at a
// grazing angle by four neighbours up to 1 m away, labelled road: with plane_sweep.label_directions the
// stage fits the ground from the first sweep and sweeps its planes too, and more of the frame's points lie
// on the ground.
TEST(StereoLabelStage, AMultiViewFrameSweepsTheLabelledGroundsPlanes) {
  using namespace sweep_scene;
  constexpr double kHeightM = 1.0;
  const std::vector<TexturedPlane> scene{Ground(kHeightM, 2)};
  const Pose3d world_from_reference = PitchedDown();
  const PlaneSweepView reference = Render(scene, world_from_reference);
  Frame f;
  f.id = 3;
  f.left = reference.image;
  f.calibration = {
      reference.K(0, 0), reference.K(1, 1), reference.K(0, 2), reference.K(1, 2), 1.0, kWidth, kHeight};
  f.world_from_cam = world_from_reference;
  f.labels = cv::Mat(kHeight, kWidth, CV_8UC1, cv::Scalar(ClassMap::Cityscapes().FindByName("road")));
  for (const Eigen::Vector3d& c : {Eigen::Vector3d(-1.0, 0.0, 0.0), Eigen::Vector3d(1.0, 0.0, 0.0),
                                   Eigen::Vector3d(0.0, -0.6, 0.0), Eigen::Vector3d(0.3, 0.0, 1.0)}) {
    Pose3d moved = world_from_reference;
    moved.translation() += world_from_reference.linear() * c;
    f.neighbour_views.push_back(Render(scene, moved));
  }
  DepthOptions depth;
  depth.min_depth_m = 2.0;
  depth.max_depth_m = 20.0;
  depth.max_points_per_frame = 0;  // every point
  SemanticsOptions semantics;
  semantics.source = LabelSource::kDisk;
  PlaneSweepOptions sweep;
  sweep.num_planes = 96;
  sweep.min_depth_m = 2.0;
  sweep.max_depth_m = 20.0;
  // The points within 2 % of their depth from the ground, with and without the label directions.
  auto on_ground = [&](bool label_directions) {
    sweep.label_directions = label_directions;
    const LabelledCloud cloud =
        StereoLabelStage(depth, semantics, ClassMap::Cityscapes(), false, sweep).Process(f, nullptr);
    int close = 0;
    for (const Eigen::Vector3d& p : cloud.positions_world) {
      const double depth_m = (world_from_reference.inverse() * p).z();
      close += std::abs(p.y() - kHeightM) <= 0.02 * depth_m * std::sin(0.1745 + 0.05) + 0.01;
    }
    return close;
  };
  const int fronto = on_ground(false), with_ground = on_ground(true);
  std::cout << "[ measured ] points on the ground: fronto-parallel " << fronto
            << ", with the ground's planes " << with_ground << "\n";
  EXPECT_GT(with_ground, fronto + fronto / 5)
      << "fronto-parallel " << fronto << ", with the ground's planes " << with_ground;
}

// Each stereo frame with a pose gets its right view and the earlier frames' left views, in reading order.
TEST(StereoNeighbourReader, HandsEachFrameItsRightViewAndTheEarlierFramesViews) {
  std::deque<Frame> frames;
  for (int i = 0; i < 4; ++i) {
    Pose3d pose = Pose3d::Identity();
    pose.translation().z() = i;
    frames.push_back(Plane(i, pose));
  }
  StereoNeighbourReader reader(std::make_unique<test::FramesReader>(std::move(frames)), 2);
  std::vector<std::size_t> views;
  while (auto f = reader.Next()) {
    views.push_back(f->neighbour_views.size());
    if (f->id == 3) {
      EXPECT_EQ(f->neighbour_views[1].frame_id, 2);
      EXPECT_EQ(f->neighbour_views[2].frame_id, 1);
    }
  }
  EXPECT_EQ(views, (std::vector<std::size_t>{1, 2, 3, 3}));
}

// A scene nearer than plane_sweep.stereo_min_depth_m keeps SGBM's depth: the stage's cloud with the sweep
// beside SGBM is the cloud of SGBM alone, point for point.
TEST(StereoLabelStage, KeepsSgbmsDepthNearerThanTheSweepsRange) {
  PlaneSweepOptions sweep;
  sweep.num_planes = 16;
  sweep.stereo_past_frames = 2;
  std::deque<Frame> frames;
  for (int i = 0; i < 3; ++i) {
    Pose3d pose = Pose3d::Identity();
    pose.translation().x() = 0.3 * i;
    frames.push_back(Plane(i, pose));
  }
  StereoNeighbourReader reader(std::make_unique<test::FramesReader>(std::move(frames)), 2);
  StereoLabelStage alone(SmallDepth(), SemanticsOptions{}, ClassMap::Cityscapes());
  StereoLabelStage with_sweep(SmallDepth(), SemanticsOptions{}, ClassMap::Cityscapes(), false, sweep);
  while (auto f = reader.Next()) {
    const LabelledCloud a = alone.Process(*f, nullptr), b = with_sweep.Process(*f, nullptr);
    ASSERT_EQ(a.size(), b.size()) << "frame " << f->id;
    ASSERT_GT(a.size(), 0u);
    for (std::size_t i = 0; i < a.size(); ++i)
      ASSERT_EQ(a.positions_world[i], b.positions_world[i]) << "frame " << f->id;
  }
}

}  // namespace
}  // namespace semap
