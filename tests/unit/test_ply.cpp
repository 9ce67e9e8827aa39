// PLY reader/writer: round trips, hand-built files with faces and odd types before and
// after the vertices, malformed inputs and seeded fuzzing.
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
#include "io/pcd.hpp"
#include "io/ply.hpp"

using fg::host::PointCloud;
using fg::host::ReadLimits;
using fg::host::ReadResult;

namespace {

bool& temp_created() {
  static bool flag = false;
  return flag;
}

std::filesystem::path temp_dir() {
  static const std::filesystem::path dir = [] {
    auto d = std::filesystem::temp_directory_path() /
             ("fg_test_ply_" + std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()));
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

template <typename T>
void put(std::vector<uint8_t>& b, T v) {  // little-endian, as the files are on every host
  uint8_t raw[sizeof(T)];
  fg::store_le(v, raw);
  b.insert(b.end(), raw, raw + sizeof(T));
}

ReadResult parse(const std::vector<uint8_t>& b, PointCloud& out, const std::string& name = "bad.ply",
                 const ReadLimits& limits = {}) {
  return fg::host::parse_ply(b.data(), b.size(), name, out, limits);
}

bool same_float(float a, float b) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  return a == b;
}

void write_file(const std::string& path, const std::vector<uint8_t>& b) {
  std::ofstream f(path, std::ios::binary);
  f.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

PointCloud sample_cloud(size_t n, unsigned seed) {
  PointCloud c;
  c.width = static_cast<uint32_t>(n);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-3.f, 3.f);
  c.xyz.resize(n * 3);
  for (auto& v : c.xyz) v = u(rng);
  if (n > 2) {
    c.xyz[0] = std::numeric_limits<float>::quiet_NaN();
    c.xyz[4] = -std::numeric_limits<float>::infinity();
    c.xyz[5] = std::numeric_limits<float>::denorm_min();
  }
  return c;
}

}  // namespace

TEST(PlyRoundTrip, AsciiAndBinary) {
  for (bool binary : {false, true}) {
    for (size_t n : {size_t{0}, size_t{1}, size_t{500}}) {
      const PointCloud c = sample_cloud(n, static_cast<unsigned>(n) + binary);
      const std::string path =
          (temp_dir() / ("rt_" + std::to_string(binary) + "_" + std::to_string(n) + ".ply")).string();
      ReadResult r = fg::host::write_ply(path, c, binary);
      ASSERT_TRUE(r.ok) << r.error;
      PointCloud d;
      r = fg::host::read_ply(path, d);
      ASSERT_TRUE(r.ok) << r.error;
      EXPECT_EQ(d.width, n);
      EXPECT_EQ(d.height, 1u);
      EXPECT_FALSE(d.organized());
      ASSERT_EQ(d.xyz.size(), c.xyz.size());
      for (size_t i = 0; i < c.xyz.size(); ++i) ASSERT_TRUE(same_float(c.xyz[i], d.xyz[i])) << i;
      // read_cloud picks the PLY reader by extension
      PointCloud e;
      r = fg::host::read_cloud(path, e);
      ASSERT_TRUE(r.ok) << r.error;
      EXPECT_EQ(e.xyz.size(), c.xyz.size());
    }
  }
}

TEST(PlyRoundTrip, ReadCloudUpperCaseAndUnknownExtension) {
  const PointCloud c = sample_cloud(10, 3);
  const std::string path = (temp_dir() / "UPPER.PLY").string();
  ASSERT_TRUE(fg::host::write_ply(path, c, true).ok);
  PointCloud d;
  ReadResult r = fg::host::read_cloud(path, d);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(d.size(), 10u);
  const std::string odd = (temp_dir() / "cloud.xyz").string();
  std::filesystem::copy_file(path, odd, std::filesystem::copy_options::overwrite_existing);
  r = fg::host::read_cloud(odd, d);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.error.rfind(odd + ": ", 0), 0u) << r.error;
  EXPECT_NE(r.error.find("extension"), std::string::npos) << r.error;
  const std::string none = (temp_dir() / "noext").string();
  r = fg::host::read_cloud(none, d);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("noext"), std::string::npos) << r.error;
}

