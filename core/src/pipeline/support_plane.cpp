// Stage A.5: the support plane (support_plane.hpp).
#include "fg/core/pipeline/support_plane.hpp"

#include <algorithm>

#include "fg/core/cluster.hpp"

namespace fg {

SupportPlane find_support_plane(VoxelGrid& grid, const PlannerConfig& cfg, uint8_t* state) {
  SupportPlane out;
  grid.finalize();  // sums become centroids; no more points until reset()
  const uint32_t nv = grid.size();
  const Vec3* centroids = grid.centroids();
  PlaneParams pp;
  pp.distance_m = cfg.plane_distance_m;
  pp.iterations = cfg.ransac_iterations;
  pp.seed = cfg.ransac_seed;
  pp.max_tilt_rad = cfg.plane_max_tilt_rad;
  uint32_t inliers = 0;
  out.found = ransac_plane(centroids, nv, pp, out.plane, inliers);
  if (!out.found) {
    float zmin = centroids[0].z();
    for (uint32_t i = 1; i < nv; ++i) zmin = std::min(zmin, centroids[i].z());
    out.plane.n = Vec3::UnitZ();
    out.plane.d = -zmin;
  }
  uint32_t removed = 0;
  for (uint32_t i = 0; i < nv; ++i) {
    const bool table = out.found && out.plane.height(centroids[i]) < cfg.object_min_height_m;
    state[i] = table ? kVoxelRemoved : kVoxelFree;
    removed += table ? 1u : 0u;
  }
  out.removed = removed;
  // Neighbour searches from here on (clustering, normals) look for object voxels
  // only: take the support plane out of the hash.
  static_assert(kVoxelRemoved == 0, "the states double as the keep flags");
  if (removed > 0) grid.keep_in_index_only(state);
  return out;
}

}  // namespace fg
