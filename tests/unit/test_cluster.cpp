// cluster_and_pick on voxel cells built here: well-separated blobs (nearest to the
// centre, largest), min_points, removed voxels, the target buffer's capacity, the
// target-fragment fall-back (retarget_to_cover), and the component labelling against a
// brute-force union-find over all pairs of cells (|difference| <= 1 on every axis for
// cells = 1; squared distance <= 4 for cells = 2) on random sparse cell sets, peeled one
// component at a time.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <numeric>
#include <random>
#include <set>
#include <tuple>
#include <vector>

#include "fg/core/cluster.hpp"
#include "fg/core/voxel_grid.hpp"

namespace {

using fg::ClusterParams;
using fg::ClusterResult;
using fg::Status;
using fg::Vec3;
using fg::VoxelGrid;

constexpr float kLeaf = 0.01f;

struct Cell {
  int x, y, z;
  bool operator<(const Cell& o) const { return std::tie(x, y, z) < std::tie(o.x, o.y, o.z); }
  bool operator==(const Cell& o) const { return x == o.x && y == o.y && z == o.z; }
};

// A grid holding one point at the centre of each cell, voxel i = cells[i].
struct Fixture {
  std::unique_ptr<VoxelGrid> grid = std::make_unique<VoxelGrid>();
  std::vector<Cell> cells;
  std::vector<uint8_t> state;
  std::vector<uint32_t> queue;
  std::vector<uint32_t> target;

  explicit Fixture(const std::vector<Cell>& cs) : cells(cs) {
    grid->reset(Vec3::Zero(), kLeaf);
    for (const Cell& c : cs) {
      const Vec3 p((static_cast<float>(c.x) + 0.5f) * kLeaf, (static_cast<float>(c.y) + 0.5f) * kLeaf,
                   (static_cast<float>(c.z) + 0.5f) * kLeaf);
      EXPECT_EQ(grid->insert(p), Status::ok);
    }
    EXPECT_EQ(grid->size(), cs.size());
    state.assign(cs.size(), fg::kVoxelFree);
    queue.assign(cs.size() + 1, 0);
    target.assign(cs.size() + 1, 0xDEADBEEFu);
  }
  // With `bitmap`, the walks test their neighbours in build_cell_bitmap's bitmap of the
  // free voxels (when it fits in `bitmap_words`), as plan() runs it.
  ClusterResult run(const ClusterParams& p, bool bitmap = false, uint32_t bitmap_words = 1u << 12) {
    fg::CellBitmap bits;
    std::vector<uint64_t> words(bitmap_words);
    used_bitmap = bitmap && fg::build_cell_bitmap(*grid, state.data(), fg::kVoxelFree, queue.data(), words.data(),
                                                  bitmap_words, bits);
    ClusterResult r;
    fg::cluster_and_pick(*grid, state.data(), queue.data(), p, target.data(), static_cast<uint32_t>(target.size()), r,
                         used_bitmap ? &bits : nullptr);
    return r;
  }
  bool used_bitmap = false;
  std::set<uint32_t> targets(const ClusterResult& r) const {
    return std::set<uint32_t>(target.begin(), target.begin() + r.target_size);
  }
  std::set<uint32_t> in_state(uint8_t s) const {
    std::set<uint32_t> out;
    for (uint32_t i = 0; i < state.size(); ++i)
      if (state[i] == s) out.insert(i);
    return out;
  }
};

// A solid blob of cells: a box of nx*ny*nz cells starting at (x0, y0, z0).
std::vector<Cell> box_cells(int x0, int y0, int z0, int nx, int ny, int nz) {
  std::vector<Cell> out;
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) out.push_back(Cell{x0 + x, y0 + y, z0 + z});
  return out;
}

std::set<uint32_t> range_set(uint32_t from, uint32_t to) {
  std::set<uint32_t> s;
  for (uint32_t i = from; i < to; ++i) s.insert(i);
  return s;
}

// Cell coordinates of a world x / y (for centres).
int cell_at(float m) { return static_cast<int>(std::floor(m / kLeaf)); }

TEST(Cluster, TwoBlobsNearestAndLargest) {
  // Blob A: 4x4x4 = 64 cells near the centre (0.5, 0); blob B: 6x6x6 = 216 cells far away.
  const int cx = cell_at(0.5f), cy = cell_at(0.f) + 200;  // y cells offset so indices stay >= 2
  std::vector<Cell> cells = box_cells(cx - 2, cy - 2, 10, 4, 4, 4);
  const std::vector<Cell> b = box_cells(cx + 30, cy + 20, 10, 6, 6, 6);
  cells.insert(cells.end(), b.begin(), b.end());
  ClusterParams p;
  p.min_points = 10;
  p.centre_x = 0.5f;
  p.centre_y = static_cast<float>(cy) * kLeaf;
  {
    Fixture f(cells);
    const ClusterResult r = f.run(p);
    EXPECT_EQ(r.clusters, 2u);
    EXPECT_EQ(r.target_size, 64u);
    EXPECT_EQ(r.other_points, 216u);
    EXPECT_EQ(f.targets(r), range_set(0, 64));
    EXPECT_EQ(f.in_state(fg::kVoxelTarget), range_set(0, 64));
    EXPECT_EQ(f.in_state(fg::kVoxelVisited), range_set(64, 280));
  }
  {
    Fixture f(cells);
    p.rule = fg::TargetRule::largest;
    const ClusterResult r = f.run(p);
    EXPECT_EQ(r.clusters, 2u);
    EXPECT_EQ(r.target_size, 216u);
    EXPECT_EQ(r.other_points, 64u);
    EXPECT_EQ(f.targets(r), range_set(64, 280));
    EXPECT_EQ(f.in_state(fg::kVoxelTarget), range_set(64, 280));
  }
  {
    // Moving the centre next to blob B makes B the nearest.
    Fixture f(cells);
    p.rule = fg::TargetRule::nearest_to_centre;
    p.centre_x = static_cast<float>(cx + 33) * kLeaf;
    p.centre_y = static_cast<float>(cy + 23) * kLeaf;
    const ClusterResult r = f.run(p);
    EXPECT_EQ(f.targets(r), range_set(64, 280));
  }
}

