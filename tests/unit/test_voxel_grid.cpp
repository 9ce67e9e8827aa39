// VoxelGrid against a brute-force oracle written here: a std::map from the cell index
// (computed in double) to the sum of the points' offsets and their count. Seeded
// random clouds (uniform in a box, and clustered), counts per cell, insertion order,
// find() of present and absent keys, reset() + reuse over several cycles against a
// fresh grid, the capacity limit, the key range, and a million points in one cell.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <set>
#include <tuple>
#include <vector>

#include "fg/core/limits.hpp"
#include "fg/core/voxel_grid.hpp"

namespace {

using fg::Status;
using fg::Vec3;
using fg::VoxelGrid;

using Cell = std::tuple<int, int, int>;

struct Acc {
  double sx = 0, sy = 0, sz = 0;  // sum of the points (absolute, double)
  uint32_t count = 0;
  size_t first = 0;  // order of first appearance
};

struct Oracle {
  std::map<Cell, Acc> cells;
  std::vector<Cell> order;  // cells in order of first appearance
};

// Cell of p in double arithmetic; false when p is within `guard` cells of a cell
// boundary (float and double may then disagree: such points are not used).
bool cell_of(const Vec3& p, const Vec3& origin, float leaf, Cell& c, double guard = 1e-3) {
  int idx[3];
  for (int a = 0; a < 3; ++a) {
    const double f = (static_cast<double>(p[a]) - static_cast<double>(origin[a])) / static_cast<double>(leaf);
    const double fl = std::floor(f);
    if (f - fl < guard || fl + 1.0 - f < guard) return false;
    idx[a] = static_cast<int>(fl);
  }
  c = Cell{idx[0], idx[1], idx[2]};
  return true;
}

// Drops points near cell boundaries (see cell_of) and builds the oracle.
Oracle build_oracle(std::vector<Vec3>& pts, const Vec3& origin, float leaf) {
  Oracle o;
  std::vector<Vec3> kept;
  kept.reserve(pts.size());
  for (const Vec3& p : pts) {
    Cell c;
    if (!cell_of(p, origin, leaf, c)) continue;
    kept.push_back(p);
    auto it = o.cells.find(c);
    if (it == o.cells.end()) {
      Acc a;
      a.first = o.order.size();
      it = o.cells.emplace(c, a).first;
      o.order.push_back(c);
    }
    it->second.sx += p.x();
    it->second.sy += p.y();
    it->second.sz += p.z();
    it->second.count += 1;
  }
  pts.swap(kept);
  return o;
}

uint32_t key_of(const Cell& c) {
  return VoxelGrid::pack(static_cast<uint32_t>(std::get<0>(c)), static_cast<uint32_t>(std::get<1>(c)),
                         static_cast<uint32_t>(std::get<2>(c)));
}

std::unique_ptr<VoxelGrid> make_grid(const Vec3& origin, float leaf) {
  auto g = std::make_unique<VoxelGrid>();
  g->reset(origin, leaf);
  return g;
}

void insert_all(VoxelGrid& g, const std::vector<Vec3>& pts) {
  for (size_t i = 0; i < pts.size(); ++i) {
    const Status s = g.insert(pts[i]);
    ASSERT_EQ(s, Status::ok) << "point " << i << " (" << pts[i].transpose() << ")";
  }
}

// Compares a grid with the oracle: same cells, same counts, same first-appearance
// order, centroids within tol (m), and find() of every key.
void expect_matches(const VoxelGrid& g, const Oracle& o, double tol) {
  ASSERT_EQ(g.size(), o.cells.size());
  for (uint32_t i = 0; i < g.size(); ++i) {
    const fg::Voxel& v = g.voxel(i);
    const Cell c{static_cast<int>(VoxelGrid::key_x(v.key)), static_cast<int>(VoxelGrid::key_y(v.key)),
                 static_cast<int>(VoxelGrid::key_z(v.key))};
    auto it = o.cells.find(c);
    ASSERT_NE(it, o.cells.end()) << "voxel " << i << " is not an oracle cell";
    EXPECT_EQ(o.order[i], c) << "voxel " << i << " out of insertion order";
    EXPECT_EQ(v.count, it->second.count) << "voxel " << i;
    const Vec3 cen = g.centroid(i);
    const double n = it->second.count;
    EXPECT_NEAR(cen.x(), it->second.sx / n, tol) << "voxel " << i;
    EXPECT_NEAR(cen.y(), it->second.sy / n, tol) << "voxel " << i;
    EXPECT_NEAR(cen.z(), it->second.sz / n, tol) << "voxel " << i;
    EXPECT_EQ(g.find(v.key), i);
  }
  for (const auto& kv : o.cells) {
    const uint32_t idx = g.find(key_of(kv.first));
    ASSERT_NE(idx, VoxelGrid::kNone);
    EXPECT_EQ(idx, kv.second.first);
  }
}

std::vector<Vec3> uniform_box(std::mt19937& rng, const Vec3& lo, const Vec3& hi, size_t n) {
  std::uniform_real_distribution<float> ux(lo.x(), hi.x()), uy(lo.y(), hi.y()), uz(lo.z(), hi.z());
  std::vector<Vec3> pts(n);
  for (Vec3& p : pts) p = Vec3(ux(rng), uy(rng), uz(rng));
  return pts;
}

std::vector<Vec3> clustered(std::mt19937& rng, const Vec3& lo, const Vec3& hi, int blobs, size_t per_blob,
                            float sigma) {
  std::vector<Vec3> pts;
  std::uniform_real_distribution<float> ux(lo.x(), hi.x()), uy(lo.y(), hi.y()), uz(lo.z(), hi.z());
  std::normal_distribution<float> nd(0.f, sigma);
  for (int b = 0; b < blobs; ++b) {
    const Vec3 c(ux(rng), uy(rng), uz(rng));
    for (size_t i = 0; i < per_blob; ++i) {
      Vec3 p = c + Vec3(nd(rng), nd(rng), nd(rng));
      p = p.cwiseMax(lo).cwiseMin(hi);
      pts.push_back(p);
    }
  }
  return pts;
}

// ---------------------------------------------------------------------------------

TEST(VoxelGrid, UniformBoxMatchesBruteForce) {
  std::mt19937 rng(1234);
  const Vec3 origin(-0.3f, -0.6f, 0.1f);
  const float leaf = 0.005f;
  const Vec3 lo = origin + Vec3::Constant(0.02f), hi = lo + Vec3(0.2f, 0.15f, 0.1f);
  std::vector<Vec3> pts = uniform_box(rng, lo, hi, 60000);
  const Oracle o = build_oracle(pts, origin, leaf);
  auto g = make_grid(origin, leaf);
  insert_all(*g, pts);
  expect_matches(*g, o, 2e-6);
}

TEST(VoxelGrid, DenseUniformBoxManyPointsPerCell) {
  std::mt19937 rng(77);
  const Vec3 origin(0.f, 0.f, 0.f);
  const float leaf = 0.01f;
  const Vec3 lo(0.05f, 0.05f, 0.05f), hi(0.15f, 0.12f, 0.09f);  // 10 x 7 x 4 cells
  std::vector<Vec3> pts = uniform_box(rng, lo, hi, 200000);
  const Oracle o = build_oracle(pts, origin, leaf);
  auto g = make_grid(origin, leaf);
  insert_all(*g, pts);
  expect_matches(*g, o, 2e-6);
  uint32_t total = 0;
  for (uint32_t i = 0; i < g->size(); ++i) total += g->voxel(i).count;
  EXPECT_EQ(total, pts.size());
}

TEST(VoxelGrid, ClusteredCloudMatchesBruteForce) {
  std::mt19937 rng(99);
  const Vec3 origin(0.1f, -0.5f, -0.2f);
  const float leaf = 0.005f;
  const Vec3 lo = origin + Vec3::Constant(0.05f), hi = lo + Vec3(0.8f, 0.8f, 0.5f);
  std::vector<Vec3> pts = clustered(rng, lo, hi, 12, 8000, 0.01f);
  const Oracle o = build_oracle(pts, origin, leaf);
  auto g = make_grid(origin, leaf);
  insert_all(*g, pts);
  expect_matches(*g, o, 2e-6);
}

TEST(VoxelGrid, InterleavedCellsAcrossTheLastKeyCache) {
  // Alternating between cells (A B A B ...) and runs (A A A B B B) give the same sums.
  const Vec3 origin(0.f, 0.f, 0.f);
  const float leaf = 0.005f;
  std::vector<Vec3> pts;
  for (int i = 0; i < 1000; ++i) {
    const float f = 0.001f + 0.003f * static_cast<float>(i % 7) / 7.f;
    // cells [10, 11) and [20, 21) along x; 0.0502 keeps clear of the cell boundaries
    pts.push_back(Vec3(0.0502f + f, 0.0522f, 0.0502f + f));
    pts.push_back(Vec3(0.1002f + f, 0.0502f + f, 0.0522f));
    if (i % 3 == 0) pts.push_back(Vec3(0.0502f + f, 0.0522f, 0.0502f + f));
  }
  std::vector<Vec3> keep = pts;
  const Oracle o = build_oracle(keep, origin, leaf);
  ASSERT_EQ(keep.size(), pts.size());
  auto g = make_grid(origin, leaf);
  insert_all(*g, keep);
  expect_matches(*g, o, 1e-6);
}

TEST(VoxelGrid, FindOfAbsentKeys) {
  std::mt19937 rng(5);
  const Vec3 origin(0.f, 0.f, 0.f);
  const float leaf = 0.005f;
  std::vector<Vec3> pts = uniform_box(rng, Vec3(0.1f, 0.1f, 0.1f), Vec3(0.3f, 0.3f, 0.2f), 5000);
  const Oracle o = build_oracle(pts, origin, leaf);
  auto g = make_grid(origin, leaf);
  insert_all(*g, pts);
  std::uniform_int_distribution<uint32_t> kx(0, 2047), ky(0, 2047), kz(0, 1023);
  int absent = 0;
  for (int i = 0; i < 20000; ++i) {
    const Cell c{static_cast<int>(kx(rng)), static_cast<int>(ky(rng)), static_cast<int>(kz(rng))};
    const uint32_t idx = g->find(key_of(c));
    if (o.cells.count(c)) {
      EXPECT_NE(idx, VoxelGrid::kNone);
    } else {
      ++absent;
      EXPECT_EQ(idx, VoxelGrid::kNone) << std::get<0>(c) << " " << std::get<1>(c) << " " << std::get<2>(c);
    }
  }
  EXPECT_GT(absent, 19000);
  // Every neighbour of a present cell that is not itself present is absent.
  for (const auto& kv : o.cells) {
    for (int d = 0; d < 6; ++d) {
      Cell n = kv.first;
      const int s = (d & 1) ? 1 : -1;
      if (d / 2 == 0) std::get<0>(n) += s;
      if (d / 2 == 1) std::get<1>(n) += s;
      if (d / 2 == 2) std::get<2>(n) += s;
      const uint32_t idx = g->find(key_of(n));
      EXPECT_EQ(idx != VoxelGrid::kNone, o.cells.count(n) == 1);
    }
  }
  // An empty grid finds nothing.
  auto e = make_grid(origin, leaf);
  EXPECT_EQ(e->size(), 0u);
  EXPECT_EQ(e->find(key_of(o.order[0])), VoxelGrid::kNone);
  EXPECT_EQ(e->find(0u), VoxelGrid::kNone);
}

TEST(VoxelGrid, ResetThenReuseEqualsFreshGrid) {
  std::mt19937 rng(2024);
  auto reused = std::make_unique<VoxelGrid>();
  struct Cycle {
    Vec3 origin;
    float leaf;
    Vec3 lo, size;
    size_t n;
    bool clustered;
  };
  const Cycle cycles[] = {
      {Vec3(0.f, 0.f, 0.f), 0.005f, Vec3(0.05f, 0.05f, 0.05f), Vec3(0.3f, 0.3f, 0.2f), 80000, false},
      {Vec3(0.f, 0.f, 0.f), 0.005f, Vec3(0.06f, 0.02f, 0.05f), Vec3(0.05f, 0.05f, 0.05f), 300, false},
      {Vec3(-1.f, 0.5f, 0.2f), 0.003f, Vec3(-0.9f, 0.6f, 0.3f), Vec3(0.4f, 0.4f, 0.4f), 50000, true},
      {Vec3(0.f, 0.f, 0.f), 0.005f, Vec3(0.05f, 0.05f, 0.05f), Vec3(0.3f, 0.3f, 0.2f), 80000, false},
      {Vec3(0.2f, 0.2f, 0.2f), 0.01f, Vec3(0.3f, 0.3f, 0.3f), Vec3(1.f, 1.f, 1.f), 40000, false},
      {Vec3(0.f, 0.f, 0.f), 0.005f, Vec3(0.05f, 0.05f, 0.05f), Vec3(0.3f, 0.3f, 0.2f), 0, false},
      {Vec3(0.f, 0.f, 0.f), 0.005f, Vec3(0.05f, 0.05f, 0.05f), Vec3(0.3f, 0.3f, 0.2f), 1000, true},
  };
  std::vector<uint32_t> previous_keys;
  for (size_t ci = 0; ci < sizeof(cycles) / sizeof(cycles[0]); ++ci) {
    SCOPED_TRACE("cycle " + std::to_string(ci));
    const Cycle& cy = cycles[ci];
    std::vector<Vec3> pts = cy.clustered ? clustered(rng, cy.lo, cy.lo + cy.size, 6, cy.n / 6, 0.02f)
                                         : uniform_box(rng, cy.lo, cy.lo + cy.size, cy.n);
    const Oracle o = build_oracle(pts, cy.origin, cy.leaf);
    reused->reset(cy.origin, cy.leaf);
    EXPECT_EQ(reused->size(), 0u);
    // Nothing of the previous cycle can be found after the reset.
    for (uint32_t k : previous_keys) EXPECT_EQ(reused->find(k), VoxelGrid::kNone);
    insert_all(*reused, pts);
    auto fresh = make_grid(cy.origin, cy.leaf);
    insert_all(*fresh, pts);
    ASSERT_EQ(reused->size(), fresh->size());
    for (uint32_t i = 0; i < fresh->size(); ++i) {
      const fg::Voxel &a = reused->voxel(i), &b = fresh->voxel(i);
      EXPECT_EQ(a.key, b.key);
      EXPECT_EQ(a.count, b.count);
      const Vec3 ca = reused->centroid(i), cb = fresh->centroid(i);
      EXPECT_EQ(std::memcmp(ca.data(), cb.data(), 3 * sizeof(float)), 0);
      EXPECT_EQ(reused->find(a.key), i);
    }
    expect_matches(*reused, o, 2e-6);
    for (uint32_t k : previous_keys) {
      const uint32_t ia = reused->find(k), ib = fresh->find(k);
      EXPECT_EQ(ia, ib);
    }
    previous_keys.clear();
    for (uint32_t i = 0; i < reused->size(); ++i) previous_keys.push_back(reused->voxel(i).key);
  }
}

// finalize() keeps every centroid bit for bit, refuses further points until reset(),
// and only then lends the storage the counts used, which shares memory with the
// packed centroids and must not overlap them.
TEST(VoxelGrid, FinalizeKeepsCentroidsAndLendsCounts) {
  std::mt19937 rng(11);
  const Vec3 origin(-0.1f, -0.1f, -0.1f);
  const std::vector<Vec3> pts = clustered(rng, Vec3(0.f, 0.f, 0.f), Vec3(0.3f, 0.2f, 0.1f), 6, 400, 0.02f);
  auto g = make_grid(origin, 0.005f);
  insert_all(*g, pts);
  EXPECT_EQ(g->lend_count_storage(), nullptr);
  std::vector<Vec3> before;
  for (uint32_t i = 0; i < g->size(); ++i) before.push_back(g->centroid(i));
  const uint32_t n = g->size(), count0 = g->voxel(0).count;
  ASSERT_GT(count0, 0u);
  g->finalize();
  g->finalize();  // a second call changes nothing
  ASSERT_TRUE(g->finalized());
  ASSERT_EQ(g->size(), n);
  for (uint32_t i = 0; i < n; ++i) {
    EXPECT_EQ(std::memcmp(g->centroids()[i].data(), before[i].data(), sizeof(float) * 3), 0);
    EXPECT_EQ(std::memcmp(g->centroid(i).data(), before[i].data(), sizeof(float) * 3), 0);
  }
  EXPECT_EQ(g->insert(pts[0]), Status::invalid_sequence);
  EXPECT_EQ(g->size(), n);
  EXPECT_EQ(g->voxel(0).count, 0u);
  uint32_t* scratch = g->lend_count_storage();
  ASSERT_NE(scratch, nullptr);
  for (uint32_t i = 0; i < n; ++i) scratch[i] = 0xDEADBEEFu;
  for (uint32_t i = 0; i < n; ++i)
    EXPECT_EQ(std::memcmp(g->centroids()[i].data(), before[i].data(), sizeof(float) * 3), 0);
  for (uint32_t i = 0; i < n; ++i) EXPECT_EQ(g->find(g->key(i)), i);
  g->reset(origin, 0.005f);
  EXPECT_FALSE(g->finalized());
  insert_all(*g, pts);
  ASSERT_EQ(g->size(), n);
  EXPECT_EQ(g->voxel(0).count, count0);
  for (uint32_t i = 0; i < n; ++i)
    EXPECT_EQ(std::memcmp(g->centroid(i).data(), before[i].data(), sizeof(float) * 3), 0);
}

// finalize() turns four voxels per step and the rest one by one: for every count
// around those steps, with cells at the far ends of the key range (a z above 511 sets
// the key's top bit) and 1-5 points per cell, each centroid stays the same bit for bit.
TEST(VoxelGrid, FinalizeKeepsEveryCentroidForEveryCountAndKeyRange) {
  std::mt19937 rng(12);
  std::uniform_real_distribution<float> frac(0.f, 1.f);
  std::uniform_int_distribution<int> cx(2, VoxelGrid::kMaxX - 3), cz(2, VoxelGrid::kMaxZ - 3), reps(1, 5);
  const float leaf = 0.005f;
  const Vec3 origin(-5.f, -5.f, -2.5f);
  for (uint32_t m : {0u, 1u, 2u, 3u, 4u, 5u, 6u, 7u, 8u, 9u, 63u, 64u, 65u, 1001u}) {
    SCOPED_TRACE(testing::Message() << m << " cells");
    auto g = make_grid(origin, leaf);
    for (uint32_t c = 0; c < m; ++c) {
      // Alternate low and high cells, so both halves of the key range meet in a step.
      const int ix = c % 3 == 0 ? 2 : cx(rng), iy = cx(rng), iz = c % 2 == 0 ? VoxelGrid::kMaxZ - 3 : cz(rng);
      for (int r = reps(rng); r > 0; --r) {
        const Vec3 p(origin.x() + (static_cast<float>(ix) + 0.5f * frac(rng) + 0.25f) * leaf,
                     origin.y() + (static_cast<float>(iy) + 0.5f * frac(rng) + 0.25f) * leaf,
                     origin.z() + (static_cast<float>(iz) + 0.5f * frac(rng) + 0.25f) * leaf);
        ASSERT_EQ(g->insert(p), Status::ok);
      }
    }
    std::vector<Vec3> before;
    for (uint32_t i = 0; i < g->size(); ++i) before.push_back(g->centroid(i));
    g->finalize();
    ASSERT_EQ(g->size(), before.size());
    for (uint32_t i = 0; i < g->size(); ++i)
      ASSERT_EQ(std::memcmp(g->centroids()[i].data(), before[i].data(), sizeof(float) * 3), 0) << "voxel " << i;
  }
}

// The key of neighbour d (0..26 over dz, dy, dx in -1..1; 13 is the key itself).
uint32_t neighbour_key(uint32_t key, int d) {
  return VoxelGrid::pack(VoxelGrid::key_x(key) + d % 3 - 1, VoxelGrid::key_y(key) + (d / 3) % 3 - 1,
                         VoxelGrid::key_z(key) + d / 9 - 1);
}

// A finalized grid of `want` cells two apart on a lattice (no two touch), inserted in
// random order; `cells` receives them.
std::unique_ptr<VoxelGrid> finalized_lattice(std::mt19937& rng, uint32_t want, std::set<Cell>& cells) {
  const float leaf = 0.005f;
  std::vector<Vec3> pts;
  std::uniform_int_distribution<int> u(1, 120);
  while (pts.size() < want) {
    const Cell c{4 + 2 * u(rng), 4 + 2 * u(rng), 4 + 2 * u(rng)};
    if (!cells.insert(c).second) continue;
    pts.push_back(Vec3((static_cast<float>(std::get<0>(c)) + 0.5f) * leaf,
                       (static_cast<float>(std::get<1>(c)) + 0.5f) * leaf,
                       (static_cast<float>(std::get<2>(c)) + 0.5f) * leaf));
  }
  auto g = make_grid(Vec3(0.f, 0.f, 0.f), leaf);
  insert_all(*g, pts);
  g->finalize();
  return g;
}

// keep_in_index_only(): find() sees exactly the kept voxels, indices and centroids do
// not move, and a reset brings back a complete index.
// After finalize() find() consults a Bloom filter of the indexed keys before the
// table: it must still find every present cell and no absent one, with the table at
// its load limit (isolated cells: every neighbour lookup is of an absent key), and
// again after the index is pruned to a subset (the filter rebuilt for the subset).
TEST(VoxelGrid, FindAfterFinalizeAndPruningAgreesWithBruteForce) {
  std::mt19937 rng(41);
  const uint32_t want = fg::kMaxVoxels * 3 / 4;
  std::set<Cell> cells;
  auto g = finalized_lattice(rng, want, cells);
  ASSERT_EQ(g->size(), want);
  g->prepare_lookups(nullptr);
  EXPECT_TRUE(g->lookup_filter_on());  // 3/4 of kMaxVoxels: the table is more than half full
  const auto check_all = [&](const std::vector<uint8_t>* keep) {
    // Every present cell, and all 26 neighbours of each (absent: the lattice is sparse).
    uint32_t wrong = 0, absent = 0;
    for (uint32_t i = 0; i < g->size(); ++i) {
      const bool kept = keep == nullptr || (*keep)[i] != 0;
      if (g->find(g->key(i)) != (kept ? i : VoxelGrid::kNone)) ++wrong;
      for (int d = 0; d < 27; ++d) {
        if (d == 13) continue;
        ++absent;
        if (g->find(neighbour_key(g->key(i), d)) != VoxelGrid::kNone) ++wrong;
      }
    }
    EXPECT_EQ(wrong, 0u) << absent << " absent lookups";
  };
  check_all(nullptr);
  std::vector<uint8_t> keep(g->size());
  for (auto& k : keep) k = static_cast<uint8_t>(rng() % 3 == 0);
  g->keep_in_index_only(keep.data());
  g->prepare_lookups(keep.data());
  // A third: a table at most half full, filtered only when too large for the caches.
  EXPECT_EQ(g->lookup_filter_on(), g->table_slots() > VoxelGrid::kSmallTableSlots) << g->table_slots();
  check_all(&keep);
  // Pruned to most voxels: the smallest table that holds them is more than half full
  // only when they need the whole table; prepare_lookups() then builds the filter of
  // the kept set.
  for (auto& k : keep) k = static_cast<uint8_t>(rng() % 16 != 0);
  g->keep_in_index_only(keep.data());
  g->prepare_lookups(keep.data());
  EXPECT_EQ(g->lookup_filter_on(),
            2u * (want - want / 16 - 64) > fg::kVoxelHashSlots || g->table_slots() > VoxelGrid::kSmallTableSlots);
  check_all(&keep);
}

// prepare_lookups() with the caller's wide memory: the filter lives there (lookups stay
// exact, and it settles more absent keys than the grid's own: false positives counted
// on every absent neighbour of a lattice); the next prepare_lookups() without it stops
// reading it (the memory is then scribbled over and every lookup must still be right).
TEST(VoxelGrid, WideLookupFilterIsExactSettlesMoreAndIsReturned) {
  std::mt19937 rng(43);
  std::set<Cell> cells;
  auto g = finalized_lattice(rng, fg::kMaxVoxels * 3 / 4, cells);
  // Lookups right, and the filter's false positives among the absent neighbours.
  const auto check = [&](const char* what) {
    uint32_t wrong = 0, absent = 0, passed = 0;
    const VoxelGrid::LookupFilter f = g->lookup_filter();
    for (uint32_t i = 0; i < g->size(); ++i) {
      if (g->find(g->key(i)) != i) ++wrong;
      for (int d = 0; d < 27; ++d) {
        if (d == 13) continue;
        const uint32_t k = neighbour_key(g->key(i), d);
        ++absent;
        if (g->find(k) != VoxelGrid::kNone) ++wrong;
        if (f.words != nullptr && f.may_hold(VoxelGrid::filter_hash(k))) ++passed;
      }
    }
    EXPECT_EQ(wrong, 0u) << what;
    return static_cast<double>(passed) / absent;
  };
  g->prepare_lookups(nullptr);
  ASSERT_TRUE(g->lookup_filter_on());
  const double own = check("own filter");
  const uint32_t bits = fg::floor_log2(4u * ((uint64_t{1} << fg::kVoxelCacheBits)));  // 4x the own filter
  std::vector<uint64_t> wide(size_t{1} << bits, ~uint64_t{0});
  g->prepare_lookups(nullptr, wide.data(), bits);
  ASSERT_TRUE(g->lookup_filter_on());
  EXPECT_EQ(g->lookup_filter().words, wide.data());
  const double in_wide = check("wide filter");
  EXPECT_LT(in_wide, 0.5 * own) << own;
  EXPECT_LT(in_wide, 0.03) << own;
  g->prepare_lookups(nullptr);                       // back to the grid's own memory
  std::fill(wide.begin(), wide.end(), uint64_t{0});  // a wide filter read now would miss every key
  EXPECT_NE(g->lookup_filter().words, wide.data());
  EXPECT_NEAR(check("own filter again"), own, 1e-12);
  // Too small or too large a wide memory is not used.
  g->prepare_lookups(nullptr, wide.data(), fg::kVoxelCacheBits);
  EXPECT_NE(g->lookup_filter().words, wide.data());
  g->prepare_lookups(nullptr, wide.data(), 40);
  EXPECT_NE(g->lookup_filter().words, wide.data());
  check("oversized wide memory refused");
}

// The clustering forms a neighbour's filter hash as the voxel's plus the offset's: the
// hash must be exactly linear over every offset within two cells, for keys anywhere in
// the packed range (negative offsets included), or the flood would miss neighbours.
TEST(VoxelGrid, FilterHashIsLinearOverNeighbourOffsets) {
  std::mt19937 rng(8);
  std::uniform_int_distribution<uint32_t> u(2, 2045), uz(2, 1021);
  uint32_t wrong = 0;
  for (int t = 0; t < 2000; ++t) {
    const uint32_t x = u(rng), y = u(rng), z = uz(rng);
    const uint32_t k = VoxelGrid::pack(x, y, z);
    for (int dz = -2; dz <= 2; ++dz)
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          const uint32_t nk = VoxelGrid::pack(x + dx, y + dy, z + dz);
          const int64_t d = dx + dy * (int64_t{1} << 11) + dz * (int64_t{1} << 22);
          if (VoxelGrid::filter_hash(k) + VoxelGrid::filter_hash_of_offset(d) != VoxelGrid::filter_hash(nk)) ++wrong;
        }
  }
  EXPECT_EQ(wrong, 0u);
}

