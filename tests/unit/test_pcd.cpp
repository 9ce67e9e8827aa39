// PCD reader/writer and LZF: real files from shared/data/clouds (facts from its README),
// round trips, hand-written headers, malformed inputs and seeded fuzzing.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "fg/core/byte_order.hpp"
#include "io/lzf.hpp"
#include "io/pcd.hpp"
#include "io/ply.hpp"

using fg::host::PcdEncoding;
using fg::host::PointCloud;
using fg::host::ReadLimits;
using fg::host::ReadResult;

namespace {

const std::string kClouds = std::string(FG_SHARED_DIR) + "/data/clouds/";

size_t count_finite(const PointCloud& c) {
  size_t n = 0;
  for (size_t i = 0; i < c.size(); ++i) {
    if (std::isfinite(c.xyz[i * 3]) && std::isfinite(c.xyz[i * 3 + 1]) && std::isfinite(c.xyz[i * 3 + 2])) ++n;
  }
  return n;
}

bool& temp_created() {
  static bool flag = false;
  return flag;
}

std::filesystem::path temp_dir() {
  static const std::filesystem::path dir = [] {
    auto d = std::filesystem::temp_directory_path() /
             ("fg_test_pcd_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
              std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()));
    std::filesystem::create_directories(d);
    temp_created() = true;
    return d;
  }();
  return dir;
}

//! Removes the temporary folder after the last test.
struct RemoveTempDir : ::testing::Environment {
  void TearDown() override {
    std::error_code ec;
    if (temp_created()) std::filesystem::remove_all(temp_dir(), ec);
  }
};
[[maybe_unused]] ::testing::Environment* const kRemoveTempDir = ::testing::AddGlobalTestEnvironment(new RemoveTempDir);

std::vector<uint8_t> bytes_of(const std::string& s) { return std::vector<uint8_t>(s.begin(), s.end()); }

ReadResult parse(const std::vector<uint8_t>& b, PointCloud& out, const std::string& name = "bad.pcd",
                 const ReadLimits& limits = {}) {
  return fg::host::parse_pcd(b.data(), b.size(), name, out, limits);
}

ReadResult parse(const std::string& s, PointCloud& out, const std::string& name = "bad.pcd",
                 const ReadLimits& limits = {}) {
  return parse(bytes_of(s), out, name, limits);
}

template <typename T>
void put(std::vector<uint8_t>& b, T v) {  // little-endian, as the files are on every host
  uint8_t raw[sizeof(T)];
  fg::store_le(v, raw);
  b.insert(b.end(), raw, raw + sizeof(T));
}

void append(std::vector<uint8_t>& b, const std::string& s) { b.insert(b.end(), s.begin(), s.end()); }

bool same_float(float a, float b) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  return a == b;
}

void expect_same_points(const PointCloud& a, const PointCloud& b) {
  ASSERT_EQ(a.xyz.size(), b.xyz.size());
  for (size_t i = 0; i < a.xyz.size(); ++i) {
    ASSERT_TRUE(same_float(a.xyz[i], b.xyz[i])) << "index " << i << ": " << a.xyz[i] << " vs " << b.xyz[i];
  }
}

const std::string kXyzHeader = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n";

}  // namespace

// ---- real files (facts from shared/data/README.md) --------------------------------------

TEST(PcdRealFiles, MosdLearn3IsOrganizedWithLabelFirst) {
  PointCloud c;
  const ReadResult r = fg::host::read_pcd(kClouds + "mosd/learn3.pcd", c);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(c.width, 640u);
  EXPECT_EQ(c.height, 480u);
  EXPECT_TRUE(c.organized());
  EXPECT_EQ(c.size(), 307200u);
  EXPECT_EQ(count_finite(c), 206139u);
  const std::array<double, 7> identity{{0, 0, 0, 1, 0, 0, 0}};
  EXPECT_EQ(c.viewpoint, identity);
  // Optical frame, looking down on a table ~0.6 m away: every finite z is positive.
  for (size_t i = 0; i < c.size(); ++i) {
    if (std::isfinite(c.xyz[i * 3 + 2])) {
      ASSERT_GT(c.xyz[i * 3 + 2], 0.f);
    }
  }
}

TEST(PcdRealFiles, MosdOtherFinitePointCounts) {
  PointCloud c;
  ReadResult r = fg::host::read_pcd(kClouds + "mosd/learn8.pcd", c);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(count_finite(c), 208535u);
  r = fg::host::read_pcd(kClouds + "mosd/test36.pcd", c);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(count_finite(c), 173864u);
  EXPECT_EQ(c.size(), 307200u);
}

TEST(PcdRealFiles, MilkColorIsUnorganized) {
  PointCloud c;
  const ReadResult r = fg::host::read_pcd(kClouds + "pcl/milk_color.pcd", c);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(c.size(), 13704u);
  EXPECT_EQ(c.width, 13704u);
  EXPECT_EQ(c.height, 1u);
  EXPECT_FALSE(c.organized());
}