TEST(Cluster, ThreeBlobs) {
  const int cx = cell_at(0.5f), cy = 300;
  std::vector<Cell> cells;
  const std::vector<Cell> a = box_cells(cx + 10, cy - 2, 5, 3, 3, 8);   // 72, 10 cells from centre
  const std::vector<Cell> b = box_cells(cx - 2, cy + 4, 5, 5, 5, 5);    // 125, ~5 cells from centre
  const std::vector<Cell> c = box_cells(cx - 40, cy - 40, 5, 7, 7, 7);  // 343, far
  cells.insert(cells.end(), a.begin(), a.end());
  cells.insert(cells.end(), b.begin(), b.end());
  cells.insert(cells.end(), c.begin(), c.end());
  ClusterParams p;
  p.min_points = 30;
  p.centre_x = (static_cast<float>(cx) + 0.5f) * kLeaf;
  p.centre_y = (static_cast<float>(cy) + 0.5f) * kLeaf;
  {
    Fixture f(cells);
    const ClusterResult r = f.run(p);
    EXPECT_EQ(r.clusters, 3u);
    EXPECT_EQ(f.targets(r), range_set(72, 197));
    EXPECT_EQ(r.other_points, 72u + 343u);
  }
  {
    Fixture f(cells);
    p.rule = fg::TargetRule::largest;
    const ClusterResult r = f.run(p);
    EXPECT_EQ(f.targets(r), range_set(197, 540));
  }
  {
    // min_points above the middle blob's size: only the largest counts.
    Fixture f(cells);
    p.rule = fg::TargetRule::nearest_to_centre;
    p.min_points = 200;
    const ClusterResult r = f.run(p);
    EXPECT_EQ(r.clusters, 1u);
    EXPECT_EQ(f.targets(r), range_set(197, 540));
    EXPECT_EQ(r.other_points, 72u + 125u);
  }
}

TEST(Cluster, MinPointsFiltersNoiseSpecks) {
  const int cx = cell_at(0.5f), cy = 300;
  std::vector<Cell> cells;
  // Specks right at the centre: singles and pairs.
  cells.push_back(Cell{cx, cy, 10});
  cells.push_back(Cell{cx + 3, cy, 10});
  cells.push_back(Cell{cx + 4, cy + 1, 11});  // touches the previous one diagonally
  cells.push_back(Cell{cx, cy + 3, 12});
  const std::vector<Cell> obj = box_cells(cx + 15, cy + 15, 10, 4, 4, 4);  // 64
  cells.insert(cells.end(), obj.begin(), obj.end());
  ClusterParams p;
  p.min_points = 30;
  p.centre_x = (static_cast<float>(cx) + 0.5f) * kLeaf;
  p.centre_y = (static_cast<float>(cy) + 0.5f) * kLeaf;
  Fixture f(cells);
  const ClusterResult r = f.run(p);
  EXPECT_EQ(r.clusters, 1u);
  EXPECT_EQ(r.target_size, 64u);
  EXPECT_EQ(f.targets(r), range_set(4, 68));
  EXPECT_EQ(r.other_points, 4u);
  EXPECT_EQ(f.in_state(fg::kVoxelVisited), range_set(0, 4));

  // Only specks: no target.
  Fixture g(std::vector<Cell>(cells.begin(), cells.begin() + 4));
  const ClusterResult r2 = g.run(p);
  EXPECT_EQ(r2.clusters, 0u);
  EXPECT_EQ(r2.target_size, 0u);
  EXPECT_EQ(r2.other_points, 4u);

  // min_points = 2 turns the pair into a cluster; min_points = 1 every speck.
  p.min_points = 2;
  Fixture h(cells);
  EXPECT_EQ(h.run(p).clusters, 2u);
  p.min_points = 1;
  Fixture k(cells);
  const ClusterResult r3 = k.run(p);
  EXPECT_EQ(r3.clusters, 4u);
  EXPECT_EQ(r3.target_size, 1u);  // the single cell at the centre
  EXPECT_EQ(k.targets(r3), range_set(0, 1));
}

TEST(Cluster, RemovedVoxelsAreIgnoredAndBlockConnections) {
  const int cx = cell_at(0.5f), cy = 300;
  // Two blobs joined by a one-cell bridge along x.
  std::vector<Cell> cells = box_cells(cx - 5, cy, 10, 3, 3, 3);    // 27, indices 0..26
  const std::vector<Cell> b = box_cells(cx + 3, cy, 10, 3, 3, 3);  // 27, indices 27..53
  cells.insert(cells.end(), b.begin(), b.end());
  for (int x = cx - 2; x <= cx + 2; ++x) cells.push_back(Cell{x, cy + 1, 11});  // 54..58
  ClusterParams p;
  p.min_points = 5;
  p.centre_x = (static_cast<float>(cx) + 0.5f) * kLeaf;
  p.centre_y = (static_cast<float>(cy) + 1.5f) * kLeaf;
  {
    Fixture f(cells);
    const ClusterResult r = f.run(p);
    EXPECT_EQ(r.clusters, 1u);
    EXPECT_EQ(r.target_size, 59u);
  }
  {
    // The bridge's middle cell removed (e.g. below the table height): two clusters.
    Fixture f(cells);
    f.state[56] = fg::kVoxelRemoved;
    p.rule = fg::TargetRule::largest;
    const ClusterResult r = f.run(p);
    EXPECT_EQ(r.clusters, 2u);
    EXPECT_EQ(r.target_size, 29u);  // ties at 29: the component found first (index 0)
    std::set<uint32_t> expect = range_set(0, 27);
    expect.insert(54);
    expect.insert(55);
    EXPECT_EQ(f.targets(r), expect);
    EXPECT_EQ(f.state[56], fg::kVoxelRemoved);
    EXPECT_EQ(r.other_points, 29u);
  }
  {
    // Every voxel removed: nothing to pick.
    Fixture f(cells);
    std::fill(f.state.begin(), f.state.end(), static_cast<uint8_t>(fg::kVoxelRemoved));
    const ClusterResult r = f.run(p);
    EXPECT_EQ(r.clusters, 0u);
    EXPECT_EQ(r.target_size, 0u);
    EXPECT_EQ(r.other_points, 0u);
    EXPECT_EQ(f.in_state(fg::kVoxelRemoved).size(), cells.size());
  }
}

