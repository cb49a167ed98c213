#include "engine/simplify/windowed_simplifier.h"

#include <chrono>
#include <map>

#include "engine/simplify/internal/methods.h"

namespace semap {

WindowedSimplifier::WindowedSimplifier(const SimplifyOptions& options, ClassMap class_map)
    : options_(options), class_map_(std::move(class_map)) {
  options_.Check();
}

void WindowedSimplifier::Reset() {
  window_.clear();
  totals_.clear();
  frames_processed_ = 0;
}

WindowedSimplifier::FrameResult WindowedSimplifier::Process(const LabelledCloud& frame) {
  frame.AssertConsistent();
  const auto start = std::chrono::steady_clock::now();

  // Context: the decided points of the window, then the frame. Labels are made explicit on both sides so
  // that Append never mixes "absent" with a default label.
  auto with_labels = [&](const LabelledCloud& c) {
    LabelledCloud copy = c;
    if (copy.labels.empty()) copy.labels.assign(copy.size(), class_map_.unlabelled_id());
    return copy;
  };
  LabelledCloud context;
  simplify::DensitySums prior;
  for (const auto& w : window_) {
    context.Append(w.kept);
    for (int g = 0; g < simplify::kNumGroups; ++g) {
      prior.sum[g] += w.density_sum[g];
      prior.count[g] += w.density_count[g];
    }
  }
  const std::size_t num_fixed = context.size();
  context.Append(with_labels(frame));

  // A different, reproducible stream of random numbers per frame.
  constexpr std::uint64_t kGolden = 0x9E3779B97F4A7C15ULL;
  SimplifyOptions frame_options = options_;
  frame_options.seed = options_.seed + kGolden * (frames_processed_ + 1);
  simplify::DensitySums batch;
  const auto removed = simplify::RunMethod(context, class_map_, frame_options, num_fixed, prior, &batch);

  FrameResult out;
  simplify::CollectResult(context, class_map_, removed, num_fixed, &out.result);
  out.kept = frame.Subset(out.result.kept_indices);

  // Slide the window.
  WindowFrame w;
  w.kept = with_labels(out.kept);
  w.density_sum.assign(batch.sum.begin(), batch.sum.end());
  w.density_count.assign(batch.count.begin(), batch.count.end());
  window_.push_back(std::move(w));
  while (window_.size() > static_cast<std::size_t>(options_.window_frames)) window_.pop_front();

  // Totals.
  std::map<Label, ClassSimplifyStats> totals;
  for (const auto& s : totals_) totals[s.label] = s;
  for (const auto& s : out.result.per_class) {
    auto& t = totals[s.label];
    t.label = s.label;
    t.in += s.in;
    t.kept += s.kept;
    t.removed += s.removed;
  }
  totals_.clear();
  for (const auto& [label, s] : totals) totals_.push_back(s);
  ++frames_processed_;
  out.result.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace semap
