#include "engine/depth/view_selection.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>

namespace semap {

std::vector<std::size_t> SelectNeighbourViews(const Pose3d& world_from_reference,
                                              const std::vector<Pose3d>& world_from_candidates,
                                              const ViewSelectionOptions& options) {
  const Eigen::Vector3d centre = world_from_reference.translation();
  const Eigen::Vector3d axis = world_from_reference.linear().col(2);
  const double min_axis_cosine = std::cos(options.max_axis_angle_deg * M_PI / 180.0);
  std::vector<std::pair<double, std::size_t>> by_distance;
  for (std::size_t i = 0; i < world_from_candidates.size(); ++i) {
    const Pose3d& candidate = world_from_candidates[i];
    const double distance_m = (candidate.translation() - centre).norm();
    if (!(distance_m >= options.min_baseline_m)) continue;
    if (!(axis.dot(candidate.linear().col(2)) >= min_axis_cosine)) continue;
    by_distance.emplace_back(distance_m, i);
  }
  std::stable_sort(by_distance.begin(), by_distance.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::size_t> chosen;
  for (const auto& [distance_m, index] : by_distance) {
    if (static_cast<int>(chosen.size()) >= options.max_views) break;
    chosen.push_back(index);
  }
  return chosen;
}

}  // namespace semap
