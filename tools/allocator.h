// Which malloc the semap executable runs on (see SEMAP_MIMALLOC in cmake/SemapDependencies.cmake).
#pragma once

#include <string>

namespace semap::tools {

// With mimalloc: freed memory stays committed for kDecommitDelayMs before it goes back to the OS, for pages
// (MIMALLOC_DECOMMIT_DELAY) and segments (MIMALLOC_SEGMENT_DECOMMIT_DELAY), each unless its environment
// variable is set (they are set as mimalloc's defaults, which its variables override). The pipeline frees and
// allocates the same few hundred MB every frame (SGBM's buffers, the votes' scratch, CGAL's cells); with
// mimalloc 2.0's defaults (25 and 500 ms) those pages are decommitted between frames and faulted in again.
// Keeping them a second: 80 urban frames, PS, half resolution, 2 cores: 3.86 → 5.30 f/s, CPU −27 %, peak RSS
// +17 % (bench/results/frame-rate.md, "mimalloc keeps freed memory for a second"). Call first thing in
// main(), before anything allocates. No-op without mimalloc.
inline constexpr long kDecommitDelayMs = 1000;
void ConfigureAllocator();

// "mimalloc X.Y.Z, decommit delay D ms" when the build links mimalloc and a block from malloc() lies in
// mimalloc's heap, "mimalloc X.Y.Z, linked but not serving malloc" when it does not, "system malloc"
// otherwise.
std::string AllocatorDescription();

}  // namespace semap::tools