TEST(PcdRealFiles, KrylonAsciiVersionDot7NoViewpoint) {
  PointCloud c;
  c.viewpoint = {{9, 9, 9, 9, 9, 9, 9}};  // must be replaced by the default
  const ReadResult r = fg::host::read_pcd(kClouds + "gpd/krylon.pcd", c);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(c.size(), 4467u);
  EXPECT_EQ(count_finite(c), 4467u);
  const std::array<double, 7> identity{{0, 0, 0, 1, 0, 0, 0}};
  EXPECT_EQ(c.viewpoint, identity);
  float lo[3] = {1e9f, 1e9f, 1e9f}, hi[3] = {-1e9f, -1e9f, -1e9f};
  for (size_t i = 0; i < c.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], c.xyz[i * 3 + k]);
      hi[k] = std::max(hi[k], c.xyz[i * 3 + k]);
    }
  }
  // About 0.056 m diameter (x, y) and 0.105 m tall (z), centred near the origin.
  EXPECT_NEAR(hi[0] - lo[0], 0.056, 0.005);
  EXPECT_NEAR(hi[1] - lo[1], 0.056, 0.005);
  EXPECT_NEAR(hi[2] - lo[2], 0.105, 0.01);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(0.5 * (hi[k] + lo[k]), 0.0, 0.01);
}

TEST(PcdRealFiles, TableSceneMugViewpointAndCount) {
  PointCloud c;
  const ReadResult r = fg::host::read_pcd(kClouds + "pcl/table_scene_mug_stereo_textured.pcd", c);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(c.width, 640u);
  EXPECT_EQ(c.height, 480u);
  EXPECT_EQ(count_finite(c), 209280u);
  const std::array<double, 7> vp{{0, 0, 0, 0, 1, 0, 0}};
  EXPECT_EQ(c.viewpoint, vp);
}

TEST(PcdRealFiles, ReadCloudByExtension) {
  PointCloud c;
  ReadResult r = fg::host::read_cloud(kClouds + "pcl/milk_color.pcd", c);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(c.size(), 13704u);
  // Upper-case extension.
  const std::string upper = (temp_dir() / "MILK.PCD").string();
  std::filesystem::copy_file(kClouds + "pcl/milk_color.pcd", upper, std::filesystem::copy_options::overwrite_existing);
  PointCloud d;
  r = fg::host::read_cloud(upper, d);
  ASSERT_TRUE(r.ok) << r.error;
  expect_same_points(c, d);
  r = fg::host::read_cloud(kClouds + "pcl/frame_20121214T142255.814212_intrinsics.xml", d);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("frame_20121214T142255.814212_intrinsics.xml"), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("extension"), std::string::npos) << r.error;
}

TEST(PcdRealFiles, AllSharedPcdFilesRead) {
  for (const char* f : {"mosd/learn33.pcd", "mosd/learn42.pcd", "mosd/learn44.pcd", "mosd/test31.pcd",
                        "pcl/milk_cartoon_all_small_clorox.pcd", "pcl/frame_20121214T142255.814212.pcd"}) {
    PointCloud c;
    const ReadResult r = fg::host::read_pcd(kClouds + f, c);
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_EQ(c.size(), 307200u) << f;
  }
}

// ---- LZF ---------------------------------------------------------------------------------

TEST(Lzf, DecodesHandWrittenStream) {
  // literal run "abc" (ctrl 2), then back-reference len 3+... : ctrl (1<<5)|0, offset byte 2
  // -> copy 3 bytes from 3 back ("abc"); then an overlapping run: len 5 (ctrl 3<<5), dist 1.
  const std::vector<uint8_t> in = {2, 'a', 'b', 'c', (1 << 5) | 0, 2, (3 << 5) | 0, 0};
  std::vector<uint8_t> out(11);
  std::string err;
  ASSERT_TRUE(fg::host::lzf::decompress(in.data(), in.size(), out.data(), out.size(), err)) << err;
  EXPECT_EQ(std::string(out.begin(), out.end()), "abcabcccccc");
  // Long form: ctrl 7<<5, extra length 10 -> 7 + 10 + 2 = 19 bytes, distance 1.
  const std::vector<uint8_t> in2 = {0, 'z', (7 << 5) | 0, 10, 0};
  std::vector<uint8_t> out2(20);
  ASSERT_TRUE(fg::host::lzf::decompress(in2.data(), in2.size(), out2.data(), out2.size(), err)) << err;
  EXPECT_EQ(std::string(out2.begin(), out2.end()), std::string(20, 'z'));
}

TEST(Lzf, RejectsCorruptStreams) {
  std::string err;
  std::vector<uint8_t> out(64);
  const std::vector<uint8_t> before_start = {0, 'a', (1 << 5) | 0, 5};  // 6 back, 1 decoded
  EXPECT_FALSE(fg::host::lzf::decompress(before_start.data(), before_start.size(), out.data(), 64, err));
  EXPECT_NE(err.find("before the start"), std::string::npos) << err;
  const std::vector<uint8_t> overflow = {3, 'a', 'b', 'c', 'd'};
  EXPECT_FALSE(fg::host::lzf::decompress(overflow.data(), overflow.size(), out.data(), 2, err));
  EXPECT_NE(err.find("overflow"), std::string::npos) << err;
  const std::vector<uint8_t> cut_literal = {10, 'a', 'b'};
  EXPECT_FALSE(fg::host::lzf::decompress(cut_literal.data(), cut_literal.size(), out.data(), 64, err));
  EXPECT_NE(err.find("past the end"), std::string::npos) << err;
  const std::vector<uint8_t> cut_ref = {0, 'a', (7 << 5)};
  EXPECT_FALSE(fg::host::lzf::decompress(cut_ref.data(), cut_ref.size(), out.data(), 64, err));
  EXPECT_NE(err.find("cut off"), std::string::npos) << err;
  const std::vector<uint8_t> short_out = {1, 'a', 'b'};
  EXPECT_FALSE(fg::host::lzf::decompress(short_out.data(), short_out.size(), out.data(), 3, err));
  EXPECT_NE(err.find("truncated"), std::string::npos) << err;
}

