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

// Breadth-first walk of the component of `seed`; marks it `mark`; returns its size
// and leaves its voxels in queue[0, size).
uint32_t flood(const VoxelGrid& grid, uint8_t* state, uint32_t* queue, uint32_t seed,
               const Offset* off, uint32_t n_off, uint8_t mark, float& sum_x, float& sum_y) {
  uint32_t head = 0, tail = 0;
  queue[tail++] = seed;
  state[seed] = mark;
  sum_x = sum_y = 0.f;
  const bool filtered = grid.lookup_filter_on();
  while (head < tail) {  // bounded: each voxel enters the queue at most once
    const uint32_t i = queue[head++];
    const Vec3 c = grid.centroid(i);
    sum_x += c.x();
    sum_y += c.y();
    // A neighbour's key is the packed sum: inserted cells keep a 2-cell margin inside
    // each field's range, so no field under- or overflows into the next.
    // The filter's hash of a neighbour is a sum too (voxel_grid.hpp).
    const uint32_t k = grid.key(i);
    const uint64_t kh = VoxelGrid::filter_hash(k);
    for (uint32_t o = 0; o < n_off; ++o) {
      if (filtered && !grid.filter_may_hold(kh + off[o].hash)) continue;  // most absent cells
      const uint32_t j = grid.find_in_table(k + off[o].delta);
      if (j == VoxelGrid::kNone || state[j] != kVoxelFree) continue;
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
    float sx = 0.f, sy = 0.f;
    const uint32_t size = flood(grid, state, queue, i, off, n_off, kVoxelVisited, sx, sy);
    free_total += size;
    if (size < prm.min_points) continue;
    ++res.clusters;
    float score;
    if (prm.rule == TargetRule::largest) {
      score = -static_cast<float>(size);
    } else {
      const float cx = sx / static_cast<float>(size) - prm.centre_x;
      const float cy = sy / static_cast<float>(size) - prm.centre_y;
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
  float sx = 0.f, sy = 0.f;
  (void)flood(grid, state, queue, best_seed, off, n_off, kVoxelTarget, sx, sy);
  for (uint32_t i = 0; i < n; ++i)
    if (state[i] == kVoxelFree) state[i] = kVoxelVisited;
  for (uint32_t i = 0; i < target_capacity; ++i) target[i] = queue[i];
  return res;
}

}  // namespace fg