namespace {
//! Binary PLY: `edge` (list + scalar) before the vertices, vertices with x y z of
//! different types among other properties, and a face element after them.
std::vector<uint8_t> binary_with_faces(uint32_t nv, uint32_t nf) {
  std::vector<uint8_t> b = bytes_of(
      "ply\r\nformat binary_little_endian 1.0\ncomment made by hand\nobj_info test\n"
      "element edge 2\nproperty list uint8 int32 idx\nproperty short weight\n"
      "element vertex " +
      std::to_string(nv) +
      "\nproperty uchar red\nproperty double z\nproperty float nx\nproperty int16 x\n"
      "property list uchar float extra\nproperty float32 y\nproperty uint alpha\n"
      "element face " +
      std::to_string(nf) +
      "\nproperty list uchar int vertex_indices\nproperty char flag\n"
      "element empty 1000000000\n"
      "end_header\n");
  // edges
  put<uint8_t>(b, 2);
  put<int32_t>(b, 0);
  put<int32_t>(b, 1);
  put<int16_t>(b, 5);
  put<uint8_t>(b, 0);
  put<int16_t>(b, -5);
  // vertices
  for (uint32_t i = 0; i < nv; ++i) {
    put<uint8_t>(b, 200);
    put<double>(b, 0.5 * i);
    put<float>(b, 1.f);
    put<int16_t>(b, static_cast<int16_t>(-static_cast<int>(i)));
    put<uint8_t>(b, static_cast<uint8_t>(i % 3));
    for (uint32_t k = 0; k < i % 3; ++k) put<float>(b, 9.f);
    put<float>(b, 2.f * i);
    put<uint32_t>(b, 0xffffffffu);
  }
  // faces
  for (uint32_t f = 0; f < nf; ++f) {
    put<uint8_t>(b, 3);
    for (int k = 0; k < 3; ++k) put<int32_t>(b, static_cast<int32_t>((f + static_cast<uint32_t>(k)) % nv));
    put<int8_t>(b, -1);
  }
  return b;
}
}  // namespace

TEST(PlyHandWritten, BinaryWithFacesBeforeAndAfterVertices) {
  const auto b = binary_with_faces(7, 4);
  PointCloud c;
  const ReadResult r = parse(b, c, "mesh.ply");
  ASSERT_TRUE(r.ok) << r.error;
  ASSERT_EQ(c.size(), 7u);
  for (uint32_t i = 0; i < 7; ++i) {
    EXPECT_EQ(c.xyz[i * 3 + 0], -static_cast<float>(i));
    EXPECT_EQ(c.xyz[i * 3 + 1], 2.f * i);
    EXPECT_EQ(c.xyz[i * 3 + 2], 0.5f * i);
  }
  // Written to disk and read by extension, too.
  const std::string path = (temp_dir() / "mesh.ply").string();
  write_file(path, b);
  PointCloud d;
  ASSERT_TRUE(fg::host::read_cloud(path, d).ok);
  EXPECT_EQ(d.xyz, c.xyz);
}

TEST(PlyHandWritten, BinaryFixedSizeVertexWithFaceAfter) {
  std::vector<uint8_t> b = bytes_of(
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nproperty uchar red\nelement face 1\nproperty list uchar int vertex_indices\n"
      "end_header\n");
  for (int i = 0; i < 3; ++i) {
    put<float>(b, 1.f + i);
    put<float>(b, 10.f + i);
    put<float>(b, 100.f + i);
    put<uint8_t>(b, 7);
  }
  put<uint8_t>(b, 3);
  for (int k = 0; k < 3; ++k) put<int32_t>(b, k);
  PointCloud c;
  ReadResult r = parse(b, c);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(std::vector<float>(c.xyz.begin(), c.xyz.end()), (std::vector<float>{1, 10, 100, 2, 11, 101, 3, 12, 102}));
  // The face list cut short is an error even though the vertices are complete.
  b.resize(b.size() - 1);
  r = parse(b, c);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("'face'"), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("truncated"), std::string::npos) << r.error;
}

TEST(PlyHandWritten, AsciiWithCommentsAndFaces) {
  const std::string s =
      "ply\n"
      "format ascii 1.0\n"
      "comment hello\n"
      "element face 1\n"
      "property list uchar uint vertex_indices\n"
      "element vertex 3\n"
      "property int8 label\n"
      "property float64 x\n"
      "property float32 y\n"
      "property int z\n"
      "element tail 2\n"
      "property list int short values\n"
      "end_header\n"
      "3 0 1 2\n"
      "5 0.5 -1.5 7\n"
      "6 nan inf -8\n"
      "-1 1e-3 +2 0\n"
      "0\n"
      "2 4 5\n";
  PointCloud c;
  const auto b = bytes_of(s);
  const ReadResult r = parse(b, c, "ascii.ply");
  ASSERT_TRUE(r.ok) << r.error;
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c.xyz[0], 0.5f);
  EXPECT_EQ(c.xyz[1], -1.5f);
  EXPECT_EQ(c.xyz[2], 7.f);
  EXPECT_TRUE(std::isnan(c.xyz[3]));
  EXPECT_TRUE(std::isinf(c.xyz[4]));
  EXPECT_EQ(c.xyz[5], -8.f);
  EXPECT_EQ(c.xyz[6], 1e-3f);
  EXPECT_EQ(c.xyz[7], 2.f);
  EXPECT_EQ(c.xyz[8], 0.f);
}

