// When each frame is due in realtime mode, on the pipeline's clock: the sequence's time stamps (relative to
// the first frame's) divided by the playing speed, or one frame every 1 / rate_hz when the time stamps do
// not increase. Not thread-safe: the reader thread's.
#pragma once

#include <cstdint>
#include <optional>

namespace semap::pipeline_internal {

class FramePacer {
 public:
  // `start_s`: when the first frame is due, on the clock; `speed` > 0 (2 = twice the sensor's rate).
  FramePacer(double start_s, double rate_hz, double speed)
      : start_s_(start_s), rate_hz_(rate_hz), speed_(speed) {}

  // The due time of the next frame, whose time stamp is `timestamp_s`.
  double NextDueS(double timestamp_s) {
    double sensor_s = static_cast<double>(paced_++) / rate_hz_;
    if (!first_timestamp_s_) first_timestamp_s_ = timestamp_s;
    if (timestamp_s > *first_timestamp_s_) sensor_s = timestamp_s - *first_timestamp_s_;
    return start_s_ + sensor_s / speed_;
  }

 private:
  double start_s_;
  double rate_hz_;
  double speed_;
  std::optional<double> first_timestamp_s_;
  std::int64_t paced_ = 0;
};

}  // namespace semap::pipeline_internal