TEST(Lzf, CompressDecompressRoundTrip) {
  std::mt19937 rng(1234);
  for (size_t n :
       {size_t{0}, size_t{1}, size_t{2}, size_t{3}, size_t{31}, size_t{32}, size_t{33}, size_t{1000}, size_t{100000}}) {
    for (int mode = 0; mode < 3; ++mode) {
      std::vector<uint8_t> in(n);
      for (size_t i = 0; i < n; ++i) {
        in[i] = mode == 0   ? static_cast<uint8_t>(rng())              // incompressible
                : mode == 1 ? static_cast<uint8_t>(i % 7)              // periodic
                            : static_cast<uint8_t>((rng() % 4) == 0);  // low entropy
      }
      const auto packed = fg::host::lzf::compress(in.data(), in.size());
      EXPECT_LE(packed.size(), n + (n + 31) / 32) << n;
      if (mode == 1 && n >= 1000) {
        EXPECT_LT(packed.size(), n / 10);
      }
      std::vector<uint8_t> out(n);
      std::string err;
      ASSERT_TRUE(fg::host::lzf::decompress(packed.data(), packed.size(), out.data(), n, err))
          << err << " n=" << n << " mode=" << mode;
      EXPECT_EQ(in, out);
    }
  }
}

// Streams of random tokens (literal runs, back-references of every short distance and
// length, so overlapping periodic copies too) decode as a byte-at-a-time decoder of
// the LZF format written here decodes them. Every token but the last few takes the
// decoder's chunked fast paths (each distance under 8 its own pattern case).
TEST(Lzf, MatchesByteWiseReferenceDecoder) {
  std::mt19937 rng(99);
  for (int trial = 0; trial < 3000; ++trial) {
    std::vector<uint8_t> in, expect;
    const int tokens = 1 + static_cast<int>(rng() % 60);
    for (int t = 0; t < tokens; ++t) {
      if (expect.empty() || rng() % 3 == 0) {
        const size_t len = 1 + rng() % 32;
        in.push_back(static_cast<uint8_t>(len - 1));
        for (size_t k = 0; k < len; ++k) {
          const uint8_t b = static_cast<uint8_t>(rng());
          in.push_back(b);
          expect.push_back(b);
        }
      } else {
        const size_t max_dist = std::min<size_t>(expect.size(), rng() % 2 ? 20 : 8192);
        const size_t dist = 1 + rng() % max_dist;
        const size_t len = 3 + rng() % (rng() % 4 == 0 ? 262 : 40);  // 3..264
        const size_t code = len - 2;
        if (code < 7) {
          in.push_back(static_cast<uint8_t>((code << 5) | ((dist - 1) >> 8)));
        } else {
          in.push_back(static_cast<uint8_t>((7 << 5) | ((dist - 1) >> 8)));
          in.push_back(static_cast<uint8_t>(code - 7));
        }
        in.push_back(static_cast<uint8_t>((dist - 1) & 0xFF));
        for (size_t k = 0; k < len; ++k) expect.push_back(expect[expect.size() - dist]);
      }
    }
    std::vector<uint8_t> out(expect.size(), 0xAB);
    std::string err;
    ASSERT_TRUE(fg::host::lzf::decompress(in.data(), in.size(), out.data(), out.size(), err))
        << err << " trial " << trial;
    ASSERT_EQ(out, expect) << "trial " << trial;
  }
}

// ---- round trips -----------------------------------------------------------------------

namespace {
PointCloud sample_cloud(uint32_t w, uint32_t h, unsigned seed) {
  PointCloud c;
  c.width = w;
  c.height = h;
  c.viewpoint = {{0.5, -1.25, 2.0, 0.0, 1.0, 0.0, 0.0}};
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-2.f, 2.f);
  const size_t n = size_t{w} * h;
  c.xyz.resize(n * 3);
  for (size_t i = 0; i < n; ++i) {
    const bool hole = i % 5 == 3;
    for (int k = 0; k < 3; ++k) {
      c.xyz[i * 3 + k] = hole ? std::numeric_limits<float>::quiet_NaN() : u(rng);
    }
  }
  if (n > 2) {
    c.xyz[3] = std::numeric_limits<float>::infinity();
    c.xyz[4] = -0.0f;
    c.xyz[5] = std::numeric_limits<float>::denorm_min();
  }
  return c;
}
}  // namespace

TEST(PcdRoundTrip, AllEncodingsOrganizedAndNot) {
  for (auto enc : {PcdEncoding::ascii, PcdEncoding::binary, PcdEncoding::binary_compressed}) {
    for (auto [w, h] : {std::pair<uint32_t, uint32_t>{40, 30}, {1000, 1}, {0, 1}, {1, 1}}) {
      const PointCloud c = sample_cloud(w, h, w * 7 + h);
      const std::string path = (temp_dir() / ("rt_" + std::to_string(static_cast<int>(enc)) + "_" + std::to_string(w) +
                                              "x" + std::to_string(h) + ".pcd"))
                                   .string();
      ReadResult r = fg::host::write_pcd(path, c, enc);
      ASSERT_TRUE(r.ok) << r.error;
      PointCloud d;
      r = fg::host::read_pcd(path, d);
      ASSERT_TRUE(r.ok) << r.error;
      EXPECT_EQ(d.width, w);
      EXPECT_EQ(d.height, h);
      EXPECT_EQ(d.viewpoint, c.viewpoint);
      expect_same_points(c, d);
    }
  }
}