// ---- malformed ------------------------------------------------------------------------

namespace {
void expect_error(const ReadResult& r, const std::string& name, const std::string& word) {
  EXPECT_FALSE(r.ok) << "expected an error about '" << word << "'";
  EXPECT_EQ(r.error.rfind(name + ": ", 0), 0u) << r.error;
  EXPECT_NE(r.error.find(word), std::string::npos) << "'" << word << "' not in: " << r.error;
}

void expect_bad(const std::vector<uint8_t>& b, const std::string& word, const ReadLimits& limits = {}) {
  PointCloud c;
  c.xyz = {7, 8, 9};
  c.width = 1;
  expect_error(parse(b, c, "bad.ply", limits), "bad.ply", word);
  EXPECT_EQ(std::vector<float>(c.xyz.begin(), c.xyz.end()), (std::vector<float>{7, 8, 9}));
}

void expect_bad(const std::string& s, const std::string& word, const ReadLimits& limits = {}) {
  expect_bad(bytes_of(s), word, limits);
}

const std::string kVertexXyz = "element vertex 2\nproperty float x\nproperty float y\nproperty float z\n";
}  // namespace

TEST(PlyMalformed, Header) {
  expect_bad("", "empty");
  expect_bad("PLY\nformat ascii 1.0\n", "not a PLY file");
  expect_bad("solid cube\nfacet normal 0 0 1\n", "not a PLY file");
  expect_bad("ply\nformat ascii 1.0\n" + kVertexXyz, "no end_header");
  expect_bad("ply\nformat binary_big_endian 1.0\n" + kVertexXyz + "end_header\n" + std::string(24, '\0'), "big-endian");
  expect_bad("ply\nformat ascii 2.0\n" + kVertexXyz + "end_header\n1 2 3\n4 5 6\n", "version");
  expect_bad("ply\nformat utf8 1.0\n" + kVertexXyz + "end_header\n", "unknown PLY format");
  expect_bad("ply\n" + kVertexXyz + "end_header\n1 2 3\n4 5 6\n", "no format");
  expect_bad("ply\nformat ascii 1.0\nproperty float x\n" + kVertexXyz + "end_header\n", "before any element");
  expect_bad("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n",
             "no property 'z'");
  expect_bad("ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0\n",
             "no 'vertex' element");
  expect_bad(
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property list uchar float z\nend_header\n1 2 1 3\n",
      "is a list");
  expect_bad(
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty half z\n"
      "end_header\n1 2 3\n",
      "unknown property type 'half'");
  expect_bad(
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list float int vertex_indices\nend_header\n1 2 3\n0\n",
      "integer type");
  expect_bad("ply\nformat ascii 1.0\nelement vertex many\nproperty float x\nend_header\n", "non-numeric");
  expect_bad("ply\nformat ascii 1.0\nelement vertex -3\nproperty float x\nend_header\n", "count '-3'");
  expect_bad("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float x\nend_header\n",
             "duplicate property 'x'");
  expect_bad("ply\nformat ascii 1.0\n" + kVertexXyz + kVertexXyz + "end_header\n", "duplicate element");
  expect_bad("ply\nformat ascii 1.0\n" + kVertexXyz + "vertices 3\nend_header\n", "unknown header line");
  ReadLimits small;
  small.max_points = 1;
  expect_bad("ply\nformat ascii 1.0\n" + kVertexXyz + "end_header\n1 2 3\n4 5 6\n", "too many points", small);
}

TEST(PlyMalformed, VertexCountLargerThanData) {
  // binary: 2 vertices declared, 1.5 present
  expect_bad("ply\nformat binary_little_endian 1.0\n" + kVertexXyz + "end_header\n" + std::string(18, '\0'),
             "truncated");
  // ascii: 2 vertices declared, 1 present
  expect_bad("ply\nformat ascii 1.0\n" + kVertexXyz + "end_header\n1 2 3\n", "truncated");
  expect_bad("ply\nformat ascii 1.0\n" + kVertexXyz + "end_header\n1 2 3\n4 5\n", "truncated");
  expect_bad("ply\nformat ascii 1.0\n" + kVertexXyz + "end_header\n1 2 3\n4 x 6\n",
             "'x' of property 'y' is not a number");
  // ten million vertices declared in a 200-byte file: fails before allocating
  for (const char* fmt : {"ascii", "binary_little_endian"}) {
    std::string s = std::string("ply\nformat ") + fmt +
                    " 1.0\nelement vertex 10000000\nproperty float x\nproperty float y\nproperty float z\n"
                    "end_header\n";
    while (s.size() < 200) s += "1 2 3\n";
    const auto t0 = std::chrono::steady_clock::now();
    expect_bad(s, "10000000");
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_LT(ms, 200.0) << fmt;
  }
}

