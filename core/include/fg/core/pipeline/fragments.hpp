// Stage A.6, its second step: fragments of one object joined. A structured-light
// sensor loses the returns of surfaces it sees at a steep angle, so two sensors
// looking at a round body from opposite sides each see a patch of it, and the bands
// between the patches, which neither saw, split it into two clusters. The target is
// then a fragment, and a grasp planned on it closes on the unseen rest.
#pragma once
#include <cstdint>

#include "fg/core/cluster.hpp"
#include "fg/core/config.hpp"
#include "fg/core/pipeline/sensor_views.hpp"
#include "fg/core/pipeline/target.hpp"
#include "fg/core/voxel_grid.hpp"

namespace fg {

//! Pairs of listed objects tested for joining at most, per plan (the nearest the
//! workspace centre first): the step's bound.
inline constexpr uint32_t kMaxFragmentTests = 8;
//! Points of each object, near the other, that the test reads at most.
inline constexpr uint32_t kFragmentSamples = 256;

//! The gap across which two clusters may be one object: the chord across the bands a
//! sensor loses on each side of a round body (steep beyond 60 deg of incidence, 30 deg
//! of arc on either side of its silhouette) on the widest round body the gripper
//! closes on, radius half the opening: 2 r sin(30 deg) = r.
float fragment_gap(const PlannerConfig& cfg);

//! After cluster_and_pick (find_target): joins listed objects (res.objects) that meet
//! through space no sensor saw free. Two objects meet when they come within
//! fragment_gap of each other and every segment from a point of one, near the other,
//! to the nearest point of the other crosses no point some sensor saw free (a ray
//! passed it before its return): one object's fragments meet through its unseen
//! inside, two objects' gap holds space a sensor saw past them. The object nearer the
//! workspace centre keeps the other as a fragment (ObjectSummary::fragment_seed); the
//! list stays ordered by distance to the centre. The target becomes the object that
//! holds it (by_rule nearest_to_centre: the nearest object); its voxels are marked
//! kVoxelTarget and listed in `target_voxels` (capacity entries). `queue`: the
//! labelling's, untouched since (each listed object's voxels at its `first`); `lent`:
//! 2 x kFragmentSamples 32-bit words at least. Deterministic; at most
//! kMaxFragmentTests tests, each O(both objects' voxels + kFragmentSamples^2 / 16).
void join_fragments(const VoxelGrid& grid, uint8_t* state, const uint32_t* queue, const ClusterParams& cp,
                    const SensorViews& views, float max_gap, LentWords lent, uint32_t* target_voxels, uint32_t capacity,
                    ClusterResult& res);

//! Makes object `o` the target, its fragments with it (mark_cluster for each seed):
//! its voxel indices in `target` (at most capacity), its size returned (0 when its seed
//! is not a labelled voxel).
uint32_t mark_object(const VoxelGrid& grid, uint8_t* state, uint32_t* queue, const ClusterParams& cp,
                     const ObjectSummary& o, uint32_t* target, uint32_t capacity);

}  // namespace fg
