// Host-only: a plan the way `forcegrasp plan` runs and reports it, shared by the program
// and the Python module: the robot's check set up for the scene, and the contract's
// report (spec/scene-and-cli.md) of a plan's outcome as JSON.
#pragma once
#include <algorithm>
#include <nlohmann/json.hpp>
#include <vector>

#include "fg/core/config.hpp"
#include "fg/core/planner.hpp"
#include "fg/robot/ur5_grasp_check.hpp"

namespace fg::host {

//! The order to add n sensors in: the head's first, the others in theirs, so that the
//! hand's cloud is registered to the head's before it joins the grid (docs/method.md
//! A.4b). is_head(i): sensor i is the head.
template <class IsHead>
std::vector<size_t> head_first(size_t n, IsHead is_head) {
  std::vector<size_t> order(n);
  for (size_t i = 0; i < n; ++i) order[i] = i;
  std::stable_partition(order.begin(), order.end(), is_head);
  return order;
}

//! Sets up the robot's check (robot/ur5_grasp_check.hpp) for a plan: the whole tool
//! against the plane and the target always; inverse kinematics too when the arm's
//! current joints are known (`current_joints`: six angles in URDF order, or null).
//! Fills check_cfg. The check holds 64 KiB of scratch: keep one per planner.
void set_up_robot_check(robot::Ur5GraspCheck& check, const PlannerConfig& cfg, const double* current_joints,
                        robot::GraspCheckConfig& check_cfg);

//! The report of a plan that ended ok, no_grasp or with an internal error: the status,
//! the grasp with every check's margin and the arm's joints (ok), the reason and message
//! (no_grasp) or the error; then the points, the crop box, the search's counts, the
//! stages' times (timing_us) and the support plane. The caller adds its own figures.
nlohmann::json plan_report(const Planner& planner, const PlanResult& res, Status st, const PlannerConfig& cfg,
                           const robot::GraspCheckConfig& check_cfg, const robot::Ur5GraspCheck& check);

//! The ranked grasps of a plan that ended ok (`--top N`): the returned grasp, then
//! Planner::more_grasps()'s alternates, each as `grasp` is reported plus its `rank`
//! (0: the returned one) and `score`: the friction cone's margin as a share of the
//! cone's half-angle (1: the contact normals on the closing line; 0: on the cone; null:
//! not measured). The order is the planner's (force balance), not the score's.
nlohmann::json ranked_grasps_report(const PlanResult& best, const RankedGrasp* more, uint32_t n_more,
                                    const PlannerConfig& cfg, const robot::GraspCheckConfig& check_cfg);

//! The plan of the target as `forcegrasp plan` runs it, once the sensors are added and
//! the robot's check is set up (set_up_robot_check): plan() with that check, and for a
//! status ok or no_grasp the report (plan_report), with the `grasps` list of the `top`
//! best when top > 0 and the plan found a grasp. `alternates` (optional) gets the ranked
//! alternates' grasps. Returns plan()'s status; `res` is its result.
Status plan_target(Planner& planner, const PlannerConfig& cfg, robot::Ur5GraspCheck& check,
                   const robot::GraspCheckConfig& check_cfg, uint32_t top, PlanResult& res, nlohmann::json& report,
                   std::vector<Grasp>* alternates = nullptr);

//! Every object the last plan() listed (`--objects all`), nearest the workspace centre
//! first, each planned for itself (Planner::plan_object) with the others as obstacles:
//! its index, whether it is the plan's target, its centroid, box and voxels, and its
//! status with the grasp (and the `grasps` list of the `top` best) or the no_grasp reason
//! and message, or the error. Afterwards the planner's search is the last object's.
nlohmann::json objects_report(Planner& planner, const PlannerConfig& cfg, robot::Ur5GraspCheck& check,
                              const robot::GraspCheckConfig& check_cfg, uint32_t top);

//! Adds the objects to a plan's report: `objects` (objects_report), `objects_dropped` (the
//! objects beyond the build's FG_MAX_OBJECTS, left out) and, when some were, a `note`.
void add_objects(nlohmann::json& report, Planner& planner, const PlannerConfig& cfg, robot::Ur5GraspCheck& check,
                 const robot::GraspCheckConfig& check_cfg, uint32_t top);

}  // namespace fg::host
