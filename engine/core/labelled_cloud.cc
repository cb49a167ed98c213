#include "engine/core/labelled_cloud.h"

#include "engine/core/check.h"

namespace semap {

namespace {
template <typename T>
void AssertOptional(const std::vector<T>& v, size_t n, const char* name) {
  SEMAP_ASSERT(v.empty() || v.size() == n, name << " has " << v.size() << " entries for " << n << " points");
}

template <typename T>
void CopySubset(const std::vector<T>& src, const std::vector<std::uint32_t>& idx, std::vector<T>* dst) {
  if (src.empty()) return;
  dst->reserve(idx.size());
  for (auto i : idx) dst->push_back(src[i]);
}

template <typename T>
void AppendOptional(const std::vector<T>& src, size_t old_n, size_t add_n, std::vector<T>* dst) {
  // Both absent: stay absent. Otherwise fill the missing side with default values.
  if (src.empty() && dst->empty()) return;
  dst->resize(old_n);
  if (src.empty()) {
    dst->resize(old_n + add_n);
  } else {
    dst->insert(dst->end(), src.begin(), src.end());
  }
}
}  // namespace

void LabelledCloud::AssertConsistent() const {
  const size_t n = size();
  AssertOptional(colors_rgb, n, "colors_rgb");
  AssertOptional(labels, n, "labels");
  AssertOptional(pixels_px, n, "pixels_px");
  AssertOptional(confidence, n, "confidence");
  AssertOptional(camera_index, n, "camera_index");
  SEMAP_ASSERT(camera_frame_ids.empty() || camera_frame_ids.size() == camera_centers_world.size());
  SEMAP_ASSERT(camera_views.empty() || camera_views.size() == camera_centers_world.size());
  for (auto c : camera_index) SEMAP_ASSERT(c < camera_centers_world.size(), "camera index " << c);
}

LabelledCloud LabelledCloud::Subset(const std::vector<std::uint32_t>& indices) const {
  LabelledCloud out;
  CopySubset(positions_world, indices, &out.positions_world);
  CopySubset(colors_rgb, indices, &out.colors_rgb);
  CopySubset(labels, indices, &out.labels);
  CopySubset(pixels_px, indices, &out.pixels_px);
  CopySubset(confidence, indices, &out.confidence);
  CopySubset(camera_index, indices, &out.camera_index);
  out.camera_centers_world = camera_centers_world;
  out.camera_frame_ids = camera_frame_ids;
  out.camera_views = camera_views;
  return out;
}

void LabelledCloud::Append(const LabelledCloud& other) {
  const size_t old_n = size();
  const size_t add_n = other.size();
  const auto camera_offset = static_cast<std::uint32_t>(camera_centers_world.size());
  positions_world.insert(positions_world.end(), other.positions_world.begin(), other.positions_world.end());
  AppendOptional(other.colors_rgb, old_n, add_n, &colors_rgb);
  AppendOptional(other.labels, old_n, add_n, &labels);
  AppendOptional(other.pixels_px, old_n, add_n, &pixels_px);
  AppendOptional(other.confidence, old_n, add_n, &confidence);
  if (!other.camera_index.empty()) {
    camera_index.resize(old_n);
    for (auto c : other.camera_index) camera_index.push_back(c + camera_offset);
  }
  camera_centers_world.insert(camera_centers_world.end(), other.camera_centers_world.begin(),
                              other.camera_centers_world.end());
  camera_frame_ids.insert(camera_frame_ids.end(), other.camera_frame_ids.begin(),
                          other.camera_frame_ids.end());
  // Views are kept only while every camera has one.
  if (camera_views.size() + other.camera_views.size() == camera_centers_world.size()) {
    camera_views.insert(camera_views.end(), other.camera_views.begin(), other.camera_views.end());
  } else {
    camera_views.clear();
  }
}

}  // namespace semap
