#include "fg/core/voxel_grid.hpp"

#include <cstring>

#include "fg/core/byte_flags.hpp"

namespace fg {

void VoxelGrid::reset(const Vec3& origin, float leaf_m) {
  origin_ = origin;
  leaf_ = leaf_m;
  inv_leaf_ = 1.0f / leaf_m;
  slot_bits_ = kSlotBits;
  slot_mask_ = kVoxelHashSlots - 1;
  // One pass over the slots: bounded and cheap (a memset of the table), where clearing
  // slot by slot costs a probe per voxel.
  for (uint32_t s = 0; s < kVoxelHashSlots; ++s) slots_[s] = 0u;
  finalized_ = false;
  filter_on_ = false;
  wide_ = nullptr;
  filter_word_bits_ = kCacheBits;
  size_ = 0;
  indexed_ = kIndexAll;
  for (uint32_t i = 0; i < (1u << kCacheBits); ++i) cache_[i] = CacheEntry{0xFFFFFFFFu, 0u};
}

void VoxelGrid::build_filter(const uint8_t* keep) {
  // keep, when given, is the set the index was pruned to (prepare_lookups' caller
  // passes the same flags as keep_in_index_only).
  uint64_t* const words = wide_ != nullptr ? wide_ : filter_;
  const uint32_t shift = 64u - filter_word_bits_;
  for (uint32_t w = 0; w < (1u << filter_word_bits_); ++w) words[w] = 0u;
  for_each_flagged(keep, size_, [&](uint32_t i) {
    const uint64_t g = filter_mix(filter_hash(keys_[i]));
    words[g >> shift] |= filter_bits(g);
  });
  filter_on_ = true;
}

uint32_t VoxelGrid::find_in_table(uint32_t key) const {
  uint32_t s = slot_of(key);
  const uint32_t tag = tag_of(key);
  for (uint32_t probe = 0; probe < kMaxProbe; ++probe) {
    const uint32_t slot = slots_[s];
    if (slot == 0) return kNone;
    const uint32_t index = (slot & kIndexMask) - 1;
    if ((slot & ~kIndexMask) == tag && keys_[index] == key) return index;
    s = (s + 1) & slot_mask_;
  }
  return kNone;
}

uint32_t VoxelGrid::count(uint32_t i) const { return finalized_ ? 0u : static_cast<uint32_t>(store_[4 * i + 3]); }

Vec3 VoxelGrid::centroid(uint32_t i) const {
  if (finalized_) return centroids()[i];
  const float* acc = store_ + size_t{4} * i;
  const float inv = 1.0f / acc[3];
  const uint32_t k = keys_[i];
  return Vec3(origin_.x() + static_cast<float>(key_x(k)) * leaf_ + acc[0] * inv,
              origin_.y() + static_cast<float>(key_y(k)) * leaf_ + acc[1] * inv,
              origin_.z() + static_cast<float>(key_z(k)) * leaf_ + acc[2] * inv);
}

uint32_t VoxelGrid::keep_xy_range(uint32_t x0, uint32_t x1, uint32_t y0, uint32_t y1) {
  if (finalized_) return 0;
  uint32_t kept = 0, dropped_points = 0;
  for (uint32_t i = 0; i < size_; ++i) {
    const uint32_t k = keys_[i], x = key_x(k), y = key_y(k);
    if (x >= x0 && x < x1 && y >= y0 && y < y1) {
      keys_[kept] = k;
      std::memmove(store_ + size_t{4} * kept, store_ + size_t{4} * i, 4 * sizeof(float));
      ++kept;
    } else {
      dropped_points += static_cast<uint32_t>(store_[4 * i + 3]);
    }
  }
  size_ = kept;
  // Re-inserted in their order into the empty full-size table, the kept keys probe no
  // farther than they did among all keys (linear probing, no deletions), so each finds
  // its slot within kMaxProbe again.
  for (uint32_t i = 0; i < (1u << kCacheBits); ++i) cache_[i] = CacheEntry{0xFFFFFFFFu, 0u};
  (void)rebuild_index(nullptr, kSlotBits);
  return dropped_points;
}

void VoxelGrid::finalize() {
  if (finalized_) return;
  // In place, front to back, four voxels per step: their sums (floats 4i..4i+15) are
  // read before their centroids (floats 3i..3i+11) are written, at or before them, so
  // no later voxel's sums are overwritten. Each lane is centroid()'s formula in its
  // order, so the centroids are the same bit for bit.
  const V4f o[3] = {V4f{} + origin_.x(), V4f{} + origin_.y(), V4f{} + origin_.z()};
  const V4f leaf = V4f{} + leaf_;
  uint32_t i = 0;
  for (; i + 4 <= size_; i += 4) {
    const float* acc = store_ + size_t{4} * i;
    const V4f a0 = load4(acc), a1 = load4(acc + 4), a2 = load4(acc + 8), a3 = load4(acc + 12);
    const V4f xy01 = __builtin_shufflevector(a0, a1, 0, 4, 1, 5), xy23 = __builtin_shufflevector(a2, a3, 0, 4, 1, 5);
    const V4f zn01 = __builtin_shufflevector(a0, a1, 2, 6, 3, 7), zn23 = __builtin_shufflevector(a2, a3, 2, 6, 3, 7);
    const V4f sx = __builtin_shufflevector(xy01, xy23, 0, 1, 4, 5),
              sy = __builtin_shufflevector(xy01, xy23, 2, 3, 6, 7);
    const V4f sz = __builtin_shufflevector(zn01, zn23, 0, 1, 4, 5),
              cnt = __builtin_shufflevector(zn01, zn23, 2, 3, 6, 7);
    const V4f inv = 1.0f / cnt;
    V4i k;
    std::memcpy(&k, keys_ + i, sizeof k);
    const V4f kx = __builtin_convertvector(k & 0x7FF, V4f);
    const V4f ky = __builtin_convertvector((k >> 11) & 0x7FF, V4f);
    const V4f kz = __builtin_convertvector(reinterpret_cast<V4i>(reinterpret_cast<V4u>(k) >> 22), V4f);
    V4f c0, c1, c2;
    interleave_xyz((o[0] + kx * leaf) + sx * inv, (o[1] + ky * leaf) + sy * inv, (o[2] + kz * leaf) + sz * inv, c0, c1,
                   c2);
    float* out = store_ + size_t{3} * i;
    std::memcpy(out, &c0, sizeof c0);
    std::memcpy(out + 4, &c1, sizeof c1);
    std::memcpy(out + 8, &c2, sizeof c2);
  }
  for (; i < size_; ++i) {
    const Vec3 c = centroid(i);
    float* out = store_ + size_t{3} * i;
    out[0] = c.x();
    out[1] = c.y();
    out[2] = c.z();
  }
  finalized_ = true;
}

bool VoxelGrid::rebuild_index(const uint8_t* keep, uint32_t bits) {
  slot_bits_ = bits;
  slot_mask_ = (1u << bits) - 1u;
  for (uint32_t s = 0; s <= slot_mask_; ++s) slots_[s] = 0u;
  bool ok = true;
  for_each_flagged(keep, size_, [&](uint32_t i) {
    if (!ok) return;  // refused: the rest is only skipped
    uint32_t s = slot_of(keys_[i]);
    uint32_t probe = 0;
    for (; probe < kMaxProbe && slots_[s] != 0; ++probe) s = (s + 1) & slot_mask_;
    if (probe == kMaxProbe)
      ok = false;  // the caller starts again with the full table
    else
      slots_[s] = tag_of(keys_[i]) | (i + 1);
  });
  return ok;
}

void VoxelGrid::keep_in_index_only(const uint8_t* keep) {
  // A table sized for the kept voxels (at most half full) stays in the fast caches.
  uint32_t kept = 0;
  for (uint32_t i = 0; i < size_; ++i) kept += keep[i] != 0 ? 1u : 0u;
  uint32_t bits = 6;
  while (bits < kSlotBits && (1u << bits) < 2u * kept) ++bits;
  // Should a crafted cloud crowd the small table, the full one takes the kept voxels
  // back: inserted in the same order, a subset of keys never probes farther there than
  // the whole set did, so each finds its slot within kMaxProbe again.
  filter_on_ = false;
  wide_ = nullptr;
  filter_word_bits_ = kCacheBits;
  for (uint32_t s = 0; s < (1u << kCacheBits); ++s) cache_[s] = CacheEntry{0xFFFFFFFFu, 0u};
  if (!rebuild_index(keep, bits)) (void)rebuild_index(keep, kSlotBits);
  indexed_ = kept;
}

void VoxelGrid::prepare_lookups(const uint8_t* keep, uint64_t* wide, uint32_t wide_bits) {
  filter_on_ = false;
  wide_ = nullptr;
  filter_word_bits_ = kCacheBits;
  // The filter pays when the table is more than half full (an absent key's walk
  // averages about 8 slots at 3/4 load) or larger than kSmallTableSlots (its walks are
  // cache misses, a filter test is one load of a smaller array). A small table at most
  // half full (the example's, pruned to its objects) does without: an absent key's
  // walk there is about two slots in the fast caches.
  const bool pruned = indexed_ != kIndexAll;
  const uint32_t n = pruned ? indexed_ : size_;
  const uint32_t slots = slot_mask_ + 1u;
  if (!finalized_ || n == 0 || (2u * n <= slots && slots <= kSmallTableSlots)) return;
  if (wide != nullptr && wide_bits > kCacheBits && wide_bits <= kMaxFilterWordBits) {
    wide_ = wide;
    filter_word_bits_ = wide_bits;
  }
  // A filter of every voxel is a superset of a pruned index's: still exact.
  build_filter(pruned ? keep : nullptr);
}

uint32_t* VoxelGrid::lend_count_storage() {
  if (!finalized_) return nullptr;
  // The storage past the packed centroids: 4 * kMaxVoxels - 3 * size() >= size() words.
  return reinterpret_cast<uint32_t*>(store_ + size_t{3} * size_);
}

}  // namespace fg