TEST(PcdRoundTrip, CompressedIsSmallerForSmoothData) {
  PointCloud c;
  c.width = 320;
  c.height = 240;
  c.xyz.resize(size_t{320} * 240 * 3, std::numeric_limits<float>::quiet_NaN());
  for (size_t i = 0; i < c.size(); i += 2) c.xyz[i * 3 + 2] = 1.0f;  // half NaN, z = 1
  const std::string path = (temp_dir() / "smooth.pcd").string();
  ASSERT_TRUE(fg::host::write_pcd(path, c, PcdEncoding::binary_compressed).ok);
  EXPECT_LT(std::filesystem::file_size(path), c.xyz.size() * sizeof(float) / 4);
  PointCloud d;
  const ReadResult r = fg::host::read_pcd(path, d);
  ASSERT_TRUE(r.ok) << r.error;
  expect_same_points(c, d);
}

TEST(PcdRoundTrip, WriteRejectsInconsistentCloud) {
  PointCloud c;
  c.xyz = {1, 2, 3, 4, 5, 6};
  c.width = 3;
  c.height = 1;
  const std::string path = (temp_dir() / "inconsistent.pcd").string();
  const ReadResult r = fg::host::write_pcd(path, c);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("inconsistent.pcd"), std::string::npos);
}

// ---- hand-written files ------------------------------------------------------------------

TEST(PcdHandWritten, AsciiUnusualFieldOrderAndCount3) {
  const std::string s =
      "# a comment\n\n"
      "VERSION .7\n"
      "FIELDS rgb normal z label y x\n"
      "SIZE 4 4 8 2 4 4\n"
      "TYPE F F F U F F\n"
      "COUNT 1 3 1 1 1 1\n"
      "WIDTH 2\r\n"
      "HEIGHT 2\n"
      "# comment inside the header\n"
      "POINTS 4\n"
      "DATA ascii\n"
      "0 0.1 0.2 0.3 3.5 7 2.5 1.5\n"
      "\n"
      "1.0e3 1 2 3 -4 8 -5 -6e-1\r\n"
      "0 0 0 0 nan 0 nan nan\n"
      "0 0 0 0 inf 1 -inf +2\n";
  PointCloud c;
  const ReadResult r = parse(s, c, "hand.pcd");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(c.width, 2u);
  EXPECT_EQ(c.height, 2u);
  ASSERT_EQ(c.size(), 4u);
  EXPECT_FLOAT_EQ(c.xyz[0], 1.5f);
  EXPECT_FLOAT_EQ(c.xyz[1], 2.5f);
  EXPECT_FLOAT_EQ(c.xyz[2], 3.5f);
  EXPECT_FLOAT_EQ(c.xyz[3], -0.6f);
  EXPECT_FLOAT_EQ(c.xyz[4], -5.f);
  EXPECT_FLOAT_EQ(c.xyz[5], -4.f);
  EXPECT_TRUE(std::isnan(c.xyz[6]) && std::isnan(c.xyz[7]) && std::isnan(c.xyz[8]));
  EXPECT_EQ(c.xyz[9], 2.f);
  EXPECT_TRUE(std::isinf(c.xyz[10]) && c.xyz[10] < 0);
  EXPECT_TRUE(std::isinf(c.xyz[11]) && c.xyz[11] > 0);
}

TEST(PcdHandWritten, BinaryMixedTypesAndF8) {
  // FIELDS label(U1) z(F8) tag(I2 x2) x(F4) y(F8) pad(U8): one point is 1+8+4+4+8+8 = 33 bytes.
  std::vector<uint8_t> b = bytes_of(
      "FIELDS label z tag x y pad\nSIZE 1 8 2 4 8 8\nTYPE U F I F F U\nCOUNT 1 1 2 1 1 1\n"
      "WIDTH 3\nHEIGHT 1\nVIEWPOINT 1 2 3 0.7071 0 0.7071 0\nPOINTS 3\nDATA binary\n");
  for (int i = 0; i < 3; ++i) {
    put<uint8_t>(b, static_cast<uint8_t>(i));
    put<double>(b, 10.0 + i);
    put<int16_t>(b, -1);
    put<int16_t>(b, 2);
    put<float>(b, 0.25f * i);
    put<double>(b, i == 1 ? std::nan("") : -1.0 * i);
    put<uint64_t>(b, ~uint64_t{0});
  }
  PointCloud c;
  const ReadResult r = parse(b, c, "mixed.pcd");
  ASSERT_TRUE(r.ok) << r.error;
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c.xyz[0], 0.f);
  EXPECT_EQ(c.xyz[1], -0.f);
  EXPECT_EQ(c.xyz[2], 10.f);
  EXPECT_EQ(c.xyz[3], 0.25f);
  EXPECT_TRUE(std::isnan(c.xyz[4]));
  EXPECT_EQ(c.xyz[5], 11.f);
  EXPECT_EQ(c.xyz[6], 0.5f);
  EXPECT_EQ(c.xyz[7], -2.f);
  EXPECT_EQ(c.xyz[8], 12.f);
  EXPECT_DOUBLE_EQ(c.viewpoint[0], 1.0);
  EXPECT_DOUBLE_EQ(c.viewpoint[3], 0.7071);
}

