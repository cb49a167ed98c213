#include "engine/map/incremental_map.h"

#include <chrono>
#include <memory>

#include "engine/map/internal/finaliser.h"
#include "engine/map/internal/map_state.h"
#include "engine/map/internal/region_carver.h"
#include "engine/map/internal/surface_extraction.h"
#include "engine/map/internal/vote_mode.h"

namespace semap {

using namespace map_internal;

namespace {

// Milliseconds since `*since`, which is moved to now.
double Lap(std::chrono::steady_clock::time_point* since) {
  const auto now = std::chrono::steady_clock::now();
  const double ms = std::chrono::duration<double, std::milli>(now - *since).count();
  *since = now;
  return ms;
}

}  // namespace

// The map's parts and their owner: the state every step shares, the carver of the changed region, the vote
// mode map.visibility names and the finaliser, each given the state (and the parts it calls) by reference.
class IncrementalMap::Impl {
 public:
  explicit Impl(const MapOptions& options)
      : state_(options, OutputRule(options)),
        carver_(state_),
        votes_(MakeVoteMode(state_, carver_)),
        finaliser_(state_, carver_, *votes_) {}
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;

  MapUpdateResult Update(const LabelledCloud& frame, const std::vector<Observation>& extra);
  MapUpdateResult InsertHeldPoints();

  IdentifiedMesh ExtractMesh() const { return state_.mesher.ExtractLive(); }
  IdentifiedMesh TakeFinalisedMesh() { return state_.mesher.TakeFinalised(); }
  std::vector<CellVotes> CellVotesSnapshot() const { return CollectCellVotes(state_.dt); }
  MapSnapshot ExportSnapshot() const { return votes_->ExportSnapshot(); }
  MapStatistics Sizes() const;
  MapStatistics Statistics() const;

 private:
  // The steps after the points are located, in the order they run, each timed from `lap`.
  void InsertVoteCarveFinalise(std::vector<PendingVertex>* pending,
                               std::chrono::steady_clock::time_point* lap, MapUpdateResult* result);
  // The cells no longer free uncarved, the free ones carved, the manifold repaired; then the new surface
  // facets the views saw marked (carve).
  void Carve(MapUpdateResult* result);
  // The parts left behind emitted and released (every map.finalise_every_frames frames); the vertices the
  // carver could not repair handed to the mesher (finalise).
  void Finalise(MapUpdateResult* result);

  MapState state_;
  RegionCarver carver_;
  std::unique_ptr<VoteMode> votes_;
  Finaliser finaliser_;
};

// One frame: its cameras and the lattice around them; its points located (merged into the points they land
// on, or pending insertion); then insert, votes, carve, finalise.
MapUpdateResult IncrementalMap::Impl::Update(const LabelledCloud& frame,
                                             const std::vector<Observation>& extra) {
  frame.AssertConsistent();
  votes_->CheckInput(frame, extra);
  MapUpdateResult result;
  auto lap = std::chrono::steady_clock::now();
  state_.BeginFrame(frame);
  std::vector<PendingVertex> pending = votes_->Locate(frame, extra, &result);
  result.locate_ms = Lap(&lap);
  InsertVoteCarveFinalise(&pending, &lap, &result);
  return result;
}

// The held points as pending vertices, then the same steps as a frame's.
MapUpdateResult IncrementalMap::Impl::InsertHeldPoints() {
  MapUpdateResult result;
  if (!votes_->HoldsPoints()) return result;
  auto lap = std::chrono::steady_clock::now();
  state_.BeginUpdate();
  std::vector<PendingVertex> pending = votes_->LocateHeld(&result);
  result.locate_ms = Lap(&lap);
  InsertVoteCarveFinalise(&pending, &lap, &result);
  return result;
}

void IncrementalMap::Impl::InsertVoteCarveFinalise(std::vector<PendingVertex>* pending,
                                                   std::chrono::steady_clock::time_point* lap,
                                                   MapUpdateResult* result) {
  votes_->Insert(pending, result);
  result->insert_ms = Lap(lap);
  votes_->Vote(result);
  result->trace_ms = Lap(lap);
  Carve(result);
  result->carve_ms = Lap(lap);
  Finalise(result);
  result->finalise_ms = Lap(lap);
}

void IncrementalMap::Impl::Carve(MapUpdateResult* result) {
  result->cells_uncarved += carver_.ShrinkNonFree();
  result->cells_carved = carver_.Regrow();
  votes_->MarkSeenSurface();
}

void IncrementalMap::Impl::Finalise(MapUpdateResult* result) {
  finaliser_.Finalise(result);
  carver_.TakeIrregular();
}

MapStatistics IncrementalMap::Impl::Sizes() const {
  MapStatistics s = state_.Sizes();
  s.num_rays = votes_->LiveRays();
  return s;
}

MapStatistics IncrementalMap::Impl::Statistics() const {
  MapStatistics s = Sizes();
  s.num_carved_cells = CountCarvedCells(state_.dt);
  s.num_free_cells = CountFreeCells(state_.dt);
  return s;
}

IncrementalMap::IncrementalMap(const MapOptions& options) {
  options.Check();
  impl_ = std::make_unique<Impl>(options);
}
IncrementalMap::~IncrementalMap() = default;
IncrementalMap::IncrementalMap(IncrementalMap&&) noexcept = default;
IncrementalMap& IncrementalMap::operator=(IncrementalMap&&) noexcept = default;

MapUpdateResult IncrementalMap::Update(const LabelledCloud& frame_points,
                                       const std::vector<Observation>& extra) {
  return impl_->Update(frame_points, extra);
}
MapUpdateResult IncrementalMap::InsertHeldPoints() { return impl_->InsertHeldPoints(); }
Mesh IncrementalMap::ExtractMesh() const { return impl_->ExtractMesh().mesh; }
IdentifiedMesh IncrementalMap::ExtractIdentifiedMesh() const { return impl_->ExtractMesh(); }
IdentifiedMesh IncrementalMap::TakeFinalisedMesh() { return impl_->TakeFinalisedMesh(); }
std::vector<CellVotes> IncrementalMap::CellVotesSnapshot() const { return impl_->CellVotesSnapshot(); }
MapSnapshot IncrementalMap::ExportSnapshot() const { return impl_->ExportSnapshot(); }
MapStatistics IncrementalMap::Statistics() const { return impl_->Statistics(); }
MapStatistics IncrementalMap::Sizes() const { return impl_->Sizes(); }

}  // namespace semap
