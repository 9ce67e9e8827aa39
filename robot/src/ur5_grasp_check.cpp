#include "fg/robot/ur5_grasp_check.hpp"

#include <cmath>

namespace fg::robot {

void Ur5GraspCheck::configure(const GraspCheckConfig& cfg) {
  cfg_ = cfg;
  cfg_.tool.tcp_offset_m = cfg_.motion.tcp_offset_m;
  has_motion_ = false;
  clear_counts();
  do_begin_plan();
}

void Ur5GraspCheck::do_begin_plan() {
  scene_ready_ = false;
  budget_ = PathBudget::of(cfg_.path);
}

void Ur5GraspCheck::set_current_joints(const double q[6]) {
  for (int i = 0; i < 6; ++i) q_now_[i] = q[i];
  has_motion_ = false;
}

void Ur5GraspCheck::clear_counts() {
  asked_ = unreachable_ = collisions_ = path_hits_ = path_budget_hits_ = 0;
  last_hit_ = ToolHit::none;
  last_path_hit_ = PathHit::none;
}

GraspVerdict Ur5GraspCheck::do_check(const GraspQuery& q) {
  ++asked_;
#if FG_ROBOT_WITH_LIBCCD
  if (cfg_.check_tool) {
    // The tool swept over the whole approach line the motion follows.
    GraspQuery swept = q;
    swept.pregrasp = q.pregrasp - q.approach.normalized() * (cfg_.check_reach ? cfg_.motion.standoff_m : 0.f);
    last_hit_ = collision_.check(cfg_.tool, swept);
    if (last_hit_ != ToolHit::none) {
      ++collisions_;
      return GraspVerdict::collision;
    }
  }
#endif
  if (cfg_.check_reach) {
    // One way round, then the other (a parallel gripper grasps the same either way):
    // the first whose joints exist and whose executed path is clear.
    bool reachable = false;
    last_path_hit_ = PathHit::none;
    for (int turn = 0; turn < 2; ++turn) {
      GraspMotion m;
      if (plan_grasp_motion(cfg_.motion, q.position, q.approach, q.closing, q.pregrasp, q_now_, turn == 1, m) !=
          IkStatus::ok)
        continue;
      reachable = true;
      if (cfg_.check_path) {
        // Gathered again when a caller outside the planner hands in another scene.
        if (!scene_ready_ || scene_of_.scene_points != q.scene_points || scene_of_.scene_keep != q.scene_keep ||
            scene_of_.n_scene_points != q.n_scene_points || scene_of_.support != q.support) {
          scene_ = prepare_path_scene(q, &path_scratch_);
          scene_of_ = q;
          scene_ready_ = true;
        }
        const PathHit h = grasp_path_hit(cfg_.motion, cfg_.tool, cfg_.path, q_now_, m, scene_, q, nullptr, &budget_);
        if (h != PathHit::none) {
          last_path_hit_ = h;
          if (h == PathHit::budget) break;  // nothing is left to check the other way round
          continue;
        }
      }
      motion_ = m;
      has_motion_ = true;
      return GraspVerdict::pass;
    }
    if (reachable) {
      // Not cleared: a path that hits, or one the plan's budget could not pay for
      // (turned down as a collision would be: an unchecked path is not executed).
      ++collisions_;
      ++path_hits_;
      if (last_path_hit_ == PathHit::budget) ++path_budget_hits_;
      return GraspVerdict::collision;
    }
    ++unreachable_;
    return GraspVerdict::unreachable;
  }
  return GraspVerdict::pass;
}

}  // namespace fg::robot