TEST(Cluster, EmptyGrid) {
  Fixture f(std::vector<Cell>{});
  ClusterParams p;
  ClusterResult r;
  r.clusters = 7;  // filled anew
  fg::cluster_and_pick(*f.grid, nullptr, nullptr, p, nullptr, 0, r);
  EXPECT_EQ(r.clusters, 0u);
  EXPECT_EQ(r.target_size, 0u);
  EXPECT_EQ(r.other_points, 0u);
}

TEST(Cluster, TargetCapacitySmallerThanTheTarget) {
  const std::vector<Cell> cells = box_cells(100, 100, 10, 5, 5, 4);  // 100 cells
  Fixture f(cells);
  ClusterParams p;
  p.min_points = 3;
  p.centre_x = 1.0f;
  p.centre_y = 1.0f;
  std::vector<uint32_t> small(12, 0xDEADBEEFu);
  ClusterResult r;
  fg::cluster_and_pick(*f.grid, f.state.data(), f.queue.data(), p, small.data(), 10, r);
  EXPECT_EQ(r.target_size, 100u);  // the caller compares it with its capacity
  for (int i = 0; i < 10; ++i) EXPECT_LT(small[i], 100u);
  EXPECT_EQ(small[10], 0xDEADBEEFu);
  EXPECT_EQ(small[11], 0xDEADBEEFu);
  // The written indices are distinct target voxels.
  EXPECT_EQ(std::set<uint32_t>(small.begin(), small.begin() + 10).size(), 10u);
}

// ---------------------------------------------------------------------------------
// Brute-force labelling.

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  }
  void unite(int a, int b) { parent[find(a)] = find(b); }
};

bool neighbours(const Cell& a, const Cell& b, uint32_t cells) {
  const int dx = a.x - b.x, dy = a.y - b.y, dz = a.z - b.z;
  if (cells <= 1) return std::abs(dx) <= 1 && std::abs(dy) <= 1 && std::abs(dz) <= 1;
  return dx * dx + dy * dy + dz * dz <= 4;
}

// Components of the voxels with alive[i], each as a sorted list of indices; the list
// of components is ordered by smallest member.
std::vector<std::vector<uint32_t>> components(const std::vector<Cell>& cells, const std::vector<bool>& alive,
                                              uint32_t radius) {
  UnionFind uf(cells.size());
  for (size_t i = 0; i < cells.size(); ++i) {
    if (!alive[i]) continue;
    for (size_t j = i + 1; j < cells.size(); ++j)
      if (alive[j] && neighbours(cells[i], cells[j], radius)) uf.unite(static_cast<int>(i), static_cast<int>(j));
  }
  std::map<int, std::vector<uint32_t>> by_root;
  for (size_t i = 0; i < cells.size(); ++i)
    if (alive[i]) by_root[uf.find(static_cast<int>(i))].push_back(static_cast<uint32_t>(i));
  std::vector<std::vector<uint32_t>> out;
  for (auto& kv : by_root) out.push_back(kv.second);
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.front() < b.front(); });
  return out;
}

std::vector<Cell> random_cells(std::mt19937& rng, int extent, double density) {
  std::vector<Cell> cells;
  std::bernoulli_distribution keep(density);
  for (int z = 0; z < extent; ++z)
    for (int y = 0; y < extent; ++y)
      for (int x = 0; x < extent; ++x)
        if (keep(rng)) cells.push_back(Cell{x + 50, y + 60, z + 5});
  std::shuffle(cells.begin(), cells.end(), rng);  // voxel order independent of position
  return cells;
}

// Peels the components largest-first (TargetRule::largest, min_points 1): each target
// must be the oracle's largest remaining component (ties: the one with the smallest
// voxel index, i.e. found first), and the cluster count must match.
void peel_and_compare(const std::vector<Cell>& cells, const std::vector<bool>& pre_removed, uint32_t radius,
                      bool bitmap = false) {
  Fixture f(cells);
  std::vector<bool> alive(cells.size());
  for (size_t i = 0; i < cells.size(); ++i) alive[i] = !pre_removed[i];
  std::vector<std::vector<uint32_t>> comps = components(cells, alive, radius);
  ClusterParams p;
  p.cells = radius;
  p.min_points = 1;
  p.rule = fg::TargetRule::largest;
  size_t rounds = 0;
  uint32_t remaining = static_cast<uint32_t>(std::count(alive.begin(), alive.end(), true));
  while (!comps.empty()) {
    for (size_t i = 0; i < cells.size(); ++i) f.state[i] = alive[i] ? fg::kVoxelFree : fg::kVoxelRemoved;
    const ClusterResult r = f.run(p, bitmap);
    ASSERT_EQ(f.used_bitmap, bitmap);
    ASSERT_EQ(r.clusters, comps.size()) << "round " << rounds;
    size_t best = 0;
    for (size_t c = 1; c < comps.size(); ++c)
      if (comps[c].size() > comps[best].size()) best = c;
    ASSERT_EQ(r.target_size, comps[best].size()) << "round " << rounds;
    std::vector<uint32_t> got(f.target.begin(), f.target.begin() + r.target_size);
    std::sort(got.begin(), got.end());
    ASSERT_EQ(got, comps[best]) << "round " << rounds;
    EXPECT_EQ(r.other_points, remaining - r.target_size);
    // States: target = the component, visited = the other alive voxels.
    for (size_t i = 0; i < cells.size(); ++i) {
      const bool in_t = std::binary_search(comps[best].begin(), comps[best].end(), static_cast<uint32_t>(i));
      const uint8_t want = !alive[i] ? fg::kVoxelRemoved : in_t ? fg::kVoxelTarget : fg::kVoxelVisited;
      ASSERT_EQ(f.state[i], want) << "voxel " << i << " round " << rounds;
    }
    for (uint32_t i : comps[best]) alive[i] = false;
    remaining -= r.target_size;
    comps.erase(comps.begin() + static_cast<long>(best));
    ++rounds;
    if (rounds > 40) break;  // enough rounds: the rest are tiny specks
  }
}