TEST(VoxelGrid, IndexPrunedToKeptVoxels) {
  std::mt19937 rng(12);
  const Vec3 origin(-0.1f, -0.1f, -0.1f);
  const std::vector<Vec3> pts = uniform_box(rng, Vec3(0.f, 0.f, 0.f), Vec3(0.4f, 0.4f, 0.2f), 60000);
  auto g = make_grid(origin, 0.005f);
  insert_all(*g, pts);
  g->finalize();
  const uint32_t n = g->size();
  std::vector<uint8_t> keep(n);
  std::vector<Vec3> cen(n);
  for (uint32_t i = 0; i < n; ++i) {
    keep[i] = (rng() % 5 == 0) ? 1 : 0;
    cen[i] = g->centroid(i);
  }
  g->keep_in_index_only(keep.data());
  ASSERT_EQ(g->size(), n);
  for (uint32_t i = 0; i < n; ++i) {
    EXPECT_EQ(g->find(g->key(i)), keep[i] ? i : VoxelGrid::kNone) << "voxel " << i;
    EXPECT_EQ(std::memcmp(g->centroid(i).data(), cen[i].data(), sizeof(float) * 3), 0);
  }
  g->reset(origin, 0.005f);
  insert_all(*g, pts);
  ASSERT_EQ(g->size(), n);
  for (uint32_t i = 0; i < n; ++i) EXPECT_EQ(g->find(g->key(i)), i);
}

