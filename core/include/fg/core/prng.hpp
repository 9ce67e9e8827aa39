// The core's own deterministic PRNG (splitmix64 seeding + xorshift64*): the same
// seed gives the same sequence on every target, unlike <random>'s distributions.
#pragma once
#include <cstdint>

namespace fg {

class Prng {
 public:
  explicit Prng(uint64_t seed) { reseed(seed); }
  void reseed(uint64_t seed) {
    uint64_t z = seed + 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    state_ = (z ^ (z >> 31)) | 1ull;
  }
  uint64_t next() {
    state_ ^= state_ >> 12;
    state_ ^= state_ << 25;
    state_ ^= state_ >> 27;
    return state_ * 0x2545F4914F6CDD1Dull;
  }
  //! Uniform integer in [0, n) for n > 0 (multiply-shift, no modulo bias worth noting).
  uint32_t below(uint32_t n) { return static_cast<uint32_t>(((next() >> 32) * static_cast<uint64_t>(n)) >> 32); }

 private:
  uint64_t state_ = 1;
};

}  // namespace fg
