// Stage A.6: clusters and target (target.hpp).
#include "fg/core/pipeline/target.hpp"

#include "fg/core/limits.hpp"

namespace fg {

ClusterParams target_cluster_params(const PlannerConfig& cfg) {
  ClusterParams cp;
  cp.cells = cfg.cluster_cells;
  cp.min_points = cfg.min_object_points;
  cp.centre_x = cfg.workspace_centre_x_m;
  cp.centre_y = cfg.workspace_centre_y_m;
  cp.rule = cfg.target_rule;
  return cp;
}

// Not inlined: its bitmap stays off the planner's frame, which the deepest stack path
// holds.
[[gnu::noinline]] void find_target(VoxelGrid& grid, uint8_t* state, const ClusterParams& cp, uint32_t* queue,
                                   LentWords lent, uint32_t* target_voxels, ClusterResult& res) {
  CellBitmap free_cells;
  const bool dense = build_cell_bitmap(grid, state, kVoxelFree, queue, lent.words, lent.count, free_cells);
  if (!dense) grid.prepare_lookups(state, lent.words, lent.bits);
  cluster_and_pick(grid, state, queue, cp, target_voxels, kMaxObjectPoints, res, dense ? &free_cells : nullptr);
  grid.prepare_lookups(state);  // the lent memory back (the same kept set)
}

uint32_t find_covering_cluster(const VoxelGrid& grid, uint8_t* state, uint32_t* queue, const ClusterParams& cp,
                               const PointSpan& first, uint32_t* target_voxels, const ClusterResult& labelled) {
  const uint32_t n = first.size();
  if (n == 0) return 0;
  double sx = 0.0, sy = 0.0;
  for (uint32_t i = 0; i < n; ++i) {
    sx += first[i].x();
    sy += first[i].y();
  }
  const float cx = static_cast<float>(sx / n), cy = static_cast<float>(sy / n);
  return retarget_to_cover(grid, state, queue, cp, target_voxels, n, cx, cy, target_voxels, kMaxObjectPoints,
                           &labelled);
}

}  // namespace fg
