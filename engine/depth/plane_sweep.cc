#include "engine/depth/plane_sweep.h"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/core/check.h"
#include "engine/core/parallel.h"
#include "engine/depth/internal/plane_sweep_cost.h"

namespace semap {

using depth_internal::kNoCost;

namespace {

// Reference rows swept together by one task: each task warps its rows plus the window's half-side above and
// below (smaller: more parallel tasks, more rows warped twice).
constexpr int kBandRows = 32;
// A family of planes scores a pixel only where the cosine between the pixel's ray and the planes' normal
// reaches this (lower: rays that graze the planes are scored too, and the family's offsets span a wider
// range, so its steps are coarser).
constexpr double kMinRayPlaneCosine = 0.05;
// DepthRangeFromCameras: the optical axes must spread by at least this ratio of the least to the largest
// eigenvalue of their normal equations (lower: nearly parallel axes still give a, poorly defined, range).
constexpr double kMinAxisSpread = 1e-4;
// K's (1, 0), (2, 0), (2, 1) entries must be zero and (2, 2) one within this.
constexpr double kIntrinsicsTolerance = 1e-9;
constexpr float kInfinity = std::numeric_limits<float>::infinity();

void CheckView(const PlaneSweepView& view, const std::string& name) {
  if (view.image.empty()) throw std::invalid_argument("plane sweep: the " + name + " image is empty");
  if (view.image.type() != CV_8UC1) {
    throw std::invalid_argument("plane sweep: the " + name + " image must be CV_8UC1 grey (got type " +
                                std::to_string(view.image.type()) + ")");
  }
  const Eigen::Matrix3d& K = view.K;
  const bool triangular =
      std::abs(K(1, 0)) <= kIntrinsicsTolerance && std::abs(K(2, 0)) <= kIntrinsicsTolerance &&
      std::abs(K(2, 1)) <= kIntrinsicsTolerance && std::abs(K(2, 2) - 1.0) <= kIntrinsicsTolerance;
  if (!K.allFinite() || !triangular || !(K(0, 0) > 0.0) || !(K(1, 1) > 0.0)) {
    throw std::invalid_argument("plane sweep: the " + name +
                                " view's K must be finite, upper triangular with last row 0 0 1 and positive "
                                "focal lengths");
  }
}

// One direction of planes: nᵀX = d in the reference frame, d uniform in 1/d.
struct Family {
  Eigen::Vector3d normal_reference;
  Eigen::Vector3d
      ray_factor;  // nᵀ K_ref⁻¹: a pixel's ray meets the plane nᵀX = d at depth d / (ray_factor · x̃)
  double first_inverse_offset = 0.0;  // 1 / d of plane 0 (the nearest)
  double inverse_offset_step = 0.0;   // change of 1 / d from one plane to the next (negative)
  int planes = 0;                     // 0: the family meets no ray of the image
  std::vector<std::vector<Eigen::Matrix3d>> homographies;  // [plane][neighbour]: reference → neighbour pixels