// A cloud crafted so that every cell hashes to the same slot: the probe walk is capped
// (the insert is refused as capacity_exceeded) instead of growing with the cloud, and
// every cell that went in is still found.
// Keys crafted to share one home slot: exactly max_probe() of them fit, the rest are
// refused, and each kept one is found. Two homes: one inside the table, and one 3 slots
// before its end, whose walk wraps round to slot 0 (find_or_add compares eight slots
// at a time where the window does not wrap, one by one where it does).
TEST(VoxelGrid, CellsCraftedToCollideAreCapped) {
  auto fmix = [](uint32_t k) { return VoxelGrid::mix(k); };
  const uint32_t slot_bits = static_cast<uint32_t>(std::log2(static_cast<double>(fg::kVoxelHashSlots)));
  // Home slots: one in the table, one whose walks wrap at once, and one whose walks
  // fill the last window of eight slots first (the vector walk then goes on at slot 0).
  for (const uint32_t home :
       {fmix(VoxelGrid::pack(10, 10, 10)) >> (32 - slot_bits), fg::kVoxelHashSlots - 3, fg::kVoxelHashSlots - 8}) {
    SCOPED_TRACE(testing::Message() << "home slot " << home);
    const uint32_t want = VoxelGrid::max_probe() + 100;
    std::vector<uint32_t> keys;
    for (uint32_t z = 3; z < 1000 && keys.size() < want; ++z)
      for (uint32_t y = 3; y < 2000 && keys.size() < want; ++y)
        for (uint32_t x = 3; x < 2000 && keys.size() < want; x += 1) {
          const uint32_t k = VoxelGrid::pack(x, y, z);
          if ((fmix(k) >> (32 - slot_bits)) == home) keys.push_back(k);
        }
    ASSERT_EQ(keys.size(), want);
    auto g = make_grid(Vec3::Zero(), 0.01f);
    uint32_t accepted = 0, refused = 0;
    for (uint32_t k : keys) {
      const float fx = static_cast<float>(VoxelGrid::key_x(k)) + 0.5f,
                  fy = static_cast<float>(VoxelGrid::key_y(k)) + 0.5f,
                  fz = static_cast<float>(VoxelGrid::key_z(k)) + 0.5f;
      if (g->insert_cell(fx, fy, fz)) {
        ++accepted;
      } else {
        ++refused;
      }
    }
    EXPECT_EQ(accepted, VoxelGrid::max_probe());
    EXPECT_EQ(refused, 100u);
    for (uint32_t i = 0; i < g->size(); ++i) EXPECT_EQ(g->find(g->key(i)), i);
    // Every kept key again: found in place, nothing added.
    for (uint32_t i = 0; i < g->size(); ++i) {
      const uint32_t k = g->key(i);
      EXPECT_TRUE(g->insert_cell(static_cast<float>(VoxelGrid::key_x(k)) + 0.25f,
                                 static_cast<float>(VoxelGrid::key_y(k)) + 0.25f,
                                 static_cast<float>(VoxelGrid::key_z(k)) + 0.25f));
    }
    EXPECT_EQ(g->size(), VoxelGrid::max_probe());
  }
}

