// The visibility integrator of map.visibility: depth: the window of the last frames' depth views, and their
// votes added to the cells of the triangulation it works on (depth_votes.h says how a vote relates to the
// paper's formula).
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <vector>

#include "engine/core/depth_view.h"
#include "engine/map/internal/depth_votes.h"
#include "engine/map/internal/triangulation.h"
#include "engine/map/map_options.h"

namespace semap::map_internal {

// A cell with its creation time (CGAL's time stamp), to sort by.
struct Stamped {
  std::size_t time_stamp;
  CellHandle cell;
};

// Like voxblox's integrators, it takes the map it writes and reports what changed: Integrate adds the votes
// of the window's views to the cells of the triangulation and marks the facets they see as a surface, and
// lists the cells whose state the carving must look at again; after the carving, MarkSeenSurface marks the
// new surface facets the views saw. It writes the cells' votes, seen bits and stamps (CellInfo: free_q,
// matter_q, seen_facets, stamp), nothing else. Works on a triangulation it does not
// own; not thread-safe (Integrate runs its loops on TBB's workers, on distinct cells).
class DepthIntegrator {
 public:
  DepthIntegrator(Delaunay* dt, const MapOptions& options);

  // Adds one frame's views (one per camera, none null or empty) to the window; the views of the frames before
  // the last map.vote_window_frames leave it (and those before the last map.seen_window_frames leave the
  // views MarkSeenSurface looks in).
  void AddFrame(const std::vector<std::shared_ptr<const DepthView>>& views);
  // The window, oldest first (the frame just added last).
  const std::deque<VotingView>& views() const { return views_; }

  // The marks of one update in CellInfo: `created` is the `created` mark of the cells the update created;
  // `touch` and `visit` are fresh stamps (of the cells listed as touched, of the cells the walk visits).
  struct Marks {
    std::uint32_t created = 0;
    std::uint32_t touch = 0;
    std::uint32_t visit = 0;
    // Whether the newest view votes the old cells it sees (false when the update adds vertices but no frame:
    // IncrementalMap::InsertHeldPoints; its views voted those cells already).
    bool newest_view = true;
  };
  // Adds the votes of the newest view to the old cells it sees (the live unsealed cells not created now that
  // a walk from the camera's cell finds in its frustum, or every one when the camera lies outside the
  // triangulation). A cell of `created` (cells this update created, each marked `marks.created`) gets the
  // votes of every view of the window instead of those it inherited, unless none of them sees it.
  // With map.drop_unseen_surface, marks the facets the newest view sees as a surface (SeenFacets) among the
  // surface facets no view saw yet of the old cells it sees (carved as before this update); the created
  // cells' facets are looked for after the carving (MarkSeenSurface). Appends to `touched` (stamped
  // `marks.touch`) the cells the carving must look at again (created now, changed sides, or free and still
  // outside the carved region), and to `newly_seen` the cells it marked facets of seen, both in creation
  // order. Returns the number of cells that got a vote. The votes are integers: the result does not depend on
  // the threads.
  std::size_t Integrate(const std::vector<CellHandle>& created, const Marks& marks,
                        std::vector<CellHandle>* touched, std::vector<CellHandle>* newly_seen);

  // With map.drop_unseen_surface, after the carving: the surface facets of `cells` (carved on exactly one
  // side; sealed neighbours by their bits) that no view saw yet, looked for in the views of the last
  // map.seen_window_frames frames, newest first (SeenFacets). `cells`: those the update created and those
  // whose carving it changed (duplicates, infinite and sealed cells are passed over). A facet becomes a
  // surface only when a cell beside it is created or changes sides, so every surface facet is looked for
  // when it becomes one (and later by each newest view that sees it, in Integrate), and only surface facets
  // are: looking for every facet of every created cell in the vote window as the cell is voted would take
  // ~14 % of the map's CPU (KITTI 04, half resolution) for facets mostly never a surface. A facet often
  // becomes a surface a few frames after its cells were made, when the newest views have passed it: hence
  // the longer window of older views (bench/results/map-accuracy.md, "surface facets looked for when they
  // become one"). Stamps the cells of `cells` with
  // `list_mark` (a fresh mark); appends the cells it marked facets of to `newly_seen`, in creation order.
  // Returns the number of facets marked. Deterministic (threads compute, one thread marks).
  std::size_t MarkSeenSurface(const std::vector<CellHandle>& cells, std::uint32_t list_mark,
                              std::vector<CellHandle>* newly_seen);

 private:
  // The cells Integrate votes from `view` alone, appended to `cells`.
  void CollectOldCellsInView(const VotingView& view, std::vector<CellHandle>* cells);
  // The votes of the created cells, the first `created_count` of scratch_.cells, from every view of the
  // window; returns how many got a vote.
  std::size_t VoteCreatedCells(std::size_t created_count);
  // Adds a vote to a cell's record and sets `touched` when the carving must look at the cell again. Returns
  // whether the vote was not zero. Safe on distinct cells in parallel: writes the cell's votes and stamp
  // only.
  bool AddVotes(std::int64_t free_q, std::int64_t matter_q, CellInfo* info, std::uint8_t* touched) const;

  Delaunay* dt_;
  DepthVoteGeometry geometry_;
  std::size_t window_frames_;          // map.vote_window_frames
  std::size_t seen_window_frames_;     // map.seen_window_frames
  bool track_seen_;                    // map.drop_unseen_surface
  std::deque<VotingView> views_;       // the window, newest last
  std::deque<VotingView> seen_views_;  // the views MarkSeenSurface looks in, newest last (shared with views_)
  Marks marks_;                        // the running Integrate's
  // Scratch, keeping its capacity between frames: the created cells and those in the newest view (~100 k on a
  // street; every live cell, ~650 k on a long drive, when the walk cannot start), which allocated anew (and
  // paged in, and zeroed) every frame cost more than the serial part of the votes.
  struct Scratch {
    std::vector<CellHandle> cells;      // the cells this update created, then the old ones in the view
    std::vector<std::uint8_t> seen;     // facets found seen (bit per facet)
    std::vector<std::uint8_t> touched;  // goes to `touched`
    struct Created {
      std::uint64_t key;    // spatial order
      std::uint32_t index;  // in `cells`
    };
    std::vector<Created> created_order;                  // the created cells, in spatial order
    std::vector<CellHandle> walk;                        // CollectOldCellsInView's queue
    std::vector<Stamped> touched_stamped, seen_stamped;  // `touched` and `newly_seen` before their sort
    std::vector<CellHandle> surface_cells;               // MarkSeenSurface's cells, once each
  } scratch_;
};

}  // namespace semap::map_internal
