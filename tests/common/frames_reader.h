// A FrameReader that hands on prepared frames, in order: the stream of a reader or pipeline test.
#pragma once

#include <deque>
#include <optional>
#include <utility>

#include "engine/core/frame.h"
#include "engine/pipeline/stages.h"

namespace semap::test {

class FramesReader : public FrameReader {
 public:
  FramesReader() = default;
  explicit FramesReader(std::deque<Frame> frames) : frames_(std::move(frames)) {}
  std::optional<Frame> Next() override {
    if (frames_.empty()) return std::nullopt;
    Frame f = std::move(frames_.front());
    frames_.pop_front();
    return f;
  }

 protected:
  std::deque<Frame> frames_;
};

}  // namespace semap::test
