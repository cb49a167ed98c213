// The queue frames enter the pipeline by, in front of the depth workers. Exhaustive runs wait for room;
// realtime runs never wait: a frame that finds the queue full takes the place of the oldest waiting one (the
// newest frame is the one the map wants), and the evicted frame is handed back to be counted as dropped.
// Each item popped gets the next number of the pop order, so that the frames the workers take are numbered
// without gaps however many were evicted. Thread-safe (a mutex and condition variables, visible to TSan).
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <utility>

namespace semap::pipeline_internal {

template <typename T>
class AdmissionQueue {
 public:
  explicit AdmissionQueue(int capacity) : capacity_(static_cast<std::size_t>(capacity)) {}

  // Blocks while the queue is full.
  void PushWaiting(T item) {
    std::unique_lock<std::mutex> lock(mutex_);
    not_full_.wait(lock, [&] { return slots_.size() < capacity_; });
    slots_.push_back(Slot{std::move(item)});
    not_empty_.notify_one();
  }

  // Never blocks: when the queue is full, the oldest waiting item leaves it and is returned.
  std::optional<T> PushEvictingOldest(T item) {
    std::optional<T> evicted;
    std::lock_guard<std::mutex> lock(mutex_);
    if (slots_.size() >= capacity_) {
      for (auto it = slots_.begin(); it != slots_.end(); ++it) {
        if (!it->item) continue;  // an end marker is never evicted
        evicted = std::move(it->item);
        slots_.erase(it);
        break;
      }
    }
    slots_.push_back(Slot{std::move(item)});
    not_empty_.notify_one();
    return evicted;
  }

  // Marks the end of the stream for one consumer (once per consumer). Never blocks.
  void PushEnd() {
    std::lock_guard<std::mutex> lock(mutex_);
    slots_.push_back(Slot{std::nullopt});
    not_empty_.notify_one();
  }

  struct Popped {
    T item;
    std::int64_t order = 0;  // 0, 1, 2, ... in the order items left the queue by Pop()
  };
  // Blocks until an item or an end marker arrives; std::nullopt = end of stream.
  std::optional<Popped> Pop() {
    std::unique_lock<std::mutex> lock(mutex_);
    not_empty_.wait(lock, [&] { return !slots_.empty(); });
    Slot slot = std::move(slots_.front());
    slots_.pop_front();
    not_full_.notify_one();
    if (!slot.item) return std::nullopt;
    return Popped{std::move(*slot.item), next_order_++};
  }

  // Items and end markers waiting.
  int size() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return static_cast<int>(slots_.size());
  }

 private:
  struct Slot {
    std::optional<T> item;
  };
  const std::size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable not_full_;
  std::condition_variable not_empty_;
  std::deque<Slot> slots_;
  std::int64_t next_order_ = 0;
};

}  // namespace semap::pipeline_internal
