// Host-only simulation: seeded, deterministic generation of test scenes (a table, a target
// object of a given kind, maybe a second object, and the head and hand cameras).
// The ycb_* kinds are triangle meshes read from OBJ files (sim/obj_mesh.hpp), each loaded
// once per process from SceneOptions::mesh_dir.
#pragma once
#include <cstdint>
#include <functional>
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
[[nodiscard]] bool kind_from_name(const std::string& name, ObjectKind& out);
//! The OBJ file name of a mesh kind (nullptr for an analytic kind).
const char* mesh_file(ObjectKind k);
//! $FG_MESH_DIR when set and not empty, else the build's FG_DEFAULT_MESH_DIR
//! (<source>/../shared/data/meshes/ycb).
std::string default_mesh_dir();

//! Which scenes make_scene draws.
//!  classic: the project's own spread (the head 0.75-0.9 m above the table near the robot
//!    base, the wrist 0.35-0.55 m away and 25-60 deg up, the target near the workspace
//!    centre, standing as its kind does, sometimes one smaller second object); seeds
//!    pinned by tests are of this distribution.
//!  cell: what a user's robot cell shows (CellOptions): sensors anywhere they can stand,
//!    targets anywhere in the reachable area, lying where they can, wider sizes, up to three
//!    other objects, and structured-light noise (NoiseModel::structured_light).
enum class Distribution { classic, cell };
const char* distribution_name(Distribution d);
[[nodiscard]] bool distribution_from_name(const std::string& name, Distribution& out);

//! The ranges of Distribution::cell. Distances and angles are drawn uniformly unless said.
struct CellOptions {
  //! The head sensor: distance from the target's centre (m), how far its optical axis
  //! looks down (deg below horizontal), and its azimuth about the target within
  //! +-head_azimuth_half_deg of the direction from the target to the robot base (the world
  //! origin): the head stands on the robot's side of the table.
  double head_distance_min = 0.5, head_distance_max = 1.5;
  double head_down_min_deg = 25.0, head_down_max_deg = 75.0;
  double head_azimuth_half_deg = 90.0;
  //! The wrist sensor: anywhere on the hemisphere about the target's centre, distance in
  //! [min, max] and elevation in [min, max] deg (uniform over the sphere's area), any azimuth.
  double wrist_distance_min = 0.25, wrist_distance_max = 0.6;
  double wrist_elevation_min_deg = 10.0, wrist_elevation_max_deg = 90.0;
  //! Both sensors stay at least this far (m) from every object's surface.
  double sensor_clearance = 0.05;
  //! Every size range of a kind widens to [low / size_stretch, high * size_stretch].
  double size_stretch = 1.3;
  //! A kind that may lie (box, can, bottle, ellipsoid, wide_box, the upright meshes) lies
  //! with this probability: on another face, or on its side.
  double lying_rate = 0.5;
  //! Other objects besides the target: 0..others_max of them (uniform), analytic kinds with
  //! the widened sizes, each others_gap_min..others_gap_max (m) from the target surface to
  //! surface (the smallest distance between the two solids), and apart from each other.
  int others_min = 0;  //!< at least this many (then others_min..others_max, uniform)
  int others_max = 3;
  double others_gap_min = 0.03, others_gap_max = 0.30;
  //! Each other object's centre lies this much farther (m, in x-y) from the workspace
  //! centre than the target's: the planner takes the object nearest the workspace centre
  //! for its target (docs/method.md A.6), so the scene's target is the one it is asked for.
  double others_farther = 0.05;
  //! Share of objects with a dark surface (albedo 0.05-0.25; else 0.4-1; the table 0.4-1).
  double dark_rate = 0.25;
};

struct SceneOptions {
  //! The options of a distribution: SceneOptions{} is classic; of(Distribution::cell) sets
  //! the cell ranges, the contract's whole target area, fit_margin = 2 x 3 mm and the
  //! structured-light noise.
  static SceneOptions of(Distribution d);

  Distribution distribution = Distribution::classic;
  CellOptions cell;                 //!< used by Distribution::cell only
  double second_object_rate = 0.3;  //!< classic: probability of a second, smaller object
  fg::GripperGeometry gripper;      //!< the 2F-85 defaults
  Intrinsics intrinsics;            //!< both cameras
  NoiseModel noise;
  Table table;
  //! "fits" means min width <= max_opening - margin. cell: a target of a kind that fits
  //! is drawn within it (up to 3 mm per finger), one of a kind too wide wider than the opening.
  double fit_margin = 0.005;
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
  double target_min_width = 0.0;  //!< smallest horizontal width of a graspable part
  double fit_margin = 0.005;      //!< fits = target_min_width <= max_opening - fit_margin
  V3 target_centre = V3::Zero();  //!< centre of its bounding box (the cameras look here)
  Aabb target_box;
};

struct GeneratedScene {
  std::string kind;
  uint64_t seed = 0;
  Distribution distribution = Distribution::classic;
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
//! The distribution is options.distribution; the same seed draws unrelated scenes in each.
GeneratedScene make_scene(ObjectKind kind, uint64_t seed, const SceneOptions& options = {});

//! Whether a wrist camera can be at world_T_sensor.
using WristPoseTest = std::function<bool(const Rigid& world_T_sensor)>;
//! make_scene where, in cell, a wrist pose `wrist_reachable` refuses is drawn again: a wrist
//! camera is where the arm can put it (`forcegrasp sim` asks the UR5's inverse kinematics).
GeneratedScene make_scene(ObjectKind kind, uint64_t seed, const SceneOptions& options,
                          const WristPoseTest& wrist_reachable);

//! Whether a kind's target is meant to fit the default 0.085 m opening (all but big_sphere,
//! wide_box, ycb_master_chef_can and ycb_scissors).
bool kind_fits(ObjectKind k);

//! The surface-to-surface distance of two objects (m; 0 when they touch or overlap): the
//! smallest exact distance from points 4 mm apart on either surface (edges and corners
//! included; a mesh's vertices) to the other solid, so at most about 1 mm above the truth.
double surface_gap(const Object& a, const Object& b);

//! Builds an object of the kind in its own frame (bottom on z = 0, centred on the origin in
//! x and y), with sizes drawn from `rng_seed` (mesh kinds: fixed size, read from mesh_dir;
//! throws std::runtime_error as make_scene). The name is "target".
Object make_object(ObjectKind kind, uint64_t rng_seed, const std::string& mesh_dir = default_mesh_dir());

//! Recomputes the ground-truth facts of scene.world.objects[scene.target].
GroundTruth compute_truth(const World& world, int target, const fg::GripperGeometry& gripper, double fit_margin);

struct SceneImages {
  DepthImage head;
  DepthImage hand;
};

//! Renders both cameras with the scene's noise model and seeds.
SceneImages render_scene(const GeneratedScene& scene);

}  // namespace fg::sim
