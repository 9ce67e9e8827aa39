// The project's LZF decoder (platform/host/io/lzf.cpp) against liblzf, the library PCL's
// own LZF code was copied from (Debian's liblzf-dev, used here only): the streams
// liblzf's encoder writes, every binary_compressed capture in ../shared/data/clouds and
// the example scene, and damaged streams, where both must agree on what decodes.
#include <gtest/gtest.h>
#include <liblzf/lzf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "io/lzf.hpp"

namespace {

// What liblzf decodes when the caller expects exactly `expect` bytes (as the PCD reader
// does: the header declares the size): the bytes, or false when it refuses the stream
// or decodes to another length.
bool liblzf_decode(const std::vector<uint8_t>& in, size_t expect, std::vector<uint8_t>& out) {
  // One spare byte: a stream longer than expected must show as a length, not fit.
  out.assign(expect + 1, 0);
  const unsigned got =
      lzf_decompress(in.data(), static_cast<unsigned>(in.size()), out.data(), static_cast<unsigned>(out.size()));
  if (got != expect) return false;
  out.resize(expect);
  return true;
}

std::vector<uint8_t> liblzf_encode(const std::vector<uint8_t>& in) {
  std::vector<uint8_t> out(in.size() + in.size() / 16 + 64);
  const unsigned n =
      lzf_compress(in.data(), static_cast<unsigned>(in.size()), out.data(), static_cast<unsigned>(out.size()));
  out.resize(n);
  return out;
}

bool ours_decode(const std::vector<uint8_t>& in, size_t expect, std::vector<uint8_t>& out) {
  out.assign(expect, 0xA5);
  std::string err;
  return fg::host::lzf::decompress(in.data(), in.size(), out.data(), out.size(), err);
}

// The planar float layout of a binary_compressed cloud from a depth image: every x, then
// every y, then every z, NaN where the sensor saw nothing (runs of the same 4 bytes).
std::vector<uint8_t> organized_cloud_bytes(uint32_t w, uint32_t h, std::mt19937& rng) {
  std::vector<float> soa(static_cast<size_t>(w) * h * 3);
  std::normal_distribution<float> noise(0.f, 0.002f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (uint32_t v = 0; v < h; ++v)
    for (uint32_t u = 0; u < w; ++u) {
      const size_t i = static_cast<size_t>(v) * w + u;
      const bool hole = (u / 7 + v / 5) % 9 == 0 || u < 3;
      const float z = 0.8f + 0.3f * static_cast<float>(v) / static_cast<float>(h) + noise(rng);
      soa[i] = hole ? nan : (static_cast<float>(u) - 0.5f * w) / 525.f * z;
      soa[soa.size() / 3 + i] = hole ? nan : (static_cast<float>(v) - 0.5f * h) / 525.f * z;
      soa[2 * soa.size() / 3 + i] = hole ? nan : z;
    }
  std::vector<uint8_t> bytes(soa.size() * sizeof(float));
  std::memcpy(bytes.data(), soa.data(), bytes.size());
  return bytes;
}

TEST(LzfAgainstLiblzf, DecodesWhatLiblzfEncodes) {
  std::mt19937 rng(2026);
  std::vector<std::vector<uint8_t>> inputs;
  inputs.push_back(organized_cloud_bytes(640, 480, rng));
  inputs.push_back(organized_cloud_bytes(33, 7, rng));
  for (size_t n : {1u, 2u, 3u, 31u, 32u, 33u, 264u, 265u, 8191u, 8192u, 8193u, 100000u}) {
    std::vector<uint8_t> random(n), constant(n, 0x7F), periodic(n), words(n);
    for (size_t k = 0; k < n; ++k) {
      random[k] = static_cast<uint8_t>(rng());
      periodic[k] = static_cast<uint8_t>("abcdefghijk"[k % (1 + n % 11)]);
      words[k] = static_cast<uint8_t>(rng() % 4 == 0 ? rng() : k / 40);  // short repeats
    }
    inputs.insert(inputs.end(), {random, constant, periodic, words});
  }
  for (size_t t = 0; t < inputs.size(); ++t) {
    const std::vector<uint8_t>& in = inputs[t];
    const std::vector<uint8_t> packed = liblzf_encode(in);
    if (packed.empty()) continue;  // liblzf stores nothing it cannot shrink (random bytes)
    std::vector<uint8_t> out;
    ASSERT_TRUE(ours_decode(packed, in.size(), out)) << "input " << t << " of " << in.size() << " bytes";
    EXPECT_EQ(out, in) << "input " << t;
  }
}

// Every binary_compressed cloud the project ships or reads in its tests: the data section
// is <compressed size> <decompressed size> <stream>, both sizes uint32 little endian.
TEST(LzfAgainstLiblzf, SameBytesOnEveryCapture) {
  std::vector<std::string> paths = {std::string(FG_SOURCE_DIR) + "/examples/two-sensor-box/head.pcd",
                                    std::string(FG_SOURCE_DIR) + "/examples/two-sensor-box/hand.pcd"};
  const std::filesystem::path clouds = std::string(FG_SHARED_DIR) + "/data/clouds";
  if (std::filesystem::is_directory(clouds))
    for (const auto& e : std::filesystem::recursive_directory_iterator(clouds))
      if (e.path().extension() == ".pcd") paths.push_back(e.path().string());
  int compared = 0;
  for (const std::string& path : paths) {
    std::ifstream f(path, std::ios::binary);
    ASSERT_TRUE(f) << path;
    const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    static const char kTag[] = "DATA binary_compressed\n";
    const auto at = std::search(bytes.begin(), bytes.end(), kTag, kTag + sizeof kTag - 1);
    if (at == bytes.end()) continue;
    const size_t head = static_cast<size_t>(at - bytes.begin()) + sizeof kTag - 1;
    ASSERT_GE(bytes.size(), head + 8) << path;
    uint32_t packed = 0, unpacked = 0;
    std::memcpy(&packed, &bytes[head], 4);
    std::memcpy(&unpacked, &bytes[head + 4], 4);
    ASSERT_GE(bytes.size(), head + 8 + packed) << path;
    const std::vector<uint8_t> stream(bytes.begin() + static_cast<long>(head + 8),
                                      bytes.begin() + static_cast<long>(head + 8 + packed));
    std::vector<uint8_t> theirs, ours;
    ASSERT_TRUE(liblzf_decode(stream, unpacked, theirs)) << path;
    ASSERT_TRUE(ours_decode(stream, unpacked, ours)) << path;
    EXPECT_TRUE(ours == theirs) << path;
    ++compared;
  }
  // The two example clouds at least; the shared captures when ../shared is there.
  EXPECT_GE(compared, 2);
  std::printf("compared %d binary_compressed clouds\n", compared);
}

// Streams at the format's edges, each next to its neighbour one byte or one step away:
// a back-reference to exactly the first byte and to one before it, literal runs that
// end at and one past the input, a long match's length byte cut off.
TEST(LzfAgainstLiblzf, AgreesAtTheEdges) {
  std::vector<std::vector<uint8_t>> streams;
  for (uint8_t lits = 1; lits <= 9; ++lits) {
    std::vector<uint8_t> s{static_cast<uint8_t>(lits - 1)};
    for (uint8_t k = 0; k < lits; ++k) s.push_back(static_cast<uint8_t>('a' + k));
    for (unsigned dist = lits - 1; dist <= lits + 1u; ++dist) {  // offset byte = dist - 1
      if (dist == 0) continue;
      std::vector<uint8_t> short_ref = s, long_ref = s;
      short_ref.insert(short_ref.end(), {static_cast<uint8_t>(1u << 5), static_cast<uint8_t>(dist - 1)});
      long_ref.insert(long_ref.end(), {static_cast<uint8_t>(7u << 5), 20, static_cast<uint8_t>(dist - 1)});
      streams.push_back(short_ref);
      streams.push_back(long_ref);
      streams.push_back(std::vector<uint8_t>(long_ref.begin(), long_ref.end() - 1));  // cut off
    }
    std::vector<uint8_t> past_end = s;
    past_end[0] = static_cast<uint8_t>(lits);  // one literal more than the input holds
    streams.push_back(past_end);
  }
  streams.push_back({static_cast<uint8_t>(1u << 5), 0});  // a reference before any output
  int n = 0;
  for (const std::vector<uint8_t>& s : streams)
    for (size_t expect = 1; expect <= 40; ++expect) {
      std::vector<uint8_t> theirs, ours;
      const bool they = liblzf_decode(s, expect, theirs);
      ASSERT_EQ(ours_decode(s, expect, ours), they) << "stream " << n << ", " << expect << " bytes expected";
      if (they) {
        ASSERT_TRUE(ours == theirs) << "stream " << n;
      }
      ++n;
    }
}

// Damaged streams (bytes flipped, cut short, a token inserted): our decoder accepts one
// exactly when liblzf decodes it to the declared size, and then to the same bytes.
TEST(LzfAgainstLiblzf, AgreesOnDamagedStreams) {
  std::mt19937 rng(77);
  const std::vector<uint8_t> cloud = organized_cloud_bytes(64, 48, rng);
  const std::vector<uint8_t> good = liblzf_encode(cloud);
  ASSERT_FALSE(good.empty());
  int accepted = 0, refused = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    std::vector<uint8_t> s = good;
    const int kind = trial % 4;
    if (kind == 0) {
      for (int k = 0; k < 1 + trial % 3; ++k) s[rng() % s.size()] ^= static_cast<uint8_t>(1u << (rng() % 8));
    } else if (kind == 1) {
      s.resize(rng() % s.size());
    } else if (kind == 2) {
      s.insert(s.begin() + static_cast<long>(rng() % s.size()), static_cast<uint8_t>(rng()));
    } else {
      s[rng() % s.size()] = static_cast<uint8_t>(rng());
    }
    // The declared size: the true one mostly, sometimes off by a little.
    const size_t expect = trial % 5 == 0 ? cloud.size() - 1 + rng() % 3 : cloud.size();
    std::vector<uint8_t> theirs, ours;
    const bool they = liblzf_decode(s, expect, theirs);
    const bool we = ours_decode(s, expect, ours);
    ASSERT_EQ(we, they) << "trial " << trial;
    if (we) {
      ASSERT_TRUE(ours == theirs) << "trial " << trial;
      ++accepted;
    } else {
      ++refused;
    }
  }
  // Both outcomes occur (a flipped literal byte still decodes; most damage does not).
  EXPECT_GT(accepted, 100);
  EXPECT_GT(refused, 100);
}

}  // namespace
