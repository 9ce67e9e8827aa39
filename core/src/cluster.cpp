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
  const bool filtered = grid.lookup_filter_on();
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
      if (filtered && !grid.filter_may_hold(kh + off[o].hash)) continue;  // most absent cells
      const uint32_t j = grid.find_in_table(k + off[o].delta);
      if (j == VoxelGrid::kNone || state[j] != from) continue;
      state[j] = mark;
      queue[tail++] = j;
    }
  }
  return tail;
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
                           float cx, float cy, uint32_t* target, uint32_t target_capacity) {
  Offset off[128];
  const uint32_t n_off = make_offsets(prm.cells > 2 ? 2u : prm.cells, off);
  const uint32_t n = grid.size();
  const float leaf = grid.leaf();
  const Vec3& origin = grid.origin();
  // Every component of the clusters not picked, walked once (visited -> free): the
  // largest that covers (cx, cy) wins, the first found on ties.
  uint32_t best_seed = VoxelGrid::kNone, best_size = 0;
  for (uint32_t i = 0; i < n; ++i) {
    if (state[i] != kVoxelVisited) continue;
    Walk w;
    const uint32_t size = flood(grid, state, queue, i, off, n_off, kVoxelVisited, kVoxelFree, w);
    if (size < prm.min_points || size <= old_size || size > target_capacity || size <= best_size) continue;
    // The footprint: the x-y box of the cells, i.e. of the cell centres grown by half
    // a voxel.
    const float x0 = origin.x() + leaf * static_cast<float>(w.x0);
    const float x1 = origin.x() + leaf * static_cast<float>(w.x1 + 1u);
    const float y0 = origin.y() + leaf * static_cast<float>(w.y0);
    const float y1 = origin.y() + leaf * static_cast<float>(w.y1 + 1u);
    if (!(cx >= x0 && cx <= x1 && cy >= y0 && cy <= y1)) continue;
    best_seed = i;
    best_size = size;
  }
  if (best_seed != VoxelGrid::kNone) {
    // The old target joins the other objects before `target` (which may be the same
    // array) is overwritten; it is a component of its own, so the walk below, over
    // the free voxels, never reaches it.
    for (uint32_t k = 0; k < old_size; ++k) state[old_target[k]] = kVoxelVisited;
    Walk w;
    (void)flood(grid, state, queue, best_seed, off, n_off, kVoxelFree, kVoxelTarget, w);
    for (uint32_t k = 0; k < best_size; ++k) target[k] = queue[k];
  }
  for (uint32_t i = 0; i < n; ++i)
    if (state[i] == kVoxelFree) state[i] = kVoxelVisited;
  return best_size;
}

}  // namespace fg
