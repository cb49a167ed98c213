#include "tools/allocator.h"

#include <cstdlib>
#include <cstring>

#ifdef SEMAP_WITH_MIMALLOC
#include <mimalloc.h>
#endif

namespace semap::tools {

void ConfigureAllocator() {
#ifdef SEMAP_WITH_MIMALLOC
  // Defaults, not values: mimalloc reads its MIMALLOC_* variables over them when the option is first used.
  mi_option_set_default(mi_option_decommit_delay, kDecommitDelayMs);
  mi_option_set_default(mi_option_segment_decommit_delay, kDecommitDelayMs);
#endif
}

std::string AllocatorDescription() {
#ifdef SEMAP_WITH_MIMALLOC
  // Linking mimalloc replaces malloc only if the dynamic linker binds malloc to it: ask mimalloc whether it
  // owns a block that plain malloc returned.
  void* probe = std::malloc(64);
  if (probe != nullptr) std::memset(probe, 0, 64);
  const bool serves_malloc = mi_is_in_heap_region(probe);
  std::free(probe);
  const int v = mi_version();  // e.g. 209 for 2.0.9
  return "mimalloc " + std::to_string(v / 100) + "." + std::to_string(v / 10 % 10) + "." +
         std::to_string(v % 10) +
         (serves_malloc
              ? ", decommit delay " + std::to_string(mi_option_get(mi_option_decommit_delay)) + " ms"
              : ", linked but not serving malloc");
#else
  return "system malloc";
#endif
}

}  // namespace semap::tools
