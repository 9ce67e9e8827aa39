// One voxel grid shared by both sensors (so merging the clouds is free): a fixed
// open-addressing hash from packed cell keys to dense per-voxel arrays in insertion
// order (deterministic). Each voxel keeps the sum of its points relative to its cell
// corner, so centroids stay precise (micrometres for typical counts, 0.1 mm for a
// million points in one cell) wherever the cell lies.
// Memory is arranged by use, to keep the host workspace small and the ingest's random
// accesses few: a hash slot is one word, the voxel index + 1 with a tag of the key in
// the spare high bits (so most probes of other keys are rejected without reading the
// key array); a voxel's running sum and count share one 16-byte slot (one cache line
// per point); finalize() packs the centroids into the front of that storage, and the
// rest, no longer needed, is lent to the clustering as its queue.
#pragma once
#include <cstdint>
#include <cstring>

#include "fg/core/limits.hpp"
#include "fg/core/status.hpp"
#include "fg/core/types.hpp"
#include "fg/core/vec4.hpp"

namespace fg {

//! What a voxel holds besides its centroid.
struct Voxel {
  uint32_t key;    //!< x | y << 11 | z << 22 (cell indices relative to the grid origin)
  uint32_t count;  //!< points that fell in the cell (before finalize(); 0 after)
};

class VoxelGrid {
 public:
  static constexpr uint32_t kNone = 0xFFFFFFFFu;
  static constexpr int32_t kMaxX = 2047, kMaxY = 2047, kMaxZ = 1023;

  //! Empties the grid. `origin` is the corner of cell (0,0,0); callers keep every
  //! inserted point at least 2 cells inside the key range (checked by insert).
  void reset(const Vec3& origin, float leaf_m);

  //! Adds a world point. capacity_exceeded when another cell is needed but kMaxVoxels
  //! cells are in use; invalid_argument when the point is outside the key range;
  //! invalid_sequence after finalize().
  [[nodiscard]] Status insert(const Vec3& p) {
    const float fx = (p.x() - origin_.x()) * inv_leaf_;
    const float fy = (p.y() - origin_.y()) * inv_leaf_;
    const float fz = (p.z() - origin_.z()) * inv_leaf_;
    if (finalized_) return Status::invalid_sequence;
    if (!(fx >= 2.f && fy >= 2.f && fz >= 2.f && fx < kMaxX - 2 && fy < kMaxY - 2 && fz < kMaxZ - 2))
      return Status::invalid_argument;
    return insert_cell(fx, fy, fz) ? Status::ok : Status::capacity_exceeded;
  }

  //! One point in cell units: (fx, fy, fz) are coordinates in cell units from the
  //! origin, already checked to lie in [2, kMax - 2), before finalize(). False when
  //! the grid is full (or the cell's hash neighbourhood is: kMaxProbe).
  [[nodiscard]] bool insert_cell(float fx, float fy, float fz) {
    const uint32_t ix = static_cast<uint32_t>(fx), iy = static_cast<uint32_t>(fy), iz = static_cast<uint32_t>(fz);
    return add_to_cell(pack(ix, iy, iz),
                       V4f{(fx - static_cast<float>(ix)) * leaf_, (fy - static_cast<float>(iy)) * leaf_,
                           (fz - static_cast<float>(iz)) * leaf_, 1.f});
  }

  //! The hot path of the ingest: one point of the cell `key` (the packed key of a cell
  //! at least 2 inside the key range) at (o[0], o[1], o[2]) metres from the cell
  //! corner, o[3] = 1 (it is added to the count). Before finalize(). False when the
  //! grid is full (or the cell's hash neighbourhood is: kMaxProbe).
  [[nodiscard]] bool add_to_cell(uint32_t key, V4f o) {
    // A small direct-mapped cache of recent cells: neighbouring pixels of a depth
    // image (in this row and the rows above) mostly fall in the same few hundred cells.
    CacheEntry& e = cache_[(key * 0x9E3779B1u) >> (32 - kCacheBits)];
    if (e.key != key) {
      const uint32_t idx = find_or_add(key);
      if (idx == kNone) return false;
      e.key = key;
      e.offset = idx * static_cast<uint32_t>(sizeof(V4f));
    }
    // Sum and count in one vector add: the count is lane 3, a float, exact below 2^24
    // points per cell (where the float sums have long lost their last digits too).
    V4f* acc = reinterpret_cast<V4f*>(reinterpret_cast<char*>(store_) + e.offset);
    *acc += o;
    return true;
  }

