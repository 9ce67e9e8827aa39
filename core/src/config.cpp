#include "fg/core/config.hpp"

#include <cmath>

#include "fg/core/limits.hpp"

namespace fg {
namespace {
bool in(float v, float lo, float hi) { return std::isfinite(v) && v >= lo && v <= hi; }
}  // namespace

Status validate(const PlannerConfig& c, const char** field) {
  const char* bad = nullptr;
  const GripperGeometry& g = c.gripper;
  if (!in(g.max_opening_m, 0.005f, 0.5f))
    bad = "gripper.max_opening";
  else if (!in(g.min_opening_m, 0.0f, g.max_opening_m))
    bad = "gripper.min_opening";
  else if (!in(g.finger_width_m, 0.002f, 0.2f))
    bad = "gripper.finger_width";
  else if (!in(g.finger_depth_m, 0.005f, 0.3f))
    bad = "gripper.finger_depth";
  else if (!in(g.finger_thickness_m, 0.0f, 0.1f))
    bad = "gripper.finger_thickness";
  else if (!in(g.palm_depth_m, 0.0f, 0.5f))
    bad = "gripper.palm_depth";
  else if (!in(g.palm_width_m, 0.0f, 0.5f))
    bad = "gripper.palm_width";
  else if (!in(c.range_min_m, 0.0f, 20.0f))
    bad = "range_min";
  else if (!in(c.range_max_m, c.range_min_m + 0.01f, 20.0f))
    bad = "range_max";
  else if (!in(c.voxel_leaf_m, 0.001f, 0.05f))
    bad = "voxel_leaf";
  // The voxel key packs 11 + 11 + 10 bits of cell index: the crop box must fit.
  else if (!in(c.crop_half_x_m, 0.01f, 1000.f) || 2.f * c.crop_half_x_m / c.voxel_leaf_m > 2040.f)
    bad = "crop_half_x";
  else if (!in(c.crop_half_y_m, 0.01f, 1000.f) || 2.f * c.crop_half_y_m / c.voxel_leaf_m > 2040.f)
    bad = "crop_half_y";
  else if (!in(c.crop_shrink_min_m, 0.01f, 1000.f))
    bad = "crop_shrink_min";
  else if (!in(c.crop_min_z_m, -100.f, 100.f))
    bad = "crop_min_z";
  else if (!in(c.crop_max_z_m, c.crop_min_z_m + 0.01f, 100.f) ||
           (c.crop_max_z_m - c.crop_min_z_m) / c.voxel_leaf_m > 1016.f)
    bad = "crop_max_z";
  else if (!in(c.plane_distance_m, 0.0005f, 0.1f))
    bad = "plane_distance";
  else if (c.ransac_iterations < 1 || c.ransac_iterations > kRansacMaxIters)
    bad = "ransac_iterations";
  else if (!in(c.plane_max_tilt_rad, 0.0f, 1.5708f))
    bad = "plane_max_tilt";
  else if (!in(c.object_min_height_m, 0.0f, 0.2f))
    bad = "object_min_height";
  else if (c.cluster_cells < 1 || c.cluster_cells > 2)
    bad = "cluster_cells";
  else if (c.min_object_points < 3 || c.min_object_points > kMaxObjectPoints)
    bad = "min_object_points";
  else if (!in(c.workspace_centre_x_m, -100.f, 100.f))
    bad = "workspace_centre_x";
  else if (!in(c.workspace_centre_y_m, -100.f, 100.f))
    bad = "workspace_centre_y";
  else if (c.target_rule != TargetRule::nearest_to_centre && c.target_rule != TargetRule::largest)
    bad = "target_rule";
  else if (!in(c.dtheta_rad, 0.0087f, 1.5708f))
    bad = "dtheta";
  else if (!in(c.extension_dtheta_rad, 0.0087f, 1.5708f))
    bad = "extension_dtheta";
  else if (!in(c.single_sensor_arc_rad, 0.0f, 3.1416f))
    bad = "single_sensor_arc";
  else if (!in(c.vertical_snap_rad, 0.0f, 1.5708f))
    bad = "vertical_snap";
  else if (!in(c.vertical_snap_round_rad, 0.0f, 1.5708f))
    bad = "vertical_snap_round";
  else if (!in(c.axis_ratio_min, 1.0f, 100.f))
    bad = "axis_ratio_min";
  else if (!in(c.approach_view_max_rad, 0.0f, 3.1416f))
    bad = "approach_view_max";
  else if (!in(c.scan_delta_m, 0.0005f, 0.05f))
    bad = "scan_delta";
  else if (!in(c.dx_threshold_m, 0.0001f, 0.1f))
    bad = "dx_threshold";
  else if (!in(c.width_margin_m, 0.0f, g.max_opening_m * 0.5f))
    bad = "width_margin";
  else if (!in(c.hull_cell_m, 0.0005f, 0.05f))
    bad = "hull_cell";
  else if (c.hull_closing_cells > 8)
    bad = "hull_closing_cells";
  else if (c.candidates_per_view < 1 || c.candidates_per_view > 16)
    bad = "candidates_per_view";
  else if (!in(c.centre_weight, 0.0f, 100.f))
    bad = "centre_weight";
  else if (!in(c.beta_max_rad, 0.0f, 1.5708f))
    bad = "beta_max";
  else if (!in(c.contact_band_m, 0.0005f, 0.05f))
    bad = "contact_band";
  else if (!in(c.reach_width_ratio, 0.0f, 1.0f))
    bad = "reach_width_ratio";
  else if (!in(c.friction_mu, 0.0f, 10.f))
    bad = "friction_mu";
  else if (!in(c.table_clearance_m, -0.05f, 0.1f))
    bad = "table_clearance";
  else if (!in(c.collision_tolerance_m, 0.0f, 0.02f))
    bad = "collision_tolerance";
  else if (!in(c.pregrasp_clearance_m, 0.0f, 0.5f))
    bad = "pregrasp_clearance";
  else if (!in(c.palm_clearance_m, 0.0f, 0.1f))
    bad = "palm_clearance";
  if (field != nullptr) *field = bad;
  return bad == nullptr ? Status::ok : Status::invalid_config;
}

}  // namespace fg
