#include "engine/pipeline/internal/label_budget.h"

#include <algorithm>
#include <cmath>

#include "engine/core/check.h"

namespace semap::pipeline_internal {

LabelBudget::LabelBudget(double frame_period_ms, int cores, int first_gap_frames, int max_gap_frames)
    : frame_period_ms_(frame_period_ms),
      cores_(cores),
      first_gap_frames_(first_gap_frames),
      max_gap_frames_(max_gap_frames) {
  SEMAP_ASSERT(frame_period_ms > 0.0 && cores >= 1, "period " << frame_period_ms << " ms, " << cores);
  SEMAP_ASSERT(first_gap_frames >= 1 && first_gap_frames <= max_gap_frames,
               "gaps " << first_gap_frames << ", " << max_gap_frames);
}

void LabelBudget::RecordStageMs(int stage, double ms) {
  SEMAP_ASSERT(stage >= 0 && stage < kStages, "stage " << stage);
  if (!(ms >= 0.0) || !std::isfinite(ms)) return;
  std::lock_guard<std::mutex> lock(mutex_);
  stage_ms_[stage] = stage_seen_[stage] ? (1.0 - kSmoothing) * stage_ms_[stage] + kSmoothing * ms : ms;
  stage_seen_[stage] = true;
}

void LabelBudget::RecordSegmentMs(double ms) {
  if (!(ms >= 0.0) || !std::isfinite(ms)) return;
  std::lock_guard<std::mutex> lock(mutex_);
  segment_ms_ = segment_seen_ ? (1.0 - kSmoothing) * segment_ms_ + kSmoothing * ms : ms;
  segment_seen_ = true;
}

int LabelBudget::GapFrames() const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!segment_seen_ || !std::all_of(stage_seen_, stage_seen_ + kStages, [](bool seen) { return seen; }))
    return first_gap_frames_;
  return GapFor(frame_period_ms_, cores_, stage_ms_[0] + stage_ms_[1] + stage_ms_[2], segment_ms_,
                max_gap_frames_);
}

int LabelBudget::GapFor(double frame_period_ms, int cores, double frame_ms, double segment_ms,
                        int max_gap_frames) {
  const double left_ms = cores * frame_period_ms - frame_ms;
  if (!(left_ms > 0.0)) return max_gap_frames;
  const double gap = std::ceil(segment_ms / left_ms);
  return static_cast<int>(std::clamp(gap, 1.0, static_cast<double>(max_gap_frames)));
}

}  // namespace semap::pipeline_internal