TEST(Cluster, LabellingMatchesUnionFind26Connected) {
  std::mt19937 rng(17);
  for (double density : {0.02, 0.05, 0.08, 0.12}) {
    SCOPED_TRACE("density " + std::to_string(density));
    const std::vector<Cell> cells = random_cells(rng, 16, density);
    peel_and_compare(cells, std::vector<bool>(cells.size(), false), 1);
  }
}

TEST(Cluster, LabellingMatchesUnionFindRadiusTwo) {
  std::mt19937 rng(18);
  for (double density : {0.01, 0.03, 0.05}) {
    SCOPED_TRACE("density " + std::to_string(density));
    const std::vector<Cell> cells = random_cells(rng, 16, density);
    peel_and_compare(cells, std::vector<bool>(cells.size(), false), 2);
  }
}

TEST(Cluster, LabellingWithRemovedVoxelsMatchesUnionFind) {
  std::mt19937 rng(19);
  std::bernoulli_distribution rm(0.3);
  for (double density : {0.06, 0.12}) {
    const std::vector<Cell> cells = random_cells(rng, 16, density);
    std::vector<bool> removed(cells.size());
    for (size_t i = 0; i < cells.size(); ++i) removed[i] = rm(rng);
    peel_and_compare(cells, removed, 1);
  }
}

// The same oracles with the walks on the free voxels' bitmap (plan()'s path).
TEST(Cluster, BitmapLabellingMatchesUnionFind) {
  std::mt19937 rng(21);
  std::bernoulli_distribution rm(0.3);
  for (uint32_t radius : {1u, 2u})
    for (double density : {0.03, 0.08}) {
      SCOPED_TRACE("radius " + std::to_string(radius) + " density " + std::to_string(density));
      const std::vector<Cell> cells = random_cells(rng, 16, density);
      peel_and_compare(cells, std::vector<bool>(cells.size(), false), radius, true);
      std::vector<bool> removed(cells.size());
      for (size_t i = 0; i < cells.size(); ++i) removed[i] = rm(rng);
      peel_and_compare(cells, removed, radius, true);
    }
}

// The bitmap walk enters the same voxels in the same order as the hash walk: the same
// target list element by element, the same states and the same list of the largest
// clusters (so the same sums, and the fall-back reads the same candidates). Cells
// span the key range's corners of a 3-cell margin and a dense block (every neighbour
// offset in use), with voxels removed and voxels left out of the index.
TEST(Cluster, BitmapWalkMatchesTheHashWalk) {
  std::mt19937 rng(22);
  for (int trial = 0; trial < 8; ++trial) {
    std::vector<Cell> cells = random_cells(rng, 20, trial % 2 == 0 ? 0.04 : 0.15);
    for (const Cell& c : box_cells(3, 3, 3, 4, 4, 4)) cells.push_back(c);
    std::shuffle(cells.begin(), cells.end(), rng);
    Fixture a(cells), b(cells);
    std::bernoulli_distribution rm(0.2), unindexed(0.05);
    std::vector<uint8_t> keep(cells.size(), 1);
    for (size_t i = 0; i < cells.size(); ++i) {
      a.state[i] = b.state[i] = rm(rng) ? fg::kVoxelRemoved : fg::kVoxelFree;
      keep[i] = unindexed(rng) ? 0 : 1;
    }
    a.grid->finalize();
    b.grid->finalize();
    a.grid->keep_in_index_only(keep.data());
    b.grid->keep_in_index_only(keep.data());
    ClusterParams p;
    p.cells = 1u + static_cast<uint32_t>(trial % 2);
    p.min_points = 3;
    p.centre_x = 0.3f;
    p.centre_y = 0.4f;
    const ClusterResult ra = a.run(p, false), rb = b.run(p, true);
    ASSERT_TRUE(b.used_bitmap);
    EXPECT_EQ(ra.clusters, rb.clusters);
    ASSERT_EQ(ra.target_size, rb.target_size);
    EXPECT_EQ(ra.other_points, rb.other_points);
    EXPECT_TRUE(std::equal(a.target.begin(), a.target.begin() + ra.target_size, b.target.begin()));
    EXPECT_EQ(a.state, b.state);
    ASSERT_EQ(ra.n_largest, rb.n_largest);
    for (uint32_t k = 0; k < ra.n_largest; ++k) {
      EXPECT_EQ(ra.largest[k].seed, rb.largest[k].seed);
      EXPECT_EQ(ra.largest[k].size, rb.largest[k].size);
    }
  }
}

// A bitmap that does not fit (cells far apart) or has no voxel to hold is refused, and
// the clustering then walks through the hash.
TEST(Cluster, BitmapRefusedWhenTheCellsDoNotFit) {
  std::vector<Cell> cells = box_cells(10, 10, 10, 3, 3, 3);
  for (const Cell& c : box_cells(1500, 1500, 800, 3, 3, 3)) cells.push_back(c);
  Fixture f(cells);
  ClusterParams p;
  p.min_points = 1;
  p.rule = fg::TargetRule::largest;
  const ClusterResult r = f.run(p, true, 1u << 12);
  EXPECT_FALSE(f.used_bitmap);
  EXPECT_EQ(r.clusters, 2u);
  EXPECT_EQ(r.target_size, 27u);
  fg::CellBitmap none;
  std::vector<uint64_t> words(1u << 12);
  std::vector<uint8_t> removed(cells.size(), fg::kVoxelRemoved);
  EXPECT_FALSE(fg::build_cell_bitmap(*f.grid, removed.data(), fg::kVoxelFree, f.queue.data(), words.data(),
                                     static_cast<uint32_t>(words.size()), none));
}

