// Stage A.6, clusters and target: Euclidean clustering of the voxels above the support
// plane, the target cluster, and the target-fragment fall-back.
#pragma once
#include <cstdint>

#include "fg/core/cluster.hpp"
#include "fg/core/config.hpp"
#include "fg/core/point_buffer.hpp"
#include "fg/core/voxel_grid.hpp"

namespace fg {

//! Memory another stage lends while it is idle: `count` 64-bit words, 2^bits <= count.
struct LentWords {
  uint64_t* words = nullptr;
  uint32_t count = 0;
  uint32_t bits = 0;
};

//! The clustering's parameters from the configuration.
ClusterParams target_cluster_params(const PlannerConfig& cfg);

//! Labels the clusters of the kVoxelFree voxels and picks the target (cluster.hpp's
//! cluster_and_pick): its voxel indices go to `target_voxels` (kMaxObjectPoints
//! entries; the caller checks target_size against it). `queue`: grid.size() entries.
//! The walks test their neighbours in a bitmap of the objects' cells in `lent`; when the
//! cells span more than it holds, they ask the hash through the larger lookup filter
//! `lent` then holds. Either is given back before returning (the grid's lookups are
//! prepared again without it). The result goes to `res`.
void find_target(VoxelGrid& grid, uint8_t* state, const ClusterParams& cp, uint32_t* queue, LentWords lent,
                 uint32_t* target_voxels, ClusterResult& res);

//! The target-fragment fall-back (docs/method.md A.6): the larger cluster whose
//! footprint holds the x-y centroid of the first target's points `first` (a stand under
//! a standing bat, a veil of mixed pixels beside a bottle). Its size (its voxels in
//! `target_voxels`, which may hold the first target's), or 0 when there is none.
uint32_t find_covering_cluster(const VoxelGrid& grid, uint8_t* state, uint32_t* queue, const ClusterParams& cp,
                               const PointSpan& first, uint32_t* target_voxels, const ClusterResult& labelled);

}  // namespace fg
