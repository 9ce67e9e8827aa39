#include "fg/core/cluster.hpp"

namespace fg {
namespace {
struct Offset {
  uint32_t delta;  // pack(dx, dy, dz) in two's complement per field, summed
  uint64_t hash;   // VoxelGrid::filter_hash_of_offset of the signed sum
};
// Neighbour offsets within `cells` (Euclidean in cell units, so 1 -> 26, 2 -> 32).
uint32_t make_offsets(uint32_t cells, Offset* out) {
  const int32_t r = static_cast<int32_t>(cells);
  uint32_t n = 0;
  for (int32_t dz = -r; dz <= r; ++dz)
    for (int32_t dy = -r; dy <= r; ++dy)
      for (int32_t dx = -r; dx <= r; ++dx) {
        const int32_t d2 = dx * dx + dy * dy + dz * dz;
        if (d2 == 0) continue;
        if (r > 1 && d2 > r * r) continue;
        out[n++] = Offset{static_cast<uint32_t>(dx) + (static_cast<uint32_t>(dy) << 11) +
                              (static_cast<uint32_t>(dz) << 22),
                          VoxelGrid::filter_hash_of_offset(dx + dy * (int64_t{1} << 11) +
                                                           dz * (int64_t{1} << 22))};
      }
  return n;
}

// What a walk gathers: the sums of its voxels' centroids in x and y, and the x-y box
// of its cells (key indices).
struct Walk {
  float sum_x = 0.f, sum_y = 0.f;
  uint32_t x0 = 0xFFFFFFFFu, x1 = 0, y0 = 0xFFFFFFFFu, y1 = 0;
};

// Breadth-first walk of the component of `seed` through the voxels in state `from`;
// marks it `mark` (!= from); returns its size and leaves its voxels in queue[0, size).
uint32_t flood(const VoxelGrid& grid, uint8_t* state, uint32_t* queue, uint32_t seed,
               const Offset* off, uint32_t n_off, uint8_t from, uint8_t mark, Walk& w) {
  uint32_t head = 0, tail = 0;
  queue[tail++] = seed;
  state[seed] = mark;
  w = Walk{};
  const VoxelGrid::LookupFilter filter = grid.lookup_filter();
  while (head < tail) {  // bounded: each voxel enters the queue at most once
    const uint32_t i = queue[head++];
    const Vec3 c = grid.centroid(i);
    w.sum_x += c.x();
    w.sum_y += c.y();
    // A neighbour's key is the packed sum: inserted cells keep a 2-cell margin inside
    // each field's range, so no field under- or overflows into the next.
    // The filter's hash of a neighbour is a sum too (voxel_grid.hpp).
    const uint32_t k = grid.key(i);
    const uint32_t kx = VoxelGrid::key_x(k), ky = VoxelGrid::key_y(k);
    w.x0 = kx < w.x0 ? kx : w.x0;
    w.x1 = kx > w.x1 ? kx : w.x1;
    w.y0 = ky < w.y0 ? ky : w.y0;
    w.y1 = ky > w.y1 ? ky : w.y1;
    const uint64_t kh = VoxelGrid::filter_hash(k);
    for (uint32_t o = 0; o < n_off; ++o) {
      if (filter.words != nullptr && !filter.may_hold(kh + off[o].hash)) continue;  // most absent cells
      const uint32_t j = grid.find_in_table(k + off[o].delta);
      if (j == VoxelGrid::kNone || state[j] != from) continue;
      state[j] = mark;
      queue[tail++] = j;
    }
  }
  return tail;
}

// Keeps `c` in the list of the largest clusters (size descending, ties in the order
// found); the size of whatever falls off the end goes to largest_dropped.
void keep_largest(ClusterResult& res, const ClusterSummary& c) {
  uint32_t pos = res.n_largest;
  while (pos > 0 && c.size > res.largest[pos - 1].size) --pos;
  const uint32_t cap = ClusterResult::kLargestKept;
  if (pos >= cap) {
    res.largest_dropped = c.size > res.largest_dropped ? c.size : res.largest_dropped;
    return;
  }
  if (res.n_largest == cap) {
    const uint32_t evicted = res.largest[cap - 1].size;
    res.largest_dropped = evicted > res.largest_dropped ? evicted : res.largest_dropped;
  }
  const uint32_t last = res.n_largest < cap ? res.n_largest : cap - 1;
  for (uint32_t i = last; i > pos; --i) res.largest[i] = res.largest[i - 1];
  res.largest[pos] = c;
  if (res.n_largest < cap) ++res.n_largest;
}

// The cluster's x-y footprint (its cells' x-y box: the cell centres grown by half a
// voxel) contains (cx, cy).
bool footprint_covers(const VoxelGrid& grid, const ClusterSummary& c, float cx, float cy) {
  const float leaf = grid.leaf();
  const Vec3& origin = grid.origin();
  const float x0 = origin.x() + leaf * static_cast<float>(c.x0);
  const float x1 = origin.x() + leaf * static_cast<float>(c.x1 + 1u);
  const float y0 = origin.y() + leaf * static_cast<float>(c.y0);
  const float y1 = origin.y() + leaf * static_cast<float>(c.y1 + 1u);
  return cx >= x0 && cx <= x1 && cy >= y0 && cy <= y1;
}
}  // namespace

ClusterResult cluster_and_pick(const VoxelGrid& grid, uint8_t* state, uint32_t* queue,
                               const ClusterParams& prm, uint32_t* target,
                               uint32_t target_capacity) {
  Offset off[128];
  const uint32_t n_off = make_offsets(prm.cells > 2 ? 2u : prm.cells, off);
  ClusterResult res;
  const uint32_t n = grid.size();
  uint32_t best_seed = VoxelGrid::kNone, best_size = 0;
  float best_score = 0.f;
  uint32_t free_total = 0;
  for (uint32_t i = 0; i < n; ++i) {
    if (state[i] != kVoxelFree) continue;
    Walk w;
    const uint32_t size = flood(grid, state, queue, i, off, n_off, kVoxelFree, kVoxelVisited, w);
    free_total += size;
    if (size < prm.min_points) continue;
    ++res.clusters;
    keep_largest(res, ClusterSummary{i, size, w.x0, w.x1, w.y0, w.y1});
    float score;
    if (prm.rule == TargetRule::largest) {
      score = -static_cast<float>(size);
    } else {
      const float cx = w.sum_x / static_cast<float>(size) - prm.centre_x;
      const float cy = w.sum_y / static_cast<float>(size) - prm.centre_y;
      score = cx * cx + cy * cy;
    }
    if (best_seed == VoxelGrid::kNone || score < best_score) {
      best_seed = i;
      best_size = size;
      best_score = score;
      // Keep the leader's voxels (its walk is in the queue until the next flood), so
      // the winner need not be walked again. Each component is copied at most once.
      if (size <= target_capacity)
        for (uint32_t k = 0; k < size; ++k) target[k] = queue[k];
    }
  }
  if (best_seed == VoxelGrid::kNone) {
    res.other_points = free_total;
    return res;
  }
  res.target_size = best_size;
  res.other_points = free_total - best_size;
  if (best_size <= target_capacity) {
    for (uint32_t k = 0; k < best_size; ++k) state[target[k]] = kVoxelTarget;
    return res;
  }
  // Larger than the caller's list (the caller reports capacity_exceeded): walk the
  // winner again to mark it, turning it from visited into target.
  for (uint32_t i = 0; i < n; ++i)
    if (state[i] == kVoxelVisited) state[i] = kVoxelFree;
  Walk w;
  (void)flood(grid, state, queue, best_seed, off, n_off, kVoxelFree, kVoxelTarget, w);
  for (uint32_t i = 0; i < n; ++i)
    if (state[i] == kVoxelFree) state[i] = kVoxelVisited;
  for (uint32_t i = 0; i < target_capacity; ++i) target[i] = queue[i];
  return res;
}

uint32_t retarget_to_cover(const VoxelGrid& grid, uint8_t* state, uint32_t* queue,
                           const ClusterParams& prm, const uint32_t* old_target, uint32_t old_size,
                           float cx, float cy, uint32_t* target, uint32_t target_capacity,
                           const ClusterResult* labelled) {
  Offset off[128];
  const uint32_t n_off = make_offsets(prm.cells > 2 ? 2u : prm.cells, off);
  const uint32_t n = grid.size();
  // The largest that covers (cx, cy) wins, the first found on ties.
  uint32_t best_seed = VoxelGrid::kNone, best_size = 0;
  const auto consider = [&](const ClusterSummary& c) {
    if (c.size < prm.min_points || c.size <= old_size || c.size > target_capacity || c.size <= best_size) return;
    if (!footprint_covers(grid, c, cx, cy)) return;
    best_seed = c.seed;
    best_size = c.size;
  };
  // Every cluster larger than the old target in the labelling's list, in the order a
  // walk would find them among equals: no walk. Otherwise every component of the
  // clusters not picked, walked once (visited -> free).
  const bool from_list = labelled != nullptr && labelled->largest_dropped <= old_size;
  if (from_list) {
    for (uint32_t k = 0; k < labelled->n_largest; ++k) consider(labelled->largest[k]);
  } else {
    for (uint32_t i = 0; i < n; ++i) {
      if (state[i] != kVoxelVisited) continue;
      Walk w;
      const uint32_t size = flood(grid, state, queue, i, off, n_off, kVoxelVisited, kVoxelFree, w);
      consider(ClusterSummary{i, size, w.x0, w.x1, w.y0, w.y1});
    }
  }
  if (best_seed != VoxelGrid::kNone) {
    // The old target joins the other objects before `target` (which may be the same
    // array) is overwritten; it is a component of its own, so the walk below never
    // reaches it.
    for (uint32_t k = 0; k < old_size; ++k) state[old_target[k]] = kVoxelVisited;
    Walk w;
    (void)flood(grid, state, queue, best_seed, off, n_off, from_list ? kVoxelVisited : kVoxelFree, kVoxelTarget,
                w);
    for (uint32_t k = 0; k < best_size; ++k) target[k] = queue[k];
  }
  if (!from_list)
    for (uint32_t i = 0; i < n; ++i)
      if (state[i] == kVoxelFree) state[i] = kVoxelVisited;
  return best_size;
}

}  // namespace fg
