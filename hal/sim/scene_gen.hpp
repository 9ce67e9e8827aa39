// Host-only simulation: seeded, deterministic generation of test scenes (a table, a target
// object of a given kind, maybe a second object, and the head and hand cameras).
// The ycb_* kinds are triangle meshes read from OBJ files (sim/obj_mesh.hpp), each loaded
// once per process from SceneOptions::mesh_dir.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "fg/core/gripper.hpp"
#include "sim/depth_render.hpp"
#include "sim/sim_world.hpp"

namespace fg::sim {

enum class ObjectKind {
  box,             //!< upright box, narrower than the opening in exactly one horizontal direction
  can,             //!< upright cylinder
  bottle,          //!< body cylinder + ellipsoid shoulder + neck + cap
  spray_bottle,    //!< box body + neck + trigger head + nozzle
  sphere,          //!< fits the gripper
  big_sphere,      //!< too wide
  ellipsoid,       //!< resting on its lowest point, one horizontal width < 0.08 m
  lying_cylinder,  //!< axis horizontal, random yaw
  bat_standing,    //!< table-tennis bat on the edge of its disc, in a small stand
  bat_lying,       //!< table-tennis bat lying flat
  wide_box,        //!< too wide in every horizontal direction
  // YCB meshes (data/meshes/ycb), fixed sizes, each on a stable face of its convex hull.
  // Smallest horizontal widths in brackets (the opening is 0.085 m, fit margin 5 mm).
  ycb_mustard_bottle,   //!< upright (0.058)
  ycb_master_chef_can,  //!< upright; too wide (0.102)
  ycb_tomato_soup_can,  //!< upright (0.067)
  ycb_cracker_box,      //!< upright, fits by its thickness (0.072)
  ycb_banana,           //!< lying on its largest stable face (0.069)
  ycb_power_drill,      //!< upright on its battery (0.057)
  ycb_scissors,         //!< lying flat; too wide (0.087)
  ycb_chips_can,        //!< upright (0.078; the V-HACD collision hull: one closed cylinder)
};

//! The 11 analytic kinds (box .. wide_box).
const std::vector<ObjectKind>& all_kinds();
//! The ycb_* kinds, which need the mesh files.
const std::vector<ObjectKind>& mesh_kinds();
const char* kind_name(ObjectKind k);
//! Knows every kind, analytic and mesh.
bool kind_from_name(const std::string& name, ObjectKind& out);
//! The OBJ file name of a mesh kind (nullptr for an analytic kind).
const char* mesh_file(ObjectKind k);
//! $FG_MESH_DIR when set and not empty, else the build's FG_DEFAULT_MESH_DIR
//! (<source>/../shared/data/meshes/ycb).
std::string default_mesh_dir();

struct SceneOptions {
  double second_object_rate = 0.3;    //!< probability of a second, smaller object
  fg::GripperGeometry gripper;        //!< the 2F-85 defaults
  Intrinsics intrinsics;              //!< both cameras
  NoiseModel noise;
  Table table;
  double fit_margin = 0.005;          //!< "fits" means min width <= max_opening - margin
  V3 workspace_centre = V3(0.5, 0.0, 0.0);  //!< a second object is kept farther from it
  //! Where the target stands: x in [target_x_min, target_x_max], |y| <= target_y_half.
  //! The defaults keep it near the workspace centre; the scene contract's whole area
  //! (shared/spec/scene-and-cli.md) is x 0.3..0.7, y -0.35..0.35.
  double target_x_min = 0.4, target_x_max = 0.6, target_y_half = 0.15;
  //! The head camera looks at the workspace centre (a head that does not turn towards the
  //! target) instead of the target's centre.
  bool head_at_workspace = false;
  //! The head camera's height above the table (m), and the wrist camera's distance from
  //! the target's centre (m) and elevation above the table (degrees): drawn uniformly.
  double head_height_min = 0.75, head_height_max = 0.9;
  double hand_distance_min = 0.35, hand_distance_max = 0.55;
  double hand_elevation_min_deg = 25.0, hand_elevation_max_deg = 60.0;
  std::string mesh_dir = default_mesh_dir();  //!< folder of the ycb_* OBJ files
};

//! Facts about the target that a judge needs.
struct GroundTruth {
  bool target_fits = false;
  double target_min_width = 0.0;      //!< smallest horizontal width of a graspable part
  double fit_margin = 0.005;          //!< fits = target_min_width <= max_opening - fit_margin
  V3 target_centre = V3::Zero();      //!< centre of its bounding box (the cameras look here)
  Aabb target_box;
};

struct GeneratedScene {
  std::string kind;
  uint64_t seed = 0;
  World world;
  int target = 0;
  Camera head;
  Camera hand;
  NoiseModel noise;
  uint64_t head_noise_seed = 0;
  uint64_t hand_noise_seed = 0;
  fg::GripperGeometry gripper;
  GroundTruth truth;
};

//! Same kind, seed and options -> identical scene (and identical rendered images).
//! Throws std::runtime_error naming the file when a mesh kind's OBJ file is missing or bad.
GeneratedScene make_scene(ObjectKind kind, uint64_t seed, const SceneOptions& options = {});

//! Builds an object of the kind in its own frame (bottom on z = 0, centred on the origin in
//! x and y), with sizes drawn from `rng_seed` (mesh kinds: fixed size, read from mesh_dir;
//! throws std::runtime_error as make_scene). The name is "target".
Object make_object(ObjectKind kind, uint64_t rng_seed, const std::string& mesh_dir = default_mesh_dir());

//! Recomputes the ground-truth facts of scene.world.objects[scene.target].
GroundTruth compute_truth(const World& world, int target, const fg::GripperGeometry& gripper,
                          double fit_margin);

struct SceneImages {
  DepthImage head;
  DepthImage hand;
};

//! Renders both cameras with the scene's noise model and seeds.
SceneImages render_scene(const GeneratedScene& scene);

}  // namespace fg::sim
