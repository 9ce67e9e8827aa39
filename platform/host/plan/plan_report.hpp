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

}  // namespace fg::host
