// A PipelineClock the test moves: NowS() is the time the test (or a fake stage) set, and a thread sleeping on
// it wakes only when that time has come. The test can wait until a thread sleeps for a given time: the
// reader waiting for a frame's due time. No result depends on the wall clock; the bounded waits only keep a
// broken pipeline from hanging the test.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <functional>
#include <mutex>

#include "engine/pipeline/clock.h"

namespace semap::test {

class ManualClock final : public PipelineClock {
 public:
  double NowS() const override {
    std::lock_guard<std::mutex> lock(mutex_);
    return now_s_;
  }

  void SleepUntilS(double t_s, const std::function<bool()>& stop) override {
    std::unique_lock<std::mutex> lock(mutex_);
    sleeping_until_s_ = t_s;
    changed_.notify_all();
    while (now_s_ < t_s && !stop()) changed_.wait_for(lock, kStopPoll);
    sleeping_until_s_ = kNone;
    changed_.notify_all();
  }

  void AdvanceTo(double t_s) {
    std::lock_guard<std::mutex> lock(mutex_);
    now_s_ = std::max(now_s_, t_s);
    changed_.notify_all();
  }
  void Advance(double dt_s) {
    std::lock_guard<std::mutex> lock(mutex_);
    now_s_ += dt_s;
    changed_.notify_all();
  }

  // Blocks until a thread sleeps until `t_s` (within 1 µs); false when none does within `timeout`.
  bool WaitForSleeperUntil(double t_s, std::chrono::seconds timeout = std::chrono::seconds(30)) {
    std::unique_lock<std::mutex> lock(mutex_);
    return changed_.wait_for(lock, timeout, [&] { return std::abs(sleeping_until_s_ - t_s) < 1e-6; });
  }

 private:
  static constexpr double kNone = -1e300;
  static constexpr std::chrono::milliseconds kStopPoll{5};
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  double now_s_ = 100.0;  // any origin: the pipeline measures from its start
  double sleeping_until_s_ = kNone;
};

}  // namespace semap::test
