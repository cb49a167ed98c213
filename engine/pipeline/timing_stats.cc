#include "engine/pipeline/timing_stats.h"

#include <algorithm>
#include <cmath>

namespace semap {

void TimingStats::Add(double ms) {
  if (recent_.size() < window_) {
    recent_.push_back(ms);
  } else {
    recent_[next_] = ms;
    next_ = (next_ + 1) % window_;
  }
  ++count_;
  sum_ += ms;
  max_ = std::max(max_, ms);
  last_ = ms;
}

double TimingStats::Percentile(double q) const {
  if (recent_.empty()) return 0.0;
  std::vector<double> v = recent_;
  const auto rank = static_cast<size_t>(std::ceil(std::clamp(q, 0.0, 1.0) * static_cast<double>(v.size())));
  const size_t k = rank == 0 ? 0 : rank - 1;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

}  // namespace semap
