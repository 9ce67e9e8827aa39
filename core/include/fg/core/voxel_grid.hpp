// One voxel grid shared by both sensors (so merging the clouds is free): a fixed
// open-addressing hash from packed cell keys to a dense array of voxels in insertion
// order (deterministic). Each voxel keeps the sum of its points relative to its cell
// corner, so centroids stay precise (micrometres for typical counts, 0.1 mm for a
// million points in one cell) wherever the cell lies.
#pragma once
#include <cstdint>
#include "fg/core/limits.hpp"
#include "fg/core/status.hpp"
#include "fg/core/types.hpp"

namespace fg {

constexpr uint32_t detail_log2u(uint32_t v) { return v <= 1 ? 0 : 1 + detail_log2u(v >> 1); }

struct Voxel {
  uint32_t key;    //!< x | y << 11 | z << 22 (cell indices relative to the grid origin)
  uint32_t count;  //!< points that fell in the cell
  float sx, sy, sz;  //!< sum of (point - cell corner)
};

class VoxelGrid {
 public:
  static constexpr uint32_t kNone = 0xFFFFFFFFu;
  static constexpr int32_t kMaxX = 2047, kMaxY = 2047, kMaxZ = 1023;

  //! Empties the grid. `origin` is the corner of cell (0,0,0); callers keep every
  //! inserted point at least 2 cells inside the key range (checked by insert).
  void reset(const Vec3& origin, float leaf_m);

  //! Adds a world point. capacity_exceeded when another cell is needed but kMaxVoxels
  //! cells are in use; invalid_argument when the point is outside the key range.
  Status insert(const Vec3& p) {
    const float fx = (p.x() - origin_.x()) * inv_leaf_;
    const float fy = (p.y() - origin_.y()) * inv_leaf_;
    const float fz = (p.z() - origin_.z()) * inv_leaf_;
    if (!(fx >= 2.f && fy >= 2.f && fz >= 2.f && fx < kMaxX - 2 && fy < kMaxY - 2 && fz < kMaxZ - 2))
      return Status::invalid_argument;
    return insert_cell(fx, fy, fz) ? Status::ok : Status::capacity_exceeded;
  }

  //! The hot path of insert(): (fx, fy, fz) are coordinates in cell units from the
  //! origin, already checked to lie in [2, kMax - 2). False when the grid is full.
  bool insert_cell(float fx, float fy, float fz) {
    const uint32_t ix = static_cast<uint32_t>(fx), iy = static_cast<uint32_t>(fy),
                   iz = static_cast<uint32_t>(fz);
    const uint32_t key = ix | (iy << 11) | (iz << 22);
    // A small direct-mapped cache of recent cells: neighbouring pixels of a depth
    // image (in this row and the rows above) mostly fall in the same few hundred cells.
    const uint32_t h = (key * 0x9E3779B1u) >> (32 - kCacheBits);
    uint32_t idx = cache_index_[h];
    if (cache_key_[h] != key) {
      idx = find_or_add(key);
      if (idx == kNone) return false;
      cache_key_[h] = key;
      cache_index_[h] = idx;
    }
    Voxel& v = voxels_[idx];
    v.count += 1;
    v.sx += (fx - static_cast<float>(ix)) * leaf_;
    v.sy += (fy - static_cast<float>(iy)) * leaf_;
    v.sz += (fz - static_cast<float>(iz)) * leaf_;
    return true;
  }

  uint32_t size() const { return size_; }
  float leaf() const { return leaf_; }
  const Vec3& origin() const { return origin_; }
  const Voxel& voxel(uint32_t i) const { return voxels_[i]; }
  Vec3 centroid(uint32_t i) const;
  //! Index of the voxel with `key`, or kNone.
  uint32_t find(uint32_t key) const;

  static uint32_t pack(uint32_t ix, uint32_t iy, uint32_t iz) { return ix | (iy << 11) | (iz << 22); }
  static uint32_t key_x(uint32_t k) { return k & 0x7FFu; }
  static uint32_t key_y(uint32_t k) { return (k >> 11) & 0x7FFu; }
  static uint32_t key_z(uint32_t k) { return k >> 22; }

 private:
  uint32_t find_or_add(uint32_t key);
  static uint32_t slot_of(uint32_t key) {
    return (key * 0x9E3779B1u) >> (32 - kSlotBits);
  }
  static constexpr uint32_t kSlotBits = detail_log2u(kVoxelHashSlots);

  Vec3 origin_ = Vec3::Zero();
  float leaf_ = 0.005f;
  float inv_leaf_ = 200.f;
  uint32_t size_ = 0;
  static constexpr uint32_t kCacheBits = 12;
  // Empty entries hold 0xFFFFFFFF: no real key has all bits set (z < kMaxZ - 2).
  uint32_t cache_key_[1u << kCacheBits];
  uint32_t cache_index_[1u << kCacheBits];
  bool initialised_ = false;
  struct Slot {
    uint32_t key;
    uint32_t index1;  // voxel index + 1; 0 = empty
  };
  Slot slots_[kVoxelHashSlots];  // keys kept in the slots: a probe touches one cache line
  Voxel voxels_[kMaxVoxels];
};

}  // namespace fg
