// The DATA binary PCD stream (io/pcd_stream.hpp): it opens exactly the files it can
// hand over in place, gives the whole-file reader's coordinates bit for bit in pieces
// of whole points, refuses a file that shrinks while it is read with a message, and
// feeds the planner the same grid as the whole cloud does.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "fg/core/byte_order.hpp"
#include "fg/core/planner.hpp"
#include "io/pcd.hpp"
#include "io/pcd_stream.hpp"
#include "io/ply.hpp"

namespace {

using fg::host::PcdStream;
using fg::host::PointCloud;

std::filesystem::path temp_dir() {
  static const std::filesystem::path dir = [] {
    auto d = std::filesystem::temp_directory_path() /
             ("fg_test_pcd_stream_" + std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

struct RemoveTempDir : ::testing::Environment {
  void TearDown() override {
    std::error_code ec;
    std::filesystem::remove_all(temp_dir(), ec);
  }
};
[[maybe_unused]] ::testing::Environment* const kRemoveTempDir = ::testing::AddGlobalTestEnvironment(new RemoveTempDir);

//! One field of a hand-made file: name, SIZE, TYPE.
struct FieldSpec {
  const char* name;
  uint32_t size;
  char type;
};

//! A DATA binary file with these fields; x, y and z (4-byte floats) of point i are
//! pts[i], every other field's bytes are a pattern, and `tail` bytes follow the data.
std::string write_binary(const std::string& file, const std::vector<FieldSpec>& fields,
                         const std::vector<std::array<float, 3>>& pts, size_t tail = 0) {
  std::string h = "# .PCD v0.7\nVERSION 0.7\nFIELDS";
  for (const auto& f : fields) h += std::string(" ") + f.name;
  h += "\nSIZE";
  for (const auto& f : fields) h += " " + std::to_string(f.size);
  h += "\nTYPE";
  for (const auto& f : fields) h += std::string(" ") + f.type;
  h += "\nCOUNT";
  for (size_t k = 0; k < fields.size(); ++k) h += " 1";
  h += "\nWIDTH " + std::to_string(pts.size()) + "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " +
       std::to_string(pts.size()) + "\nDATA binary\n";
  std::vector<uint8_t> data;
  for (size_t i = 0; i < pts.size(); ++i) {
    for (const auto& f : fields) {
      const std::string n = f.name;
      const int axis = n == "x" ? 0 : n == "y" ? 1 : n == "z" ? 2 : -1;
      uint8_t raw[8];
      if (axis >= 0) {
        fg::store_le(pts[i][static_cast<size_t>(axis)], raw);
      } else {
        for (uint32_t b = 0; b < f.size; ++b) raw[b] = static_cast<uint8_t>(i * 7 + b);
      }
      data.insert(data.end(), raw, raw + f.size);
    }
  }
  data.resize(data.size() + tail, 0xAB);
  const std::string path = (temp_dir() / file).string();
  std::ofstream out(path, std::ios::binary);
  out.write(h.data(), static_cast<std::streamsize>(h.size()));
  out.write(reinterpret_cast<const char*>(data.data()), static_cast<std::streamsize>(data.size()));
  return path;
}

std::vector<std::array<float, 3>> random_points(size_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.f, 2.f);
  std::vector<std::array<float, 3>> pts(n);
  for (size_t i = 0; i < n; ++i) {
    pts[i] = {u(rng), u(rng), u(rng)};
    if (i % 11 == 3) pts[i][0] = std::numeric_limits<float>::quiet_NaN();  // a missing pixel
  }
  return pts;
}

//! Every piece of the stream, gathered into x y z triples; false when a piece fails.
bool drain(PcdStream& s, std::vector<float>& xyz, size_t& pieces) {
  pieces = 0;
  for (;;) {
    fg::PointPiece p;
    if (!s.next(p)) return false;
    if (p.count == 0) return true;
    ++pieces;
    EXPECT_LE(static_cast<size_t>(p.count) * p.stride, PcdStream::kChunkBytes);
    for (uint32_t i = 0; i < p.count; ++i) {
      const uint8_t* at[3] = {p.x, p.y, p.z};
      for (const uint8_t* a : at) {
        float v;
        std::memcpy(&v, a + static_cast<size_t>(i) * p.stride, 4);
        xyz.push_back(v);
      }
    }
  }
}

TEST(PcdStream, HandsOverTheWholeFileReadersPointsForAnyFieldLayout) {
  if constexpr (!fg::kLittleEndian) GTEST_SKIP() << "the stream takes little-endian floats in place only";
  const std::vector<std::vector<FieldSpec>> layouts = {
      {{"x", 4, 'F'}, {"y", 4, 'F'}, {"z", 4, 'F'}},
      {{"x", 4, 'F'}, {"y", 4, 'F'}, {"z", 4, 'F'}, {"rgb", 4, 'F'}},       // PCL's PointXYZRGB
      {{"label", 4, 'U'}, {"x", 4, 'F'}, {"y", 4, 'F'}, {"z", 4, 'F'}},     // a field before x
      {{"z", 4, 'F'}, {"_", 2, 'U'}, {"x", 4, 'F'}, {"y", 4, 'F'}},         // any order, odd offsets
      {{"x", 4, 'F'}, {"y", 4, 'F'}, {"z", 4, 'F'}, {"intensity", 1, 'U'}}  // 13 bytes a point
  };
  // Counts below one chunk, at several chunks with a partial last one, and none.
  for (size_t n : {size_t{0}, size_t{1}, size_t{5}, size_t{50'001}}) {
    for (size_t l = 0; l < layouts.size(); ++l) {
      SCOPED_TRACE(testing::Message() << n << " points, layout " << l);
      const auto pts = random_points(n, static_cast<uint32_t>(n + l));
      const std::string path = write_binary("layout" + std::to_string(l) + ".pcd", layouts[l], pts, l == 2 ? 9 : 0);
      PointCloud whole;
      ASSERT_TRUE(fg::host::read_pcd(path, whole).ok);
      PcdStream s;
      ASSERT_TRUE(s.open(path));
      EXPECT_EQ(s.points(), n);
      std::vector<float> xyz;
      size_t pieces = 0;
      ASSERT_TRUE(drain(s, xyz, pieces)) << s.error();
      ASSERT_EQ(xyz.size(), whole.xyz.size());
      if (!xyz.empty()) {  // memcmp of an empty vector's null data is undefined
        EXPECT_EQ(std::memcmp(xyz.data(), whole.xyz.data(), xyz.size() * 4), 0);
      }
      if (n == 50'001) {
        EXPECT_GT(pieces, 2u);  // bounded chunks, not the whole file
      }
      fg::PointPiece end;
      EXPECT_TRUE(s.next(end));  // the end stays the end
      EXPECT_EQ(end.count, 0u);
    }
  }
}

TEST(PcdStream, OpensOnlyWhatItCanHandOverInPlace) {
  const auto pts = random_points(100, 3);
  const std::vector<FieldSpec> xyz = {{"x", 4, 'F'}, {"y", 4, 'F'}, {"z", 4, 'F'}};
  const std::string good = write_binary("good.pcd", xyz, pts);
  std::vector<std::string> others;
  // Other encodings and double coordinates: the whole-file reader's.
  PointCloud c;
  ASSERT_TRUE(fg::host::read_pcd(good, c).ok);
  for (auto e : {fg::host::PcdEncoding::ascii, fg::host::PcdEncoding::binary_compressed}) {
    others.push_back((temp_dir() / ("enc" + std::to_string(static_cast<int>(e)) + ".pcd")).string());
    ASSERT_TRUE(fg::host::write_pcd(others.back(), c, e).ok);
  }
  others.push_back(write_binary("double.pcd", {{"x", 8, 'F'}, {"y", 8, 'F'}, {"z", 8, 'F'}}, {}));
  // Short of the declared points by one byte: the whole-file reader names it.
  const std::string shorter = write_binary("short.pcd", xyz, pts);
  std::filesystem::resize_file(shorter, std::filesystem::file_size(shorter) - 1);
  others.push_back(shorter);
  // A broken header, a missing file, a folder, a FIFO (opening it must not wait for a
  // writer), an empty file.
  others.push_back(write_binary("noxyz.pcd", {{"x", 4, 'F'}, {"y", 4, 'F'}}, {}));
  others.push_back((temp_dir() / "missing.pcd").string());
  others.push_back(temp_dir().string());
  const std::string fifo = (temp_dir() / "fifo.pcd").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  others.push_back(fifo);
  others.push_back((temp_dir() / "empty.pcd").string());
  std::ofstream(others.back()).close();
  for (const std::string& path : others) {
    SCOPED_TRACE(path);
    PcdStream s;
    EXPECT_FALSE(s.open(path));
    fg::PointPiece p;
    EXPECT_FALSE(s.next(p));  // not open: a failure, with a message
    EXPECT_FALSE(s.error().empty());
  }
  // A file whose data is short or whose header is broken is refused by the whole-file
  // reader, which the program falls back to, with the problem named.
  PointCloud out;
  const fg::host::ReadResult r = fg::host::read_cloud(shorter, out);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("truncated"), std::string::npos) << r.error;
  PcdStream s;
  EXPECT_EQ(s.open(good), fg::kLittleEndian);
}

TEST(PcdStream, AFileThatShrinksWhileItIsReadIsRefusedWithAMessage) {
  if constexpr (!fg::kLittleEndian) GTEST_SKIP() << "the stream takes little-endian floats in place only";
  const auto pts = random_points(60'000, 9);  // 720 kB: several chunks
  const std::string path = write_binary("shrinks.pcd", {{"x", 4, 'F'}, {"y", 4, 'F'}, {"z", 4, 'F'}}, pts);
  PcdStream s;
  ASSERT_TRUE(s.open(path));
  fg::PointPiece p;
  ASSERT_TRUE(s.next(p));
  ASSERT_GT(p.count, 0u);
  std::filesystem::resize_file(path, std::filesystem::file_size(path) / 2);  // another process truncates it
  bool failed = false;
  for (int i = 0; i < 100 && !failed; ++i) {
    failed = !s.next(p);
    if (!failed && p.count == 0) break;
  }
  ASSERT_TRUE(failed) << "the stream read past the new end of the file";
  EXPECT_EQ(s.error().rfind(path + ": ", 0), 0u) << s.error();
  EXPECT_NE(s.error().find("shrank"), std::string::npos) << s.error();
}

// The planner fed by the stream builds the grid the whole cloud builds: a table and a
// box seen from above, in a file with a field before x.
TEST(PcdStream, ThePlannerGetsTheSameGridAsFromTheWholeCloud) {
  if constexpr (!fg::kLittleEndian) GTEST_SKIP() << "the stream takes little-endian floats in place only";
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-0.3f, 0.3f);
  std::vector<std::array<float, 3>> pts;
  for (int i = 0; i < 40'000; ++i) {
    const float x = u(rng), y = u(rng);
    const bool on_box = std::fabs(x) < 0.03f && std::fabs(y) < 0.05f;
    pts.push_back({x, y, on_box ? 0.6f : 0.7f});  // the sensor 0.7 m above the table
  }
  const std::string path =
      write_binary("scene.pcd", {{"label", 4, 'U'}, {"x", 4, 'F'}, {"y", 4, 'F'}, {"z", 4, 'F'}}, pts);
  fg::Pose pose;  // looking straight down from 0.7 m above (0.5, 0)
  pose.R << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  pose.t = fg::Vec3(0.5f, 0.f, 0.7f);
  auto a = std::make_unique<fg::Planner>();
  auto b = std::make_unique<fg::Planner>();
  ASSERT_EQ(a->configure(fg::PlannerConfig{}), fg::Status::ok);
  ASSERT_EQ(b->configure(fg::PlannerConfig{}), fg::Status::ok);
  PointCloud whole;
  ASSERT_TRUE(fg::host::read_pcd(path, whole).ok);
  ASSERT_EQ(a->add_points(fg::SensorRole::head, whole.xyz.data(), static_cast<uint32_t>(whole.size()), 12, pose),
            fg::Status::ok);
  PcdStream s;
  ASSERT_TRUE(s.open(path));
  ASSERT_EQ(b->add_point_source(fg::SensorRole::head, s, pose), fg::Status::ok) << b->last_message();
  const fg::VoxelGrid &ga = a->voxels(), &gb = b->voxels();
  ASSERT_GT(ga.size(), 1000u);
  ASSERT_EQ(ga.size(), gb.size());
  for (uint32_t i = 0; i < ga.size(); ++i) {
    ASSERT_EQ(ga.key(i), gb.key(i));
    const fg::Vec3 ca = ga.centroid(i), cb = gb.centroid(i);
    ASSERT_EQ(std::memcmp(ca.data(), cb.data(), sizeof(float) * 3), 0) << "voxel " << i;
  }
  fg::PlanResult ra, rb;
  EXPECT_EQ(a->plan(ra), ra.status);
  EXPECT_EQ(b->plan(rb), rb.status);
  EXPECT_EQ(ra.points.input, rb.points.input);
  EXPECT_EQ(ra.points.finite, rb.points.finite);
  EXPECT_EQ(ra.points.after_filter, rb.points.after_filter);
}

}  // namespace
