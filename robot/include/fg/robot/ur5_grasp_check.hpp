// The robot's check of a planner candidate (algorithm.md F): the whole tool clear of
// the support plane and the target's convex pieces (libccd, where the build has it),
// and joint solutions inside the limits at the pre-grasp, the grasp and the lift,
// each nearest the one before, starting from the arm's current joints, and the tool
// along the joint path the arm will execute (path_check.hpp). Install it on
// the planner (Planner::set_grasp_check) before plan(); after an ok plan, motion()
// holds the joints of the returned grasp. No heap.
#pragma once
#include <cstdint>

#include "fg/core/grasp_check.hpp"
#include "fg/core/limits.hpp"
#include "fg/robot/grasp_motion.hpp"
#include "fg/robot/path_check.hpp"
#include "fg/robot/tool_collision.hpp"

#ifndef FG_ROBOT_WITH_LIBCCD
#define FG_ROBOT_WITH_LIBCCD 0
#endif

namespace fg::robot {

struct GraspCheckConfig {
  MotionConfig motion;
  ToolGeometry tool;
  bool check_reach = true;  //!< inverse kinematics (needs the current joints)
  bool check_tool = true;   //!< tool collision (ignored in builds without libccd)
  //! The tool along the joint path the arm executes (the free move from the current
  //! joints, then the approach waypoints) against the support plane and the scene
  //! points (path_check.hpp); needs check_reach. When the path of one way round (the
  //! closing direction kept or reversed) hits, the other is tried.
  bool check_path = true;
  PathCheckConfig path;
};

class Ur5GraspCheck final : public GraspCheck {
 public:
  //! tool.gripper and tool.tcp_offset_m should match the planner's gripper and
  //! motion.tcp_offset_m (configure() copies the offset across).
  void configure(const GraspCheckConfig& cfg);
  const GraspCheckConfig& config() const { return cfg_; }
  //! The arm's joints when the images were taken: IK starts from them.
  void set_current_joints(const double q[6]);

  //! Joints of the last candidate that passed (valid when has_motion()).
  bool has_motion() const { return has_motion_; }
  const GraspMotion& motion() const { return motion_; }
  //! Candidates asked about, and turned down, since the last clear_counts().
  uint32_t asked() const { return asked_; }
  uint32_t unreachable() const { return unreachable_; }
  uint32_t collisions() const { return collisions_; }
  //! Candidates turned down because the executed joint path hit (counted in collisions()).
  uint32_t path_hits() const { return path_hits_; }
  //! Of those, the ones whose path was not cleared before the plan's path-check budget
  //! ran out (PathCheckConfig::plan_samples / plan_point_tests).
  uint32_t path_budget_hits() const { return path_budget_hits_; }
  //! What is left of this plan's path-check budget.
  const PathBudget& path_budget() const { return budget_; }
  PathHit last_path_hit() const { return last_path_hit_; }
  ToolHit last_hit() const { return last_hit_; }
  void clear_counts();

  static constexpr bool kHasToolCollision = FG_ROBOT_WITH_LIBCCD != 0;

 private:
  GraspVerdict do_check(const GraspQuery& q) override;
  void do_begin_plan() override;

  GraspCheckConfig cfg_;
  double q_now_[6] = {0.0, -1.5707963267948966, 1.5707963267948966, -1.5707963267948966, -1.5707963267948966, 0.0};
  GraspMotion motion_{};
  PathSceneScratch path_scratch_;  // the kept scene points of the path check, by column
  // The path check's scene, gathered at the plan's first check (the planner's scene
  // does not change during a plan), and the plan's remaining budget.
  PathScene scene_;
  GraspQuery scene_of_{};  // the query whose scene scene_ holds (its arrays' addresses)
  bool scene_ready_ = false;
  PathBudget budget_;
  bool has_motion_ = false;
  uint32_t asked_ = 0, unreachable_ = 0, collisions_ = 0, path_hits_ = 0, path_budget_hits_ = 0;
  PathHit last_path_hit_ = PathHit::none;
  ToolHit last_hit_ = ToolHit::none;
#if FG_ROBOT_WITH_LIBCCD
  ToolCollision collision_;
#endif
};

}  // namespace fg::robot
