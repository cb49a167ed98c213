#include "app/depth/frame_at.h"

#include <memory>
#include <stdexcept>
#include <string>

namespace semap::app {

FrameAt ReadFrameAt(const std::filesystem::path& path, int index, io::FrameSourceOptions input) {
  if (index < 0) throw std::invalid_argument("--frame must be >= 0 (got " + std::to_string(index) + ")");
  input.first_frame = index;
  input.max_frames = 1;
  const std::unique_ptr<io::FrameSource> source = io::OpenFrameSource(path, input);
  std::optional<Frame> frame = source->Next();
  if (!frame) {
    throw std::runtime_error(path.string() + ": no frame " + std::to_string(index) + " in this dataset");
  }
  // The source starts at the first frame numbered >= index (stereo-2015 numbers are sparse): exact only.
  if (frame->id != index) {
    throw std::runtime_error(path.string() + ": no frame " + std::to_string(index) + " (the next one is " +
                             std::to_string(frame->id) + ")");
  }
  return {std::move(*frame), source->class_map()};
}

}  // namespace semap::app