  double InverseOffset(double plane) const { return first_inverse_offset + plane * inverse_offset_step; }
};

// Planes of one normal, uniform in 1/d over [nearest_offset_m, farthest_offset_m] (both > 0).
Family MakeFamily(const Eigen::Vector3d& normal_reference, const PlaneSweepView& reference, int num_planes,
                  double nearest_offset_m, double farthest_offset_m) {
  Family f;
  f.normal_reference = normal_reference;
  f.ray_factor = reference.K.inverse().transpose() * normal_reference;
  f.planes = num_planes;
  f.first_inverse_offset = 1.0 / nearest_offset_m;
  f.inverse_offset_step = (1.0 / farthest_offset_m - 1.0 / nearest_offset_m) / (num_planes - 1);
  return f;
}

// The family of a direction without offsets: its normal (unit, reference frame) turned towards the side
// most of the reference image looks at, its offsets every plane that crosses `range` at a pixel it scores.
Family FamilyOverRange(Eigen::Vector3d normal_reference, const PlaneSweepView& reference, int num_planes,
                       const DepthRange& range) {
  const Eigen::Matrix3d K_inverse = reference.K.inverse();
  const double w = reference.image.cols, h = reference.image.rows;
  const Eigen::Vector3d corners[] = {{0, 0, 1}, {w, 0, 1}, {0, h, 1}, {w, h, 1}};
  // nᵀ K⁻¹ x̃ is linear in the pixel: its extremes over the image are at the corners.
  double sum = 0.0;
  for (const auto& c : corners) sum += normal_reference.dot(K_inverse * c);
  if (sum < 0.0) normal_reference = -normal_reference;
  double highest = -kInfinity, lowest = kInfinity;
  for (const auto& c : corners) {
    highest = std::max(highest, normal_reference.dot(K_inverse * c));
    lowest = std::min(lowest, normal_reference.dot(K_inverse * c));
  }
  // Every scored ray has a factor ≥ kMinRayPlaneCosine · |K⁻¹ x̃| ≥ kMinRayPlaneCosine (|K⁻¹ x̃| ≥ 1).
  lowest = std::max(lowest, kMinRayPlaneCosine);
  if (!(highest >= lowest)) return Family{normal_reference, {}, 0.0, 0.0, 0, {}};
  return MakeFamily(normal_reference, reference, num_planes, range.min_depth_m * lowest,
                    range.max_depth_m * highest);
}

// The family of a caller's direction in the reference frame (throws when it is unusable).
Family DirectionFamily(const SweepDirection& direction, const PlaneSweepView& reference, int num_planes,
                       const DepthRange& range) {
  if (!(direction.normal_world.norm() > 0.0) || !direction.normal_world.allFinite())
    throw std::invalid_argument("plane sweep: a sweep direction's normal is zero or not finite");
  const Eigen::Vector3d normal_world = direction.normal_world.normalized();
  const Eigen::Vector3d normal_reference = reference.world_from_cam.linear().transpose() * normal_world;
  if (direction.min_offset_m == 0.0 && direction.max_offset_m == 0.0)
    return FamilyOverRange(normal_reference, reference, num_planes, range);
  // World plane nᵀX = c is the reference plane (Rᵀn)ᵀX_ref = c − nᵀC.
  const double along_centre = normal_world.dot(reference.world_from_cam.translation());
  double nearest = direction.min_offset_m - along_centre, farthest = direction.max_offset_m - along_centre;
  if (!(direction.max_offset_m > direction.min_offset_m) || !std::isfinite(nearest) ||
      !std::isfinite(farthest) || nearest * farthest <= 0.0) {
    throw std::invalid_argument(
        "plane sweep: a sweep direction's offsets must be finite, min < max, with the reference camera on "
        "neither plane nor between them");
  }
  if (nearest < 0.0) return MakeFamily(-normal_reference, reference, num_planes, -farthest, -nearest);
  return MakeFamily(normal_reference, reference, num_planes, nearest, farthest);
}

void AddHomographies(const PlaneSweepView& reference, const std::vector<PlaneSweepView>& neighbours,
                     Family* f) {
  f->homographies.resize(static_cast<size_t>(f->planes));
  for (int p = 0; p < f->planes; ++p) {
    const double offset_m = 1.0 / f->InverseOffset(p);
    for (const PlaneSweepView& n : neighbours) {
      const Pose3d neighbour_from_reference =
          n.world_from_cam.inverse(Eigen::Isometry) * reference.world_from_cam;
      f->homographies[static_cast<size_t>(p)].push_back(depth_internal::PlaneHomography(
          reference.K, n.K, neighbour_from_reference, f->normal_reference, offset_m));
    }
  }
}

// Per pixel of a band, the two lowest local minima of one family's cost over its planes, found as the
// planes stream past (a local minimum is lower than the plane before it, and no higher than the one after;
// the sweep's ends count as higher than any cost).
class MinimaTracker {
 public:
  explicit MinimaTracker(size_t pixels)
      : prev1_(pixels, kInfinity),
        prev2_(pixels, kInfinity),
        best_(pixels, kInfinity),
        left_(pixels, kInfinity),
        right_(pixels, kInfinity),
        second_(pixels, kInfinity),
        index_(pixels, -1) {}