namespace {
//! A binary_compressed PCD with fields `label x y z rgba` laid out as PCL does
//! (structure of arrays), `n` points.
std::vector<uint8_t> compressed_pcd(uint32_t n, std::vector<float>& xyz_out) {
  std::vector<uint8_t> soa;
  xyz_out.assign(size_t{n} * 3, 0.f);
  for (uint32_t i = 0; i < n; ++i) put<uint32_t>(soa, i % 3 == 0 ? 0u : 20u + i % 10);
  for (int k = 0; k < 3; ++k) {
    for (uint32_t i = 0; i < n; ++i) {
      const float v = i % 3 == 0 ? std::numeric_limits<float>::quiet_NaN() : 0.001f * i + static_cast<float>(k);
      xyz_out[size_t{i} * 3 + k] = v;
      put<float>(soa, v);
    }
  }
  for (uint32_t i = 0; i < n; ++i) put<uint32_t>(soa, 0x00ff8040u);
  const auto packed = fg::host::lzf::compress(soa.data(), soa.size());
  std::vector<uint8_t> b = bytes_of(
      "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS label x y z rgba\n"
      "SIZE 4 4 4 4 4\nTYPE U F F F U\nCOUNT 1 1 1 1 1\nWIDTH " +
      std::to_string(n) + "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + std::to_string(n) +
      "\nDATA binary_compressed\n");
  put<uint32_t>(b, static_cast<uint32_t>(packed.size()));
  put<uint32_t>(b, static_cast<uint32_t>(soa.size()));
  b.insert(b.end(), packed.begin(), packed.end());
  return b;
}
}  // namespace

TEST(PcdHandWritten, CompressedStructureOfArraysLabelFirst) {
  std::vector<float> xyz;
  const auto b = compressed_pcd(500, xyz);
  PointCloud c;
  const ReadResult r = parse(b, c, "soa.pcd");
  ASSERT_TRUE(r.ok) << r.error;
  PointCloud expect;
  expect.xyz.assign(xyz.begin(), xyz.end());
  expect_same_points(expect, c);
}

TEST(PcdHandWritten, CompressedPlanarWhenAllowed) {
  // With ReadLimits::planar the decompressed block is handed over (x, y and z arrays
  // after the labels), with the same points, labels and counts as the triples.
  std::vector<float> xyz;
  const auto b = compressed_pcd(500, xyz);
  ReadLimits planar;
  planar.planar = true;
  PointCloud c, t;
  ASSERT_TRUE(parse(b, c, "soa.pcd", planar).ok);
  ASSERT_TRUE(parse(b, t, "soa.pcd").ok);
  ASSERT_TRUE(c.planar());
  EXPECT_FALSE(t.planar());
  EXPECT_TRUE(c.xyz.empty());
  EXPECT_EQ(c.size(), 500u);
  EXPECT_EQ(c.labels, t.labels);
  for (size_t i = 0; i < 500; ++i)
    for (int k = 0; k < 3; ++k) {
      const float v = c.planar_array(k)[i], w = xyz[i * 3 + static_cast<size_t>(k)];
      if (std::isnan(w)) {
        EXPECT_TRUE(std::isnan(v)) << i << " " << k;
      } else {
        EXPECT_EQ(v, w) << i << " " << k;
      }
    }
  // Other encodings fill the triples whatever the flag says.
  const std::string path = ::testing::TempDir() + "planar_ascii.pcd";
  ASSERT_TRUE(fg::host::write_pcd(path, t, PcdEncoding::ascii).ok);
  PointCloud a;
  ASSERT_TRUE(fg::host::read_pcd(path, a, planar).ok);
  EXPECT_FALSE(a.planar());
  EXPECT_EQ(a.size(), 500u);
}

TEST(PcdRealFiles, PlanarReadOfACaptureMatchesTheTriples) {
  // learn3.pcd is binary_compressed `label x y z rgba`, 640 x 480.
  ReadLimits planar;
  planar.planar = true;
  PointCloud c, t;
  ASSERT_TRUE(fg::host::read_pcd(kClouds + "mosd/learn3.pcd", c, planar).ok);
  ASSERT_TRUE(fg::host::read_pcd(kClouds + "mosd/learn3.pcd", t).ok);
  ASSERT_TRUE(c.planar());
  ASSERT_EQ(c.size(), t.size());
  size_t finite = 0;
  for (size_t i = 0; i < c.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const float v = c.planar_array(k)[i], w = t.xyz[i * 3 + static_cast<size_t>(k)];
      ASSERT_EQ(std::memcmp(&v, &w, 4), 0) << i << " " << k;
      finite += k == 2 && std::isfinite(v) ? 1u : 0u;
    }
  EXPECT_EQ(finite, 206139u);
}

// ---- malformed inputs ---------------------------------------------------------------------

