// Euclidean clustering on the voxel grid (cells within `cells` of each other are
// neighbours: 26-connectivity for 1) and the choice of the target cluster.
#pragma once
#include <cstdint>

#include "fg/core/config.hpp"
#include "fg/core/limits.hpp"
#include "fg/core/types.hpp"
#include "fg/core/voxel_grid.hpp"

namespace fg {

//! Per-voxel state used by the clustering (one byte per voxel).
enum VoxelState : uint8_t { kVoxelRemoved = 0, kVoxelFree = 1, kVoxelVisited = 2, kVoxelTarget = 3 };

//! What picks the target among the clusters: the configured rule (the default), the
//! cluster nearest a world point (the least distance from the point to any of its
//! voxel centroids), or the cluster with the most voxel centroids inside a world box.
enum class TargetKind : uint8_t { by_rule = 0, nearest_point = 1, inside_box = 2 };
struct TargetSpec {
  TargetKind kind = TargetKind::by_rule;
  Vec3 point = Vec3::Zero();                            //!< nearest_point
  Vec3 box_min = Vec3::Zero(), box_max = Vec3::Zero();  //!< inside_box (inclusive)
};

//! A target spec's own check: a known kind, finite numbers, a box whose minimum is at
//! most its maximum on every axis. invalid_argument or non_finite (message: static text
//! naming the problem), ok otherwise.
[[nodiscard]] Status validate(const TargetSpec& t, const char** message);

struct ClusterParams {
  uint32_t cells = 1;
  uint32_t min_points = 30;
  float centre_x = 0.5f, centre_y = 0.f;
  TargetRule rule = TargetRule::nearest_to_centre;
  TargetSpec target;  //!< by_rule: `rule` picks
};

//! Clusters joined to one object at most, besides its own (pipeline/fragments.hpp):
//! every other listed one.
inline constexpr uint32_t kMaxJoinedFragments = kMaxObjects > 1u ? kMaxObjects - 1u : 1u;

//! One object on the support plane, as the labelling found it (world frame).
struct ObjectSummary {
  uint32_t seed = 0;             //!< its first voxel (lowest index): mark_cluster() takes it again
  uint32_t voxels = 0;           //!< its voxels (its fragments' included)
  Vec3 centroid = Vec3::Zero();  //!< the mean of its voxel centroids
  Vec3 box_min = Vec3::Zero(), box_max = Vec3::Zero();  //!< the box of its voxels' cells
  //! Clusters of the same object that no connected voxels join to it, only space no
  //! sensor saw (join_fragments): a seed each.
  uint32_t fragment_seed[kMaxJoinedFragments] = {};
  uint32_t fragments = 0;
  //! Right after cluster_and_pick: its voxels' indices start at queue[first] (the
  //! labelling's queue holds every listed cluster, one after another).
  uint32_t first = 0;
};

//! One cluster as the labelling found it: its first voxel (lowest index), its size
//! and the x-y box of its cells (key indices).
struct ClusterSummary {
  uint32_t seed = 0, size = 0;
  uint32_t x0 = 0, x1 = 0, y0 = 0, y1 = 0;
};

struct ClusterResult {
  uint32_t clusters = 0;      //!< clusters of at least min_points
  uint32_t target_size = 0;   //!< voxels in the target (0: none)
  uint32_t other_points = 0;  //!< non-removed voxels outside the target
  //! The largest clusters of at least min_points (the target among them), largest
  //! first, ties in the order found; a cluster that did not fit in the list leaves its
  //! size in largest_dropped. retarget_to_cover reads its candidates from here instead
  //! of walking every voxel again when none larger than the target was dropped.
  static constexpr uint32_t kLargestKept = 8;
  ClusterSummary largest[kLargestKept];
  uint32_t n_largest = 0;
  uint32_t largest_dropped = 0;
  //! The clusters of at least min_points nearest the workspace centre (x-y distance of
  //! their centroids), nearest first, ties in the order found; `objects_dropped` counts
  //! those beyond kMaxObjects, which are left out.
  ObjectSummary objects[kMaxObjects];
  uint32_t n_objects = 0;
  uint32_t objects_dropped = 0;
  //! Empty lists and counts (the lists' entries past their counts are never read). Not
  //! an assignment of a fresh result: clang-tidy takes the loop variable of the
  //! implicit copy of the arrays for a reserved identifier.
  void clear() {
    clusters = target_size = other_points = 0;
    n_largest = largest_dropped = 0;
    n_objects = objects_dropped = 0;
  }
};

//! The cells of the voxels in one state as a bitmap over their bounding box grown by 2
//! cells on every side (so every neighbour offset of the clustering stays inside), in
//! caller memory. The clustering's walk then settles each neighbour with one bit test
//! and asks the hash only for the cells it enters: of the example's 73,000 neighbour
//! look-ups about one in 32 finds a voxel not yet walked.
struct CellBitmap {
  uint64_t* words = nullptr;
  uint32_t x0 = 0, y0 = 0, z0 = 0;  // key indices of the box's first cell, less 2
  uint32_t nx = 0, ny = 0;          // the box's cells along x and y
  uint32_t cell(uint32_t key) const {
    return (VoxelGrid::key_x(key) - x0) + nx * ((VoxelGrid::key_y(key) - y0) + ny * (VoxelGrid::key_z(key) - z0));
  }
};

//! Sets `out` to the bitmap of the voxels whose state is `from` when it fits in
//! `n_words` words of `words` (false, and nothing usable, otherwise: a box of stray
//! voxels far apart, or no such voxel). `list`: scratch of grid.size() entries (the
//! clustering's queue will do). One pass over the voxels' states, then over the set's.
[[nodiscard]] bool build_cell_bitmap(const VoxelGrid& grid, const uint8_t* state, uint8_t from, uint32_t* list,
                                     uint64_t* words, uint32_t n_words, CellBitmap& out);

//! Labels the connected components of the voxels whose state is kVoxelFree, picks the
//! target (params.target; by rule: nearest centroid to the centre in x-y, or the
//! largest; ties go to the component found first; inside_box: none when no cluster has
//! a voxel centroid in the box), lists the objects (ClusterResult::objects) and marks its voxels kVoxelTarget (the
//! others kVoxelVisited). `queue` needs grid.size() entries. Target voxel indices are written to `target` in
//! breadth-first order (at most target_capacity; the caller checks target_size against it). O(voxels * neighbours):
//! every voxel is queued once. `free_cells`, optional: build_cell_bitmap's bitmap of the kVoxelFree voxels (it is
//! consumed: the walks clear the bits they visit); the same result, faster.
//! The result goes to `res` (about a kilobyte: filled in place, never a temporary).
void cluster_and_pick(const VoxelGrid& grid, uint8_t* state, uint32_t* queue, const ClusterParams& params,
                      uint32_t* target, uint32_t target_capacity, ClusterResult& res, CellBitmap* free_cells = nullptr);

//! The target-fragment fall-back (docs/method.md A.6), after cluster_and_pick: among
//! the components of the voxels marked kVoxelVisited (the clusters not picked), the
//! largest of at least min_points and more than `old_size` voxels, at most
//! `target_capacity`, whose x-y footprint (the x-y box of its cells: its voxel centres
//! grown by half a voxel) contains (cx, cy), the old target's x-y centroid: the old
//! target is a fragment over or beside it. Ties go to the component found first. When
//! there is one, the old target's voxels (old_target[0, old_size)) become
//! kVoxelVisited, the chosen cluster's kVoxelTarget, its voxel indices go to `target` in
//! breadth-first order and its size is returned; else 0, and every state is as it
//! was. `old_target` may be `target`. `queue` needs grid.size() entries.
//! With `labelled` (cluster_and_pick's result for this state) holding every cluster
//! larger than old_size, only the chosen cluster is walked; otherwise (or with nullptr)
//! O(voxels * neighbours): every non-target voxel is walked once, the chosen cluster twice.
uint32_t retarget_to_cover(const VoxelGrid& grid, uint8_t* state, uint32_t* queue, const ClusterParams& params,
                           const uint32_t* old_target, uint32_t old_size, float cx, float cy, uint32_t* target,
                           uint32_t target_capacity, const ClusterResult* labelled = nullptr);

//! Makes the cluster of voxel `seed` the target: every kVoxelTarget voxel becomes
//! kVoxelVisited, then the component of `seed` through kVoxelVisited voxels becomes
//! kVoxelTarget (after cluster_and_pick, a seed of its object list). Its voxel indices go
//! to `target` in breadth-first order (at most target_capacity) and its size is returned
//! (0 when seed is not a voxel in kVoxelVisited or kVoxelTarget state: nothing changes).
//! `queue` needs grid.size() entries. O(voxels + the cluster's voxels * neighbours).
uint32_t mark_cluster(const VoxelGrid& grid, uint8_t* state, uint32_t* queue, const ClusterParams& params,
                      uint32_t seed, uint32_t* target, uint32_t target_capacity);

//! The component of voxel `seed` through voxels in state `from`, marked `mark` (!=
//! from); its voxel indices in queue[0, size), its size returned (0 when seed is not
//! in state `from`). `queue` needs grid.size() entries.
uint32_t walk_cluster(const VoxelGrid& grid, uint8_t* state, uint32_t* queue, const ClusterParams& params,
                      uint32_t seed, uint8_t from, uint8_t mark);

namespace detail {
//! The lookup filter's verdicts on the hashes kh + oh[o], o < n <= 32: bit o set when
//! f.may_hold(kh + oh[o]). The flood's neighbour test; exposed for its tests. The
//! vector form reads oh in whole steps of four (pad it) and needs
//! filter_mask_vector_available() (AVX2 on x86-64; elsewhere it is the scalar form).
uint32_t filter_mask_scalar(const VoxelGrid::LookupFilter& f, uint64_t kh, const uint64_t* oh, uint32_t n);
uint32_t filter_mask_vector(const VoxelGrid::LookupFilter& f, uint64_t kh, const uint64_t* oh, uint32_t n);
bool filter_mask_vector_available();
}  // namespace detail

}  // namespace fg