  // True when the best local minimum became the plane before `plane`.
  bool Push(size_t i, int plane, float cost) {
    const bool moved = plane > 0 && Consider(i, plane - 1, cost);
    prev2_[i] = prev1_[i];
    prev1_[i] = cost;
    return moved;
  }
  // True when the best local minimum became the last plane.
  bool Finish(size_t i, int planes) { return Consider(i, planes - 1, kInfinity); }

  float best(size_t i) const { return best_[i]; }
  float left(size_t i) const { return left_[i]; }
  float right(size_t i) const { return right_[i]; }
  float second(size_t i) const { return second_[i]; }
  int index(size_t i) const { return index_[i]; }

 private:
  // Plane `plane`, whose cost is prev1_ and whose neighbours' are prev2_ and `next`; true when it becomes the
  // best.
  bool Consider(size_t i, int plane, float next) {
    const float m = prev1_[i], before = prev2_[i];
    if (!(m < kNoCost && m < before && m <= next)) return false;
    if (m < best_[i]) {
      second_[i] = best_[i];
      best_[i] = m;
      left_[i] = before;
      right_[i] = next;
      index_[i] = plane;
      return true;
    }
    if (m < second_[i]) second_[i] = m;
    return false;
  }
  std::vector<float> prev1_, prev2_, best_, left_, right_, second_;
  std::vector<int> index_;
};

// Per pixel of a band and per neighbour, what that neighbour alone says of one family's planes as they
// stream past: the plane of its own lowest cost, and its cost at the plane the MinimaTracker holds as best.
// Costs are NaN where the neighbour does not see the window or the plane is not scored at the pixel.
class ViewTracker {
 public:
  ViewTracker(size_t pixels, size_t views)
      : views_(views),
        own_best_(pixels * views, kInfinity),
        own_plane_(pixels * views, -1),
        previous_(pixels * views, std::numeric_limits<float>::quiet_NaN()),
        at_best_(pixels * views, std::numeric_limits<float>::quiet_NaN()) {}

  // The views' costs of plane `plane` at pixel i; `best_moved`: MinimaTracker::Push's answer for it.
  void Push(size_t i, int plane, const float* costs, bool best_moved) {
    float* previous = &previous_[i * views_];
    if (best_moved) std::copy(previous, previous + views_, &at_best_[i * views_]);
    for (size_t j = 0; j < views_; ++j) {
      const float c = costs[j];
      if (c < own_best_[i * views_ + j]) {  // false for NaN
        own_best_[i * views_ + j] = c;
        own_plane_[i * views_ + j] = plane;
      }
      previous[j] = c;
    }
  }
  // `best_moved`: MinimaTracker::Finish's answer at pixel i.
  void Finish(size_t i, bool best_moved) {
    if (best_moved) std::copy(&previous_[i * views_], &previous_[i * views_] + views_, &at_best_[i * views_]);
  }

  // The neighbours at pixel i whose own lowest cost lies within `planes` planes of `winner` and whose cost
  // at the winner is at most `max_cost`.
  int Agreeing(size_t i, int winner, int planes, float max_cost) const {
    int agreeing = 0;
    for (size_t j = 0; j < views_; ++j) {
      const int own = own_plane_[i * views_ + j];
      if (own >= 0 && std::abs(own - winner) <= planes && at_best_[i * views_ + j] <= max_cost) ++agreeing;
    }
    return agreeing;
  }

