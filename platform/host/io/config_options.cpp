#include "config_options.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "text_parse.hpp"

namespace fg::host {

std::vector<ConfigOption> config_options(PlannerConfig& c) {
  using K = ConfigOption::Kind;
  return {
      {"max_opening", "gripper opening (m)", K::real, &c.gripper.max_opening_m},
      {"min_opening", "smallest graspable width (m)", K::real, &c.gripper.min_opening_m},
      {"finger_width", "pad extent across the closing plane (m)", K::real, &c.gripper.finger_width_m},
      {"finger_depth", "pad extent along the approach (m)", K::real, &c.gripper.finger_depth_m},
      {"finger_thickness", "finger extent along the closing direction (m)", K::real, &c.gripper.finger_thickness_m},
      {"palm_depth", "palm box extent along the approach (m)", K::real, &c.gripper.palm_depth_m},
      {"palm_width", "palm box extent across the closing plane (m)", K::real, &c.gripper.palm_width_m},
      {"range_min", "sensor depth filter, near limit (m)", K::real, &c.range_min_m},
      {"range_max", "sensor depth filter, far limit (m)", K::real, &c.range_max_m},
      {"crop_half_x", "crop box half size in x about the workspace centre (m)", K::real, &c.crop_half_x_m},
      {"crop_half_y", "crop box half size in y about the workspace centre (m)", K::real, &c.crop_half_y_m},
      {"crop_shrink_min", "on voxel overflow the crop box x/y halves shrink down to this (m)", K::real,
       &c.crop_shrink_min_m},
      {"crop_min_z", "crop box lower z (m)", K::real, &c.crop_min_z_m},
      {"crop_max_z", "crop box upper z (m)", K::real, &c.crop_max_z_m},
      {"voxel_leaf", "voxel grid leaf (m)", K::real, &c.voxel_leaf_m},
      {"plane_distance", "RANSAC inlier distance (m)", K::real, &c.plane_distance_m},
      {"ransac_iterations", "RANSAC iteration bound", K::count, &c.ransac_iterations},
      {"ransac_seed", "RANSAC PRNG seed", K::count, &c.ransac_seed},
      {"plane_max_tilt", "support plane normal tilt from z (rad)", K::real, &c.plane_max_tilt_rad},
      {"object_min_height", "points lower above the plane are table (m)", K::real, &c.object_min_height_m},
      {"cluster_cells", "clustering neighbour radius in voxels (1 or 2)", K::count, &c.cluster_cells},
      {"min_object_points", "smallest target cluster (voxels)", K::count, &c.min_object_points},
      {"workspace_centre_x", "workspace centre x (m)", K::real, &c.workspace_centre_x_m},
      {"workspace_centre_y", "workspace centre y (m)", K::real, &c.workspace_centre_y_m},
      {"target_rule", "nearest (to the workspace centre) or largest", K::rule, &c.target_rule},
      {"dtheta", "viewpoint step (rad)", K::real, &c.dtheta_rad},
      {"extension_dtheta", "viewpoint step of the extended search (rad)", K::real, &c.extension_dtheta_rad},
      {"single_sensor_arc", "viewpoint half arc with one sensor (rad)", K::real, &c.single_sensor_arc_rad},
      {"vertical_snap", "principal axis this close to z becomes z (rad)", K::real, &c.vertical_snap_rad},
      {"vertical_snap_round", "the same for a round body: middle eigenvalue < 6 x smallest (rad)", K::real,
       &c.vertical_snap_round_rad},
      {"axis_ratio_min", "largest/middle eigenvalue below this: axis = z", K::real, &c.axis_ratio_min},
      {"extend_search", "search other viewpoint families when the arc fails", K::flag, &c.extend_search},
      {"approach_view_max", "approaches stay within this angle of a sensor's sight line (rad)", K::real,
       &c.approach_view_max_rad},
      {"scan_delta", "scan line spacing (m)", K::real, &c.scan_delta_m},
      {"dx_threshold", "discontinuity threshold (m)", K::real, &c.dx_threshold_m},
      {"width_margin", "lines must be narrower than max_opening - margin (m)", K::real, &c.width_margin_m},
      {"hull_cell", "concave hull raster cell (m)", K::real, &c.hull_cell_m},
      {"hull_closing_cells", "concave hull closing radius (cells)", K::count, &c.hull_closing_cells},
      {"candidates_per_view", "candidates kept per viewpoint", K::count, &c.candidates_per_view},
      {"centre_weight", "rank = beta + weight * |window - centroid| (rad/m)", K::real, &c.centre_weight},
      {"beta_max", "XOY balance threshold (rad)", K::real, &c.beta_max_rad},
      {"contact_band", "contact region depth (m)", K::real, &c.contact_band_m},
      {"reach_width_ratio", "width within the pads' reach / silhouette width, at least", K::real, &c.reach_width_ratio},
      {"friction_mu", "friction coefficient of the contact-normal test (0: off)", K::real, &c.friction_mu},
      {"round_flanks", "round flanks seen to a grazing edge close on their unseen tangents", K::flag, &c.round_flanks},
      {"table_clearance", "gripper clearance above the support plane (m)", K::real, &c.table_clearance_m},
      {"collision_tolerance", "points this close to a gripper box face are tolerated (m)", K::real,
       &c.collision_tolerance_m},
      {"pregrasp_clearance", "pre-grasp back-off beyond the finger depth (m)", K::real, &c.pregrasp_clearance_m},
      {"palm_clearance", "the palm stops this far before the first surface (m)", K::real, &c.palm_clearance_m},
      {"paper_depth", "position at the contacts' mean depth, as the paper", K::flag, &c.paper_depth},
      {"executability_checks", "table, collision and friction checks", K::flag, &c.executability_checks},
  };
}

namespace {
bool parse_real(const std::string& s, float& out) {
  if (s.empty()) return false;
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (errno != 0 || end != s.c_str() + s.size() || !std::isfinite(v)) return false;
  out = static_cast<float>(v);
  return std::isfinite(out);
}
}  // namespace

bool set_config_option(PlannerConfig& cfg, const std::string& name, const std::string& value, std::string& error) {
  for (const ConfigOption& o : config_options(cfg)) {
    if (name != o.name) continue;
    switch (o.kind) {
      case ConfigOption::real: {
        float v = 0;
        if (!parse_real(value, v)) {
          error = text::cat("option ", name, ": \"", value, "\" is not a finite number");
          return false;
        }
        *static_cast<float*>(o.field) = v;
        return true;
      }
      case ConfigOption::count: {
        char* end = nullptr;
        errno = 0;
        const unsigned long long v = std::strtoull(value.c_str(), &end, 10);
        if (value.empty() || value[0] == '-' || errno != 0 || end != value.c_str() + value.size() ||
            v > 0xFFFFFFFFull) {
          error = text::cat("option ", name, ": \"", value, "\" is not a whole number");
          return false;
        }
        *static_cast<uint32_t*>(o.field) = static_cast<uint32_t>(v);
        return true;
      }
      case ConfigOption::flag:
        if (value == "true" || value == "1" || value == "on")
          *static_cast<bool*>(o.field) = true;
        else if (value == "false" || value == "0" || value == "off")
          *static_cast<bool*>(o.field) = false;
        else {
          error = text::cat("option ", name, ": \"", value, "\" is not true or false");
          return false;
        }
        return true;
      case ConfigOption::rule:
        if (value == "nearest")
          *static_cast<TargetRule*>(o.field) = TargetRule::nearest_to_centre;
        else if (value == "largest")
          *static_cast<TargetRule*>(o.field) = TargetRule::largest;
        else {
          error = text::cat("option ", name, ": \"", value, "\" is not nearest or largest");
          return false;
        }
        return true;
    }
  }
  error = "unknown option \"" + name + "\"";
  // Names an earlier version used: say what the option is called now.
  static const char* const kRenamed[][2] = {{"delta", "scan_delta"}, {"dx_th", "dx_threshold"}};
  for (const auto& r : kRenamed)
    if (name == r[0]) error += text::cat(" (it is named ", r[1], ")");
  return false;
}

nlohmann::json default_config_json() { return config_json(PlannerConfig{}); }

nlohmann::json config_json(PlannerConfig cfg) {
  nlohmann::json j = nlohmann::json::object();
  for (const ConfigOption& o : config_options(cfg)) {
    switch (o.kind) {
      case ConfigOption::real: {
        char buf[32];  // the float's shortest faithful decimal, not its double expansion
        std::snprintf(buf, sizeof buf, "%.7g", static_cast<double>(*static_cast<float*>(o.field)));
        j[o.name] = std::strtod(buf, nullptr);
        break;
      }
      case ConfigOption::count:
        j[o.name] = *static_cast<uint32_t*>(o.field);
        break;
      case ConfigOption::flag:
        j[o.name] = *static_cast<bool*>(o.field);
        break;
      case ConfigOption::rule:
        j[o.name] = *static_cast<TargetRule*>(o.field) == TargetRule::largest ? "largest" : "nearest";
        break;
    }
  }
  return j;
}

bool load_config_file(PlannerConfig& cfg, const std::string& path, std::string& error) {
  std::ifstream f(path, std::ios::binary);
  if (!f) {
    error = path + ": cannot open the configuration file";
    return false;
  }
  std::stringstream ss;
  ss << f.rdbuf();
  const std::string text = ss.str();
  if (text.size() > (1u << 20)) {
    error = path + ": configuration file is larger than 1 MiB";
    return false;
  }
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    error = path + ": invalid JSON: " + e.what();
    return false;
  }
  if (!j.is_object()) {
    error = path + ": the configuration must be a JSON object of options";
    return false;
  }
  for (auto it = j.begin(); it != j.end(); ++it) {
    std::string value;
    if (it->is_boolean())
      value = it->get<bool>() ? "true" : "false";
    else if (it->is_number_unsigned())
      value = std::to_string(it->get<uint64_t>());
    else if (it->is_number()) {
      std::ostringstream os;
      os.precision(9);
      os << it->get<double>();
      value = os.str();
    } else if (it->is_string())
      value = it->get<std::string>();
    else {
      error = text::cat(path, ": option ", it.key(), " must be a number, boolean or string");
      return false;
    }
    std::string e;
    if (!set_config_option(cfg, it.key(), value, e)) {
      error = text::cat(path, ": ", e);
      return false;
    }
  }
  return true;
}

}  // namespace fg::host
