#pragma once
/// @file
/// Portable seeded randomness shared by the simulator and the dataset corruption model. Only raw
/// std::mt19937_64 output (whose sequence the C++ standard fixes) is used; the distributions are
/// implemented here because the standard library's differ between implementations, which would
/// make generated data platform-dependent. Single-owner objects, not thread-safe.

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>

namespace mvtrack::core {

/// SplitMix64 finaliser (Steele, Lea & Flood 2014): a bijective 64-bit mixer.
inline std::uint64_t Mix64(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

/// A std::mt19937_64 with portable distributions.
class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}

  /// Uniform in [0, 1) with 53 random bits.
  double Uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  /// Uniform in [lo, hi).
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
  /// True with probability p (exactly one draw, whatever p).
  bool Bernoulli(double p) { return Uniform() < p; }
  /// Uniform integer in [0, n), n >= 1 (multiply-shift; bias < n / 2^53, negligible here).
  std::uint64_t Index(std::uint64_t n) {
    const auto i = static_cast<std::uint64_t>(Uniform() * static_cast<double>(n));
    return i < n ? i : n - 1;
  }
  /// Standard normal by the Box-Muller transform (two draws per value, no cached state).
  double Normal() {
    const double u1 = 1.0 - Uniform();  // (0, 1]
    const double u2 = Uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }
  /// Poisson variate by Knuth's multiplication method (O(mean) draws; mean <= ~50 here).
  int Poisson(double mean) {
    if (!(mean > 0.0)) return 0;
    const double limit = std::exp(-mean);
    int k = 0;
    double p = Uniform();
    while (p > limit) {
      ++k;
      p *= Uniform();
    }
    return k;
  }

 private:
  std::mt19937_64 engine_;
};

}  // namespace mvtrack::core
