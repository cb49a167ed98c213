// semap_enet_keyframe_eval: what running ENet on keyframes only (semantics.enet_every_frames) does to the
// labels of the depth stage's points, on any sequence semap reads.
//
// Every frame goes through the pipeline's depth stage (StereoLabelStage with keyframe labels, default depth
// options, semantics.drop_sky off so that every configuration labels the same points) once per
// configuration: keyframes every N frames (KeyframeSchedule, as the pipeline chooses them), the frames
// between them labelled from their keyframe by reprojection or reuse (semantics.enet_propagation). Label
// sources: ENet (the keyframe's ENet labels) and, when the sequence has label images (a generated sequence's
// exact labels), those (isolating what propagation itself costs). Reported per configuration, over all frames
// and over the frames between keyframes only:
//   - accuracy: share of points whose label is the exact label at their pixel (sequences with label images);
//   - role accuracy: the same for the simplifier's role (ground / wall / keep);
//   - agreement: share of points labelled as with the same source on every frame (N = 1); for ENet, the
//     reference is ENet on every frame at --reference-input (default: semantics' default input), so that a
//     smaller --enet-input is measured against the default network input;
//   - agreement per class: for each class of the reference, the share of its points given that class (the
//     ENet rows; all frames).
//
// Usage: semap_enet_keyframe_eval SEQUENCE [--frames N] [--every 1,2,4,8] [--model FILE]
//        [--enet-input 1024x512] [--reference-input 1024x512] [--write-labels DIR]
// --write-labels writes each frame's ENet label image (NNNNNN.png for KITTI odometry, NNNNNNNNNN.png for
// raw / generated sequences), usable as input.labels_dir ("a run with label files" in bench/enet_rate.sh).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
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
  std::string enet_input, reference_input;
  std::string write_labels;
  app.add_option("SEQUENCE", sequence, "dataset folder (KITTI raw, odometry, or generated)")->required();
  app.add_option("--frames", max_frames, "frames to evaluate (0 = all)");
  app.add_option("--every", every, "keyframe intervals to evaluate (1 = ENet on every frame, the reference)")
      ->delimiter(',');
  app.add_option("--model", model, "ENet model");
  app.add_option("--enet-input", enet_input, "ENet input size WxH (default: semantics' default)");
  app.add_option(
      "--reference-input", reference_input,
      "ENet input size WxH of the agreement reference, ENet on every frame (default: semantics' default)");
  app.add_option("--write-labels", write_labels, "write each frame's ENet label image into this folder");
  CLI11_PARSE(app, argc, argv);
  try {
    namespace fs = std::filesystem;
    semap::SemanticsOptions semantics;
    semantics.source = semap::LabelSource::kEnet;
    semantics.enet_model_path = model;
    semantics.drop_sky = false;  // the same points in every configuration
    semap::SemanticsOptions reference_semantics = semantics;
    if (!enet_input.empty() && std::sscanf(enet_input.c_str(), "%dx%d", &semantics.enet_input_width_px,
                                           &semantics.enet_input_height_px) != 2) {
      throw std::runtime_error("--enet-input: expected WxH, got " + enet_input);
    }
    if (!reference_input.empty() &&
        std::sscanf(reference_input.c_str(), "%dx%d", &reference_semantics.enet_input_width_px,
                    &reference_semantics.enet_input_height_px) != 2) {
      throw std::runtime_error("--reference-input: expected WxH, got " + reference_input);
    }
    semantics.Check();
    reference_semantics.Check();
    const bool separate_reference =
        reference_semantics.enet_input_width_px != semantics.enet_input_width_px ||
        reference_semantics.enet_input_height_px != semantics.enet_input_height_px;
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
        std::snprintf(name, sizeof(name), raw_names ? "%010lld.png" : "%06lld.png",
                      static_cast<long long>(f.id));
        const fs::path path = fs::path(write_labels) / name;
        if (!cv::imwrite(path.string(), enet_labels.back()))
          throw std::runtime_error(path.string() + ": cannot write");
      }
    }

    // The reference's ENet labels when its input differs (untimed).
    std::vector<cv::Mat> reference_labels;
    if (separate_reference) {
      auto reference_segmenter = semap::MakeSegmenter(reference_semantics);
      for (const auto& f : frames) reference_labels.push_back(reference_segmenter->Segment(f.left));
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
    // ENet configurations' agreement per reference class: name → class → {points, agreeing}.
    std::vector<std::pair<std::string, std::map<Label, std::pair<std::size_t, std::size_t>>>> per_class;
    if (separate_reference) {
      // The reference: the depth stage's points labelled by the reference's ENet on every frame.
      semap::StereoLabelStage stage(depth, semantics, classes, /*labels_from_keyframes=*/true);
      semap::KeyframeLabels keyframe;
      for (std::size_t k = 0; k < frames.size(); ++k) {
        keyframe.frame_id = frames[k].id;
        keyframe.world_from_cam = frames[k].world_from_cam;
        keyframe.labels = reference_labels[k];
        reference["enet"].push_back(stage.Process(frames[k], &keyframe).labels);
      }
    }
    std::printf(
        "| labels | every N | propagation | keyframes | accuracy, all frames | between keyframes | "
        "role accuracy, all | agreement with N = 1, all | between keyframes |\n");
    std::printf("|---|---:|---|---:|---:|---:|---:|---:|---:|\n");
    for (const std::string& label_source : sources) {
      for (const int n : every) {
        for (const auto propagation :
             {semap::LabelPropagation::kReproject, semap::LabelPropagation::kReuse}) {
          if (n == 1 && propagation == semap::LabelPropagation::kReuse) continue;  // the same as reproject
          semap::SemanticsOptions s = semantics;
          s.enet_propagation = propagation;
          semap::StereoLabelStage stage(depth, s, classes, /*labels_from_keyframes=*/true);
          semap::KeyframeSchedule schedule(n);
          semap::KeyframeLabels keyframe;
          Result r;
          std::vector<std::vector<Label>>& ref = reference[label_source];
          const bool fill_reference = n == 1 && !(label_source == "enet" && separate_reference);
          std::map<Label, std::pair<std::size_t, std::size_t>>* classes_agree = nullptr;
          if (label_source == "enet") {
            char name[64];
            std::snprintf(
                name, sizeof(name), "N = %d%s", n,
                n == 1 ? ""
                       : (propagation == semap::LabelPropagation::kReproject ? ", reproject" : ", reuse"));
            per_class.emplace_back(name, std::map<Label, std::pair<std::size_t, std::size_t>>{});
            classes_agree = &per_class.back().second;
          }
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
            if (fill_reference) ref.push_back(cloud.labels);
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
              if (classes_agree != nullptr) {
                auto& c = (*classes_agree)[per_frame[i]];
                ++c.first;
                c.second += label == per_frame[i];
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
                      Cell(r.all, r.all.correct, exact).c_str(),
                      Cell(r.between, r.between.correct, exact).c_str(),
                      Cell(r.all, r.all.role_correct, exact).c_str(), Cell(r.all, r.all.agree, true).c_str(),
                      Cell(r.between, r.between.agree, true).c_str());
          std::fflush(stdout);
        }
      }
    }
    // Agreement per class of the reference (ENet on every frame at the reference input), all frames.
    std::printf(
        "\nAgreement per class with ENet on every frame at %dx%d (share of the points of each reference "
        "class given that class; ENet at %dx%d):\n\n| class | points |",
        reference_semantics.enet_input_width_px, reference_semantics.enet_input_height_px,
        semantics.enet_input_width_px, semantics.enet_input_height_px);
    for (const auto& [name, counts] : per_class) std::printf(" %s |", name.c_str());
    std::printf("\n|---|---:|");
    for (std::size_t k = 0; k < per_class.size(); ++k) std::printf("---:|");
    std::printf("\n");
    if (!per_class.empty()) {
      for (const auto& [label, first] : per_class.front().second) {
        const std::string name = classes.Contains(label) ? classes.Get(label).name : std::to_string(label);
        std::printf("| %s | %zu |", name.c_str(), first.first);
        for (const auto& [name, counts] : per_class) {
          const auto it = counts.find(label);
          const auto c = it == counts.end() ? std::pair<std::size_t, std::size_t>{0, 0} : it->second;
          std::printf(" %.1f %% |", c.first ? 100.0 * double(c.second) / double(c.first) : 0.0);
        }
        std::printf("\n");
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
