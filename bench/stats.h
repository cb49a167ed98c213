// Summary statistics the bench programs print (not API): NaN for an empty sample.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace semap::bench {

inline double Mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return v.empty() ? std::nan("") : s / static_cast<double>(v.size());
}

// The upper median (the element at n / 2 once sorted).
inline double Median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// The bin of `value` among ascending `edges` (bin b is [edges[b], edges[b + 1])), or -1 outside them all.
template <std::size_t N>
int BinOf(const double (&edges)[N], double value) {
  for (std::size_t b = 0; b + 1 < N; ++b) {
    if (value >= edges[b] && value < edges[b + 1]) return static_cast<int>(b);
  }
  return -1;
}

}  // namespace semap::bench
