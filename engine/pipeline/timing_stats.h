// Running statistics of a stage's time per frame: mean and max over the whole run, percentiles over a
// bounded window of recent frames (memory stays constant on long runs). Not thread-safe.
#pragma once

#include <cstddef>
#include <vector>

namespace semap {

class TimingStats {
 public:
  explicit TimingStats(size_t window = 1024) : window_(window) {}
  void Add(double ms);
  size_t count() const { return count_; }
  double last() const { return last_; }
  double mean() const { return count_ ? sum_ / static_cast<double>(count_) : 0.0; }
  double max() const { return max_; }
  // Percentile q in [0, 1] of the recent window (nearest rank); 0 when empty.
  double Percentile(double q) const;

 private:
  size_t window_;
  std::vector<double> recent_;  // ring buffer
  size_t next_ = 0;
  size_t count_ = 0;
  double sum_ = 0.0;
  double max_ = 0.0;
  double last_ = 0.0;
};

}  // namespace semap
