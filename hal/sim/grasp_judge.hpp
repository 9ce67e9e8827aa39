// Host-only simulation: judges a parallel-gripper grasp on the TRUE geometry of a world.
//
// Gripper frame (core/include/fg/core/gripper.hpp): origin at `position`, +z = approach,
// +x = closing, +y = z cross x. At the open pose the inner pad faces are at
// x = -max_opening/2 and +max_opening/2; each finger is a box x in [face - thickness, face]
// (left) or [face, face + thickness] (right), y in +-finger_width/2, z in +-finger_depth/2;
// the palm box spans x in +-(max_opening/2 + thickness), y in +-palm_width/2,
// z in [-finger_depth/2 - palm_depth, -finger_depth/2].
//
// Success requires, in this order (the reason names the first failure):
//  (a) no collision at the open pose: fingers and palm above the table top and clear of
//      every object (penetration up to collision_tolerance is allowed);
//  (b) closing: rays through each pad's footprint, parallel to x, from the open pad face
//      inwards; each pad's first contact must be on the target (another object or the
//      table reached first is a collision) and both pads must touch it;
//  (c) friction: at each pad, the contact patch is the set of rays meeting the target within
//      0.2 mm of the first contact; the normals there are the target SDF's gradients at
//      points just inside the surface (so at an edge they are the two faces' normals, never
//      the bisector), skipping points on the SDF's creases. The best face of the patch must
//      be inside the friction cone: angle(closing force, -outward normal) <= atan(mu). A flat
//      pad on a face beside an edge passes; a box's diagonal (edges only) fails;
//  (d) |reported width - true width| <= width_tolerance.
#pragma once
#include <string>

#include "fg/core/gripper.hpp"
#include "fg/core/types.hpp"
#include "sim/sim_world.hpp"

namespace fg::sim {

//! A grasp as the planner reports it (spec/scene-and-cli.md), in world.
struct Grasp {
  fg::Vec3 position = fg::Vec3::Zero();
  fg::Vec3 approach = fg::Vec3::UnitZ();
  fg::Vec3 closing = fg::Vec3::UnitX();
  float width = 0.0f;
};

struct JudgeOptions {
  double mu = 0.5;                     //!< friction coefficient of the pads
  double width_tolerance = 0.01;       //!< |reported - true| width allowed (m)
  double collision_tolerance = 0.001;  //!< penetration allowed at the open pose (m)
  int rays_across = 9;                 //!< closing rays across the pad (grasp y)
  int rays_along = 17;                 //!< closing rays along the pad (grasp z)
  double max_frame_skew = 0.05;        //!< |approach . closing| allowed before "invalid_grasp"
};

struct JudgeResult {
  bool success = false;
  std::string reason;        //!< "success" or the first failed criterion
  float true_width = -1.0f;  //!< x_R - x_L between the first contacts (m); -1 if unknown
  float angle_left = -1.0f;  //!< friction angle at each contact (rad); -1 if unknown
  float angle_right = -1.0f;
  fg::Vec3 contact_left = fg::Vec3::Zero();  //!< first contact points (world)
  fg::Vec3 contact_right = fg::Vec3::Zero();
  float max_penetration = 0.0f;  //!< deepest penetration found at the open pose (m), if any
};

[[nodiscard]] JudgeResult judge_grasp(const World& world, int target, const Grasp& grasp,
                                      const fg::GripperGeometry& gripper, const JudgeOptions& options = {});

//! Convenience overload with mu and the other options at their defaults.
[[nodiscard]] JudgeResult judge_grasp(const World& world, int target, const Grasp& grasp,
                                      const fg::GripperGeometry& gripper, double mu);

//! Criterion (a) alone: the open gripper at grasp's pose (width ignored) against the
//! table and every object. "" when clear, else judge_grasp's reason
//! ("collision_open_pose:<what> <part> DEPTH"; "invalid_grasp" for a degenerate frame).
[[nodiscard]] std::string open_pose_collision(const World& world, int target, const Grasp& grasp,
                                              const fg::GripperGeometry& gripper, double tolerance = 0.001);

//! Does the object fit the gripper in some direction? Minimum width over horizontal
//! closing directions of its graspable parts (and of the whole object).
//! Vertical closing is not counted: it needs a finger under the object, which is impossible
//! for objects resting on the table (none of the generated kinds has such an overhang).
struct FitReport {
  bool fits = false;
  double min_width = 0.0;      //!< smallest horizontal width found (m)
  int part = -1;               //!< part giving it (-1 = the whole object)
  V3 direction = V3::UnitX();  //!< closing direction giving it (horizontal, unit)
};

[[nodiscard]] FitReport target_fit(const Object& object, const fg::GripperGeometry& gripper, double margin = 0.005);

}  // namespace fg::sim