namespace {
void expect_error(const ReadResult& r, const std::string& name, const std::string& word) {
  EXPECT_FALSE(r.ok) << "expected an error about '" << word << "'";
  EXPECT_EQ(r.error.rfind(name + ": ", 0), 0u) << r.error;
  EXPECT_NE(r.error.find(word), std::string::npos) << "'" << word << "' not in: " << r.error;
}

void expect_bad(const std::string& text, const std::string& word, const ReadLimits& limits = {}) {
  PointCloud c;
  c.xyz = {7, 8, 9};
  c.width = 1;
  const ReadResult r = parse(text, c, "bad.pcd", limits);
  expect_error(r, "bad.pcd", word);
  // The output is untouched on error.
  EXPECT_EQ(std::vector<float>(c.xyz.begin(), c.xyz.end()), (std::vector<float>{7, 8, 9}));
}
}  // namespace

TEST(PcdMalformed, HeaderProblems) {
  expect_bad("", "empty");
  expect_bad("VERSION 0.7\nFIELDS x y z\nSIZE 4 4", "truncated");
  expect_bad(kXyzHeader + "WIDTH 1\nHEIGHT 1\nPOINTS 1\n", "no DATA");
  expect_bad(kXyzHeader + "WIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA binary_lz4\n", "unknown DATA kind");
  expect_bad("VERSION 0.7\nFIELDS x y z\nSIZE 4 4\nTYPE F F F\nWIDTH 1\nPOINTS 1\nDATA ascii\n1 2 3\n",
             "SIZE has 2 entries");
  expect_bad("VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F F\nWIDTH 1\nPOINTS 1\nDATA ascii\n1 2 3\n",
             "TYPE has 4 entries");
  expect_bad("VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1\nWIDTH 1\nPOINTS 1\nDATA ascii\n1 2 3\n",
             "COUNT has 2 entries");
  expect_bad("VERSION 0.7\nFIELDS x y z\nTYPE F F F\nWIDTH 1\nPOINTS 1\nDATA ascii\n1 2 3\n", "no SIZE");
  expect_bad("VERSION 0.7\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nPOINTS 1\nDATA ascii\n1 2 3\n", "no FIELDS");
  expect_bad(kXyzHeader + "WIDTH 640\nHEIGHT 480\nPOINTS 1000\nDATA ascii\n", "does not match POINTS");
  expect_bad(kXyzHeader + "WIDTH abc\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3\n", "WIDTH value 'abc'");
  expect_bad(kXyzHeader + "WIDTH -1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3\n", "non-numeric");
  expect_bad(kXyzHeader + "WIDTH 1\nHEIGHT 1\nPOINTS 99999999999999999999999\nDATA ascii\n", "POINTS value");
  expect_bad("VERSION 0.7\nFIELDS x y z\nSIZE 4 4 x\nTYPE F F F\nWIDTH 1\nPOINTS 1\nDATA ascii\n1 2 3\n", "SIZE 'x'");
  expect_bad("VERSION 0.7\nFIELDS x y z\nSIZE 4 4 3\nTYPE F F F\nWIDTH 1\nPOINTS 1\nDATA ascii\n1 2 3\n",
             "not 1, 2, 4 or 8");
  expect_bad("VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F Q\nWIDTH 1\nPOINTS 1\nDATA ascii\n1 2 3\n",
             "not I, U or F");
  expect_bad("VERSION 0.7\nFIELDS x y z\nSIZE 4 4 2\nTYPE F F F\nWIDTH 1\nPOINTS 1\nDATA ascii\n1 2 3\n",
             "TYPE F with SIZE 2");
  expect_bad("VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 0 1\nWIDTH 1\nPOINTS 1\nDATA ascii\n1 2 3\n",
             "COUNT '0'");
  expect_bad("VERSION 0.7\nFIELDS x y rgb\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nPOINTS 1\nDATA ascii\n1 2 3\n",
             "missing field 'z'");
  expect_bad("VERSION 0.7\nFIELDS x y z x\nSIZE 4 4 4 4\nTYPE F F F F\nWIDTH 1\nPOINTS 1\nDATA ascii\n1 2 3 4\n",
             "duplicate field 'x'");
  expect_bad("VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F I\nWIDTH 1\nPOINTS 1\nDATA ascii\n1 2 3\n",
             "field 'z' must be TYPE F");
  expect_bad("VERSION 0.5\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nPOINTS 1\nDATA ascii\n1 2 3\n",
             "unsupported VERSION");
  expect_bad(kXyzHeader + "WIDTH 1\nVIEWPOINT 0 0 0 1 0 0\nPOINTS 1\nDATA ascii\n1 2 3\n", "VIEWPOINT needs 7");
  expect_bad(kXyzHeader + "WIDTH 1\nVIEWPOINT 0 0 nan 1 0 0 0\nPOINTS 1\nDATA ascii\n1 2 3\n",
             "VIEWPOINT value 'nan' is not finite");
  expect_bad(kXyzHeader + "WIDTH 1\nVIEWPOINT 0 0 0 0 0 0 0\nPOINTS 1\nDATA ascii\n1 2 3\n", "quaternion");
  expect_bad(kXyzHeader + "WIDTH 1\nWIDTH 1\nPOINTS 1\nDATA ascii\n1 2 3\n", "duplicate WIDTH");
  expect_bad(kXyzHeader + "HIGHT 1\nWIDTH 1\nPOINTS 1\nDATA ascii\n1 2 3\n", "unknown header line 'HIGHT 1'");
  expect_bad(kXyzHeader + "DATA ascii\n1 2 3\n", "neither WIDTH nor POINTS");
}

