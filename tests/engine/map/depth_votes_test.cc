// The depth-map votes of one cell against a brute-force reference: every pixel's ray cast through the cell.
#include "engine/map/internal/depth_votes.h"

#include <gtest/gtest.h>

#include <random>
#include <set>

#include "engine/map/internal/vote_weights.h"
#include "tests/engine/map/map_test_util.h"

namespace semap::map_internal {
namespace {

constexpr int kWidthPx = 160;
constexpr int kHeightPx = 120;
constexpr double kFocalPx = 100.0;

// A camera at the origin looking along +z (world = camera frame), seeing a wall at z = wall_m (0 = no depth,
// kFreeToFarRange = sky) over the whole image.
std::shared_ptr<const DepthView> WallView(float wall_m, double max_depth_m = 40.0) {
  auto view = test::PinholeDepthView(kWidthPx, kHeightPx, kFocalPx, max_depth_m);
  view->depth_m.setTo(wall_m);
  view->rays_per_pixel = 4.0;  // as from a depth map at stride 2
  return view;
}

// Whether the segment a → b crosses the tetrahedron (clipped against its four half-spaces).
bool SegmentCrossesTet(const std::array<Eigen::Vector3d, 4>& t, const Eigen::Vector3d& a,
                       const Eigen::Vector3d& b) {
  double lo = 0.0, hi = 1.0;
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3d& p0 = t[(i + 1) % 4];
    Eigen::Vector3d n = (t[(i + 2) % 4] - p0).cross(t[(i + 3) % 4] - p0);
    if (n.dot(t[i] - p0) < 0) n = -n;  // inward
    const double fa = n.dot(a - p0), fb = n.dot(b - p0);
    if (fa < 0 && fb < 0) return false;
    if (fa < 0) lo = std::max(lo, fa / (fa - fb));
    if (fb < 0) hi = std::min(hi, fa / (fa - fb));
  }
  return lo < hi;
}

// The rays (pixel centres) whose segment camera → end_depth crosses the tetrahedron, × rays_per_pixel.
double CrossingRays(const std::array<Eigen::Vector3d, 4>& tet, double end_depth_m, const DepthView& view) {
  int n = 0;
  for (int v = 0; v < kHeightPx; ++v) {
    for (int u = 0; u < kWidthPx; ++u) {
      const Eigen::Vector3d dir((u + 0.5 - view.intrinsics.cx_px) / kFocalPx,
                                (v + 0.5 - view.intrinsics.cy_px) / kFocalPx, 1.0);
      n += SegmentCrossesTet(tet, Eigen::Vector3d::Zero(), dir * end_depth_m) ? 1 : 0;
    }
  }
  return n * view.rays_per_pixel;
}

std::array<Eigen::Vector3d, 4> RandomTet(std::mt19937* rng, double z_lo, double z_hi, double xy_m) {
  std::uniform_real_distribution<double> xy(-xy_m, xy_m), z(z_lo, z_hi);
  std::array<Eigen::Vector3d, 4> t;
  for (auto& p : t) p = {xy(*rng), xy(*rng), z(*rng)};
  return t;
}

double Rays(std::int64_t q) { return DequantiseVote(q); }

// The paper's values (MapOptions' defaults) with exact depth (no disparity noise band).
DepthVoteGeometry PaperGeometry() {
  MapOptions options;
  options.disparity_sigma_px = 0.0;
  return DepthVoteGeometry(options);
}

TEST(DepthVotes, FreeVoteOfACellBeforeAWallCountsTheRaysCrossingIt) {
  const VotingView view(WallView(10.0f));
  std::mt19937 rng(3);
  int checked = 0;
  double total_estimate = 0.0, total_reference = 0.0;
  for (int trial = 0; trial < 60; ++trial) {
    const auto tet = RandomTet(&rng, 3.0, 8.0, 1.5);
    const double reference = CrossingRays(tet, 10.0, *view.view);
    if (reference < 200.0) continue;  // too small a footprint to compare
    const VoteIncrement v = VoteCell(tet, view, PaperGeometry());
    EXPECT_EQ(v.matter_q, 0);
    // The footprint (the hull of the projected vertices) is exact up to the pixel grid; the weight is 1
    // for every sample (2 m or more before the wall).
    EXPECT_NEAR(Rays(v.free_q), reference, 0.15 * reference + 60.0) << "trial " << trial;
    total_estimate += Rays(v.free_q);
    total_reference += reference;
    ++checked;
  }
  EXPECT_GT(checked, 20);
  EXPECT_NEAR(total_estimate / total_reference, 1.0, 0.03);
}

TEST(DepthVotes, MatterOnlyWithinTheExtensionBehindTheWall) {
  const VotingView view(WallView(10.0f));
  // Just behind the wall (within σ_matter·10 = 0.1 m): matter; farther behind: nothing.
  const std::array<Eigen::Vector3d, 4> behind{Eigen::Vector3d(-1, -1, 10.03), Eigen::Vector3d(1, -1, 10.03),
                                              Eigen::Vector3d(0, 1, 10.03), Eigen::Vector3d(0, 0, 10.09)};
  const VoteIncrement v = VoteCell(behind, view, PaperGeometry());
  EXPECT_EQ(v.free_q, 0);
  EXPECT_GT(Rays(v.matter_q), 0.5 * CrossingRays(behind, 10.2, *view.view));
  const std::array<Eigen::Vector3d, 4> far{Eigen::Vector3d(-1, -1, 11), Eigen::Vector3d(1, -1, 11),
                                           Eigen::Vector3d(0, 1, 11), Eigen::Vector3d(0, 0, 12)};
  const VoteIncrement none = VoteCell(far, view, PaperGeometry());
  EXPECT_EQ(none.free_q, 0);
  EXPECT_EQ(none.matter_q, 0);
}

// With depth noise each pixel's point votes by the probability that the true surface lies beyond the sample:
// free Φ(d/σ), matter 1 − Φ(d/σ), out to the extension + matter_behind_sigmas σ behind it.
TEST(DepthVotes, NoisyPointsVoteByTheProbabilityOfTheSurface) {
  // σ_z at 10 m with f·B = 100 px · 2 (stride) · 0.5 m and σ = 1 px: 100 / 100 = 1 m (along the ray within
  // 1 % near the image centre).
  const VotingView view(WallView(10.0f));
  DepthVoteGeometry noisy = PaperGeometry();
  noisy.disparity_sigma_px = 1.0;
  noisy.matter_behind_sigmas = 3.0;
  // A flat cell at the wall: as much free as matter.
  const auto flat_cell = [](double z_m) {
    return std::array<Eigen::Vector3d, 4>{
        Eigen::Vector3d(-0.5, -0.5, z_m - 0.01), Eigen::Vector3d(0.5, -0.5, z_m - 0.01),
        Eigen::Vector3d(0, 0.5, z_m - 0.01), Eigen::Vector3d(0, 0, z_m + 0.02)};
  };
  const VoteIncrement at = VoteCell(flat_cell(10.0), view, noisy);
  EXPECT_GT(at.free_q, 0);
  EXPECT_NEAR(double(at.free_q) / double(at.free_q + at.matter_q), 0.5, 0.02);
  // 1 σ in front: free 0.84; 1 σ behind: matter 0.84 (Φ(1) = 0.841).
  const VoteIncrement before = VoteCell(flat_cell(9.0), view, noisy);
  EXPECT_NEAR(double(before.free_q) / double(before.free_q + before.matter_q), 0.841, 0.02);
  const VoteIncrement behind = VoteCell(flat_cell(11.0), view, noisy);
  EXPECT_NEAR(double(behind.matter_q) / double(behind.free_q + behind.matter_q), 0.841, 0.02);
  // The votes of a cell are those of its rays: the sum is the cell's footprint, whatever its depth.
  EXPECT_NEAR(Rays(at.free_q + at.matter_q) / Rays(before.free_q + before.matter_q), 81.0 / 100.0, 0.03);
  // 6 σ in front: free only; beyond 3 σ + the extension behind: nothing.
  const VoteIncrement far_before = VoteCell(flat_cell(3.0), view, noisy);
  EXPECT_EQ(far_before.matter_q, 0);
  EXPECT_GT(far_before.free_q, 0);
  const VoteIncrement far_behind = VoteCell(flat_cell(13.5), view, noisy);
  EXPECT_EQ(far_behind.free_q, 0);
  EXPECT_EQ(far_behind.matter_q, 0);
  // The paper's exact-point weights vote the same cells differently: 1 σ behind the wall is beyond the
  // extension (nothing), 1 σ in front saturated free.
  const VoteIncrement exact_behind = VoteCell(flat_cell(11.0), view, PaperGeometry());
  EXPECT_EQ(exact_behind.free_q + exact_behind.matter_q, 0);
  const VoteIncrement exact_before = VoteCell(flat_cell(9.0), view, PaperGeometry());
  EXPECT_EQ(exact_before.matter_q, 0);
}

// Summed over many noisy sightings of one wall, the free/matter boundary is where the wall is: the carved
// side ends at the surface, not at the far tail of the noise (as it does with exact-point weights, which
// carve wherever any sighting lay behind the cell).
TEST(DepthVotes, ManyNoisySightingsPutTheBoundaryAtTheSurface) {
  DepthVoteGeometry noisy = PaperGeometry();
  noisy.disparity_sigma_px = 1.0;  // σ_z = 1 m at 10 m
  noisy.matter_behind_sigmas = 3.0;
  std::mt19937 rng(9);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<VotingView> views;
  for (int k = 0; k < 200; ++k) views.emplace_back(WallView(float(10.0 + noise(rng))));
  // The depth (along the optical axis) where a flat cell turns from free to matter, by bisection.
  const auto boundary = [&](const DepthVoteGeometry& geometry) {
    double lo = 5.0, hi = 15.0;
    for (int it = 0; it < 30; ++it) {
      const double z = 0.5 * (lo + hi);
      const std::array<Eigen::Vector3d, 4> cell{
          Eigen::Vector3d(-0.5, -0.5, z - 0.01), Eigen::Vector3d(0.5, -0.5, z - 0.01),
          Eigen::Vector3d(0, 0.5, z - 0.01), Eigen::Vector3d(0, 0, z + 0.02)};
      std::int64_t free = 0, matter = 0;
      for (const VotingView& view : views) {
        const VoteIncrement v = VoteCell(cell, view, geometry);
        free += v.free_q;
        matter += v.matter_q;
      }
      (free > matter ? lo : hi) = z;
    }
    return 0.5 * (lo + hi);
  };
  // Within the standard error of the mean of 200 sightings (0.07 m) a few times over.
  EXPECT_NEAR(boundary(noisy), 10.0, 0.25);
  EXPECT_GT(boundary(PaperGeometry()), 11.5) << "exact-point weights carve into the noise's far tail";
}

TEST(DepthVotes, SkyVotesFreeUpToTheFarRangeAndNoMatter) {
  const VotingView view(WallView(kFreeToFarRange, /*max_depth_m=*/20.0));
  std::mt19937 rng(4);
  const auto near = RandomTet(&rng, 5.0, 12.0, 2.0);
  const VoteIncrement v = VoteCell(near, view, PaperGeometry());
  EXPECT_NEAR(Rays(v.free_q), CrossingRays(near, 20.0, *view.view),
              0.15 * CrossingRays(near, 20.0, *view.view) + 60);
  EXPECT_EQ(v.matter_q, 0);
  const auto beyond = RandomTet(&rng, 25.0, 30.0, 2.0);
  const VoteIncrement none = VoteCell(beyond, view, PaperGeometry());
  EXPECT_EQ(none.free_q, 0);
  EXPECT_EQ(none.matter_q, 0);
}

TEST(DepthVotes, NothingBehindTheCameraOutsideTheImageOrWithoutDepth) {
  const VotingView view(WallView(10.0f));
  std::mt19937 rng(5);
  const auto behind = RandomTet(&rng, -8.0, -3.0, 2.0);
  EXPECT_EQ(VoteCell(behind, view, PaperGeometry()).free_q, 0);
  std::array<Eigen::Vector3d, 4> aside = RandomTet(&rng, 3.0, 5.0, 0.5);
  for (auto& p : aside) p.x() += 20.0;  // far right of a ±39° view
  const VoteIncrement v = VoteCell(aside, view, PaperGeometry());
  EXPECT_EQ(v.free_q, 0);
  EXPECT_EQ(v.matter_q, 0);
  const VotingView blind(WallView(0.0f));
  const auto tet = RandomTet(&rng, 3.0, 8.0, 1.5);
  EXPECT_EQ(VoteCell(tet, blind, PaperGeometry()).free_q, 0);
}

TEST(DepthVotes, TheCellHoldingTheCameraGetsEveryRay) {
  const VotingView view(WallView(10.0f));
  const std::array<Eigen::Vector3d, 4> around{Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, -1, -1),
                                              Eigen::Vector3d(0, 1, -1), Eigen::Vector3d(0, 0, 2)};
  const VoteIncrement v = VoteCell(around, view, PaperGeometry());
  EXPECT_EQ(Rays(v.free_q), double(kWidthPx) * kHeightPx * view.view->rays_per_pixel);
  EXPECT_EQ(v.matter_q, 0);
}