TEST(PlyMalformed, ListProblems) {
  const auto b = binary_with_faces(5, 3);
  // a negative list count (signed count type)
  std::vector<uint8_t> neg = bytes_of(
      "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list char int vertex_indices\nend_header\n");
  put<float>(neg, 1.f);
  put<float>(neg, 2.f);
  put<float>(neg, 3.f);
  put<int8_t>(neg, -1);
  expect_bad(neg, "negative count");
  // a huge face count must not hang: it ends with the data
  std::vector<uint8_t> huge = bytes_of(
      "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float z\nelement face 4000000000\nproperty list uchar int vertex_indices\nend_header\n");
  put<float>(huge, 1.f);
  put<float>(huge, 2.f);
  put<float>(huge, 3.f);
  for (int i = 0; i < 10; ++i) put<uint8_t>(huge, 0);
  expect_bad(huge, "'face' declares 4000000000 items");
  // cut each element of the mesh at every byte: always an error, never a crash
  for (size_t cut = 0; cut + 1 < b.size(); ++cut) {
    PointCloud c;
    const std::vector<uint8_t> part(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(cut));
    const ReadResult r = parse(part, c);
    ASSERT_FALSE(r.ok) << cut;
    ASSERT_EQ(r.error.rfind("bad.ply: ", 0), 0u) << r.error;
  }
  // ascii list with too few values
  expect_bad(
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n1 2 3\n3 0 1\n",
      "truncated");
  expect_bad(
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n1 2 3\n-3 0 1\n",
      "list count '-3'");
}

TEST(PlyMalformed, FilesOnDisk) {
  PointCloud c;
  const std::string missing = (temp_dir() / "missing.ply").string();
  expect_error(fg::host::read_ply(missing, c), missing, "cannot open");
  expect_error(fg::host::read_cloud(missing, c), missing, "cannot open");
  const std::string empty = (temp_dir() / "empty.ply").string();
  { std::ofstream f(empty); }
  expect_error(fg::host::read_ply(empty, c), empty, "empty");
  ReadLimits small;
  small.max_file_bytes = 10;
  const std::string path = (temp_dir() / "ten.ply").string();
  ASSERT_TRUE(fg::host::write_ply(path, sample_cloud(10, 1), false).ok);
  expect_error(fg::host::read_ply(path, c, small), path, "larger than the limit");
}

// ---- fuzzing (seeded) ---------------------------------------------------------------------

TEST(PlyFuzz, RandomBytesAndMutations) {
  std::vector<std::vector<uint8_t>> seeds;
  seeds.push_back(binary_with_faces(6, 3));
  seeds.push_back(
      bytes_of("ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty uchar q\n"
               "property float y\nproperty float z\nelement face 1\n"
               "property list uchar int vertex_indices\nend_header\n1 2 3 4\n5 6 7 8\n3 0 1 1\n"));
  const std::string words[] = {"element", "property", "list", "uchar", "int", "float",      "double", "vertex",
                               "face",    "\n",       " ",    "0",     "255", "4294967295", "-1",     "end_header\n"};
  std::mt19937 rng(99);
  for (int it = 0; it < 6000; ++it) {
    std::vector<uint8_t> b;
    if (it % 3 == 0) {
      b.resize(rng() % 400);
      for (auto& x : b) x = static_cast<uint8_t>(rng());
      if (it % 2 == 0) {
        const std::string magic = "ply\nformat binary_little_endian 1.0\n";
        b.insert(b.begin(), magic.begin(), magic.end());
      }
    } else {
      b = seeds[static_cast<size_t>(it) % seeds.size()];
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
            const std::string& w = words[rng() % std::size(words)];
            b.insert(b.begin() + static_cast<std::ptrdiff_t>(p), w.begin(), w.end());
            break;
          }
          default:
            b[p] ^= static_cast<uint8_t>(1u << (rng() % 8));
            break;
        }
      }
    }
    PointCloud c;
    ReadLimits limits;
    limits.max_points = 100000;
    const ReadResult r = parse(b, c, "fuzz.ply", limits);
    if (!r.ok) {
      ASSERT_EQ(r.error.rfind("fuzz.ply: ", 0), 0u) << r.error;
    } else {
      ASSERT_EQ(c.xyz.size(), size_t{c.width} * 3);
      ASSERT_EQ(c.height, 1u);
    }
  }
}