TEST(Cluster, CellsAboveTwoAreClampedToTwo) {
  std::mt19937 rng(20);
  const std::vector<Cell> cells = random_cells(rng, 14, 0.03);
  ClusterParams p;
  p.min_points = 1;
  p.rule = fg::TargetRule::largest;
  p.cells = 2;
  Fixture a(cells);
  const ClusterResult ra = a.run(p);
  p.cells = 7;
  Fixture b(cells);
  const ClusterResult rb = b.run(p);
  EXPECT_EQ(ra.clusters, rb.clusters);
  EXPECT_EQ(ra.target_size, rb.target_size);
  EXPECT_EQ(a.state, b.state);
}

TEST(Cluster, NearestRuleMatchesBruteForceCentroids) {
  std::mt19937 rng(23);
  for (int trial = 0; trial < 6; ++trial) {
    const std::vector<Cell> cells = random_cells(rng, 18, 0.06);
    const std::vector<std::vector<uint32_t>> comps = components(cells, std::vector<bool>(cells.size(), true), 1);
    ClusterParams p;
    p.min_points = 3;
    p.centre_x = (50.f + 9.f * static_cast<float>(trial % 3)) * kLeaf;
    p.centre_y = (60.f + 4.f * static_cast<float>(trial)) * kLeaf;
    // Oracle: the eligible component whose mean cell centre is nearest in x-y.
    std::vector<std::pair<double, size_t>> d;
    for (size_t c = 0; c < comps.size(); ++c) {
      if (comps[c].size() < p.min_points) continue;
      double sx = 0, sy = 0;
      for (uint32_t i : comps[c]) {
        sx += (cells[i].x + 0.5) * kLeaf;
        sy += (cells[i].y + 0.5) * kLeaf;
      }
      const double mx = sx / comps[c].size() - p.centre_x, my = sy / comps[c].size() - p.centre_y;
      d.push_back({mx * mx + my * my, c});
    }
    std::sort(d.begin(), d.end());
    ASSERT_GE(d.size(), 2u);
    if (d[1].first - d[0].first < 1e-6) continue;  // an exact tie: order-dependent, skip
    Fixture f(cells);
    const ClusterResult r = f.run(p);
    EXPECT_EQ(r.clusters, d.size());
    std::vector<uint32_t> got(f.target.begin(), f.target.begin() + r.target_size);
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, comps[d[0].second]) << "trial " << trial;
  }
}

// The target-fragment fall-back: a 3x3x1 fragment F (nearest the centre) over a 4x4x4
// blob A and a 5x5x2 blob C, both of whose x-y footprints hold F's centroid, and a
// 6x6x6 blob B, larger but elsewhere.
struct FallbackScene {
  int cx = cell_at(0.5f), cy = cell_at(0.f) + 200;
  std::vector<Cell> cells;
  uint32_t a0 = 0, c0 = 0, b0 = 0;  // first voxel index of A, C, B
  ClusterParams p;
  explicit FallbackScene(bool with_covers) {
    cells = box_cells(cx - 1, cy - 1, 30, 3, 3, 1);  // F: voxels 0..8
    if (with_covers) {
      a0 = static_cast<uint32_t>(cells.size());
      const std::vector<Cell> a = box_cells(cx - 2, cy - 2, 10, 4, 4, 4);
      cells.insert(cells.end(), a.begin(), a.end());
      c0 = static_cast<uint32_t>(cells.size());
      const std::vector<Cell> c = box_cells(cx - 2, cy - 3, 20, 5, 5, 2);
      cells.insert(cells.end(), c.begin(), c.end());
    }
    b0 = static_cast<uint32_t>(cells.size());
    const std::vector<Cell> b = box_cells(cx + 30, cy + 20, 10, 6, 6, 6);
    cells.insert(cells.end(), b.begin(), b.end());
    p.min_points = 5;
    p.centre_x = (static_cast<float>(cx) + 0.5f) * kLeaf;  // F's centroid
    p.centre_y = (static_cast<float>(cy) + 0.5f) * kLeaf;
  }
};

TEST(Cluster, RetargetToTheLargestClusterUnderTheFragment) {
  const FallbackScene s(true);
  for (uint32_t capacity : {1000u, 60u}) {
    SCOPED_TRACE(capacity);
    Fixture f(s.cells);
    const ClusterResult r = f.run(s.p);
    ASSERT_EQ(r.target_size, 9u);
    ASSERT_EQ(f.targets(r), range_set(0, 9));
    // A (64) is the largest cover; with room for 60 voxels only, C (50).
    const uint32_t got = fg::retarget_to_cover(*f.grid, f.state.data(), f.queue.data(), s.p, f.target.data(), 9,
                                               s.p.centre_x, s.p.centre_y, f.target.data(), capacity);
    const std::set<uint32_t> want = capacity >= 64 ? range_set(s.a0, s.a0 + 64) : range_set(s.c0, s.c0 + 50);
    ASSERT_EQ(got, want.size());
    EXPECT_EQ(std::set<uint32_t>(f.target.begin(), f.target.begin() + got), want);
    EXPECT_EQ(f.in_state(fg::kVoxelTarget), want);
    EXPECT_EQ(f.in_state(fg::kVoxelFree), std::set<uint32_t>{});
    EXPECT_EQ(f.in_state(fg::kVoxelVisited).size(), s.cells.size() - want.size());
    EXPECT_EQ(f.in_state(fg::kVoxelVisited).count(0), 1u);  // F is one of the others now
  }
}

TEST(Cluster, RetargetFindsNoCoverAndChangesNothing) {
  const FallbackScene s(false);  // F and B only: B is larger, its footprint elsewhere
  Fixture f(s.cells);
  const ClusterResult r = f.run(s.p);
  ASSERT_EQ(r.target_size, 9u);
  const std::vector<uint8_t> state = f.state;
  const std::vector<uint32_t> target = f.target;
  EXPECT_EQ(fg::retarget_to_cover(*f.grid, f.state.data(), f.queue.data(), s.p, f.target.data(), 9, s.p.centre_x,
                                  s.p.centre_y, f.target.data(), 1000),
            0u);
  EXPECT_EQ(f.state, state);
  EXPECT_EQ(f.target, target);
}