TEST(DepthVotes, AFacetIsSeenWhereItLiesAtItsPixelsDepth) {
  const VotingView view(WallView(10.0f));
  // The facet opposite vertex 3 lies on the wall (within the 0.1 m extension). (The other three reach 2 m in
  // front of it; near their edge on the wall they come within the tolerance of the wall's points.)
  const std::array<Eigen::Vector3d, 4> tet{Eigen::Vector3d(-2, -2, 10.05), Eigen::Vector3d(2, -2, 10.05),
                                           Eigen::Vector3d(0, 2, 10.05), Eigen::Vector3d(0, 0, 8)};
  EXPECT_EQ(SeenFacets(tet, 0x8, view, PaperGeometry()), 0x8);
  EXPECT_EQ(SeenFacets(tet, 0x7, view, PaperGeometry()) & 0x8, 0x0) << "only the candidates are tested";
  // A cell floating 1.5–2 m in front of the wall: none of its facets.
  std::array<Eigen::Vector3d, 4> floating = tet;
  for (auto& p : floating) p.z() = p.z() == 8.0 ? 8.0 : 8.5;
  EXPECT_EQ(SeenFacets(floating, 0xF, view, PaperGeometry()), 0x0);
  // A facet parallel to the wall, 0.95 m in front of it: seen only within a tolerance that reaches the wall.
  // With depth noise the tolerance widens: σ_z = 1 m at 10 m (σ = 1 px, f·B = 100 px · 2 · 0.5 m).
  const std::array<Eigen::Vector3d, 4> before{Eigen::Vector3d(-1, -1, 9.05), Eigen::Vector3d(1, -1, 9.05),
                                              Eigen::Vector3d(0, 1, 9.05), Eigen::Vector3d(0, 0, 8.5)};
  EXPECT_EQ(SeenFacets(before, 0x8, view, PaperGeometry()), 0x0);
  DepthVoteGeometry noisy = PaperGeometry();
  noisy.disparity_sigma_px = 1.0;
  noisy.seen_noise_sigmas = 1.0;  // 0.1 + 1 m ≥ 0.95 m
  EXPECT_EQ(SeenFacets(before, 0x8, view, noisy), 0x8);
  noisy.seen_noise_sigmas = 0.5;  // 0.1 + 0.5 m < 0.95 m
  EXPECT_EQ(SeenFacets(before, 0x8, view, noisy), 0x0);
  // A 2 cm facet edge-on to the camera, 3 m before the wall: the wall point seen through its centroid lies in
  // its plane, but far outside the facet.
  const std::array<Eigen::Vector3d, 4> edge_on{Eigen::Vector3d(0, -0.01, 6.99),
                                               Eigen::Vector3d(0, 0.01, 6.99), Eigen::Vector3d(0, 0, 7.01),
                                               Eigen::Vector3d(0.01, 0, 7)};
  noisy.seen_noise_sigmas = 1.0;
  EXPECT_EQ(SeenFacets(edge_on, 0x8, view, noisy), 0x0);
  // Against the sky, without depth, behind the camera or outside the image: never seen.
  EXPECT_EQ(SeenFacets(tet, 0xF, VotingView(WallView(kFreeToFarRange)), PaperGeometry()), 0x0);
  EXPECT_EQ(SeenFacets(tet, 0xF, VotingView(WallView(0.0f)), PaperGeometry()), 0x0);
  std::array<Eigen::Vector3d, 4> behind = tet, aside = tet;
  for (auto& p : behind) p.z() = -p.z();
  for (auto& p : aside) p.x() += 20.0;
  EXPECT_EQ(SeenFacets(behind, 0xF, view, PaperGeometry()), 0x0);
  EXPECT_EQ(SeenFacets(aside, 0xF, view, PaperGeometry()), 0x0);
}

