#include "fg/robot/grasp_motion.hpp"

#include <cmath>

namespace fg::robot {

PoseD to_d(const Pose& p) {
  PoseD d;
  d.R = p.R.cast<double>();
  d.t = p.t.cast<double>();
  return d;
}

Pose to_f(const PoseD& d) {
  Pose p;
  p.R = d.R.cast<float>();
  p.t = d.t.cast<float>();
  return p;
}

PoseD compose(const PoseD& a, const PoseD& b) {
  PoseD c;
  c.R = a.R * b.R;
  c.t = a.R * b.t + a.t;
  return c;
}

PoseD inverse(const PoseD& a) {
  PoseD c;
  c.R = a.R.transpose();
  c.t = -(c.R * a.t);
  return c;
}

PoseD tool0_pose(const MotionConfig& cfg, const Vec3& centre, const Vec3& approach, const Vec3& closing, bool turned) {
  PoseD w;
  const Eigen::Vector3d z = approach.cast<double>().normalized();
  Eigen::Vector3d x = (turned ? -1.0 : 1.0) * closing.cast<double>();
  x = (x - z * z.dot(x)).normalized();  // exactly orthogonal in double
  w.R.col(0) = x;
  w.R.col(1) = z.cross(x);
  w.R.col(2) = z;
  w.t = centre.cast<double>() - z * static_cast<double>(cfg.tcp_offset_m);
  return w;
}

namespace {
bool solve(const MotionConfig& cfg, const PoseD& base_T_tool0, const double* near, double* out) {
  IkSolutions sols;
  if (!ik_has_solution(ur5_inverse(cfg.robot, base_T_tool0, sols, cfg.ik))) return false;
  const IkChoice c = choose_nearest(near, sols, cfg.ik.limits);
  if (c.status != IkStatus::ok) return false;
  for (int i = 0; i < 6; ++i) out[i] = c.q[i];
  return true;
}
}  // namespace

IkStatus plan_grasp_motion(const MotionConfig& cfg, const Vec3& position, const Vec3& approach, const Vec3& closing,
                           const Vec3& pregrasp, const double q_now[6], bool turned, GraspMotion& out) {
  if (!position.allFinite() || !approach.allFinite() || !closing.allFinite() || !pregrasp.allFinite())
    return IkStatus::invalid_argument;
  for (int i = 0; i < 6; ++i)
    if (!std::isfinite(q_now[i])) return IkStatus::invalid_argument;
  if (!(approach.norm() > 0.5f) || !(closing.norm() > 0.5f)) return IkStatus::invalid_argument;
  const PoseD base_T_world = inverse(to_d(cfg.world_T_base));
  const Vec3 start = pregrasp - approach.normalized() * cfg.standoff_m;
  const PoseD pre = compose(base_T_world, tool0_pose(cfg, start, approach, closing, turned));
  bool ok = solve(cfg, pre, q_now, out.pregrasp);
  const double* previous = out.pregrasp;
  for (int k = 1; k <= GraspMotion::kApproachSteps && ok; ++k) {
    const float f = static_cast<float>(k) / static_cast<float>(GraspMotion::kApproachSteps);
    const Vec3 centre = k == GraspMotion::kApproachSteps ? position : Vec3(start + (position - start) * f);
    const PoseD step = compose(base_T_world, tool0_pose(cfg, centre, approach, closing, turned));
    ok = solve(cfg, step, previous, out.approach[k - 1]);
    previous = out.approach[k - 1];
  }
  if (!ok) return IkStatus::unreachable;
  for (int i = 0; i < 6; ++i) out.grasp[i] = previous[i];
  PoseD lift_w = tool0_pose(cfg, position, approach, closing, turned);
  lift_w.t.z() += static_cast<double>(cfg.lift_m);
  if (!solve(cfg, compose(base_T_world, lift_w), out.grasp, out.lift)) return IkStatus::unreachable;
  out.turned = turned;
  return IkStatus::ok;
}

IkStatus plan_grasp_motion(const MotionConfig& cfg, const Vec3& position, const Vec3& approach, const Vec3& closing,
                           const Vec3& pregrasp, const double q_now[6], GraspMotion& out) {
  for (int turn = 0; turn < 2; ++turn) {
    const IkStatus s = plan_grasp_motion(cfg, position, approach, closing, pregrasp, q_now, turn == 1, out);
    if (s != IkStatus::unreachable) return s;
  }
  return IkStatus::unreachable;
}

}  // namespace fg::robot
