// The collision check's near list (near_list.hpp) against oracles written here:
// sort_by_cell against std::sort of the same entries (a permutation, ordered by cell),
// and near_list_hits against a scan of every point for random boxes in random frames,
// over uniform and clustered clouds, boxes inside, across and outside the grid.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "fg/core/near_list.hpp"

namespace {

using fg::FrameBox;
using fg::NearGrid;
using fg::Vec3;

constexpr uint32_t kIndexBits = 17;

// Entries of points (all in the grid's cube or beyond it), sorted as the planner does.
std::vector<uint32_t> sorted_entries(const std::vector<Vec3>& pts, const NearGrid& g, uint32_t cell_bits) {
  std::vector<uint32_t> e(pts.size());
  for (uint32_t i = 0; i < pts.size(); ++i) e[i] = (g.cell_of(pts[i]) << kIndexBits) | i;
  std::vector<uint32_t> next(1u << cell_bits), end(1u << cell_bits);
  fg::sort_by_cell(e.data(), static_cast<uint32_t>(e.size()), kIndexBits, cell_bits, next.data(), end.data());
  return e;
}

// A random rotation (a normalised Gaussian quaternion) as three axes.
void random_axes(std::mt19937& rng, Vec3 axes[3]) {
  std::normal_distribution<float> n(0.f, 1.f);
  Eigen::Quaternionf q(n(rng), n(rng), n(rng), n(rng));
  q.normalize();
  const fg::Mat3 R = q.toRotationMatrix();
  for (int a = 0; a < 3; ++a) axes[a] = R.col(a);
}

bool brute_force_hits(const std::vector<Vec3>& pts, const std::vector<uint8_t>& state, const Vec3& pos,
                      const Vec3 axes[3], const FrameBox& b, float tol) {
  for (uint32_t i = 0; i < pts.size(); ++i) {
    if (state[i] == 0) continue;
    const Vec3 d = pts[i] - pos;
    const float x = axes[0].dot(d), y = axes[1].dot(d), z = axes[2].dot(d);
    if (x > b.x0 + tol && x < b.x1 - tol && y > b.y0 + tol && y < b.y1 - tol && z > b.z0 + tol && z < b.z1 - tol)
      return true;
  }
  return false;
}

TEST(NearList, SortByCellIsAPermutationOrderedByCell) {
  std::mt19937 rng(11);
  for (uint32_t cell_bits : {3u, 7u, 12u, 15u}) {
    for (uint32_t n : {0u, 1u, 2u, 100u, 20000u}) {
      std::uniform_int_distribution<uint32_t> cell(0, (1u << cell_bits) - 1u);
      std::vector<uint32_t> e(n);
      for (uint32_t i = 0; i < n; ++i) e[i] = (cell(rng) << kIndexBits) | i;
      std::vector<uint32_t> expect = e;
      std::sort(expect.begin(), expect.end());
      std::vector<uint32_t> next(1u << cell_bits), end(1u << cell_bits);
      fg::sort_by_cell(e.data(), n, kIndexBits, cell_bits, next.data(), end.data());
      for (uint32_t i = 1; i < n; ++i)
        ASSERT_LE(e[i - 1] >> kIndexBits, e[i] >> kIndexBits) << "bits " << cell_bits << " n " << n << " at " << i;
      std::vector<uint32_t> got = e;
      std::sort(got.begin(), got.end());
      EXPECT_EQ(got, expect) << "bits " << cell_bits << " n " << n;
    }
  }
}

TEST(NearList, CellsClampToTheGridAndTakeNaNToCellZero) {
  const NearGrid g = NearGrid::around(Vec3(0.5f, 0.f, 0.2f), 0.3f, 15);
  EXPECT_EQ(g.bits[0] + g.bits[1] + g.bits[2], 15u);
  EXPECT_EQ(g.axis(-10.f, 0), 0u);
  EXPECT_EQ(g.axis(10.f, 0), (1u << g.bits[0]) - 1u);
  EXPECT_EQ(g.axis(std::nanf(""), 1), 0u);
  // The cube's corners fall in the first and last cells.
  EXPECT_EQ(g.cell_of(Vec3(0.2001f, -0.2999f, -0.0999f)), 0u);
  EXPECT_EQ(g.cell_of(Vec3(0.7999f, 0.2999f, 0.4999f)), (1u << 15) - 1u);
}

TEST(NearList, HitsMatchAScanOfEveryPoint) {
  std::mt19937 rng(2026);
  const Vec3 centre(0.5f, 0.05f, 0.15f);
  const float r = 0.3f;
  uint32_t hits = 0, misses = 0;
  for (int cloud = 0; cloud < 6; ++cloud) {
    // Uniform in (and a little beyond) the cube, or clustered in small blobs.
    std::vector<Vec3> pts;
    std::uniform_real_distribution<float> u(-1.1f * r, 1.1f * r);
    const uint32_t n = cloud % 2 == 0 ? 3000u : 20000u;
    if (cloud < 4) {
      for (uint32_t i = 0; i < n; ++i) pts.push_back(centre + Vec3(u(rng), u(rng), u(rng)));
    } else {
      std::normal_distribution<float> blob(0.f, 0.01f);
      for (uint32_t k = 0; k < 20; ++k) {
        const Vec3 c = centre + Vec3(u(rng), u(rng), u(rng));
        for (uint32_t i = 0; i < n / 20; ++i) pts.push_back(c + Vec3(blob(rng), blob(rng), blob(rng)));
      }
    }
    std::vector<uint8_t> state(pts.size());
    std::bernoulli_distribution kept(0.9);
    for (auto& s : state) s = kept(rng) ? 1 : 0;
    const uint32_t cell_bits = cloud % 3 == 0 ? 15u : (cloud % 3 == 1 ? 9u : 4u);
    const NearGrid g = NearGrid::around(centre, r, cell_bits);
    const std::vector<uint32_t> e = sorted_entries(pts, g, cell_bits);
    std::uniform_real_distribution<float> size(0.005f, 0.15f), place(-1.3f * r, 1.3f * r), tol(0.f, 0.003f);
    for (int q = 0; q < 600; ++q) {
      Vec3 axes[3];
      random_axes(rng, axes);
      const float sx = size(rng), sy = size(rng), sz = size(rng);
      const float ox = 0.5f * size(rng), oy = 0.5f * size(rng), oz = 0.5f * size(rng);
      const FrameBox b{ox - sx, ox, oy - sy, oy, oz - sz, oz};  // offset from the placement point
      const Vec3 pos = centre + Vec3(place(rng), place(rng), place(rng));
      const float t = tol(rng);
      const bool expect = brute_force_hits(pts, state, pos, axes, b, t);
      const bool got = fg::near_list_hits(e.data(), static_cast<uint32_t>(e.size()), kIndexBits, g, pts.data(),
                                          state.data(), pos, axes, b, t);
      ASSERT_EQ(got, expect) << "cloud " << cloud << " query " << q;
      (expect ? hits : misses) += 1;
    }
  }
  // Both answers were exercised often.
  EXPECT_GT(hits, 500u);
  EXPECT_GT(misses, 500u);
}

TEST(NearList, ABoxShrunkToNothingHitsNothing) {
  const NearGrid g = NearGrid::around(Vec3::Zero(), 0.1f, 6);
  const std::vector<Vec3> pts = {Vec3::Zero()};
  const std::vector<uint8_t> state = {1};
  const std::vector<uint32_t> e = sorted_entries(pts, g, 6);
  const Vec3 axes[3] = {Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()};
  const FrameBox b{-0.001f, 0.001f, -0.01f, 0.01f, -0.01f, 0.01f};
  EXPECT_TRUE(fg::near_list_hits(e.data(), 1, kIndexBits, g, pts.data(), state.data(), Vec3::Zero(), axes, b, 0.f));
  EXPECT_FALSE(fg::near_list_hits(e.data(), 1, kIndexBits, g, pts.data(), state.data(), Vec3::Zero(), axes, b, 0.001f));
}

}  // namespace
