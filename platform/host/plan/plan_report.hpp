// Host-only: a plan the way `forcegrasp plan` runs and reports it, shared by the program
// and the Python module: the robot's check set up for the scene, and the contract's
// report (spec/scene-and-cli.md) of a plan's outcome as JSON.
#pragma once
#include <nlohmann/json.hpp>

#include "fg/core/config.hpp"
#include "fg/core/planner.hpp"
#include "fg/robot/ur5_grasp_check.hpp"

namespace fg::host {

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

}  // namespace fg::host
