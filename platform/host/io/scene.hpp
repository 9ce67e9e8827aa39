// Host-only: the scene manifest of spec/scene-and-cli.md.
#pragma once
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "fg/core/types.hpp"
#include "point_cloud.hpp"

namespace fg::host {

struct PoseD {
  std::array<double, 3> position{{0, 0, 0}};
  std::array<std::array<double, 3>, 3> rotation{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
};

struct SceneSensor {
  std::string name;                             //!< "head" or "hand"
  std::string cloud_path;                       //!< resolved against the manifest's folder
  std::optional<PoseD> pose;                    //!< world_T_sensor
  std::optional<std::array<double, 6>> joints;  //!< UR5 joints, instead of pose
  std::optional<PoseD> hand_eye;                //!< tool0_T_sensor with joints
  double units_m = 1.0;                         //!< metres per unit of the cloud ("units": m, cm, mm)
};

//! The metres per unit of a cloud's units by name: "m" 1, "cm" 0.01, "mm" 0.001; false
//! for any other name.
[[nodiscard]] bool units_by_name(const std::string& name, double& metres_per_unit);

struct SceneGripper {
  double max_opening = 0.085;
  double finger_width = 0.022;
  double finger_depth = 0.040;
};

//! One value of a scene's gripper block by its key (max_opening, finger_width,
//! finger_depth; metres, each within its range); false with err naming the key and the
//! problem (an unknown key, a value that is not finite or out of range).
[[nodiscard]] bool set_gripper_value(SceneGripper& g, const std::string& key, double value, std::string& err);

struct Scene {
  std::string manifest_path;
  std::vector<SceneSensor> sensors;
  SceneGripper gripper;
};

//! Parses and validates a manifest: JSON syntax, nesting depth, sensor names (head,
//! hand; each at most once), pose shapes and finiteness, rotation orthonormality,
//! gripper ranges. Errors name the file and the problem.
[[nodiscard]] ReadResult read_scene(const std::string& path, Scene& out);
[[nodiscard]] ReadResult parse_scene(const std::string& text, const std::string& manifest_path, Scene& out);

//! A manifest pose as the planner takes it (float).
Pose to_pose(const PoseD& p);

//! Writes a manifest (used by exporters and tests).
[[nodiscard]] ReadResult write_scene(const std::string& path, const Scene& scene);

}  // namespace fg::host
