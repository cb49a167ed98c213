// semap_enet_keyframe_eval: what running ENet on keyframes only (semantics.enet_every_frames) does to the
// labels of the depth stage's points, on any sequence semap reads.
//
// Every frame goes through the pipeline's depth stage (StereoLabelStage with keyframe labels, default depth
// options, semantics.drop_sky off so that every configuration labels the same points) once per
// configuration: keyframes every N frames (KeyframeSchedule, as the pipeline chooses them), the frames between
// them labelled from their keyframe by reprojection or reuse (semantics.enet_propagation). Label sources:
// ENet (the keyframe's ENet labels) and, when the sequence has label images (a generated sequence's exact
// labels), those (isolating what propagation itself costs). Reported per configuration, over all frames and
// over the frames between keyframes only:
//   - accuracy: share of points whose label is the exact label at their pixel (sequences with label images);
//   - role accuracy: the same for the simplifier's role (ground / wall / keep);
//   - agreement: share of points labelled as with the same source on every frame (N = 1).
//
// Usage: semap_enet_keyframe_eval SEQUENCE [--frames N] [--every 1,2,4,8] [--model FILE]
//        [--enet-input 1024x512] [--write-labels DIR]
// --write-labels writes each frame's ENet label image (NNNNNN.png for KITTI odometry, NNNNNNNNNN.png for
// raw / generated sequences), usable as input.labels_dir ("a run with label files" in bench/enet_rate.sh).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "engine/pipeline/semap_stages.h"
#include "engine/semantics/keyframe_labels.h"
#include "engine/semantics/segmenter.h"
#include "io/frame_source.h"