TEST(DepthVotes, AWideFacetIsSeenOnlyWhereItsHalfwayPointsAgreeTooWhenAsked) {
  // A wall at 10 m whose left part (image columns < 70) lies 2 m farther back: a depth edge.
  auto stepped = test::PinholeDepthView(kWidthPx, kHeightPx, kFocalPx, 40.0);
  stepped->depth_m.setTo(10.0f);
  stepped->depth_m.colRange(0, 70).setTo(12.0f);
  const VotingView view(stepped);
  // A facet on the near wall (the facet opposite vertex 3) whose centroid's pixel (column 80) sees the near
  // wall, and which spans over the edge: the point halfway to its left corner is at column 60, where the view
  // saw the far part. Its corners lie up to 4.2 m from its centroid.
  const std::array<Eigen::Vector3d, 4> wide{Eigen::Vector3d(-4, -2, 10.05), Eigen::Vector3d(2, -2, 10.05),
                                            Eigen::Vector3d(2, 2, 10.05), Eigen::Vector3d(0, 0, 8)};
  DepthVoteGeometry geometry = PaperGeometry();
  EXPECT_EQ(SeenFacets(wide, 0x8, view, geometry), 0x8) << "the centroid alone (the default)";
  geometry.seen_halfway_min_radius_m = 1.0;
  EXPECT_EQ(SeenFacets(wide, 0x8, view, geometry), 0x0)
      << "halfway to the left corner the view saw 2 m beyond";
  geometry.seen_halfway_min_radius_m = 5.0;
  EXPECT_EQ(SeenFacets(wide, 0x8, view, geometry), 0x8) << "narrower than the radius: the centroid alone";
  // The same facet in front of a flat wall: its halfway points agree.
  geometry.seen_halfway_min_radius_m = 1.0;
  EXPECT_EQ(SeenFacets(wide, 0x8, VotingView(WallView(10.0f)), geometry), 0x8);
  // Where the view has no depth halfway (sky or none), the centroid decides.
  auto holed = test::PinholeDepthView(kWidthPx, kHeightPx, kFocalPx, 40.0);
  holed->depth_m.setTo(10.0f);
  holed->depth_m.colRange(0, 70).setTo(kFreeToFarRange);
  EXPECT_EQ(SeenFacets(wide, 0x8, VotingView(holed), geometry), 0x8);
}