  //! Before finalize(): keeps only the voxels whose cell lies in x0 <= x < x1 and
  //! y0 <= y < y1 (key cell indices), in their order, with their sums untouched, and
  //! rebuilds the hash: the grid is then the one those cells' points alone would have
  //! made. Returns the points of the voxels dropped. One pass over the voxels and one
  //! over the slots.
  uint32_t keep_xy_range(uint32_t x0, uint32_t x1, uint32_t y0, uint32_t y1);

  //! Turns every voxel's sum into its centroid (world frame), in place; insert() is
  //! refused from then on until reset(). Calling it again does nothing.
  void finalize();
  bool finalized() const { return finalized_; }
  //! The centroids as one contiguous array of size() points (after finalize()).
  const Vec3* centroids() const { return reinterpret_cast<const Vec3*>(store_); }
  //! Rebuilds the hash so that find() sees only the voxels with keep[i] != 0 (the
  //! others stay in the arrays and keep their indices). Planning drops the support
  //! plane this way: the later neighbour searches then probe a nearly empty table.
  void keep_in_index_only(const uint8_t* keep);
  //! After finalize(), before many lookups (the clustering, the normals): when the
  //! index in use is more than half full or larger than kSmallTableSlots, find() gets
  //! a filter that settles most lookups of absent keys without walking the table. `keep`: the flags last given
  //! to keep_in_index_only(), or null when the index holds every voxel.
  //! `wide`: optional caller memory of 2^wide_bits 64-bit words, idle until the next
  //! prepare_lookups() or reset() (which stop using it); when larger than the grid's
  //! own it holds the filter, whose false positives (each a walk of the table, a cache
  //! miss) then fall roughly with the square of its size.
  void prepare_lookups(const uint8_t* keep, uint64_t* wide = nullptr, uint32_t wide_bits = 0);
  bool lookup_filter_on() const { return filter_on_; }
  //! Tables of at most this many slots (64 KiB) stay in the fast caches: at most half
  //! full they get no filter (prepare_lookups).
  static constexpr uint32_t kSmallTableSlots = 1u << 14;
  uint32_t table_slots() const { return slot_mask_ + 1u; }
  //! After finalize(): lends the storage the counts used, past the packed centroids
  //! (size() entries), as caller scratch, valid until reset(). nullptr before.
  uint32_t* lend_count_storage();

  uint32_t size() const { return size_; }
  float leaf() const { return leaf_; }
  const Vec3& origin() const { return origin_; }
  Voxel voxel(uint32_t i) const { return Voxel{keys_[i], count(i)}; }
  uint32_t key(uint32_t i) const { return keys_[i]; }
  //! Mean of the voxel's points (world frame), before and after finalize().
  Vec3 centroid(uint32_t i) const;
  //! Index of the voxel with `key`, or kNone.
  uint32_t find(uint32_t key) const {
    if (filter_on_ && !filter_may_hold(filter_hash(key))) return kNone;  // most absent keys
    return find_in_table(key);
  }
  //! The lookup filter's hash: multiplicative, so linear in the key (mod 2^64). The
  //! hash of key + d is filter_hash(key) + filter_hash_of_offset(d), one add per
  //! neighbour (d: a packed offset as a signed sum; voxel keys never wrap).
  static uint64_t filter_hash(uint32_t key) { return static_cast<uint64_t>(key) * kFilterMul; }
  static uint64_t filter_hash_of_offset(int64_t d) { return static_cast<uint64_t>(d) * kFilterMul; }
  //! The filter as neighbour loops test it themselves, read once: may_hold() false
  //! means absent for sure; true, ask find_in_table(). `words` is null when off.
  //! filter_mix's multiplier (public for the clustering's vector form of may_hold()).
  static constexpr uint64_t kFilterMixMul = 0xD6E8FEB86659FD93ull;
  struct LookupFilter {
    const uint64_t* words;
    uint32_t shift;  // 64 - log2(word count)
    bool may_hold(uint64_t h) const {
      const uint64_t g = filter_mix(h);
      const uint64_t m = filter_bits(g);
      return (words[g >> shift] & m) == m;
    }
  };
  LookupFilter lookup_filter() const {
    return LookupFilter{filter_on_ ? (wide_ != nullptr ? wide_ : filter_) : nullptr, 64u - filter_word_bits_};
  }
  bool filter_may_hold(uint64_t h) const { return lookup_filter().may_hold(h); }
  //! The index walk of find() without the filter.
  uint32_t find_in_table(uint32_t key) const;