TEST(VoxelGrid, CapacityExceededBeyondMaxVoxels) {
  const Vec3 origin(0.f, 0.f, 0.f);
  const float leaf = 0.01f;
  auto g = make_grid(origin, leaf);
  // Exactly kMaxVoxels distinct cells: nx * ny * nz with nx = ny = 64.
  const uint32_t nx = 64, ny = 64;
  const uint32_t nz = (fg::kMaxVoxels + nx * ny - 1) / (nx * ny);
  uint32_t inserted = 0;
  auto centre = [&](uint32_t ix, uint32_t iy, uint32_t iz) {
    return Vec3((static_cast<float>(ix) + 0.5f) * leaf, (static_cast<float>(iy) + 0.5f) * leaf,
                (static_cast<float>(iz) + 0.5f) * leaf);
  };
  bool stop = false;
  for (uint32_t iz = 0; iz < nz && !stop; ++iz)
    for (uint32_t iy = 0; iy < ny && !stop; ++iy)
      for (uint32_t ix = 0; ix < nx; ++ix) {
        if (inserted == fg::kMaxVoxels) {
          stop = true;
          break;
        }
        ASSERT_EQ(g->insert(centre(ix + 10, iy + 10, iz + 10)), Status::ok) << inserted;
        ++inserted;
      }
  ASSERT_EQ(g->size(), fg::kMaxVoxels);
  // One more distinct cell: refused, nothing changes.
  const Vec3 extra = centre(1000, 1000, 500);
  EXPECT_EQ(g->insert(extra), Status::capacity_exceeded);
  EXPECT_EQ(g->insert(extra), Status::capacity_exceeded);
  EXPECT_EQ(g->size(), fg::kMaxVoxels);
  EXPECT_EQ(g->find(VoxelGrid::pack(1000, 1000, 500)), VoxelGrid::kNone);
  // Points in existing cells are still accepted and counted.
  EXPECT_EQ(g->insert(centre(10, 10, 10)), Status::ok);
  EXPECT_EQ(g->voxel(0).count, 2u);
  const uint32_t last = g->find(g->voxel(fg::kMaxVoxels - 1).key);
  EXPECT_EQ(last, fg::kMaxVoxels - 1);
  EXPECT_EQ(g->insert(g->centroid(fg::kMaxVoxels - 1)), Status::ok);
  EXPECT_EQ(g->voxel(fg::kMaxVoxels - 1).count, 2u);
  // After a reset the grid takes new cells again.
  g->reset(origin, leaf);
  EXPECT_EQ(g->insert(extra), Status::ok);
  EXPECT_EQ(g->size(), 1u);
}

