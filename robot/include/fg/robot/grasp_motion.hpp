// From a grasp to joint targets: the flange (tool0) poses of the pre-grasp, the grasp
// and the lift, and their inverse kinematics, each solution nearest the one before
// (so the approach and the lift stay on one arm branch). Embedded side: no heap.
#pragma once
#include "fg/core/types.hpp"
#include "fg/robot/ur5.hpp"
#include "fg/robot/ur5_ik.hpp"

namespace fg::robot {

PoseD to_d(const Pose& p);
Pose to_f(const PoseD& p);
PoseD compose(const PoseD& a, const PoseD& b);
PoseD inverse(const PoseD& a);

struct MotionConfig {
  Ur5Params robot = ur5_nominal();
  Pose world_T_base;           //!< the arm's base_link in the planner's world (identity:
                               //!< world = base_link, as in the scene contract)
  float tcp_offset_m = 0.15f;  //!< flange (tool0) to the pads' centre along tool0 +z
  float lift_m = 0.10f;        //!< straight up (world z) after closing
  //! The arm's free move (joint space, from wherever it is) ends this far behind the
  //! planner's pre-grasp along the approach; the rest is the approach line in steps.
  float standoff_m = 0.06f;
  IkOptions ik;  //!< with the joint limits (ik.limits)
};

struct GraspMotion {
  //! The approach from the pre-grasp to the grasp as a straight line of the pads: joint
  //! targets at equal steps along it, the last one the grasp (a joint-space move between
  //! two poses leaves the line in between; short steps keep it close).
  static constexpr int kApproachSteps = 6;
  double pregrasp[6];  //!< standoff_m behind the planner's pre-grasp
  double approach[kApproachSteps][6];
  double grasp[6];
  double lift[6];
  bool turned;  //!< the closing direction was reversed (the gripper half a turn about
                //!< the approach): a parallel gripper grasps the same way
};

//! world_T_tool0 with the pads' centre at `centre`: tool0 z along `approach`, x along
//! `closing` (reversed when `turned`), the flange tcp_offset behind.
PoseD tool0_pose(const MotionConfig& cfg, const Vec3& centre, const Vec3& approach, const Vec3& closing, bool turned);

//! Joint targets for the grasp (position, approach, closing, pre-grasp in world; the
//! motion starts standoff_m behind that pre-grasp) from
//! the current joints `q_now`: ok, unreachable (no solution inside the limits for one
//! of the three poses, both ways round) or invalid_argument (non-finite input).
[[nodiscard]] IkStatus plan_grasp_motion(const MotionConfig& cfg, const Vec3& position, const Vec3& approach,
                                         const Vec3& closing, const Vec3& pregrasp, const double q_now[6],
                                         GraspMotion& out);
//! Same, one way round only: `turned` false keeps the closing direction, true reverses it.
[[nodiscard]] IkStatus plan_grasp_motion(const MotionConfig& cfg, const Vec3& position, const Vec3& approach,
                                         const Vec3& closing, const Vec3& pregrasp, const double q_now[6], bool turned,
                                         GraspMotion& out);

}  // namespace fg::robot
