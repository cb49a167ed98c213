#include "engine/core/calibration.h"

#include <cmath>

namespace semap {

bool StereoCalibration::IsValid() const {
  const bool finite = std::isfinite(fx_px) && std::isfinite(fy_px) && std::isfinite(cx_px) &&
                      std::isfinite(cy_px) && std::isfinite(baseline_m);
  return finite && fx_px > 0.0 && fy_px > 0.0 && baseline_m > 0.0 && width_px > 0 && height_px > 0;
}

}  // namespace semap