TEST(VoxelGrid, PointsOutsideTheKeyRangeAreInvalid) {
  const Vec3 origin(1.f, -2.f, 0.5f);
  const float leaf = 0.005f;
  auto g = make_grid(origin, leaf);
  auto at = [&](double cx, double cy, double cz) {  // position in cell units
    return Vec3(static_cast<float>(origin.x() + cx * leaf), static_cast<float>(origin.y() + cy * leaf),
                static_cast<float>(origin.z() + cz * leaf));
  };
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const Vec3 bad[] = {at(1.5, 100, 100),
                      at(100, 1.5, 100),
                      at(100, 100, 1.5),  // within 2 cells of 0
                      at(-10, 100, 100),
                      at(100, -1e6, 100),
                      at(100, 100, -3),  // below the origin
                      at(2045.5, 100, 100),
                      at(100, 2045.5, 100),
                      at(100, 100, 1021.5),  // within 2 cells of the top
                      at(4000, 100, 100),
                      at(100, 100, 1030),
                      at(1e9, 1e9, 1e9),
                      Vec3(nan, 0.f, 0.f),
                      Vec3(origin.x() + 0.5f, nan, origin.z() + 0.5f),
                      Vec3(origin.x() + 0.5f, origin.y() + 0.5f, nan),
                      Vec3(inf, origin.y() + 0.5f, origin.z() + 0.5f),
                      Vec3(-inf, -inf, -inf)};
  for (const Vec3& p : bad) EXPECT_EQ(g->insert(p), Status::invalid_argument) << p.transpose();
  EXPECT_EQ(g->size(), 0u);
  // The extreme cells that are allowed.
  const Vec3 good[] = {at(2.5, 2.5, 2.5), at(2044.5, 2044.5, 1020.5), at(2.5, 2044.5, 500.5)};
  for (const Vec3& p : good) EXPECT_EQ(g->insert(p), Status::ok) << p.transpose();
  EXPECT_EQ(g->size(), 3u);
  EXPECT_NE(g->find(VoxelGrid::pack(2, 2, 2)), VoxelGrid::kNone);
  EXPECT_NE(g->find(VoxelGrid::pack(2044, 2044, 1020)), VoxelGrid::kNone);
  for (uint32_t i = 0; i < g->size(); ++i) {
    EXPECT_NEAR((g->centroid(i) - good[i]).norm(), 0.0, 1e-5) << i;
  }
}

