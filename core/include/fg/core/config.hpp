// Planner configuration: every tunable of design/algorithm.md with its documented
// default (docs/configuration.md) and a validator that names the offending field.
#pragma once
#include <cstdint>

#include "fg/core/gripper.hpp"
#include "fg/core/status.hpp"

namespace fg {

enum class TargetRule : uint8_t { nearest_to_centre = 0, largest = 1 };

struct PlannerConfig {
  GripperGeometry gripper;

  // A. partial model
  float range_min_m = 0.30f;  //!< sensor-frame depth (z) range filter
  float range_max_m = 1.50f;
  float crop_half_x_m = 0.60f;  //!< workspace crop box about the workspace centre
  float crop_half_y_m = 0.60f;
  //! When the merged cloud would need more than kMaxVoxels voxels, the crop box's x and
  //! y halves shrink about the workspace centre, not below this (docs/method.md A).
  float crop_shrink_min_m = 0.45f;
  float crop_min_z_m = -0.50f;  //!< world z limits of the crop box
  float crop_max_z_m = 1.50f;
  float voxel_leaf_m = 0.005f;
  float plane_distance_m = 0.010f;   //!< RANSAC inlier distance
  uint32_t ransac_iterations = 200;  //!< at most kRansacMaxIters
  uint32_t ransac_seed = 42;
  float plane_max_tilt_rad = 0.3490659f;  //!< 20 deg from world z
  float object_min_height_m = 0.006f;     //!< points lower than this above the plane are table
  uint32_t cluster_cells = 1;             //!< neighbour radius in voxels (1: 26-connected)
  uint32_t min_object_points = 30;        //!< smaller clusters are noise
  float workspace_centre_x_m = 0.5f;
  float workspace_centre_y_m = 0.0f;
  TargetRule target_rule = TargetRule::nearest_to_centre;

  // B/C. object frame and viewpoints
  float dtheta_rad = 0.0872665f;               //!< 5 deg viewpoint step
  float single_sensor_arc_rad = 1.5707963f;    //!< +-90 deg with one sensor
  float vertical_snap_rad = 0.2617994f;        //!< principal axis within 15 deg of z -> z
  float vertical_snap_round_rad = 0.5235988f;  //!< the same for a round body, within 30 deg
  float axis_ratio_min = 1.3f;                 //!< largest/middle eigenvalue below this -> axis = z
  bool extend_search = true;                   //!< rest of the circle + other PCA axes when the arc fails;
                                               //!< the target-fragment fall-back (docs/method.md A.6)
  float extension_dtheta_rad = 0.1745329f;     //!< 10 deg viewpoint step of those families
  float approach_view_max_rad = 1.0471976f;    //!< approach within 60 deg of a sensor's sight line

  // D. XOY force balance
  float scan_delta_m = 0.002f;       //!< scan line spacing
  float dx_threshold_m = 0.004f;     //!< discontinuity threshold
  float width_margin_m = 0.004f;     //!< keep lines narrower than max_opening - margin
  float hull_cell_m = 0.0025f;       //!< concave hull raster cell
  uint32_t hull_closing_cells = 2;   //!< concave hull closing radius (cells)
  uint32_t candidates_per_view = 3;  //!< best candidates kept per viewpoint
  float centre_weight = 0.5f;        //!< rad/m: rank = beta + w |y_window - y_centroid|
                                     //!< (1e-6: the paper, centre only breaks ties)

  // E/F. XOZ balance, selection, checks
  float beta_max_rad = 0.2f;
  float contact_band_m = 0.004f;     //!< contact region depth inside each side
  float reach_width_ratio = 0.6f;    //!< width within the pads' reach / silhouette width, at least
  float friction_mu = 0.5f;          //!< friction-cone test of contact normals (0 = off)
  bool round_flanks = true;          //!< a round body's flanks seen to a grazing edge close on
                                     //!< their unseen tangents (docs/method.md, check 5)
  float table_clearance_m = 0.003f;  //!< gripper boxes stay this far above the plane
  float collision_tolerance_m = 0.001f;
  float pregrasp_clearance_m = 0.02f;
  float palm_clearance_m = 0.005f;   //!< the palm stops this far before the first surface
  bool paper_depth = false;          //!< true: position at the contacts' mean z (the paper)
  bool executability_checks = true;  //!< table, collision and friction checks
};

//! Checks every field; on failure returns invalid_config and points `field` at the
//! name of the first offending field (a static string).
[[nodiscard]] Status validate(const PlannerConfig& cfg, const char** field);

}  // namespace fg
