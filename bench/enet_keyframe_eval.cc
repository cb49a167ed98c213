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

// Per class of the reference: {points, points given that class}.
using ClassAgreement = std::map<Label, std::pair<std::size_t, std::size_t>>;

// Sets the ENet input size of `semantics` from "WxH" (`option` names it in the error); nothing when empty.
void ParseInputSize(const std::string& text, const char* option, semap::SemanticsOptions* semantics) {
  if (!text.empty() && std::sscanf(text.c_str(), "%dx%d", &semantics->enet_input_width_px,
                                   &semantics->enet_input_height_px) != 2) {
    throw std::runtime_error(std::string(option) + ": expected WxH, got " + text);
  }
}

// Each frame's ENet labels (what a keyframe gets from the segment thread), and their CPU and wall time.
struct EnetLabels {
  std::vector<cv::Mat> labels;
  double cpu_s = 0.0, wall_s = 0.0;
};

// ENet on every frame, timed after a warm-up (network buffers); each label image written into
// `write_labels` when it is not empty (KITTI odometry names when !raw_names).
EnetLabels LabelEveryFrame(const semap::SemanticsOptions& semantics, const std::vector<semap::Frame>& frames,
                           const std::string& write_labels, bool raw_names) {
  namespace fs = std::filesystem;
  auto segmenter = semap::MakeSegmenter(semantics);
  segmenter->Segment(frames.front().left);  // warm-up: network buffers
  EnetLabels out;
  if (!write_labels.empty()) fs::create_directories(write_labels);
  for (const auto& f : frames) {
    const std::clock_t c0 = std::clock();
    const auto t0 = std::chrono::steady_clock::now();
    out.labels.push_back(segmenter->Segment(f.left));
    out.cpu_s += double(std::clock() - c0) / CLOCKS_PER_SEC;
    out.wall_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!write_labels.empty()) {
      char name[32];
      std::snprintf(name, sizeof(name), raw_names ? "%010lld.png" : "%06lld.png",
                    static_cast<long long>(f.id));
      const fs::path path = fs::path(write_labels) / name;
      if (!cv::imwrite(path.string(), out.labels.back()))
        throw std::runtime_error(path.string() + ": cannot write");
    }
  }
  return out;
}

// The depth stage's points of every frame labelled from that frame's own `labels` (ENet on every frame).
std::vector<std::vector<Label>> PointLabelsFromEveryFrame(const semap::SemanticsOptions& semantics,
                                                          const semap::ClassMap& classes,
                                                          const std::vector<semap::Frame>& frames,
                                                          const std::vector<cv::Mat>& labels) {
  semap::StereoLabelStage stage(semap::DepthOptions(), semantics, classes, /*labels_from_keyframes=*/true);
  semap::KeyframeLabels keyframe;
  std::vector<std::vector<Label>> out;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    keyframe.frame_id = frames[k].id;
    keyframe.world_from_cam = frames[k].world_from_cam;
    keyframe.labels = labels[k];
    out.push_back(stage.Process(frames[k], &keyframe).labels);
  }
  return out;
}

// Adds one frame's points to the tallies: accuracy against the frame's exact labels (when `exact`),
// agreement with `reference` (the same points' labels with N = 1), per class when `classes_agree`.
void TallyFrame(const semap::Frame& f, const semap::LabelledCloud& cloud, const std::vector<Label>& reference,
                const semap::ClassMap& classes, bool exact, bool is_keyframe, Result* r,
                ClassAgreement* classes_agree) {
  if (reference.size() != cloud.size()) throw std::runtime_error("point sets differ between runs");
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Label label = cloud.labels[i];
    bool correct = false, role = false;
    if (exact) {
      const int u = static_cast<int>(std::lround(cloud.pixels_px[i].x()));
      const int v = static_cast<int>(std::lround(cloud.pixels_px[i].y()));
      const Label truth =
          f.labels.at<Label>(std::clamp(v, 0, f.labels.rows - 1), std::clamp(u, 0, f.labels.cols - 1));
      correct = label == truth;
      role = classes.Role(label) == classes.Role(truth);
    }
    if (classes_agree != nullptr) {
      auto& c = (*classes_agree)[reference[i]];
      ++c.first;
      c.second += label == reference[i];
    }
    for (Tally* t : {&r->all, is_keyframe ? nullptr : &r->between}) {
      if (t == nullptr) continue;
      ++t->points;
      t->correct += correct;
      t->role_correct += role;
      t->agree += label == reference[i];
    }
  }
}