  // A full avalanche of the key (murmur3's finaliser): neighbouring cells land far
  // apart, so runs of occupied slots stay short for any cloud.
  //! The key hash: a slot is its top bits (tests craft colliding clouds with it).
  static uint32_t mix(uint32_t key) {
    key ^= key >> 16;
    key *= 0x85EBCA6Bu;
    key ^= key >> 13;
    key *= 0xC2B2AE35u;
    return key ^ (key >> 16);
  }
  static uint32_t pack(uint32_t ix, uint32_t iy, uint32_t iz) { return ix | (iy << 11) | (iz << 22); }
  static uint32_t key_x(uint32_t k) { return k & 0x7FFu; }
  static uint32_t key_y(uint32_t k) { return (k >> 11) & 0x7FFu; }
  static uint32_t key_z(uint32_t k) { return k >> 22; }

 private:
  uint32_t find_or_add(uint32_t key);
  //! Voxel size_ for `key` in the empty slot s (kNone when the grid is full).
  uint32_t add_at(uint32_t s, uint32_t tag, uint32_t key);
  [[nodiscard]] bool rebuild_index(const uint8_t* keep, uint32_t bits);
  uint32_t slot_of(uint32_t key) const { return mix(key) >> (32 - slot_bits_); }
  static constexpr uint32_t kSlotBits = floor_log2(kVoxelHashSlots);
  // A slot: index + 1 (0 = empty) in the low kIndexBits, the key's tag above.
  static constexpr uint32_t kIndexBits = floor_log2(kMaxVoxels) + 1;
  static constexpr uint32_t kIndexMask = (1u << kIndexBits) - 1u;
  static_assert(kIndexBits <= 23, "the slot word keeps at least 8 tag bits below its top bit");
  // The tag: low bits of the mixed key, which the slot (its high bits) does not use,
  // with the top bit set so that no tag is 0 (an empty slot never matches one).
  static uint32_t tag_of(uint32_t key) { return (mix(key) << kIndexBits) | 0x80000000u; }

  Vec3 origin_ = Vec3::Zero();
  float leaf_ = 0.005f;
  float inv_leaf_ = 200.f;
  uint32_t size_ = 0;
  static constexpr uint32_t kCacheBits = kVoxelCacheBits;
  // No key sits more than kMaxProbe slots past its home slot: an insert that would is
  // refused (capacity_exceeded), so every probe loop stays bounded even for a cloud
  // crafted to collide, and find() stops there too. Random keys at the 3/4 load limit
  // reach ~150 (measured: 20 fills of 98,304 keys into 131,072 slots); 1,024 leaves
  // honest clouds untouched.
  static constexpr uint32_t kMaxProbe = kVoxelHashSlots < 1024u ? kVoxelHashSlots : 1024u;

 public:
  static constexpr uint32_t max_probe() { return kMaxProbe; }

 private:
  uint32_t count(uint32_t i) const;

