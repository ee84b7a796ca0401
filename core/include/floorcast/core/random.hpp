// Counter-based randomness: every random number is a pure function of (seed, stream, indices),
// so results never depend on thread count or evaluation order.
//
//   const CounterRng rng(seed, kStreamNoise, view, pixel);
//   double u = rng.uniform(0);   // draw number 0 of this (seed, stream, view, pixel)
//   double n = rng.normal(1);    // draw number 1, standard normal
#pragma once

#include <cstdint>

namespace floorcast {

/// SplitMix64 finaliser: a bijective 64-bit mixer with full avalanche.
inline std::uint64_t mix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

namespace detail {
constexpr int kNormalTableCells = 1 << 12;
/// Phi^-1 at u_k = k / kNormalTableCells (k = 0..cells), ends clamped; filled at static
/// initialisation (random.cpp).
extern const float* const normal_quantile_table;
}  // namespace detail

/// Standard normal quantile Phi^-1(u) for u in (0, 1) via a precomputed table with linear
/// interpolation (2^12 float cells, 16 KB, so it stays in L1; |error| < 1e-4 for |z| < 2.5,
/// coarser in the far tails, which are clamped at |z| = 4.0; the variance is within 1e-3 of 1).
inline double normal_quantile_fast(double u) {
  const double s = u * detail::kNormalTableCells;
  int k = static_cast<int>(s);
  k = k < 0 ? 0 : (k > detail::kNormalTableCells - 1 ? detail::kNormalTableCells - 1 : k);
  const double f = s - k;
  const double z0 = detail::normal_quantile_table[k], z1 = detail::normal_quantile_table[k + 1];
  return z0 + f * (z1 - z0);
}

/// Exact (double precision) standard normal quantile, for tests and table construction.
double normal_quantile(double u);

/// Standard normal from 32 uniform bits: the top 12 bits pick the table cell, the rest
/// interpolate linearly inside it.
inline float normal_from_u32(std::uint32_t b) {
  static_assert(detail::kNormalTableCells == 1 << 12, "12 index bits");
  const std::uint32_t k = b >> 20;
  const float f = static_cast<float>(b & 0xFFFFFu) * (1.0f / 1048576.0f);
  const float z0 = detail::normal_quantile_table[k], z1 = detail::normal_quantile_table[k + 1];
  return z0 + f * (z1 - z0);
}

class CounterRng {
 public:
  CounterRng(std::uint64_t seed, std::uint64_t stream, std::uint64_t a = 0, std::uint64_t b = 0)
      : key_(mix64(mix64(mix64(seed ^ mix64(stream)) ^ a) + 0x632be59bd9b4e019ULL * (b + 1))) {}

  /// An independent generator for item i of this one (e.g. a pixel of a view): cheaper than
  /// building a generator from the seed for every item.
  CounterRng child(std::uint64_t i) const { return CounterRng(mix64(key_ ^ (0xd1342543de82ef95ULL * (i + 1)))); }

  /// One standard normal for item i (e.g. a pixel) with a single hash: the cheapest draw when an
  /// item needs just one number. Independent of child(i)'s draws.
  double item_normal(std::uint64_t i) const {
    const std::uint64_t b = mix64(key_ ^ (0x9fb21c651e98df25ULL * (i + 1)));
    return normal_quantile_fast((static_cast<double>(b >> 11) + 0.5) * (1.0 / 9007199254740992.0));
  }

  /// Two standard normals for item i from a single hash (32 bits each, table lookup in float):
  /// the cheapest way to draw per-pixel noise for pixel pairs.
  void item_normal_pair(std::uint64_t i, float& z0, float& z1) const {
    const std::uint64_t b = mix64(key_ ^ (0xc2b2ae3d27d4eb4fULL * (i + 1)));
    z0 = normal_from_u32(static_cast<std::uint32_t>(b));
    z1 = normal_from_u32(static_cast<std::uint32_t>(b >> 32));
  }

  /// 64 random bits, draw k.
  std::uint64_t bits(std::uint64_t k) const { return mix64(key_ ^ mix64(k + 0x5851f42d4c957f2dULL)); }
  /// Uniform in (0, 1) (never exactly 0 or 1), draw k.
  double uniform(std::uint64_t k) const {
    return (static_cast<double>(bits(k) >> 11) + 0.5) * (1.0 / 9007199254740992.0);
  }
  /// Standard normal, draw k (table-based quantile transform: fast, deterministic).
  double normal(std::uint64_t k) const { return normal_quantile_fast(uniform(k)); }

 private:
  explicit CounterRng(std::uint64_t key) : key_(key) {}
  std::uint64_t key_;
};

/// Stream identifiers: different uses of one seed never share random numbers.
enum RngStream : std::uint64_t {
  kRngViewScale = 1,
  kRngViewWarp = 2,
  kRngPixelNoise = 3,
  kRngPixelJitter = 4,
  kRngGlass = 5,
  kRngTracker = 6,
  kRngDropout = 7,
  kRngFlying = 8,
  kRngClutter = 9,
  // Monocular depth model (sim/scan_sim.cpp).
  kRngScanScale = 20,
  kRngViewShift = 21,
  kRngTextureless = 22,
  kRngNoGround = 23,
};

}  // namespace floorcast
