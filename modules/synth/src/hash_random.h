#pragma once
// Counter-based random numbers: every value is a pure function of its integer coordinates (seed,
// frame, pixel, ...), so the output does not depend on thread scheduling or evaluation order.
#include <cmath>
#include <cstdint>

namespace pf2 {
namespace synth {

inline std::uint64_t mix64(std::uint64_t x) {  // splitmix64 finaliser
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

inline std::uint64_t hashOf(std::uint64_t a, std::uint64_t b = 0, std::uint64_t c = 0,
                            std::uint64_t d = 0) {
  return mix64(mix64(mix64(mix64(a) ^ b) ^ c) ^ d);
}

// One mixing round for lattice coordinates (texture noise): cheaper than hashOf, still well spread.
inline std::uint64_t hashLattice(std::uint64_t seed, std::uint64_t i, std::uint64_t j) {
  return mix64(seed ^ (i * 0x9e3779b97f4a7c15ULL) ^ (j * 0xc2b2ae3d27d4eb4fULL));
}

// Uniform in [0, 1).
inline double uniform01(std::uint64_t h) { return static_cast<double>(h >> 11) * 0x1.0p-53; }

inline double uniform(std::uint64_t h, double lo, double hi) { return lo + (hi - lo) * uniform01(h); }

// Standard normal from a table of 4096 equally likely values (the normal quantiles at
// (k + 0.5) / 4096): deterministic, fast, tails cut at 3.5 sigma.
double gaussianFromTable(std::uint64_t h);

// Standard normal (Box–Muller) from one 64-bit hash.
inline double gaussian(std::uint64_t h) {
  const double u1 = (static_cast<double>(h >> 40) + 0.5) * 0x1.0p-24;
  const double u2 = static_cast<double>((h >> 16) & 0xffffffULL) * 0x1.0p-24;
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
}

// A small deterministic generator for sequential draws (scene layout, people's scripts).
class HashRng {
 public:
  explicit HashRng(std::uint64_t seed) : state_(mix64(seed)) {}
  std::uint64_t next() { return state_ = mix64(state_); }
  double uniform(double lo, double hi) { return synth::uniform(next(), lo, hi); }
  int integer(int lo, int hi) {  // inclusive
    return lo + static_cast<int>(uniform01(next()) * (hi - lo + 1));
  }
  double gaussian() { return synth::gaussian(next()); }

 private:
  std::uint64_t state_;
};

}  // namespace synth
}  // namespace pf2
