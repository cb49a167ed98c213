// A bounded multi-producer multi-consumer queue between pipeline stages (TBB's concurrent_bounded_queue)
// with an explicit end of stream. Thread-safe.
#pragma once

#include <optional>
#include <utility>

#include <tbb/concurrent_queue.h>

namespace semap::internal {

template <typename T>
class BoundedQueue {
 public:
  explicit BoundedQueue(int capacity) { queue_.set_capacity(capacity); }

  // Blocks while the queue is full.
  void Push(T item) { queue_.push(Slot{std::move(item)}); }
  // Returns false (and drops nothing) when the queue is full.
  bool TryPush(T item) { return queue_.try_push(Slot{std::move(item)}); }
  // Marks the end of the stream for one consumer (call once per consumer). Blocks while full.
  void PushEnd() { queue_.push(Slot{std::nullopt}); }
  // Blocks until an item or an end marker arrives; std::nullopt = end of stream.
  std::optional<T> Pop() {
    Slot slot;
    queue_.pop(slot);
    return std::move(slot.item);
  }
  // Items waiting (may be momentarily off under concurrency; for statistics).
  int size() const { return static_cast<int>(queue_.size()); }

 private:
  struct Slot {
    std::optional<T> item;
  };
  tbb::concurrent_bounded_queue<Slot> queue_;
};

}  // namespace semap::internal
