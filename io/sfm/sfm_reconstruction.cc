#include "io/sfm/sfm_reconstruction.h"

#include <algorithm>
#include <stdexcept>

#include "engine/core/check.h"
#include "io/sfm/colmap.h"
#include "io/sfm/openmvg.h"
#include "io/sfm/slam_json.h"

namespace semap::io {

const char* SfmFormatName(SfmFormat format) {
  switch (format) {
    case SfmFormat::kColmap:
      return "colmap";
    case SfmFormat::kOpenMvg:
      return "openmvg";
    case SfmFormat::kSlamJson:
      return "slam-json";
  }
  return "?";
}

SfmFormat SfmFormatFromName(const std::string& name) {
  for (SfmFormat f : {SfmFormat::kColmap, SfmFormat::kOpenMvg, SfmFormat::kSlamJson}) {
    if (name == SfmFormatName(f)) return f;
  }
  throw std::invalid_argument("unknown reconstruction format '" + name + "' (colmap, openmvg, slam-json)");
}

void SfmReconstruction::AssertConsistent() const {
  SEMAP_ASSERT(point_ids.size() == num_points(),
               "point_ids: " << point_ids.size() << " for " << num_points());
  SEMAP_ASSERT(point_colors_rgb.empty() || point_colors_rgb.size() == num_points());
  SEMAP_ASSERT(point_labels.empty() || point_labels.size() == num_points());
  for (std::size_t i = 0; i < observations.size(); ++i) {
    const SfmObservation& o = observations[i];
    SEMAP_ASSERT(o.point < num_points() && o.view < views.size(),
                 "observation (point " << o.point << ", view " << o.view << ") out of range");
    SEMAP_ASSERT(i == 0 || observations[i - 1].point < o.point ||
                     (observations[i - 1].point == o.point && observations[i - 1].view <= o.view),
                 "observations not sorted by (point, view) at " << i);
  }
}

void SfmReconstruction::SortObservations() {
  std::stable_sort(observations.begin(), observations.end(),
                   [](const SfmObservation& a, const SfmObservation& b) {
                     return a.point != b.point ? a.point < b.point : a.view < b.view;
                   });
}

const SfmIntrinsics* SfmReconstruction::FindIntrinsics(std::int64_t id) const {
  for (const SfmIntrinsics& k : intrinsics) {
    if (k.id == id) return &k;
  }
  return nullptr;
}

SfmReconstruction ReadSfm(const std::filesystem::path& path, SfmFormat format) {
  switch (format) {
    case SfmFormat::kColmap:
      return ReadColmapModel(path);
    case SfmFormat::kOpenMvg:
      return ReadOpenMvgJson(path);
    case SfmFormat::kSlamJson:
      return ReadSlamJson(path);
  }
  throw std::invalid_argument("unknown reconstruction format");
}

}  // namespace semap::io
