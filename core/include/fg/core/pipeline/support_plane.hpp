// Stage A.5, the support plane: RANSAC over the merged cloud's voxel centroids, then
// the plane and everything below object_min_height taken out of the object search.
#pragma once
#include <cstdint>

#include "fg/core/config.hpp"
#include "fg/core/plane.hpp"
#include "fg/core/voxel_grid.hpp"

namespace fg {

struct SupportPlane {
  Plane plane;           //!< found, or the level plane through the lowest point
  bool found = false;    //!< a plane within plane_max_tilt of level had enough inliers
  uint32_t removed = 0;  //!< voxels taken out (the plane and below)
};

//! Finalizes `grid` (sums become centroids), finds the support plane, and sets
//! state[i] (grid.size() entries) to kVoxelRemoved for the voxels less than
//! object_min_height above it, kVoxelFree for the rest; the removed voxels leave the
//! grid's index. Without a plane nothing is removed, and the level plane through the
//! lowest voxel stands in for the floor in the clearance checks. The grid must hold at
//! least one voxel.
SupportPlane find_support_plane(VoxelGrid& grid, const PlannerConfig& cfg, uint8_t* state);

}  // namespace fg
