// The collision check's near list (Planner::build_near_list): the voxels a gripper
// could touch, sorted by their cell of a coarse grid over the cube around the
// gripper's reach, so that the check of a box reads only the cells under it instead of
// every voxel in reach (a bound set by the box's size, not the scene's voxel count).
#pragma once
#include <cstdint>

#include "fg/core/types.hpp"

namespace fg {

//! An axis-aligned box in a frame (a gripper part in the grasp frame): x0 < x1 etc.
struct FrameBox {
  float x0, x1, y0, y1, z0, z1;
  //! (x, y, z) lies strictly inside the box shrunk by tol on every side.
  bool holds(float x, float y, float z, float tol) const {
    return x > x0 + tol && x < x1 - tol && y > y0 + tol && y < y1 - tol && z > z0 + tol && z < z1 - tol;
  }
};

//! The coarse grid: cell (x, y, z) of bits[0..2] bits per axis, x slowest, over the
//! cube from `lo`; coordinates outside it fall in its border cells.
struct NearGrid {
  Vec3 lo;
  float inv_cell[3];
  uint32_t bits[3];
  //! The grid over the cube [centre - r, centre + r] with cell_bits bits in all
  //! (split over the axes as evenly as they go).
  static NearGrid around(const Vec3& centre, float r, uint32_t cell_bits);
  //! The cell along axis a of coordinate v, clamped to the grid (NaN: 0).
  uint32_t axis(float v, int a) const {
    const float c = (v - lo[a]) * inv_cell[a];
    const float top = static_cast<float>((1u << bits[a]) - 1u);
    return static_cast<uint32_t>(c >= 0.f ? (c > top ? top : c) : 0.f);
  }
  uint32_t cell(uint32_t x, uint32_t y, uint32_t z) const { return (x << (bits[1] + bits[2])) | (y << bits[2]) | z; }
  uint32_t cell_of(const Vec3& p) const { return cell(axis(p.x(), 0), axis(p.y(), 1), axis(p.z(), 2)); }
};

//! Sorts entries (cell << index_bits | index) by cell, in place, in O(n + 2^cell_bits):
//! one American flag pass. `next` and `end` are caller tables of 2^cell_bits words.
void sort_by_cell(uint32_t* entries, uint32_t n, uint32_t index_bits, uint32_t cell_bits, uint32_t* next,
                  uint32_t* end);

//! True when a point of the sorted entries (points[entry & index mask], skipped where
//! state is 0) lies strictly inside box `b` shrunk by `tol`, the box placed at `pos`
//! with axes[0..2] as its frame's x, y, z in world. Reads only the cells under the
//! box's world bounding box: a binary search and a scan per column of cells.
bool near_list_hits(const uint32_t* entries, uint32_t n, uint32_t index_bits, const NearGrid& g, const Vec3* points,
                    const uint8_t* state, const Vec3& pos, const Vec3 axes[3], const FrameBox& b, float tol);

}  // namespace fg
