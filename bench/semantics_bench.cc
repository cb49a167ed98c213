// Semantic stage micro-benchmarks: ENet Cityscapes on a real KITTI frame (one core, cv::setNumThreads(1)),
// the first-camera labelling of a dense frame cloud, and a keyframe's labels reprojected into the next frame
// (what a frame between keyframes costs instead of ENet, semantics.enet_every_frames).
// Run: ./build/bench/semantics_bench
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <opencv2/core/utility.hpp>
#include <string>

#include "engine/depth/stereo_depth.h"
#include "engine/semantics/keyframe_labels.h"
#include "engine/semantics/labelling.h"
#include "engine/semantics/segmenter.h"
#include "tests/common/kitti2015_subset.h"

namespace {

std::string Shared() {
  const char* env = std::getenv("SEMAP_SHARED");
  return env ? env : std::string(SEMAP_SHARED_DIR);
}

const semap::test::Stereo2015Frame& TestFrame() {
  static const semap::test::Stereo2015Frame frame =
      semap::test::LoadStereo2015Frame(Shared() + "/data/kitti_stereo2015_subset", "000002_10");
  return frame;
}

void BM_EnetSegment(benchmark::State& state) {
  cv::setNumThreads(static_cast<int>(state.range(0)));
  semap::SemanticsOptions o;
  o.source = semap::LabelSource::kEnet;
  o.enet_model_path = Shared() + "/models/enet-cityscapes/enet-model.net";
  // Second argument: 1 = the fused head (the default), 0 = OpenCV's last layer over the whole output.
  const bool fused = state.range(1) != 0;
  semap::EnetSegmenter segmenter(o, fused ? semap::EnetHead::kFused : semap::EnetHead::kNetwork);
  const cv::Mat& image = TestFrame().frame.left;
  segmenter.Segment(image);  // first call allocates the network's buffers
  for (auto _ : state) benchmark::DoNotOptimize(segmenter.Segment(image));
  state.SetLabel(std::to_string(cv::getNumThreads()) + " thread(s), " +
                 (segmenter.head() == semap::EnetHead::kFused ? "fused head" : "network head"));
}
BENCHMARK(BM_EnetSegment)
    ->Args({1, 1})
    ->Args({1, 0})
    ->Args({2, 1})
    ->Args({2, 0})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(3.0);

void BM_FirstCameraLabels(benchmark::State& state) {
  cv::setNumThreads(1);
  const auto& f = TestFrame().frame;
  const semap::LabelledCloud cloud = semap::StereoDepth(semap::DepthOptions{}).Process(f);
  const cv::Mat labels(f.left.size(), CV_8UC1, cv::Scalar(3));
  for (auto _ : state) {
    semap::LabelledCloud c = cloud;
    benchmark::DoNotOptimize(semap::ApplyFirstCameraLabels(c, f.id, labels, f.left.size(), 0));
  }
  state.counters["points"] = static_cast<double>(cloud.size());
}
BENCHMARK(BM_FirstCameraLabels)->Unit(benchmark::kMillisecond);

// The frame's labels from a keyframe 1 m behind it (one core): every pixel with an SGBM depth (the frame's
// own disparity) lifted, moved and projected; the others as points at infinity.
void BM_PropagateLabels(benchmark::State& state) {
  const auto& f = TestFrame().frame;
  semap::StereoCalibration intrinsics = f.calibration;
  intrinsics.width_px = f.left.cols;
  intrinsics.height_px = f.left.rows;
  const cv::Mat disparity = semap::StereoDepth(semap::DepthOptions{}).Compute(f.left, f.right).disparity_px;
  cv::Mat depth_m(disparity.size(), CV_32FC1, cv::Scalar(0.0f));
  const cv::Mat valid = disparity > 0.0f;
  cv::divide(intrinsics.fx_px * intrinsics.baseline_m, disparity, depth_m, 1.0, CV_32F);
  depth_m.setTo(0.0f, ~valid);
  semap::KeyframeLabels keyframe;
  keyframe.world_from_cam = semap::Pose3d::Identity();
  keyframe.labels = cv::Mat(f.left.size(), CV_8UC1, cv::Scalar(3));
  const semap::Pose3d world_from_cam(Eigen::Translation3d(0.0, 0.0, 1.0));
  for (auto _ : state) {
    benchmark::DoNotOptimize(semap::PropagateLabels(keyframe, world_from_cam, depth_m, intrinsics, 0));
  }
  state.counters["pixels"] = static_cast<double>(f.left.total());
  state.counters["with_depth"] = static_cast<double>(cv::countNonZero(valid));
}
BENCHMARK(BM_PropagateLabels)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
