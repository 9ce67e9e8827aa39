// Host-only simulation: portable seeded random numbers (the standard distributions differ
// between library implementations, so the conversions to doubles are our own).
//
// One draw per full expression: the order in which a call's arguments (or an operator's
// operands) are evaluated is unspecified in C++, and GCC draws V3(rng.uniform(),
// rng.uniform(), rng.uniform()) right to left on x86-64 but left to right on mips, so
// the same seed made another scene there. The simulator's draws are named locals, in
// the order x86-64 drew them before (the same scenes as before on the host).
#pragma once
#include <cmath>
#include <cstdint>
#include <random>

namespace fg::sim {

//! SplitMix64 step: a good 64-bit mixer for deriving seeds.
inline uint64_t splitmix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

class Rng {
 public:
  explicit Rng(uint64_t seed) : gen_(splitmix64(seed)) {}
  //! Uniform in [0, 1).
  double uniform() { return static_cast<double>(gen_() >> 11) * 0x1.0p-53; }
  //! Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  //! Integer in [0, n).
  uint64_t index(uint64_t n) { return n == 0 ? 0 : static_cast<uint64_t>(uniform() * static_cast<double>(n)) % n; }
  bool chance(double p) { return uniform() < p; }
  uint64_t bits() { return gen_(); }
  //! Standard normal (Box-Muller).
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u1 = uniform();
    while (u1 <= 0.0) u1 = uniform();
    const double u2 = uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    constexpr double kTwoPi = 6.283185307179586476925;
    spare_ = r * std::sin(kTwoPi * u2);
    has_spare_ = true;
    return r * std::cos(kTwoPi * u2);
  }

 private:
  std::mt19937_64 gen_;
  bool has_spare_ = false;
  double spare_ = 0.0;
};

}  // namespace fg::sim