 private:
  size_t views_;
  std::vector<float> own_best_;
  std::vector<int> own_plane_;
  std::vector<float> previous_, at_best_;
};

// A family's answer at one pixel.
struct Candidate {
  bool valid = false;
  float depth_m = 0.0f, cost = kNoCost, confidence = 0.0f;
};

Candidate Refine(const MinimaTracker& t, size_t i, const Family& f, double factor, const PlaneSweepOptions& o,
                 const DepthRange& range) {
  Candidate c;
  const float m = t.best(i), l = t.left(i), r = t.right(i);
  // The parabola needs both neighbouring planes scored; a minimum at the sweep's end or next to an unscored
  // plane may lie beyond it: no depth.
  if (t.index(i) < 0 || !(l < kNoCost) || !(r < kNoCost)) return c;
  const float curvature = l - 2.0f * m + r;  // > 0: m is below l and no higher than r
  const float shift = curvature > 0.0f ? 0.5f * (l - r) / curvature : 0.0f;
  c.cost = m - 0.25f * (l - r) * shift;
  c.confidence = std::isinf(t.second(i)) ? 1.0f : (t.second(i) > 0.0f ? 1.0f - m / t.second(i) : 0.0f);
  c.depth_m = static_cast<float>(1.0 / (f.InverseOffset(t.index(i) + shift) * factor));
  c.valid = c.cost <= o.max_cost && c.confidence >= o.min_confidence && c.depth_m >= range.min_depth_m &&
            c.depth_m <= range.max_depth_m;
  return c;
}

// The rays' factors of a band for one family (0 where the family does not score the pixel).
std::vector<float> RayFactors(const Family& f, const Eigen::Matrix3d& K_inverse, int first_row, int rows,
                              int width) {
  std::vector<float> factors(static_cast<size_t>(rows) * static_cast<size_t>(width), 0.0f);
  for (int r = 0; r < rows; ++r) {
    for (int u = 0; u < width; ++u) {
      const Eigen::Vector3d x(u, first_row + r, 1.0);
      const double factor = f.ray_factor.dot(x);
      if (factor >= kMinRayPlaneCosine * (K_inverse * x).norm())
        factors[static_cast<size_t>(r) * static_cast<size_t>(width) + static_cast<size_t>(u)] = float(factor);
    }
  }
  return factors;
}

// Everything one sweep shares between its bands.
struct Sweep {
  const PlaneSweepOptions& options;
  DepthRange range;
  depth_internal::ReferenceWindows reference;
  Eigen::Matrix3d K_reference_inverse;
  std::vector<cv::Mat> neighbours;  // CentredGrey
  std::vector<Family> families;
  depth_internal::Aggregation aggregation;
  int min_agreeing_views = 0;  // the options' value, at most the number of neighbours; 0: no agreement test
};

// One family over reference rows [first_row, first_row + rows): its planes' aggregated costs streamed into
// `tracker`, and each neighbour's own costs into `views_tracker` (when not null).
void SweepFamily(const Sweep& s, const Family& f, const std::vector<float>& factors, int first_row, int rows,
                 MinimaTracker* tracker, ViewTracker* views_tracker) {
  const int width = s.reference.image.cols, height = s.reference.image.rows;
  const int half = s.options.window_px / 2;
  const int band_first = std::max(0, first_row - half);
  const int band_rows = std::min(height, first_row + rows + half) - band_first;
  const size_t views = s.neighbours.size();
  depth_internal::WarpedBand band;
  depth_internal::CostScratch scratch;
  std::vector<cv::Mat> costs(views);
  std::vector<float> pixel_costs(views), aggregate_scratch(views);
  const std::vector<float> unscored(views, std::numeric_limits<float>::quiet_NaN());
  const float lowest_inverse = float(1.0 / s.range.max_depth_m),
              highest_inverse = float(1.0 / s.range.min_depth_m);
  for (int p = 0; p < f.planes; ++p) {
    for (size_t j = 0; j < views; ++j) {
      depth_internal::WarpBand(s.neighbours[j], f.homographies[size_t(p)][j], band_first, band_rows, width,
                               &band);
      depth_internal::BandCost(s.reference, band, band_first, first_row, rows, s.options.min_window_stddev,
                               &scratch, &costs[j]);
    }
    const float inverse_offset = float(f.InverseOffset(p));
    for (int r = 0; r < rows; ++r) {
      const std::uint8_t* textured = s.reference.textured.ptr<std::uint8_t>(first_row + r);
      for (int u = 0; u < width; ++u) {
        const size_t i = size_t(r) * size_t(width) + size_t(u);
        // The plane's inverse depth at this pixel: scored only within the swept range.
        const float inverse_depth = inverse_offset * factors[i];
        float cost = kNoCost;
        const bool scored =
            textured[u] && inverse_depth >= lowest_inverse && inverse_depth <= highest_inverse;
        if (scored) {
          for (size_t j = 0; j < views; ++j) pixel_costs[j] = costs[j].ptr<float>(r)[u];
          cost = depth_internal::AggregateCosts(s.aggregation, pixel_costs.data(), int(views),
                                                aggregate_scratch.data());
        }
        const bool best_moved = tracker->Push(i, p, cost);
        if (views_tracker != nullptr)
          views_tracker->Push(i, p, scored ? pixel_costs.data() : unscored.data(), best_moved);
      }
    }
  }
  for (size_t i = 0; i < factors.size(); ++i) {
    const bool best_moved = tracker->Finish(i, f.planes);
    if (views_tracker != nullptr) views_tracker->Finish(i, best_moved);
  }
}

// Sweeps every family over reference rows [first_row, first_row + rows) and writes the winners there.
void SweepBand(const Sweep& s, int first_row, int rows, PlaneSweepResult* out) {
  const int width = s.reference.image.cols;
  std::vector<Candidate> winners(size_t(rows) * size_t(width));
  std::vector<std::uint8_t> winning_family(winners.size(), kNoFamily);
  for (size_t k = 0; k < s.families.size(); ++k) {
    const Family& f = s.families[k];
    if (f.planes == 0) continue;
    const std::vector<float> factors = RayFactors(f, s.K_reference_inverse, first_row, rows, width);
    MinimaTracker tracker(winners.size());
    std::optional<ViewTracker> views;
    if (s.min_agreeing_views > 0) views.emplace(winners.size(), s.neighbours.size());
    SweepFamily(s, f, factors, first_row, rows, &tracker, views ? &*views : nullptr);
    for (size_t i = 0; i < winners.size(); ++i) {
      Candidate c = Refine(tracker, i, f, factors[i], s.options, s.range);
      if (c.valid && views) {
        c.valid = views->Agreeing(i, tracker.index(i), s.options.agreement_planes,
                                  float(s.options.agreement_max_cost)) >= s.min_agreeing_views;
      }
      if (c.valid && (!winners[i].valid || c.cost < winners[i].cost)) {
        winners[i] = c;
        winning_family[i] = static_cast<std::uint8_t>(k);
      }
    }
  }
  for (int r = 0; r < rows; ++r) {
    for (int u = 0; u < width; ++u) {
      const size_t i = size_t(r) * size_t(width) + size_t(u);
      const Candidate& c = winners[i];
      const int v = first_row + r;
      out->depth_m.at<float>(v, u) = c.valid ? c.depth_m : 0.0f;
      out->confidence.at<float>(v, u) = c.valid ? c.confidence : 0.0f;
      out->cost.at<float>(v, u) = c.valid ? c.cost : kNoCost;
      out->valid.at<std::uint8_t>(v, u) = c.valid ? 255 : 0;
      out->family.at<std::uint8_t>(v, u) = winning_family[i];
    }
  }
}

DepthRange SweptRange(const PlaneSweepOptions& o, const PlaneSweepView& reference,
                      const std::vector<PlaneSweepView>& neighbours) {
  if (o.min_depth_m > 0.0) return {o.min_depth_m, o.max_depth_m};
  const auto range = DepthRangeFromCameras(reference, neighbours, o.camera_range_factor);
  if (!range) {
    throw std::invalid_argument(
        "plane sweep: no depth range: min_depth_m and max_depth_m are 0 and the cameras' optical axes do not "
        "meet in front of the reference");
  }
  return *range;
}

}  // namespace

void PlaneSweepOptions::Check() const {
  CheckDeclaredRanges(*this);
  if (stereo_max_depth_m <= stereo_min_depth_m) {
    throw OptionError(*this, stereo_max_depth_m, "must be greater than " + KeyOf(*this, stereo_min_depth_m));
  }
  if (min_depth_m == 0.0 && max_depth_m == 0.0) return;  // the range from the cameras
  if (min_depth_m <= 0.0) {
    throw OptionError(*this, min_depth_m,
                      "must be > 0, or 0 with " + KeyOf(*this, max_depth_m) + " = 0 (from the cameras)");
  }
  if (max_depth_m <= min_depth_m) {
    throw OptionError(*this, max_depth_m,
                      "must be greater than " + KeyOf(*this, min_depth_m) + ", or 0 with " +
                          KeyOf(*this, min_depth_m) + " = 0");
  }
}

std::optional<DepthRange> DepthRangeFromCameras(const PlaneSweepView& reference,
                                                const std::vector<PlaneSweepView>& neighbours,
                                                double factor) {
  // The point X nearest to every optical axis (centre c, unit direction a): Σ (I − a aᵀ) X = Σ (I − a aᵀ) c.
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  auto add = [&](const PlaneSweepView& view) {
    const Eigen::Vector3d axis = view.world_from_cam.linear().col(2).normalized();
    const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - axis * axis.transpose();
    A += P;
    b += P * view.world_from_cam.translation();
  };
  add(reference);
  for (const PlaneSweepView& n : neighbours) add(n);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(A);
  if (!(eigen.eigenvalues()(0) > kMinAxisSpread * eigen.eigenvalues()(2))) return std::nullopt;
  const Eigen::Vector3d meeting_world = A.ldlt().solve(b);
  const double depth_m = (reference.world_from_cam.inverse(Eigen::Isometry) * meeting_world).z();
  if (!(depth_m > 0.0) || !std::isfinite(depth_m)) return std::nullopt;
  return DepthRange{depth_m / factor, depth_m * factor};
}

PlaneSweepDepth::PlaneSweepDepth(const PlaneSweepOptions& options) : options_(options) { options_.Check(); }

PlaneSweepResult PlaneSweepDepth::Compute(const PlaneSweepView& reference,
                                          const std::vector<PlaneSweepView>& neighbours,
                                          const std::vector<SweepDirection>& directions) const {
  CheckView(reference, "reference");
  if (neighbours.empty()) throw std::invalid_argument("plane sweep: needs at least one neighbour view");
  for (size_t j = 0; j < neighbours.size(); ++j) CheckView(neighbours[j], "neighbour " + std::to_string(j));
  Sweep s{
      options_,
      SweptRange(options_, reference, neighbours),
      depth_internal::MakeReferenceWindows(reference.image, options_.window_px, options_.min_window_stddev),
      reference.K.inverse(),
      {},
      {},
      {},
      std::min(options_.min_agreeing_views, int(neighbours.size()))};
  for (const PlaneSweepView& n : neighbours) s.neighbours.push_back(depth_internal::CentredGrey(n.image));
  s.aggregation = {options_.best_views, options_.min_views, {}, options_.left_right_subsets};
  const Pose3d reference_from_world = reference.world_from_cam.inverse(Eigen::Isometry);
  for (const PlaneSweepView& n : neighbours)
    s.aggregation.left.push_back((reference_from_world * n.world_from_cam.translation()).x() < 0.0);
  s.families.push_back(FamilyOverRange(Eigen::Vector3d::UnitZ(), reference, options_.num_planes, s.range));
  for (const SweepDirection& d : directions)
    s.families.push_back(DirectionFamily(d, reference, options_.num_planes, s.range));
  for (Family& f : s.families) AddHomographies(reference, neighbours, &f);
  const cv::Size size = reference.image.size();
  PlaneSweepResult out{cv::Mat(size, CV_32F),  cv::Mat(size, CV_32F),  cv::Mat(size, CV_32F),
                       cv::Mat(size, CV_8UC1), cv::Mat(size, CV_8UC1), s.range};
  const int bands = (size.height + kBandRows - 1) / kBandRows;
  ParallelFor(0, bands, 1, [&](int first, int last) {
    for (int b = first; b < last; ++b) {
      const int first_row = b * kBandRows;
      SweepBand(s, first_row, std::min(kBandRows, size.height - first_row), &out);
    }
  });
  return out;
}

}  // namespace semap