// retarget_to_cover from cluster_and_pick's list of the largest clusters against the
// walk over every voxel (no list): the same new target, in the same breadth-first
// order, and the same states, on random scenes of blobs around and under a small
// target; with more than kLargestKept clusters larger than the target the list is
// incomplete and the walk runs.
TEST(Cluster, RetargetFromTheLabellingMatchesTheWalk) {
  std::mt19937 rng(2024);
  const int cx = cell_at(0.5f), cy = cell_at(0.f) + 200;
  uint32_t from_list = 0, walked = 0, found = 0;
  for (int trial = 0; trial < 200; ++trial) {
    std::set<Cell> unique;
    std::vector<Cell> cells;
    const auto add = [&](const std::vector<Cell>& b) {
      for (const Cell& c : b)
        if (unique.insert(c).second) cells.push_back(c);
    };
    add(box_cells(cx - 1, cy - 1, 40, 2, 2, 1));  // the fragment nearest the centre
    const int blobs = 1 + static_cast<int>(rng() % 14);
    int nx = 0, ny = 0, nz = 0, x0 = 0, y0 = 0;
    for (int b = 0; b < blobs; ++b) {
      // Now and then a copy of the previous blob above it: clusters of equal size over
      // the same footprint, where the one found first must win.
      if (b == 0 || rng() % 3 != 0) {
        nx = 2 + static_cast<int>(rng() % 4);
        ny = 2 + static_cast<int>(rng() % 4);
        nz = 1 + static_cast<int>(rng() % 4);
        x0 = cx - 6 + static_cast<int>(rng() % 12) - nx / 2;
        y0 = cy - 6 + static_cast<int>(rng() % 12) - ny / 2;
      }
      add(box_cells(x0, y0, 2 + 6 * b, nx, ny, nz));
    }
    // Two copies of the scene: one retargets from the labelling, one walks.
    ClusterParams p;
    p.min_points = 3;
    p.centre_x = (static_cast<float>(cx) + 0.f) * kLeaf;
    p.centre_y = (static_cast<float>(cy) + 0.f) * kLeaf;
    Fixture a(cells), b(cells);
    const ClusterResult ra = a.run(p), rb = b.run(p);
    ASSERT_EQ(ra.target_size, rb.target_size);
    if (ra.target_size == 0) continue;
    ASSERT_EQ(a.state, b.state);
    double sx = 0, sy = 0;
    for (uint32_t k = 0; k < ra.target_size; ++k) {
      const Vec3 c = a.grid->centroid(a.target[k]);
      sx += c.x();
      sy += c.y();
    }
    const float tx = static_cast<float>(sx / ra.target_size), ty = static_cast<float>(sy / ra.target_size);
    const uint32_t cap = static_cast<uint32_t>(a.target.size());
    const uint32_t ga = fg::retarget_to_cover(*a.grid, a.state.data(), a.queue.data(), p, a.target.data(),
                                              ra.target_size, tx, ty, a.target.data(), cap, &ra);
    const uint32_t gb = fg::retarget_to_cover(*b.grid, b.state.data(), b.queue.data(), p, b.target.data(),
                                              rb.target_size, tx, ty, b.target.data(), cap);
    ASSERT_EQ(ga, gb) << "trial " << trial;
    EXPECT_EQ(a.state, b.state) << "trial " << trial;
    EXPECT_TRUE(std::equal(a.target.begin(), a.target.begin() + ga, b.target.begin())) << "trial " << trial;
    found += ga > 0 ? 1u : 0u;
    (ra.largest_dropped <= ra.target_size ? from_list : walked) += 1;
  }
  // Both paths ran, and retargets happened.
  EXPECT_GT(from_list, 20u);
  EXPECT_GT(walked, 5u);
  EXPECT_GT(found, 20u);
}

}  // namespace

// The flood's neighbour test in vector lanes (AVX2 where the CPU has it) gives, bit for
// bit, the verdicts of VoxelGrid::LookupFilter::may_hold, one hash at a time: random
// filters of every density, word counts and hashes (the 64-bit products' high halves
// and the shifts' top counts included), every neighbour count 1-32.
TEST(ClusterFilterMask, VectorLanesGiveMayHoldsVerdicts) {
  std::mt19937_64 rng(2026);
  if (!fg::detail::filter_mask_vector_available())
    GTEST_LOG_(INFO) << "no AVX2 here: the vector form is the scalar one";
  uint32_t hits = 0, tests = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const uint32_t word_bits = 1u + static_cast<uint32_t>(rng() % 20u);
    std::vector<uint64_t> words(size_t{1} << word_bits);
    const int density = static_cast<int>(rng() % 4);  // 0: sparse .. 3: nearly full
    for (uint64_t& w : words) {
      w = rng();
      for (int d = 0; d < 3 - density; ++d) w &= rng();
      if (density == 3) w |= rng();
    }
    const VoxelGrid::LookupFilter f{words.data(), 64u - word_bits};
    alignas(32) uint64_t oh[32];
    for (uint64_t& h : oh) h = rng();
    const uint64_t kh = rng();
    for (uint32_t n = 1; n <= 32; ++n) {
      uint32_t expect = 0;
      for (uint32_t o = 0; o < n; ++o)
        if (f.may_hold(kh + oh[o])) expect |= 1u << o;
      ASSERT_EQ(fg::detail::filter_mask_scalar(f, kh, oh, n), expect) << "trial " << trial << " n " << n;
      ASSERT_EQ(fg::detail::filter_mask_vector(f, kh, oh, n), expect) << "trial " << trial << " n " << n;
      hits += static_cast<uint32_t>(__builtin_popcount(expect));
      tests += n;
    }
  }
  // Both verdicts occur often enough for a wrong lane to show.
  EXPECT_GT(hits, tests / 20u);
  EXPECT_LT(hits, tests - tests / 20u);
}