TEST(PcdMalformed, TooManyPointsForTheLimit) {
  ReadLimits small;
  small.max_points = 100;
  expect_bad(kXyzHeader + "WIDTH 101\nHEIGHT 1\nPOINTS 101\nDATA binary\n" + std::string(101 * 12, '\0'),
             "too many points", small);
  expect_bad(kXyzHeader + "WIDTH 10000001\nHEIGHT 1\nPOINTS 10000001\nDATA binary\n", "limit");
}

TEST(PcdMalformed, TenMillionPointsInATinyFileFailFast) {
  for (const std::string kind : {"binary", "ascii", "binary_compressed"}) {
    std::vector<uint8_t> b = bytes_of(
        "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 10000\nHEIGHT 1000\nPOINTS 10000000\nDATA " + kind + "\n");
    if (kind == "binary_compressed") {
      put<uint32_t>(b, static_cast<uint32_t>(200 - b.size() - 8));
      put<uint32_t>(b, 120000000u);  // what 10^7 points of 12 bytes need
    }
    while (b.size() < 200) append(b, kind == "ascii" ? "1 2 3\n" : "\x01");
    ASSERT_LE(b.size(), 205u);
    const auto t0 = std::chrono::steady_clock::now();
    PointCloud c;
    const ReadResult r = parse(b, c, "tiny.pcd");
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    expect_error(r, "tiny.pcd", "10000x1000 points");
    EXPECT_LT(ms, 200.0) << kind;
  }
  // the message of the brief, word for word in its shape
  std::string s = kXyzHeader + "WIDTH 640\nHEIGHT 480\nPOINTS 307200\nDATA binary\n" + std::string(1200, '\0');
  PointCloud c;
  const ReadResult r = parse(s, c, "head.pcd");
  EXPECT_EQ(r.error.rfind("head.pcd: DATA binary holds 1200 bytes but 640x480 points need 3686400", 0), 0u) << r.error;
}

TEST(PcdMalformed, BinaryData) {
  const std::string h = kXyzHeader + "WIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA binary\n";
  expect_bad(h + std::string(23, '\0'), "truncated");
  PointCloud c;
  EXPECT_TRUE(parse(h + std::string(24, '\0'), c).ok);
  EXPECT_TRUE(parse(h + std::string(30, '\0'), c).ok);  // trailing bytes (PCL page padding) are fine
}

TEST(PcdMalformed, CompressedData) {
  std::vector<float> xyz;
  const std::vector<uint8_t> good = compressed_pcd(200, xyz);
  PointCloud c;
  ASSERT_TRUE(parse(good, c).ok);
  const size_t hdr = std::string(good.begin(), good.end()).find("binary_compressed\n") + 18;

  auto with_sizes = [&](uint32_t cs, uint32_t us) {
    std::vector<uint8_t> b = good;
    fg::store_le(cs, b.data() + hdr);
    fg::store_le(us, b.data() + hdr + 4);
    return b;
  };
  const uint32_t cs = fg::load_le<uint32_t>(good.data() + hdr);
  const uint32_t us = fg::load_le<uint32_t>(good.data() + hdr + 4);
  ASSERT_EQ(us, 200u * 20u);

  auto bad = [&](const std::vector<uint8_t>& b, const std::string& word) {
    PointCloud d;
    expect_error(parse(b, d), "bad.pcd", word);
  };
  bad(with_sizes(cs + 1, us), "compressed size");
  bad(with_sizes(0xffffffffu, us), "larger than");
  bad(with_sizes(cs, us + 4), "uncompressed size");
  bad(with_sizes(cs, us - 20), "uncompressed size");
  bad(with_sizes(cs - 1, us), "LZF");  // stream cut short
  bad(std::vector<uint8_t>(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(hdr + 5)), "8-byte");

  // A back-reference before the start: the first control byte says "match".
  std::vector<uint8_t> b = good;
  b[hdr + 8] = (1 << 5) | 3;
  bad(b, "before the start");
  // Output overflow: a declared size too small for the stream (header agrees with it).
  std::vector<uint8_t> soa(40, 1);
  const auto packed = fg::host::lzf::compress(soa.data(), soa.size());
  std::vector<uint8_t> ov = bytes_of(kXyzHeader + "WIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA binary_compressed\n");
  put<uint32_t>(ov, static_cast<uint32_t>(packed.size()));
  put<uint32_t>(ov, 12u);
  ov.insert(ov.end(), packed.begin(), packed.end());
  bad(ov, "overflow");
  // Impossible ratio: 3 compressed bytes cannot hold 10000x1000 points.
  std::vector<uint8_t> ratio =
      bytes_of(kXyzHeader + "WIDTH 1000\nHEIGHT 1000\nPOINTS 1000000\nDATA binary_compressed\n");
  put<uint32_t>(ratio, 3u);
  put<uint32_t>(ratio, 12000000u);
  for (int i = 0; i < 3; ++i) put<uint8_t>(ratio, 0);
  bad(ratio, "cannot come from 3 compressed bytes");
}