// What one configuration labels, frame by frame, and what it is compared with.
struct Configuration {
  const std::vector<semap::Frame>& frames;
  const semap::ClassMap& classes;
  bool exact = false;  // the frames have exact label images
  const std::vector<cv::Mat>& enet_labels;
};

// One configuration through every frame: keyframes every `n` frames labelled by `label_source` ("exact": the
// label images, else ENet's), the frames between them by `semantics`' propagation. With `fill_reference`,
// each frame's labels are appended to `reference` (N = 1) before it is compared with them.
Result RunConfiguration(const Configuration& c, const std::string& label_source, int n,
                        const semap::SemanticsOptions& semantics, bool fill_reference,
                        std::vector<std::vector<Label>>* reference, ClassAgreement* classes_agree) {
  semap::StereoLabelStage stage(semap::DepthOptions(), semantics, c.classes, /*labels_from_keyframes=*/true);
  semap::KeyframeSchedule schedule(n);
  semap::KeyframeLabels keyframe;
  Result r;
  for (std::size_t k = 0; k < c.frames.size(); ++k) {
    const semap::Frame& f = c.frames[k];
    const bool has_pose = f.world_from_cam.has_value();
    const bool is_keyframe = schedule.IsDue(f.id, has_pose);
    if (is_keyframe) {
      schedule.Record(f.id, has_pose);
      keyframe.frame_id = f.id;
      keyframe.world_from_cam = f.world_from_cam;
      keyframe.labels = label_source == "exact" ? f.labels : c.enet_labels[k];
      ++r.keyframes;
    }
    const semap::LabelledCloud cloud = stage.Process(f, &keyframe);
    if (fill_reference) reference->push_back(cloud.labels);
    TallyFrame(f, cloud, reference->at(k), c.classes, c.exact, is_keyframe, &r, classes_agree);
  }
  return r;
}

// The configuration's name in the per-class table.
std::string ConfigurationName(int n, semap::LabelPropagation propagation) {
  char name[64];
  std::snprintf(
      name, sizeof(name), "N = %d%s", n,
      n == 1 ? "" : (propagation == semap::LabelPropagation::kReproject ? ", reproject" : ", reuse"));
  return name;
}

// Every configuration (label source × N × propagation; N = 1 first, the agreement reference of the others),
// a table row each. `reference` holds each source's N = 1 labels (ENet's already when its reference input
// differs); the ENet configurations' per-class agreement goes to `per_class`.
void RunConfigurations(const Configuration& c, const std::vector<std::string>& sources,
                       const std::vector<int>& every, const semap::SemanticsOptions& semantics,
                       bool separate_reference,
                       std::map<std::string, std::vector<std::vector<Label>>>* reference,
                       std::vector<std::pair<std::string, ClassAgreement>>* per_class) {
  std::printf(
      "| labels | every N | propagation | keyframes | accuracy, all frames | between keyframes | "
      "role accuracy, all | agreement with N = 1, all | between keyframes |\n");
  std::printf("|---|---:|---|---:|---:|---:|---:|---:|---:|\n");
  for (const std::string& label_source : sources) {
    for (const int n : every) {
      for (const auto propagation : {semap::LabelPropagation::kReproject, semap::LabelPropagation::kReuse}) {
        if (n == 1 && propagation == semap::LabelPropagation::kReuse) continue;  // the same as reproject
        semap::SemanticsOptions s = semantics;
        s.enet_propagation = propagation;
        const bool fill_reference = n == 1 && !(label_source == "enet" && separate_reference);
        ClassAgreement* classes_agree = nullptr;
        if (label_source == "enet") {
          per_class->emplace_back(ConfigurationName(n, propagation), ClassAgreement{});
          classes_agree = &per_class->back().second;
        }
        const Result r = RunConfiguration(c, label_source, n, s, fill_reference, &(*reference)[label_source],
                                          classes_agree);
        std::printf("| %s | %d | %s | %d | %s | %s | %s | %s | %s |\n", label_source.c_str(), n,
                    n == 1 ? "–" : semap::LabelPropagationName(propagation), r.keyframes,
                    Cell(r.all, r.all.correct, c.exact).c_str(),
                    Cell(r.between, r.between.correct, c.exact).c_str(),
                    Cell(r.all, r.all.role_correct, c.exact).c_str(), Cell(r.all, r.all.agree, true).c_str(),
                    Cell(r.between, r.between.agree, true).c_str());
        std::fflush(stdout);
      }
    }
  }
}