// CellsInView against every cell: the cells a view votes or sees a facet of are all among those it walks to.
TEST(CellsInView, HoldsEveryCellTheViewVotesOrSees) {
  std::mt19937 rng(17);
  // A turned camera inside a cloud of points; depths at random, with holes and sky.
  auto depth = test::PinholeDepthView(kWidthPx, kHeightPx, kFocalPx, 40.0);
  std::uniform_real_distribution<float> depth_m(1.0f, 50.0f), unit(0.0f, 1.0f);
  for (int v = 0; v < kHeightPx; ++v) {
    for (int u = 0; u < kWidthPx; ++u) {
      const float r = unit(rng);
      depth->depth_m.at<float>(v, u) = r < 0.1f ? 0.0f : r < 0.15f ? kFreeToFarRange : depth_m(rng);
    }
  }
  depth->world_from_cam = Eigen::Translation3d(2.0, -1.0, 3.0) *
                          Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.2, 1.0, 0.1).normalized());
  const VotingView view(depth);
  Delaunay dt;
  std::uniform_real_distribution<double> coordinate(-40.0, 40.0);
  for (int i = 0; i < 3000; ++i) dt.insert(Point(coordinate(rng), coordinate(rng), coordinate(rng)));

  std::vector<CellHandle> walked;
  ASSERT_TRUE(CellsInView(dt, view, /*visit_mark=*/1, &walked));
  const std::set<CellHandle> in_view(walked.begin(), walked.end());
  EXPECT_EQ(in_view.size(), walked.size()) << "a cell was walked to twice";
  std::size_t voted = 0, finite = 0;
  for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c) {
    ++finite;
    std::array<Eigen::Vector3d, 4> vertices;
    for (int k = 0; k < 4; ++k) vertices[k] = ToEigen(c->vertex(k)->point());
    const VoteIncrement vote = VoteCell(vertices, view, PaperGeometry());
    const std::uint8_t seen = SeenFacets(vertices, 0xF, view, PaperGeometry());
    if (vote.free_q == 0 && vote.matter_q == 0 && seen == 0) continue;
    ++voted;
    EXPECT_EQ(in_view.count(c), 1u) << "a cell the view votes is not walked to";
  }
  EXPECT_GT(voted, 500u);
  // The walk passes over most of the cells out of view.
  EXPECT_LT(walked.size(), finite / 2);
}

TEST(CellsInView, FailsForACameraOutsideTheTriangulation) {
  auto depth = test::PinholeDepthView(kWidthPx, kHeightPx, kFocalPx, 40.0);
  depth->world_from_cam = Eigen::Translation3d(0.0, 0.0, -100.0) * Eigen::AngleAxisd::Identity();
  Delaunay dt;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> coordinate(-10.0, 10.0);
  for (int i = 0; i < 100; ++i) dt.insert(Point(coordinate(rng), coordinate(rng), coordinate(rng)));
  std::vector<CellHandle> walked;
  EXPECT_FALSE(CellsInView(dt, VotingView(depth), 1, &walked));
  EXPECT_TRUE(walked.empty());
}

}  // namespace
}  // namespace semap::map_internal