namespace {

using semap::Label;

struct Tally {
  std::size_t points = 0, correct = 0, role_correct = 0, agree = 0;
  double Pct(std::size_t n) const { return points ? 100.0 * double(n) / double(points) : 0.0; }
};

struct Result {
  Tally all, between;  // all frames; frames between keyframes only
  int keyframes = 0;
};

std::string Cell(const Tally& t, std::size_t n, bool available) {
  if (!available || t.points == 0) return "–";
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.2f %%", t.Pct(n));
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Label accuracy and agreement of ENet on keyframes only (reprojected or reused labels)"};
  std::string sequence;
  int max_frames = 0;
  std::vector<int> every = {1, 2, 3, 4, 6, 8};
  std::string model = std::string(SEMAP_SHARED_DIR) + "/models/enet-cityscapes/enet-model.net";
  std::string enet_input;
  std::string write_labels;
  app.add_option("SEQUENCE", sequence, "dataset folder (KITTI raw, odometry, or generated)")->required();
  app.add_option("--frames", max_frames, "frames to evaluate (0 = all)");
  app.add_option("--every", every, "keyframe intervals to evaluate (1 = ENet on every frame, the reference)")
      ->delimiter(',');
  app.add_option("--model", model, "ENet model");
  app.add_option("--enet-input", enet_input, "ENet input size WxH (default: semantics' default)");
  app.add_option("--write-labels", write_labels, "write each frame's ENet label image into this folder");
  CLI11_PARSE(app, argc, argv);
  try {
    namespace fs = std::filesystem;
    semap::SemanticsOptions semantics;
    semantics.source = semap::LabelSource::kEnet;
    semantics.enet_model_path = model;
    semantics.drop_sky = false;  // the same points in every configuration
    if (!enet_input.empty() &&
        std::sscanf(enet_input.c_str(), "%dx%d", &semantics.enet_input_width_px, &semantics.enet_input_height_px) != 2) {
      throw std::runtime_error("--enet-input: expected WxH, got " + enet_input);
    }
    semantics.Check();
    semap::io::FrameSourceOptions input;
    input.load_velodyne = false;
    input.max_frames = max_frames;
    auto source = semap::io::OpenFrameSource(sequence, input);
    const semap::ClassMap classes = source->class_map();
    const bool raw_names = source->layout() != semap::io::DatasetLayout::kKittiOdometry;
    std::vector<semap::Frame> frames;
    while (auto f = source->Next()) frames.push_back(std::move(*f));
    if (frames.empty()) throw std::runtime_error(sequence + ": no frame");
    bool exact = true;
    for (const auto& f : frames) exact = exact && !f.labels.empty() && f.labels.size() == f.left.size();

    // Each frame's ENet labels (what a keyframe gets from the segment thread), timed.
    auto segmenter = semap::MakeSegmenter(semantics);
    segmenter->Segment(frames.front().left);  // warm-up: network buffers
    std::vector<cv::Mat> enet_labels;
    double enet_cpu_s = 0.0, enet_wall_s = 0.0;
    if (!write_labels.empty()) fs::create_directories(write_labels);
    for (const auto& f : frames) {
      const std::clock_t c0 = std::clock();
      const auto t0 = std::chrono::steady_clock::now();
      enet_labels.push_back(segmenter->Segment(f.left));
      enet_cpu_s += double(std::clock() - c0) / CLOCKS_PER_SEC;
      enet_wall_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (!write_labels.empty()) {
        char name[32];
        std::snprintf(name, sizeof(name), raw_names ? "%010lld.png" : "%06lld.png", static_cast<long long>(f.id));
        const fs::path path = fs::path(write_labels) / name;
        if (!cv::imwrite(path.string(), enet_labels.back())) throw std::runtime_error(path.string() + ": cannot write");
      }
    }

    // N = 1 first: it is the agreement reference of the others.
    std::sort(every.begin(), every.end());
    every.erase(std::unique(every.begin(), every.end()), every.end());
    if (every.empty() || every.front() != 1) every.insert(every.begin(), 1);
    const semap::DepthOptions depth;
    std::vector<std::string> sources = {"enet"};
    if (exact) sources.push_back("exact");
    // The per-frame labels of each source (N = 1), per frame and point: the agreement reference.
    std::map<std::string, std::vector<std::vector<Label>>> reference;
    std::printf("| labels | every N | propagation | keyframes | accuracy, all frames | between keyframes | "
                "role accuracy, all | agreement with N = 1, all | between keyframes |\n");
    std::printf("|---|---:|---|---:|---:|---:|---:|---:|---:|\n");
    for (const std::string& label_source : sources) {
      for (const int n : every) {
        for (const auto propagation : {semap::LabelPropagation::kReproject, semap::LabelPropagation::kReuse}) {
          if (n == 1 && propagation == semap::LabelPropagation::kReuse) continue;  // the same as reproject
          semap::SemanticsOptions s = semantics;
          s.enet_propagation = propagation;
          semap::StereoLabelStage stage(depth, s, classes, /*labels_from_keyframes=*/true);
          semap::KeyframeSchedule schedule(n);
          semap::KeyframeLabels keyframe;
          Result r;
          std::vector<std::vector<Label>>& ref = reference[label_source];
          for (std::size_t k = 0; k < frames.size(); ++k) {
            const semap::Frame& f = frames[k];
            const bool has_pose = f.world_from_cam.has_value();
            const bool is_keyframe = schedule.IsDue(f.id, has_pose);
            if (is_keyframe) {
              schedule.Record(f.id, has_pose);
              keyframe.frame_id = f.id;
              keyframe.world_from_cam = f.world_from_cam;
              keyframe.labels = label_source == "exact" ? f.labels : enet_labels[k];
              ++r.keyframes;
            }
            const semap::LabelledCloud cloud = stage.Process(f, &keyframe);
            if (n == 1) ref.push_back(cloud.labels);
            const std::vector<Label>& per_frame = ref.at(k);
            if (per_frame.size() != cloud.size()) throw std::runtime_error("point sets differ between runs");
            for (std::size_t i = 0; i < cloud.size(); ++i) {
              const Label label = cloud.labels[i];
              bool correct = false, role = false;
              if (exact) {
                const int u = static_cast<int>(std::lround(cloud.pixels_px[i].x()));
                const int v = static_cast<int>(std::lround(cloud.pixels_px[i].y()));
                const Label truth = f.labels.at<Label>(std::clamp(v, 0, f.labels.rows - 1),
                                                       std::clamp(u, 0, f.labels.cols - 1));
                correct = label == truth;
                role = classes.Role(label) == classes.Role(truth);
              }
              for (Tally* t : {&r.all, is_keyframe ? nullptr : &r.between}) {
                if (t == nullptr) continue;
                ++t->points;
                t->correct += correct;
                t->role_correct += role;
                t->agree += label == per_frame[i];
              }
            }
          }
          std::printf("| %s | %d | %s | %d | %s | %s | %s | %s | %s |\n", label_source.c_str(), n,
                      n == 1 ? "–" : semap::LabelPropagationName(propagation), r.keyframes,
                      Cell(r.all, r.all.correct, exact).c_str(), Cell(r.between, r.between.correct, exact).c_str(),
                      Cell(r.all, r.all.role_correct, exact).c_str(), Cell(r.all, r.all.agree, true).c_str(),
                      Cell(r.between, r.between.agree, true).c_str());
          std::fflush(stdout);
        }
      }
    }
    std::printf("\n%s: %zu frames, ENet input %dx%d: %.0f ms CPU, %.0f ms wall per frame\n", sequence.c_str(),
                frames.size(), semantics.enet_input_width_px, semantics.enet_input_height_px,
                1000.0 * enet_cpu_s / double(frames.size()), 1000.0 * enet_wall_s / double(frames.size()));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "semap_enet_keyframe_eval: %s\n", e.what());
    return 1;
  }
  return 0;
}
