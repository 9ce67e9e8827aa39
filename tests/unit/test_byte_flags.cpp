// Byte flags read eight at a time (byte_flags.hpp) against a byte-by-byte loop (the
// oracle): the indices visited and their order, for every length 0..70 (whole words and
// tails), every density, flags of any non-zero value, and null flags (every index).
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "fg/core/byte_flags.hpp"

namespace {

std::vector<uint32_t> visited(const uint8_t* flags, uint32_t n) {
  std::vector<uint32_t> out;
  fg::for_each_flagged(flags, n, [&](uint32_t i) { out.push_back(i); });
  return out;
}

TEST(ByteFlags, ForEachFlaggedVisitsTheNonZeroBytesInOrder) {
  std::mt19937 rng(2811);
  for (uint32_t n = 0; n <= 70; ++n) {
    for (double density : {0.0, 0.02, 0.2, 0.5, 0.9, 1.0}) {
      for (int rep = 0; rep < 20; ++rep) {
        // One guard byte past n, set: it must never be visited.
        std::vector<uint8_t> flags(n + 1, 0);
        std::vector<uint32_t> expected;
        for (uint32_t i = 0; i < n; ++i) {
          if (std::uniform_real_distribution<double>(0.0, 1.0)(rng) < density)
            flags[i] = static_cast<uint8_t>(1 + rng() % 255);  // 0x80 and 0x01 alike
          if (flags[i] != 0) expected.push_back(i);
        }
        flags[n] = 0xFF;
        EXPECT_EQ(visited(flags.data(), n), expected) << "n " << n << " density " << density;
      }
    }
  }
}

TEST(ByteFlags, NullFlagsVisitEveryIndex) {
  for (uint32_t n : {0u, 1u, 7u, 8u, 9u, 64u, 65u}) {
    std::vector<uint32_t> expected(n);
    for (uint32_t i = 0; i < n; ++i) expected[i] = i;
    EXPECT_EQ(visited(nullptr, n), expected);
  }
}

TEST(ByteFlags, NonzeroBytes8SetsOneBitPerNonZeroByte) {
  std::mt19937 rng(7);
  for (int rep = 0; rep < 10000; ++rep) {
    uint8_t b[8];
    uint32_t expected = 0;
    for (uint32_t k = 0; k < 8; ++k) {
      const uint32_t r = rng();
      b[k] = (r & 3u) == 0 ? 0 : static_cast<uint8_t>(r >> 8);  // a quarter zeros, then any value (0 too)
      if (b[k] != 0) expected |= 1u << k;
    }
    EXPECT_EQ(fg::nonzero_bytes8(b), expected);
  }
}

}  // namespace
