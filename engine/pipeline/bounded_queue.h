// A bounded multi-producer multi-consumer queue between pipeline stages with an explicit end of stream:
// moodycamel's BlockingConcurrentQueue (lock-free, header-only) bounded by a semaphore of free slots.
// Header-only on purpose: every hand-over is visible to ThreadSanitizer (Debian's libtbb is not instrumented,
// so TSan could not check a TBB queue's hand-overs). FIFO per producer; the pipeline's single-producer queues
// are therefore FIFO, and the depth workers' output is reordered by sequence number anyway. Thread-safe.
#pragma once

#include <concurrentqueue/blockingconcurrentqueue.h>
#include <concurrentqueue/lightweightsemaphore.h>

#include <optional>
#include <utility>

namespace semap::pipeline_internal {

template <typename T>
class BoundedQueue {
 public:
  explicit BoundedQueue(int capacity) : queue_(static_cast<size_t>(capacity)), free_slots_(capacity) {}

  // Blocks while the queue is full.
  void Push(T item) {
    while (!free_slots_.wait()) {
    }
    queue_.enqueue(Slot{std::move(item)});
  }
  // Returns false (and drops nothing) when the queue is full.
  bool TryPush(T item) {
    if (!free_slots_.tryWait()) return false;
    queue_.enqueue(Slot{std::move(item)});
    return true;
  }
  // Marks the end of the stream for one consumer (call once per consumer). Blocks while full.
  void PushEnd() {
    while (!free_slots_.wait()) {
    }
    queue_.enqueue(Slot{std::nullopt});
  }
  // Blocks until an item or an end marker arrives; std::nullopt = end of stream.
  std::optional<T> Pop() {
    Slot slot;
    queue_.wait_dequeue(slot);
    free_slots_.signal();
    return std::move(slot.item);
  }
  // Items waiting (approximate under concurrency; for statistics).
  int size() const { return static_cast<int>(queue_.size_approx()); }

 private:
  struct Slot {
    std::optional<T> item;
  };
  moodycamel::BlockingConcurrentQueue<Slot> queue_;
  moodycamel::LightweightSemaphore free_slots_;
};

}  // namespace semap::pipeline_internal
