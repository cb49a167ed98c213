// Which malloc the semap executable runs on (see SEMAP_MIMALLOC in cmake/SemapDependencies.cmake).
#pragma once

#include <string>

namespace semap::tools {

// "mimalloc X.Y.Z" when the build links mimalloc and a block from malloc() lies in mimalloc's heap,
// "mimalloc X.Y.Z, linked but not serving malloc" when it does not, "system malloc" otherwise.
std::string AllocatorDescription();

}  // namespace semap::tools
