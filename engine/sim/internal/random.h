// Deterministic, platform-independent random numbers and procedural noise for the generator.
// Everything is a pure function of its inputs (no global state), so frames can be produced in any order and
// on any thread with identical results.
#pragma once

#include <cmath>
#include <cstdint>

namespace semap::sim::sim_internal {

// SplitMix64 finaliser: a good 64-bit mix of one value.
inline std::uint64_t Mix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

inline std::uint64_t HashCombine(std::uint64_t a, std::uint64_t b) {
  return Mix64(a ^ (Mix64(b) + 0x632be59bd9b4e019ULL));
}

// A small counter-based generator (SplitMix64 stream). Not thread-safe: one per thread/task.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(Mix64(seed)) {}
  std::uint64_t NextU64() {
    state_ += 0x9e3779b97f4a7c15ULL;
    std::uint64_t z = state_;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  // Uniform in [0, 1).
  double Uniform() { return static_cast<double>(NextU64() >> 11) * 0x1.0p-53; }
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
  // Uniform integer in [lo, hi].
  int UniformInt(int lo, int hi) { return lo + static_cast<int>(Uniform() * (hi - lo + 1)); }
  bool Bernoulli(double p) { return Uniform() < p; }
  // Approximately standard normal (Irwin-Hall: the sum of four 16-bit uniforms, centred and scaled to unit
  // variance; bounded at +-3.46). One draw per call: fast enough for per-pixel image noise.
  float FastNormal() {
    const std::uint64_t r = NextU64();
    const float sum =
        static_cast<float>((r & 0xffff) + ((r >> 16) & 0xffff) + ((r >> 32) & 0xffff) + (r >> 48));
    return (sum * (1.0f / 65536.0f) - 2.0f) * 1.7320508f;
  }
  // Standard normal (Box-Muller; the second value of each pair is kept for the next call).
  double Normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u1 = 1.0 - Uniform();  // (0, 1]
    const double u2 = Uniform();
    const double r = std::sqrt(-2.0 * std::log(u1)), a = 6.283185307179586 * u2;
    spare_ = r * std::sin(a);
    has_spare_ = true;
    return r * std::cos(a);
  }

 private:
  std::uint64_t state_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

// Uniform value in [0, 1) from a lattice point and a seed (one 64-bit mix: fast enough for per-pixel noise).
inline float LatticeValue(std::int64_t x, std::int64_t y, std::int64_t z, std::uint64_t seed) {
  const std::uint64_t h = seed ^ (static_cast<std::uint64_t>(x) * 0x9e3779b97f4a7c15ULL) ^
                          (static_cast<std::uint64_t>(y) * 0xc2b2ae3d27d4eb4fULL) ^
                          (static_cast<std::uint64_t>(z) * 0x165667b19e3779f9ULL);
  return static_cast<float>(Mix64(h) >> 40) * (1.0f / 16777216.0f);
}

inline float Smooth(float t) { return t * t * (3.0f - 2.0f * t); }

// 3D value noise in [0, 1) with unit lattice spacing.
inline float ValueNoise(double x, double y, double z, std::uint64_t seed) {
  const double fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
  const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy),
             iz = static_cast<std::int64_t>(fz);
  const float tx = Smooth(static_cast<float>(x - fx)), ty = Smooth(static_cast<float>(y - fy)),
              tz = Smooth(static_cast<float>(z - fz));
  auto lerp = [](float a, float b, float t) { return a + (b - a) * t; };
  const float c00 = lerp(LatticeValue(ix, iy, iz, seed), LatticeValue(ix + 1, iy, iz, seed), tx);
  const float c10 = lerp(LatticeValue(ix, iy + 1, iz, seed), LatticeValue(ix + 1, iy + 1, iz, seed), tx);
  const float c01 = lerp(LatticeValue(ix, iy, iz + 1, seed), LatticeValue(ix + 1, iy, iz + 1, seed), tx);
  const float c11 =
      lerp(LatticeValue(ix, iy + 1, iz + 1, seed), LatticeValue(ix + 1, iy + 1, iz + 1, seed), tx);
  return lerp(lerp(c00, c10, ty), lerp(c01, c11, ty), tz);
}

// Band-limited fractal noise in about [0, 1): octaves from `base_wavelength_m` down, halving each time;
// an octave whose wavelength is below two `footprint_m` (the size of a pixel on the surface) fades out and
// is replaced by its mean, so that distant textures do not alias.
inline float Fbm(double x, double y, double z, double base_wavelength_m, int octaves, double footprint_m,
                 std::uint64_t seed) {
  float sum = 0.0f, norm = 0.0f, amp = 1.0f;
  double wl = base_wavelength_m;
  for (int o = 0; o < octaves; ++o) {
    const double ratio = wl / (2.0 * footprint_m);
    if (ratio <= 0.5) {
      sum += amp * 0.5f;  // fully faded: the mean
    } else {
      const float w = ratio >= 1.0 ? 1.0f : static_cast<float>(2.0 * ratio - 1.0);
      const float n = ValueNoise(x / wl, y / wl, z / wl, seed + static_cast<std::uint64_t>(o) * 7919u);
      sum += amp * (w * n + (1.0f - w) * 0.5f);
    }
    norm += amp;
    amp *= 0.55f;
    wl *= 0.5;
  }
  return sum / norm;
}

}  // namespace semap::sim::sim_internal
