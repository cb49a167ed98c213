#include "engine/pipeline/clock.h"

#include <algorithm>
#include <chrono>
#include <thread>

namespace semap {

namespace {
using Seconds = std::chrono::duration<double>;
// How long a sleep goes on before it looks at the stop request again: how late a stop (Ctrl-C) is seen.
constexpr Seconds kStopPoll(0.05);
}  // namespace

double SteadyClock::NowS() const {
  return std::chrono::duration_cast<Seconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void SteadyClock::SleepUntilS(double t_s, const std::function<bool()>& stop) {
  using std::chrono::steady_clock;
  const auto due = steady_clock::time_point(std::chrono::duration_cast<steady_clock::duration>(Seconds(t_s)));
  while (!stop() && steady_clock::now() < due) {
    const auto poll = std::chrono::duration_cast<steady_clock::duration>(kStopPoll);
    std::this_thread::sleep_until(std::min(due, steady_clock::now() + poll));
  }
}

}  // namespace semap
