#include "engine/depth/internal/disparity_fill.h"

#include <algorithm>

#include "engine/core/check.h"

namespace semap::depth_internal {

void FillDisparity(int max_gap_px, int border_px, float gap_confidence, cv::Mat* disparity,
                   cv::Mat* confidence) {
  SEMAP_ASSERT(disparity && confidence && disparity->type() == CV_32FC1);
  confidence->create(disparity->size(), CV_32FC1);
  for (int v = 0; v < disparity->rows; ++v) {
    float* d = disparity->ptr<float>(v);
    float* c = confidence->ptr<float>(v);
    const int cols = disparity->cols;
    for (int u = 0; u < cols; ++u) {
      if (!(d[u] > 0.0f)) d[u] = 0.0f;  // NaN and negative → invalid
      c[u] = d[u] > 0.0f ? 1.0f : 0.0f;
    }
    int first_valid = -1;
    int last_valid = -1;
    for (int u = 0; u < cols; ++u) {
      if (c[u] != 1.0f) continue;
      if (first_valid < 0) first_valid = u;
      const int gap = u - last_valid - 1;
      if (last_valid >= 0 && gap > 0 && gap <= max_gap_px) {
        const float fill = std::min(d[last_valid], d[u]);
        for (int g = last_valid + 1; g < u; ++g) {
          d[g] = fill;
          c[g] = gap_confidence;
        }
      }
      last_valid = u;
    }
    if (border_px > 0 && first_valid > 0 && first_valid <= border_px) {
      for (int u = 0; u < first_valid; ++u) {
        d[u] = d[first_valid];
        c[u] = 0.0f;
      }
    }
  }
}

}  // namespace semap::depth_internal