TEST(VoxelGrid, PackAndUnpackKeys) {
  for (uint32_t x : {0u, 1u, 2u, 1000u, 2047u})
    for (uint32_t y : {0u, 3u, 2047u})
      for (uint32_t z : {0u, 5u, 1023u}) {
        const uint32_t k = VoxelGrid::pack(x, y, z);
        EXPECT_EQ(VoxelGrid::key_x(k), x);
        EXPECT_EQ(VoxelGrid::key_y(k), y);
        EXPECT_EQ(VoxelGrid::key_z(k), z);
      }
}

// A million points in one cell: the centroid must stay exact (the header's promise:
// offsets from the cell corner keep it exact with hundreds of thousands per cell).
TEST(VoxelGrid, MillionRandomPointsInOneCell) {
  const Vec3 origin(-0.4f, -0.6f, -0.1f);
  const float leaf = 0.005f;
  auto g = make_grid(origin, leaf);
  const Vec3 corner = origin + Vec3::Constant(100.f * leaf);
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> u(0.1f, 0.9f);
  double s[3] = {0, 0, 0};
  const int n = 1000000;
  for (int i = 0; i < n; ++i) {
    const Vec3 p = corner + Vec3(u(rng), u(rng), u(rng)) * leaf;
    ASSERT_EQ(g->insert(p), Status::ok);
    for (int a = 0; a < 3; ++a) s[a] += p[a];
  }
  ASSERT_EQ(g->size(), 1u);
  EXPECT_EQ(g->voxel(0).count, static_cast<uint32_t>(n));
  const Vec3 c = g->centroid(0);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(c[a], s[a] / n, 1e-5) << "axis " << a;
}

