// The clock the pipeline plays frames and measures latency by. The pipeline takes one (SteadyClock unless a
// caller sets another) so that a test can drive pacing with time it controls.
#pragma once

#include <functional>

namespace semap {

// Thread-safe: the pipeline's threads read it concurrently, and the reader thread sleeps on it.
class PipelineClock {
 public:
  virtual ~PipelineClock() = default;
  // Seconds on the clock's own monotonic scale (its origin is arbitrary).
  virtual double NowS() const = 0;
  // Blocks until NowS() >= t_s, or until `stop()` is true (polled: a stop is seen within a few tens of
  // milliseconds); returns at once when either already holds.
  virtual void SleepUntilS(double t_s, const std::function<bool()>& stop) = 0;
};

// std::chrono::steady_clock.
class SteadyClock final : public PipelineClock {
 public:
  double NowS() const override;
  void SleepUntilS(double t_s, const std::function<bool()>& stop) override;
};

}  // namespace semap