  // Empty entries hold key 0xFFFFFFFF: no real key has all bits set (z < kMaxZ - 2).
  // The voxel's byte offset in store_, not its index: the hot path adds it as it is.
  struct CacheEntry {
    uint32_t key;
    uint32_t offset;
  };
  static_assert(uint64_t{4} * sizeof(float) * kMaxVoxels <= 0xFFFFFFFFull, "a voxel's byte offset fits 32 bits");
  // The ingest's recent-cell cache; once the grid is finalized (no more inserts) the
  // same memory holds a Bloom filter of the indexed keys, which find() consults first:
  // most neighbour lookups of the clustering and the normals ask for cells that are
  // empty, and at the table's 3/4 load an absent key's probe walk is long (about 8
  // slots on average) where one load and mask test settles most of them (87% with
  // kMaxVoxels isolated cells on the host; the two-word filter of murmur bits before
  // it settled 89% at 12 more instructions per test).
  union {
    CacheEntry cache_[1u << kCacheBits];
    uint64_t filter_[1u << kCacheBits];
  };
  // A blocked Bloom filter: each key sets two bits of one 64-bit word, so a test is one
  // load. Word and bits come from disjoint fields of the mixed hash (filter_mix).
  static constexpr uint64_t kFilterMul = 0x9E3779B97F4A7C15ull;  // 2^64 / golden ratio, odd
  static constexpr uint32_t kMaxFilterWordBits = 26;             // word bits [38, 64), bit fields [26, 38)
  static_assert(kCacheBits <= kMaxFilterWordBits, "filter word and bit fields are disjoint");
  // The sum hash is linear, so structured keys (a lattice of cells) give correlated
  // fields; one xor-shift and multiply per test decorrelates word and bits.
  static uint64_t filter_mix(uint64_t h) { return (h ^ (h >> 32)) * kFilterMixMul; }
  static uint64_t filter_bits(uint64_t g) {
    return (uint64_t{1} << ((g >> 32) & 63u)) | (uint64_t{1} << ((g >> 26) & 63u));
  }
  void build_filter(const uint8_t* keep);  // keep null: every voxel
  bool filter_on_ = false;
  uint64_t* wide_ = nullptr;  // the caller's memory holding the filter, or null: filter_
  uint32_t filter_word_bits_ = kCacheBits;
  static constexpr uint32_t kIndexAll = 0xFFFFFFFFu;
  uint32_t indexed_ = kIndexAll;  // voxels in the index when pruned (kIndexAll: every one)
  bool finalized_ = false;
  uint32_t slot_bits_ = kSlotBits;  // slots in use: 2^slot_bits_ (fewer once pruned)
  uint32_t slot_mask_ = kVoxelHashSlots - 1;
  uint32_t slots_[kVoxelHashSlots];  // tag | (voxel index + 1); 0 = empty
  uint32_t keys_[kMaxVoxels];
  // Before finalize(): per voxel {sum of (point - cell corner), count} as 4 floats.
  // After: size() packed centroids (3 floats each), then the lendable rest.
  alignas(16) float store_[4 * kMaxVoxels];
};

// The ingest's walk of the hash for a cell the recent-cell cache missed: inline, so
// the ingest's loop keeps its registers across it (a call cost it about a dozen
// instructions of spills, pushes and pops per miss, and the adversarial ingests miss on
// most points).
inline uint32_t VoxelGrid::find_or_add(uint32_t key) {
  uint32_t s = slot_of(key);
  // The table is never more than 3/4 full (limits.hpp), so an empty slot is near; past
  // kMaxProbe the cell is refused (a cloud crafted to collide).
  const uint32_t tag = tag_of(key);
  uint32_t probe = 0;
#if defined(__SSE2__) || defined(__aarch64__)
  // Eight slots per step where a vector unit compares them at once, while the window
  // does not wrap: the same walk as the loop below (the first slot holding the key or
  // the first empty one), with a branch per window instead of one per slot, whose
  // outcome (about three slots to the first empty at this load) the predictor cannot
  // know. kMaxProbe is a multiple of 8 here, so the windows end where the loop would.
  static_assert(kMaxProbe % 8 == 0, "whole windows of probes");
  const uint32_t slots = slot_mask_ + 1u;
  const V4i tag4 = V4i{} + static_cast<int32_t>(tag);
  const V4i hi_mask = V4i{} + static_cast<int32_t>(~kIndexMask);
  for (; probe < kMaxProbe && s + 8 <= slots; probe += 8, s += 8) {
    V4i a, b;
    std::memcpy(&a, slots_ + s, sizeof a);
    std::memcpy(&b, slots_ + s + 4, sizeof b);
    // Slots are never emptied until reset(), so a key held by the table lies before
    // the first empty slot of its walk: a tag match past it is another key, which the
    // key test rejects (a tag matches another key 1 time in 16,384 or less; no tag
    // matches an empty slot).
    for (uint32_t cand = lane_mask((a & hi_mask) == tag4) | (lane_mask((b & hi_mask) == tag4) << 4); cand != 0;
         cand &= cand - 1) {
      const uint32_t index = (slots_[s + static_cast<uint32_t>(__builtin_ctz(cand))] & kIndexMask) - 1;
      if (keys_[index] == key) return index;
    }
    const uint32_t empty = lane_mask(a == 0) | (lane_mask(b == 0) << 4);
    if (empty != 0) return add_at(s + static_cast<uint32_t>(__builtin_ctz(empty)), tag, key);
  }
  // A walk through the table's last window goes on at its first slot.
  s &= slot_mask_;
#endif
  for (; probe < kMaxProbe; ++probe) {
    const uint32_t slot = slots_[s];
    if (slot == 0) return add_at(s, tag, key);
    const uint32_t index = (slot & kIndexMask) - 1;
    if ((slot & ~kIndexMask) == tag && keys_[index] == key) return index;
    s = (s + 1) & slot_mask_;
  }
  return kNone;
}

inline uint32_t VoxelGrid::add_at(uint32_t s, uint32_t tag, uint32_t key) {
  if (size_ >= kMaxVoxels) return kNone;
  keys_[size_] = key;
  float* acc = store_ + size_t{4} * size_;
  acc[0] = acc[1] = acc[2] = acc[3] = 0.f;
  slots_[s] = tag | ++size_;
  return size_ - 1;
}

}  // namespace fg
