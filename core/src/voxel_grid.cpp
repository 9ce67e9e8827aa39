#include "fg/core/voxel_grid.hpp"

namespace fg {

void VoxelGrid::reset(const Vec3& origin, float leaf_m) {
  origin_ = origin;
  leaf_ = leaf_m;
  inv_leaf_ = 1.0f / leaf_m;
  if (!initialised_) {
    for (uint32_t s = 0; s < kVoxelHashSlots; ++s) slots_[s] = Slot{0u, 0u};
  } else {
    // Clear only the slots in use, so a reset costs O(voxels), not O(slots). Each
    // voxel's slot holds its index + 1; probe from its home slot until found.
    for (uint32_t i = 0; i < size_; ++i) {
      uint32_t s = slot_of(voxels_[i].key);
      for (uint32_t probe = 0; probe < kVoxelHashSlots; ++probe) {
        if (slots_[s].index1 == i + 1) {
          slots_[s].index1 = 0;
          break;
        }
        s = (s + 1) & (kVoxelHashSlots - 1);
      }
    }
  }
  initialised_ = true;
  size_ = 0;
  for (uint32_t i = 0; i < (1u << kCacheBits); ++i) {
    cache_key_[i] = 0xFFFFFFFFu;
    cache_index_[i] = 0;
  }
}

uint32_t VoxelGrid::find(uint32_t key) const {
  uint32_t s = slot_of(key);
  for (uint32_t probe = 0; probe < kVoxelHashSlots; ++probe) {
    const Slot& sl = slots_[s];
    if (sl.index1 == 0) return kNone;
    if (sl.key == key) return sl.index1 - 1;
    s = (s + 1) & (kVoxelHashSlots - 1);
  }
  return kNone;
}

uint32_t VoxelGrid::find_or_add(uint32_t key) {
  uint32_t s = slot_of(key);
  // The table is never more than half full (limits.hpp), so an empty slot is near.
  for (uint32_t probe = 0; probe < kVoxelHashSlots; ++probe) {
    Slot& sl = slots_[s];
    if (sl.index1 == 0) {
      if (size_ >= kMaxVoxels) return kNone;
      voxels_[size_] = Voxel{key, 0u, 0.f, 0.f, 0.f};
      sl.key = key;
      sl.index1 = ++size_;
      return size_ - 1;
    }
    if (sl.key == key) return sl.index1 - 1;
    s = (s + 1) & (kVoxelHashSlots - 1);
  }
  return kNone;
}

Vec3 VoxelGrid::centroid(uint32_t i) const {
  const Voxel& v = voxels_[i];
  const float inv = 1.0f / static_cast<float>(v.count);
  return Vec3(origin_.x() + static_cast<float>(key_x(v.key)) * leaf_ + v.sx * inv,
              origin_.y() + static_cast<float>(key_y(v.key)) * leaf_ + v.sy * inv,
              origin_.z() + static_cast<float>(key_z(v.key)) * leaf_ + v.sz * inv);
}

}  // namespace fg