// The object list (ClusterResult::objects), the target chosen by a point or a box, and
// mark_cluster, against the brute-force components of random sparse cell sets: every
// component of at least min_points, its centroid (mean cell centre), its cell box, and
// the order by x-y distance of the centroid to the workspace centre (found order on
// ties, i.e. by smallest voxel index).
namespace {
struct OracleObject {
  std::vector<uint32_t> voxels;  // sorted
  Vec3 centroid, box_min, box_max;
  double d2 = 0;  // x-y, to the centre
};
Vec3 cell_centre(const Cell& c) {
  return Vec3((static_cast<float>(c.x) + 0.5f) * kLeaf, (static_cast<float>(c.y) + 0.5f) * kLeaf,
              (static_cast<float>(c.z) + 0.5f) * kLeaf);
}
std::vector<OracleObject> oracle_objects(const std::vector<Cell>& cells, const ClusterParams& p) {
  std::vector<OracleObject> out;
  for (const auto& comp : components(cells, std::vector<bool>(cells.size(), true), p.cells)) {
    if (comp.size() < p.min_points) continue;
    OracleObject o;
    o.voxels = comp;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    Cell lo = cells[comp[0]], hi = cells[comp[0]];
    for (uint32_t i : comp) {
      sum += cell_centre(cells[i]).cast<double>();
      lo = Cell{std::min(lo.x, cells[i].x), std::min(lo.y, cells[i].y), std::min(lo.z, cells[i].z)};
      hi = Cell{std::max(hi.x, cells[i].x), std::max(hi.y, cells[i].y), std::max(hi.z, cells[i].z)};
    }
    o.centroid = (sum / static_cast<double>(comp.size())).cast<float>();
    o.box_min = Vec3(static_cast<float>(lo.x), static_cast<float>(lo.y), static_cast<float>(lo.z)) * kLeaf;
    o.box_max = Vec3(static_cast<float>(hi.x + 1), static_cast<float>(hi.y + 1), static_cast<float>(hi.z + 1)) * kLeaf;
    const double dx = o.centroid.x() - p.centre_x, dy = o.centroid.y() - p.centre_y;
    o.d2 = dx * dx + dy * dy;
    out.push_back(o);
  }
  std::stable_sort(out.begin(), out.end(), [](const OracleObject& a, const OracleObject& b) { return a.d2 < b.d2; });
  return out;
}
}  // namespace

TEST(ClusterObjects, ListMatchesBruteForceComponents) {
  std::mt19937 rng(41);
  int full_lists = 0;
  for (int trial = 0; trial < 8; ++trial) {
    const std::vector<Cell> cells = random_cells(rng, 22, trial < 4 ? 0.05 : 0.12);
    ClusterParams p;
    p.min_points = 3;
    p.centre_x = (55.f + 3.f * static_cast<float>(trial)) * kLeaf;
    p.centre_y = (70.f - 2.f * static_cast<float>(trial)) * kLeaf;
    const std::vector<OracleObject> want = oracle_objects(cells, p);
    Fixture f(cells);
    const ClusterResult r = f.run(p, trial % 2 == 1);
    ASSERT_EQ(r.clusters, want.size());
    const uint32_t listed = std::min<uint32_t>(fg::kMaxObjects, static_cast<uint32_t>(want.size()));
    ASSERT_EQ(r.n_objects, listed) << "trial " << trial;
    EXPECT_EQ(r.objects_dropped, want.size() - listed);
    full_lists += want.size() > fg::kMaxObjects ? 1 : 0;
    for (uint32_t k = 0; k < listed; ++k) {
      SCOPED_TRACE("trial " + std::to_string(trial) + " object " + std::to_string(k));
      // Exact ties of the distance are order-dependent in float: compare the sets then.
      const fg::ObjectSummary& o = r.objects[k];
      EXPECT_EQ(o.voxels, want[k].voxels.size());
      EXPECT_EQ(o.seed, want[k].voxels.front());
      EXPECT_LT((o.centroid - want[k].centroid).norm(), 1e-5f);
      EXPECT_LT((o.box_min - want[k].box_min).norm(), 1e-5f);
      EXPECT_LT((o.box_max - want[k].box_max).norm(), 1e-5f);
    }
  }
  EXPECT_GT(full_lists, 0) << "no trial had more objects than the list holds";
}

TEST(ClusterObjects, NearestPointPicksTheClusterWithTheClosestVoxel) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  int checked = 0;
  for (int trial = 0; trial < 12; ++trial) {
    const std::vector<Cell> cells = random_cells(rng, 18, 0.06);
    ClusterParams p;
    p.min_points = 3;
    p.target.kind = fg::TargetKind::nearest_point;
    p.target.point = Vec3(50.f + 18.f * u(rng), 60.f + 18.f * u(rng), 5.f + 18.f * u(rng)) * kLeaf;
    // Oracle: the eligible component with the least distance from a cell centre to the point.
    std::vector<std::pair<double, std::vector<uint32_t>>> d;
    for (const auto& comp : components(cells, std::vector<bool>(cells.size(), true), 1)) {
      if (comp.size() < p.min_points) continue;
      double best = 1e30;
      for (uint32_t i : comp)
        best = std::min(best, (cell_centre(cells[i]) - p.target.point).cast<double>().squaredNorm());
      d.push_back({best, comp});
    }
    std::sort(d.begin(), d.end());
    ASSERT_GE(d.size(), 2u);
    if (d[1].first - d[0].first < 1e-7) continue;  // two clusters equally near: order-dependent
    Fixture f(cells);
    const ClusterResult r = f.run(p, trial % 2 == 0);
    std::vector<uint32_t> got(f.target.begin(), f.target.begin() + r.target_size);
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, d[0].second) << "trial " << trial;
    ++checked;
  }
  EXPECT_GE(checked, 8);
}