TEST(PcdMalformed, AsciiData) {
  const std::string h = kXyzHeader + "WIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n";
  expect_bad(h + "1 2 3\n4 5\n", "too few values");
  expect_bad(h + "1 2 3\n4 5 6 7\n", "too many values");
  expect_bad(h + "1 2 3\n", "too few rows");
  expect_bad(h + "1 2\n", "too few for 2 points");
  expect_bad(h + "1 2 3\n4 5 6\n7 8 9\n", "more rows");
  expect_bad(h + "1 2 3\n4 five 6\n", "'five' of field 'y' is not a number");
  expect_bad(h + "1 2 3\n4 5 6e\n", "not a number");
  expect_bad(h + "1 2 3\n4 5 0x10\n", "not a number");
  // NaN / Inf are allowed and kept; values beyond float become inf.
  PointCloud c;
  const ReadResult r = parse(h + "nan NaN -nan\ninf -INF 1e300\n", c);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_TRUE(std::isnan(c.xyz[0]) && std::isnan(c.xyz[1]) && std::isnan(c.xyz[2]));
  EXPECT_TRUE(std::isinf(c.xyz[3]) && std::isinf(c.xyz[4]) && std::isinf(c.xyz[5]));
}

TEST(PcdMalformed, FilesOnDisk) {
  PointCloud c;
  const std::string missing = (temp_dir() / "no_such_file.pcd").string();
  ReadResult r = fg::host::read_pcd(missing, c);
  expect_error(r, missing, "cannot open");
  r = fg::host::read_pcd(temp_dir().string(), c);
  expect_error(r, temp_dir().string(), "directory");
  ReadLimits small;
  small.max_file_bytes = 1000;
  const std::string milk = kClouds + "pcl/milk_color.pcd";
  r = fg::host::read_pcd(milk, c, small);
  expect_error(r, milk, "larger than the limit");
  const std::string empty = (temp_dir() / "empty.pcd").string();
  { std::ofstream f(empty); }
  r = fg::host::read_pcd(empty, c);
  expect_error(r, empty, "empty");
}

// ---- fuzzing (seeded) --------------------------------------------------------------------

namespace {
void check_fuzz_result(const ReadResult& r, const PointCloud& c, const std::string& name) {
  if (!r.ok) {
    ASSERT_EQ(r.error.rfind(name + ": ", 0), 0u) << r.error;
    ASSERT_GT(r.error.size(), name.size() + 4);
  } else {
    ASSERT_EQ(c.xyz.size(), size_t{c.width} * c.height * 3);
  }
}
}  // namespace

TEST(PcdFuzz, RandomBytes) {
  std::mt19937 rng(20240601);
  for (int it = 0; it < 3000; ++it) {
    std::vector<uint8_t> b(rng() % 600);
    for (auto& x : b) x = static_cast<uint8_t>(rng());
    PointCloud c;
    const ReadResult r = fg::host::parse_pcd(b.data(), b.size(), "fuzz.pcd", c);
    check_fuzz_result(r, c, "fuzz.pcd");
    EXPECT_FALSE(r.ok);
  }
}

TEST(PcdFuzz, MutatedValidFiles) {
  std::vector<float> xyz;
  std::vector<std::vector<uint8_t>> seeds;
  seeds.push_back(compressed_pcd(64, xyz));
  seeds.push_back(bytes_of(kXyzHeader + "WIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n"
                                        "1 2 3\nnan nan nan\n-1 0.5 2e-3\n"));
  {
    std::vector<uint8_t> b = bytes_of(
        "FIELDS label x y z\nSIZE 2 4 8 4\nTYPE U F F F\nCOUNT 1 1 1 1\nWIDTH 2\nHEIGHT 2\nPOINTS 4\nDATA binary\n");
    for (int i = 0; i < 4; ++i) {
      put<uint16_t>(b, 1);
      put<float>(b, 1.f * i);
      put<double>(b, 2.0 * i);
      put<float>(b, 3.f * i);
    }
    seeds.push_back(b);
  }
  std::mt19937 rng(77);
  const std::string hdr_words[] = {
      "FIELDS", "SIZE", "TYPE", "COUNT", "WIDTH", "HEIGHT", "POINTS", "DATA",  "VIEWPOINT",         "\n",
      " ",      "0",    "4",    "8",     "F",     "U",      "binary", "ascii", "binary_compressed", "4294967295",
      "-1",     "nan"};
  for (int it = 0; it < 6000; ++it) {
    std::vector<uint8_t> b = seeds[static_cast<size_t>(it) % seeds.size()];
    const int edits = 1 + static_cast<int>(rng() % 4);
    for (int e = 0; e < edits && !b.empty(); ++e) {
      const size_t p = rng() % b.size();
      switch (rng() % 5) {
        case 0:
          b[p] = static_cast<uint8_t>(rng());
          break;
        case 1:
          b.resize(p);
          break;
        case 2:
          b.erase(b.begin() + static_cast<std::ptrdiff_t>(p));
          break;
        case 3: {
          const std::string& w = hdr_words[rng() % std::size(hdr_words)];
          b.insert(b.begin() + static_cast<std::ptrdiff_t>(p), w.begin(), w.end());
          break;
        }
        default:
          b[p] ^= static_cast<uint8_t>(1u << (rng() % 8));
          break;
      }
    }
    PointCloud c;
    ReadLimits limits;
    limits.max_points = 100000;
    const ReadResult r = fg::host::parse_pcd(b.data(), b.size(), "mut.pcd", c, limits);
    check_fuzz_result(r, c, "mut.pcd");
  }
}
