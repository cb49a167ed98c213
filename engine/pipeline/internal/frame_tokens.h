// How many frames may be between the input queue and the end of the map at once (realtime mode): a depth
// worker takes a token before it takes a frame, the map gives it back once the frame is integrated. With
// few tokens a frame never queues behind many others on its way to the map, so the map takes the newest
// frames and the published mesh stays young; the input queue meanwhile keeps only the newest frame.
// Thread-safe (a mutex and a condition variable).
#pragma once

#include <condition_variable>
#include <mutex>

namespace semap::pipeline_internal {

class FrameTokens {
 public:
  // `tokens` ≤ 0: no limit (Acquire never blocks).
  explicit FrameTokens(int tokens) : limited_(tokens > 0), free_(tokens) {}

  // Blocks until a token is free, and takes it.
  void Acquire() {
    if (!limited_) return;
    std::unique_lock<std::mutex> lock(mutex_);
    freed_.wait(lock, [&] { return free_ > 0; });
    --free_;
  }
  void Release() {
    if (!limited_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    ++free_;
    freed_.notify_one();
  }

 private:
  const bool limited_;
  std::mutex mutex_;
  std::condition_variable freed_;
  int free_;
};

}  // namespace semap::pipeline_internal