// Agreement per class of the reference (ENet on every frame at the reference input), all frames.
void PrintPerClass(const semap::SemanticsOptions& semantics,
                   const semap::SemanticsOptions& reference_semantics, const semap::ClassMap& classes,
                   const std::vector<std::pair<std::string, ClassAgreement>>& per_class) {
  std::printf(
      "\nAgreement per class with ENet on every frame at %dx%d (share of the points of each reference "
      "class given that class; ENet at %dx%d):\n\n| class | points |",
      reference_semantics.enet_input_width_px, reference_semantics.enet_input_height_px,
      semantics.enet_input_width_px, semantics.enet_input_height_px);
  for (const auto& [name, counts] : per_class) std::printf(" %s |", name.c_str());
  std::printf("\n|---|---:|");
  for (std::size_t k = 0; k < per_class.size(); ++k) std::printf("---:|");
  std::printf("\n");
  if (per_class.empty()) return;
  for (const auto& [label, first] : per_class.front().second) {
    const std::string name = classes.Contains(label) ? classes.Get(label).name : std::to_string(label);
    std::printf("| %s | %zu |", name.c_str(), first.first);
    for (const auto& [config_name, counts] : per_class) {
      const auto it = counts.find(label);
      const auto c = it == counts.end() ? std::pair<std::size_t, std::size_t>{0, 0} : it->second;
      std::printf(" %.1f %% |", c.first ? 100.0 * double(c.second) / double(c.first) : 0.0);
    }
    std::printf("\n");
  }
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
    semap::SemanticsOptions semantics;
    semantics.source = semap::LabelSource::kEnet;
    semantics.enet_model_path = model;
    semantics.drop_sky = false;  // the same points in every configuration
    semap::SemanticsOptions reference_semantics = semantics;
    ParseInputSize(enet_input, "--enet-input", &semantics);
    ParseInputSize(reference_input, "--reference-input", &reference_semantics);
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

    const EnetLabels enet = LabelEveryFrame(semantics, frames, write_labels, raw_names);
    // The per-frame labels of each source (N = 1), per frame and point: the agreement reference. The
    // reference's ENet labels, when its input differs, label the depth stage's points first (untimed).
    std::map<std::string, std::vector<std::vector<Label>>> reference;
    if (separate_reference) {
      std::vector<cv::Mat> reference_labels;
      auto reference_segmenter = semap::MakeSegmenter(reference_semantics);
      for (const auto& f : frames) reference_labels.push_back(reference_segmenter->Segment(f.left));
      reference["enet"] = PointLabelsFromEveryFrame(semantics, classes, frames, reference_labels);
    }
    // N = 1 first: it is the agreement reference of the others.
    std::sort(every.begin(), every.end());
    every.erase(std::unique(every.begin(), every.end()), every.end());
    if (every.empty() || every.front() != 1) every.insert(every.begin(), 1);
    std::vector<std::string> sources = {"enet"};
    if (exact) sources.push_back("exact");
    // ENet configurations' agreement per reference class: name → class → {points, agreeing}.
    std::vector<std::pair<std::string, ClassAgreement>> per_class;
    RunConfigurations({frames, classes, exact, enet.labels}, sources, every, semantics, separate_reference,
                      &reference, &per_class);
    PrintPerClass(semantics, reference_semantics, classes, per_class);
    std::printf("\n%s: %zu frames, ENet input %dx%d: %.0f ms CPU, %.0f ms wall per frame\n", sequence.c_str(),
                frames.size(), semantics.enet_input_width_px, semantics.enet_input_height_px,
                1000.0 * enet.cpu_s / double(frames.size()), 1000.0 * enet.wall_s / double(frames.size()));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "semap_enet_keyframe_eval: %s\n", e.what());
    return 1;
  }
  return 0;
}
