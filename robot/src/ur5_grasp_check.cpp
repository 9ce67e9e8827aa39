#include "fg/robot/ur5_grasp_check.hpp"

#include <cmath>

namespace fg::robot {

void Ur5GraspCheck::configure(const GraspCheckConfig& cfg) {
  cfg_ = cfg;
  cfg_.tool.tcp_offset_m = cfg_.motion.tcp_offset_m;
  has_motion_ = false;
  clear_counts();
}

void Ur5GraspCheck::set_current_joints(const double q[6]) {
  for (int i = 0; i < 6; ++i) q_now_[i] = q[i];
  has_motion_ = false;
}

void Ur5GraspCheck::clear_counts() {
  asked_ = unreachable_ = collisions_ = 0;
  last_hit_ = ToolHit::none;
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
    GraspMotion m;
    if (plan_grasp_motion(cfg_.motion, q.position, q.approach, q.closing, q.pregrasp, q_now_, m) !=
        IkStatus::ok) {
      ++unreachable_;
      return GraspVerdict::unreachable;
    }
    motion_ = m;
    has_motion_ = true;
  }
  return GraspVerdict::pass;
}

}  // namespace fg::robot
