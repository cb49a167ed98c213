// Machinery shared by the region methods: inputs, class planes, ranking scores, parallel loops.
#include "engine/core/check.h"
#include "engine/core/parallel.h"
#include "engine/simplify/internal/methods.h"

namespace semap::simplify {

namespace {
// Block size of the parallel loops: large enough to amortise scheduling, small enough to balance 2 cores.
constexpr std::size_t kBlockSize = 2048;
}  // namespace

void ParallelBlocks(std::size_t n, const std::function<void(std::size_t, std::size_t)>& body) {
  ParallelFor(std::size_t(0), n, kBlockSize, body);
}

MethodInput MakeMethodInput(const LabelledCloud& cloud, const ClassMap& class_map, bool semantic,
                            std::size_t num_fixed) {
  cloud.AssertConsistent();
  SEMAP_ASSERT(num_fixed <= cloud.size());
  MethodInput in;
  in.cloud = &cloud;
  in.num_fixed = num_fixed;
  const std::size_t n = cloud.size();
  in.labels = cloud.labels.empty() ? std::vector<Label>(n, class_map.unlabelled_id()) : cloud.labels;
  in.groups.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (!semantic) {
      in.groups[i] = 1;
      continue;
    }
    switch (class_map.Role(in.labels[i])) {
      case ClassRole::kKeep:
        in.groups[i] = 0;
        break;
      case ClassRole::kGround:
        in.groups[i] = 1;
        break;
      case ClassRole::kWall:
        in.groups[i] = 2;
        break;
    }
  }
  return in;
}

GroupPlanes FitGroupPlanes(const MethodInput& in, const SimplifyOptions& options, std::mt19937_64& rng) {
  std::array<std::vector<std::uint32_t>, kNumGroups> members;
  for (std::size_t i = 0; i < in.size(); ++i) {
    if (in.groups[i] != 0) members[in.groups[i]].push_back(static_cast<std::uint32_t>(i));
  }
  GroupPlanes planes;
  for (int g = 1; g < kNumGroups; ++g) {
    const auto plane =
        FitPlaneRansac(in.cloud->positions_world, members[g], options.ransac_threshold_m,
                       options.ransac_iterations, options.ransac_max_points, options.ransac_confidence, rng);
    if (plane) {
      planes.plane[g] = *plane;
      planes.has[g] = true;
    }
  }
  return planes;
}

std::vector<float> RankingScores(const MethodInput& in, const GroupPlanes& planes, const PointIndex& index,
                                 const SimplifyOptions& options) {
  const auto& pts = in.cloud->positions_world;
  std::vector<float> r(in.size(), 0.0f);
  ParallelBlocks(in.size() - in.num_fixed, [&](std::size_t begin, std::size_t end) {
    std::vector<std::uint32_t> nn;
    for (std::size_t k = begin; k < end; ++k) {
      const std::size_t i = in.num_fixed + k;
      const GroupId g = in.groups[i];
      if (g == 0 || !planes.has[g]) continue;
      index.Knn(pts[i], options.normal_k, &nn);
      const PcaResult pca = Pca(pts, nn);
      if (!pca.valid) continue;
      Eigen::Vector3d n_l = planes.plane[g].normal;
      Eigen::Vector3d n_i = pca.normal;
      if (const Eigen::Vector3d* view = in.Viewpoint(i)) {
        n_l = OrientTowards(n_l, pts[i], *view);
        n_i = OrientTowards(n_i, pts[i], *view);
      } else if (n_i.dot(n_l) < 0.0) {
        n_i = -n_i;
      }
      r[i] = static_cast<float>((n_i - n_l).squaredNorm());
    }
  });
  return r;
}

}  // namespace semap::simplify