// Why the distance to the nearest voxel and not to the centroid: a point at the tip of a
// long bar's end is 30 cells from the bar's centroid and 8 from a small cube's, yet on
// the bar.
TEST(ClusterObjects, NearestPointOnALongBarIsTheBar) {
  std::vector<Cell> cells = box_cells(100, 100, 10, 60, 2, 2);  // the bar, x 100..159
  const std::vector<Cell> cube = box_cells(160, 110, 10, 3, 3, 3);
  cells.insert(cells.end(), cube.begin(), cube.end());
  ClusterParams p;
  p.min_points = 5;
  p.target.kind = fg::TargetKind::nearest_point;
  p.target.point = Vec3(159.5f, 101.f, 11.f) * kLeaf;  // on the bar's far end
  Fixture f(cells);
  const ClusterResult r = f.run(p);
  EXPECT_EQ(r.target_size, 240u);
  EXPECT_EQ(f.targets(r), range_set(0, 240));
}

TEST(ClusterObjects, BoxPicksTheClusterWithMostVoxelsInside) {
  // Two 4x4x4 blobs side by side 2 cells apart; the box holds one column of A and two of B.
  std::vector<Cell> cells = box_cells(100, 100, 10, 4, 4, 4);    // A: voxels 0..63, x 100..103
  const std::vector<Cell> b = box_cells(106, 100, 10, 4, 4, 4);  // B: 64..127, x 106..109
  cells.insert(cells.end(), b.begin(), b.end());
  ClusterParams p;
  p.min_points = 5;
  p.target.kind = fg::TargetKind::inside_box;
  p.target.box_min = Vec3(103.f, 99.f, 9.f) * kLeaf;
  p.target.box_max = Vec3(107.9f, 105.f, 15.f) * kLeaf;
  {
    Fixture f(cells);
    const ClusterResult r = f.run(p);
    EXPECT_EQ(f.targets(r), range_set(64, 128));  // B: 32 voxels inside, A 16
    EXPECT_EQ(r.n_objects, 2u);
  }
  p.target.box_min.x() = 100.f * kLeaf;  // now A has all 64 inside, B still 32
  {
    Fixture f(cells);
    const ClusterResult r = f.run(p);
    EXPECT_EQ(f.targets(r), range_set(0, 64));
  }
  // A box between them (the gap) holds nothing: no target, the objects still listed.
  p.target.box_min = Vec3(104.f, 99.f, 9.f) * kLeaf;
  p.target.box_max = Vec3(105.9f, 105.f, 15.f) * kLeaf;
  {
    Fixture f(cells);
    const ClusterResult r = f.run(p);
    EXPECT_EQ(r.target_size, 0u);
    EXPECT_EQ(r.clusters, 2u);
    EXPECT_EQ(r.n_objects, 2u);
    EXPECT_TRUE(f.in_state(fg::kVoxelTarget).empty());
  }
}

TEST(ClusterObjects, MarkClusterTakesEachListedObject) {
  std::mt19937 rng(5);
  const std::vector<Cell> cells = random_cells(rng, 20, 0.07);
  ClusterParams p;
  p.min_points = 2;
  p.centre_x = 60.f * kLeaf;
  p.centre_y = 70.f * kLeaf;
  const std::vector<OracleObject> want = oracle_objects(cells, p);
  Fixture f(cells);
  const ClusterResult r = f.run(p);
  ASSERT_GE(r.n_objects, 4u);
  const std::set<uint32_t> others_and_target = [&] {
    std::set<uint32_t> s = f.in_state(fg::kVoxelVisited);
    const std::set<uint32_t> t = f.in_state(fg::kVoxelTarget);
    s.insert(t.begin(), t.end());
    return s;
  }();
  for (uint32_t k = r.n_objects; k-- > 0;) {  // backwards: not the list's order
    const uint32_t size = fg::mark_cluster(*f.grid, f.state.data(), f.queue.data(), p, r.objects[k].seed,
                                           f.target.data(), static_cast<uint32_t>(f.target.size()));
    ASSERT_EQ(size, r.objects[k].voxels);
    std::vector<uint32_t> got(f.target.begin(), f.target.begin() + size);
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, want[k].voxels) << "object " << k;
    const std::set<uint32_t> t = f.in_state(fg::kVoxelTarget);
    EXPECT_EQ(std::vector<uint32_t>(t.begin(), t.end()), want[k].voxels);
    std::set<uint32_t> all = f.in_state(fg::kVoxelVisited);
    all.insert(t.begin(), t.end());
    EXPECT_EQ(all, others_and_target) << "mark_cluster changed voxels outside the objects";
  }
  // A removed voxel, or one past the grid, is no seed: nothing changes.
  const std::vector<uint8_t> before = f.state;
  EXPECT_EQ(fg::mark_cluster(*f.grid, f.state.data(), f.queue.data(), p, static_cast<uint32_t>(cells.size()),
                             f.target.data(), 1u),
            0u);
  EXPECT_EQ(f.state, before);
}

TEST(ClusterObjects, TargetSpecValidation) {
  const char* why = nullptr;
  fg::TargetSpec t;
  EXPECT_EQ(fg::validate(t, &why), Status::ok);
  EXPECT_STREQ(why, "");
  t.kind = fg::TargetKind::nearest_point;
  t.point = Vec3(0.5f, NAN, 0.f);
  EXPECT_EQ(fg::validate(t, &why), Status::non_finite);
  EXPECT_STREQ(why, "target point: a coordinate is not finite");
  t.kind = fg::TargetKind::inside_box;
  t.box_min = Vec3(0.4f, -0.1f, 0.f);
  t.box_max = Vec3(0.6f, -0.2f, 0.3f);
  EXPECT_EQ(fg::validate(t, &why), Status::invalid_argument);
  EXPECT_STREQ(why, "target box: a minimum is above its maximum");
  t.box_max.y() = INFINITY;
  EXPECT_EQ(fg::validate(t, &why), Status::non_finite);
  t.box_max.y() = 0.1f;
  EXPECT_EQ(fg::validate(t, &why), Status::ok);
  t.kind = static_cast<fg::TargetKind>(9);
  EXPECT_EQ(fg::validate(t, &why), Status::invalid_argument);
  EXPECT_STREQ(why, "target: unknown kind");
}
