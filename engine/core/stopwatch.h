// Wall time elapsed on the steady clock since a start, in milliseconds: the stage and step timings that runs
// report (frames.csv, summary.json).
#pragma once

#include <chrono>

namespace semap {

// Starts when constructed. Not shared between threads (each timing owns its stopwatch).
class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  double ElapsedMs() const {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

}  // namespace semap