// The adversarial case of the same promise: one point repeated (a static scene seen
// many times, or a saturated sensor). The true centroid is the point itself.
void repeated_point_case(int n) {
  const Vec3 origin(-0.4f, -0.6f, -0.1f);
  const float leaf = 0.005f;
  auto g = make_grid(origin, leaf);
  const Vec3 p = origin + Vec3(100.74f, 100.74f, 100.74f) * leaf;  // 3.7 mm into the cell
  for (int i = 0; i < n; ++i) ASSERT_EQ(g->insert(p), Status::ok);
  ASSERT_EQ(g->size(), 1u);
  EXPECT_EQ(g->voxel(0).count, static_cast<uint32_t>(n));
  const Vec3 c = g->centroid(0);
  // Float sums of in-cell offsets: exact to well under a micrometre for typical counts,
  // and to 0.1 mm (2% of a leaf, far below sensor noise) even for a million points.
  const double tol = n > 500000 ? 1e-4 : 1e-5;
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(c[a], p[a], tol) << "axis " << a << ", n = " << n;
}

TEST(VoxelGrid, MillionIdenticalPointsInOneCell) { repeated_point_case(1000000); }

TEST(VoxelGrid, ThreeHundredThousandIdenticalPointsInOneCell) { repeated_point_case(300000); }

TEST(VoxelGrid, TenThousandIdenticalPointsInOneCell) { repeated_point_case(10000); }

}  // namespace
