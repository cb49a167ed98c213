#include "engine/map/map_options.h"

#include <cmath>

#include "engine/map/map_types.h"

namespace semap {

void MapOptions::Check() const {
  CheckDeclaredRanges(*this);
  if (!(steiner_spacing_m > 2.0 * ray_extension_m())) {
    throw OptionError(*this, steiner_spacing_m,
                      "must exceed twice the ray extension (" + KeyOf(*this, ray_extension_factor) + " * " +
                          KeyOf(*this, sigma_matter_m) + ")");
  }
}

std::int64_t MapOptions::repair_fill_cost_q() const {
  return std::llround(repair_fill_cost * kVoteFixedScale);
}

}  // namespace semap
