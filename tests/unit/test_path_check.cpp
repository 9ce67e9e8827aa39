// The tool along the executed joint path (robot/path_check.hpp) against independent
// oracles: forward kinematics sampled ten times denser than the check, with the
// gripper's boxes written out here from GripperGeometry; constructed planes and points
// at poses the path is known to pass through; and the UR5 check, whose accepted
// motions must have a clear path by that oracle.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "fg/robot/path_check.hpp"
#include "fg/robot/ur5_grasp_check.hpp"

using namespace fg;
using robot::PathHit;
using V3d = Eigen::Vector3d;

namespace {

struct Pads {
  V3d centre;
  Eigen::Matrix3d R;  // x closing, z approach
};

Pads pads_at(const robot::MotionConfig& mc, const double q[6]) {
  robot::PoseD t;
  EXPECT_TRUE(robot::ur5_forward_d(mc.robot, q, t));
  const robot::PoseD w = robot::compose(robot::to_d(mc.world_T_base), t);
  return {w.t + w.R.col(2) * static_cast<double>(mc.tcp_offset_m), w.R};
}

// Depth of p inside the open fingers or the palm (grasp frame boxes written from the
// geometry), > 0 inside, <= 0 outside.
double depth_in_gripper(const GripperGeometry& g, const Pads& pose, const V3d& p) {
  const V3d l = pose.R.transpose() * (p - pose.centre);
  const double ho = 0.5 * g.max_opening_m, t = g.finger_thickness_m, hfd = 0.5 * g.finger_depth_m;
  struct B {
    V3d lo, hi;
  } boxes[3] = {{V3d(-ho - t, -0.5 * g.finger_width_m, -hfd), V3d(-ho, 0.5 * g.finger_width_m, hfd)},
                {V3d(ho, -0.5 * g.finger_width_m, -hfd), V3d(ho + t, 0.5 * g.finger_width_m, hfd)},
                {V3d(-ho - t, -0.5 * g.palm_width_m, -hfd - g.palm_depth_m), V3d(ho + t, 0.5 * g.palm_width_m, -hfd)}};
  double best = -1e9;
  for (const B& b : boxes) {
    const V3d a = (l - b.lo).cwiseMin(b.hi - l);
    best = std::max(best, a.minCoeff());
  }
  return best;
}

// Lowest corner of the open fingers and the palm above the plane z = 0.
double lowest_gripper_corner(const GripperGeometry& g, const Pads& pose) {
  const double ho = 0.5 * g.max_opening_m + g.finger_thickness_m, hfd = 0.5 * g.finger_depth_m;
  const double hw = 0.5 * std::max(g.palm_width_m, g.finger_width_m);
  double zmin = 1e9;
  for (int k = 0; k < 8; ++k) {
    const V3d c((k & 1) ? ho : -ho, (k & 2) ? hw : -hw, (k & 4) ? hfd : -hfd - g.palm_depth_m);
    zmin = std::min(zmin, (pose.centre + pose.R * c).z());
  }
  return zmin;
}

robot::ToolGeometry no_body_tool() {
  robot::ToolGeometry tool;
  tool.tcp_offset_m = 0.055f;  // the palm reaches the flange: fingers and palm only, as the oracle has them
  return tool;
}

robot::MotionConfig motion_for(const robot::ToolGeometry& tool) {
  robot::MotionConfig mc;
  mc.tcp_offset_m = tool.tcp_offset_m;
  return mc;
}

const double kQa[6] = {0.3, -1.2, 1.4, -1.8, -1.57, 0.2};
const double kQb[6] = {-0.9, -1.9, 2.1, -1.2, -1.2, 1.0};

}  // namespace

TEST(PathCheck, APointOnThePathIsFoundAndOneAwayFromItIsNot) {
  const robot::ToolGeometry tool = no_body_tool();
  const robot::MotionConfig mc = motion_for(tool);
  const robot::PathCheckConfig cfg;
  // The palm's centre half way along the joint line (forward kinematics of the mean joints).
  double qm[6];
  for (int i = 0; i < 6; ++i) qm[i] = 0.5 * (kQa[i] + kQb[i]);
  const Pads mid = pads_at(mc, qm);
  const Vec3 palm = (mid.centre - mid.R.col(2) * (0.5 * tool.gripper.finger_depth_m + 0.5 * tool.gripper.palm_depth_m))
                        .cast<float>();
  std::vector<Vec3> pts{Vec3(2.f, 2.f, 2.f), palm};
  uint8_t keep[2] = {1, 1};
  GraspQuery q{};
  q.scene_points = pts.data();
  q.scene_keep = keep;
  q.n_scene_points = 2;
  double at = -1.0;
  EXPECT_EQ(robot::joint_segment_hit(mc, tool, cfg, kQa, kQb, q, &at), PathHit::scene);
  EXPECT_GT(at, 0.3);
  EXPECT_LT(at, 0.7);
  keep[1] = 0;  // the same point taken for the support plane: ignored
  EXPECT_EQ(robot::joint_segment_hit(mc, tool, cfg, kQa, kQb, q), PathHit::none);
  q.scene_keep = nullptr;  // no flags: every point counts
  EXPECT_EQ(robot::joint_segment_hit(mc, tool, cfg, kQa, kQb, q), PathHit::scene);
  q.n_scene_points = 1;  // only the far point
  EXPECT_EQ(robot::joint_segment_hit(mc, tool, cfg, kQa, kQb, q), PathHit::none);
}

TEST(PathCheck, AgreesWithADenseForwardKinematicsOracle) {
  // Random joint segments and random points near the path: a point the dense samples
  // put more than 8 mm inside the gripper (the palm: a finger is 10 mm thick) is found; one they keep more than 4 mm
  // outside everywhere is not (the check's samples are at most 0.01 rad apart).
  const robot::ToolGeometry tool = no_body_tool();
  const robot::MotionConfig mc = motion_for(tool);
  const robot::PathCheckConfig cfg;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uq(-0.6, 0.6), uf(0.0, 1.0), ub(-0.06, 0.06);
  int inside = 0, outside = 0;
  for (int trial = 0; trial < 60; ++trial) {
    double qa[6], qb[6];
    for (int i = 0; i < 6; ++i) {
      qa[i] = kQa[i] + uq(rng);
      qb[i] = kQa[i] + uq(rng);
    }
    // A point near the gripper somewhere along the segment.
    double qs[6];
    const double f = uf(rng);
    for (int i = 0; i < 6; ++i) qs[i] = qa[i] + f * (qb[i] - qa[i]);
    const Pads p = pads_at(mc, qs);
    const V3d point = p.centre + p.R * V3d(ub(rng), ub(rng), ub(rng) - 0.03);
    double deepest = -1e9;
    constexpr int kDense = 4000;
    for (int k = 1; k <= kDense; ++k) {
      double qd[6];
      for (int i = 0; i < 6; ++i) qd[i] = qa[i] + (qb[i] - qa[i]) * k / kDense;
      deepest = std::max(deepest, depth_in_gripper(tool.gripper, pads_at(mc, qd), point));
    }
    const Vec3 pf = point.cast<float>();
    GraspQuery q{};
    q.scene_points = &pf;
    q.n_scene_points = 1;
    const PathHit h = robot::joint_segment_hit(mc, tool, cfg, qa, qb, q);
    if (deepest > 0.008) {
      ++inside;
      EXPECT_EQ(h, PathHit::scene) << "trial " << trial << " depth " << deepest;
    } else if (deepest < -0.004) {
      ++outside;
      EXPECT_EQ(h, PathHit::none) << "trial " << trial << " depth " << deepest;
    }
  }
  EXPECT_GE(inside, 10);
  EXPECT_GE(outside, 10);
}

TEST(PathCheck, APlaneThePathDipsUnderIsFound) {
  const robot::ToolGeometry tool = no_body_tool();
  const robot::MotionConfig mc = motion_for(tool);
  const robot::PathCheckConfig cfg;
  // A segment whose gripper dips at least 2 cm below both its ends (seeded search),
  // its lowest corner by dense sampling.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uq(-1.2, 1.2);
  double qa[6], qb[6], q_low[6], low = 1e9, ends = -1e9;
  for (int attempt = 0; attempt < 200 && !(low < ends - 0.02); ++attempt) {
    for (int i = 0; i < 6; ++i) {
      qa[i] = kQa[i] + uq(rng);
      qb[i] = kQa[i] + uq(rng);
    }
    low = 1e9;
    constexpr int kDense = 4000;
    for (int k = 0; k <= kDense; ++k) {
      double qd[6];
      for (int i = 0; i < 6; ++i) qd[i] = qa[i] + (qb[i] - qa[i]) * k / kDense;
      const double z = lowest_gripper_corner(tool.gripper, pads_at(mc, qd));
      if (z < low) {
        low = z;
        for (int i = 0; i < 6; ++i) q_low[i] = qd[i];
      }
    }
    ends = std::min(lowest_gripper_corner(tool.gripper, pads_at(mc, qa)),
                    lowest_gripper_corner(tool.gripper, pads_at(mc, qb)));
  }
  ASSERT_LT(low, ends - 0.02) << "no segment that dips below its ends";
  Plane plane;
  plane.n = Vec3::UnitZ();
  GraspQuery q{};
  q.support = &plane;
  // A plane between the dip and the ends: only samples in between can find it.
  plane.d = -static_cast<float>(0.5 * (low + ends));
  EXPECT_EQ(robot::joint_segment_hit(mc, tool, cfg, qa, qb, q), PathHit::support_plane);
  // Starting at the dip, under that plane: the tool is leaving a contact it is in; the
  // way up is not judged until it is clear, and the rest of the way is (the way back
  // down from the far end is not).
  EXPECT_EQ(robot::joint_segment_hit(mc, tool, cfg, q_low, qb, q), PathHit::none);
  EXPECT_EQ(robot::joint_segment_hit(mc, tool, cfg, qb, q_low, q), PathHit::support_plane);
  // A plane more than the clearance plus 5 mm below the dip: clear.
  plane.d = -static_cast<float>(low - cfg.plane_clearance_m - 0.005);
  EXPECT_EQ(robot::joint_segment_hit(mc, tool, cfg, qa, qb, q), PathHit::none);
}

TEST(PathCheck, TheUr5CheckAcceptsOnlyMotionsWhosePathIsClear) {
  // A reachable grasp in front of the arm; then a point on the palm half way along the
  // free move of the motion it chose: that motion is refused, and any motion accepted
  // instead (the gripper turned round) keeps its free move clear by the dense oracle.
  robot::Ur5GraspCheck check;
  robot::GraspCheckConfig cfg;
  check.configure(cfg);
  const double q_now[6] = {0.0, -1.9, 1.9, -1.57, -1.57, 0.0};
  check.set_current_joints(q_now);
  const Vec3 pos(0.0f, -0.45f, 0.10f), approach(0.f, -0.6f, -0.8f), closing(1.f, 0.f, 0.f);
  GraspQuery q{};
  q.position = pos;
  q.approach = approach;
  q.closing = closing;
  q.pregrasp = pos - approach * 0.06f;
  q.width = 0.05f;
  ASSERT_EQ(check.check(q), GraspVerdict::pass);
  const robot::GraspMotion first = check.motion();
  const robot::MotionConfig& mc = check.config().motion;
  double qm[6];
  for (int i = 0; i < 6; ++i) qm[i] = 0.5 * (q_now[i] + first.pregrasp[i]);
  const Pads mid = pads_at(mc, qm);
  const Vec3 palm =
      (mid.centre - mid.R.col(2) * (0.5 * cfg.tool.gripper.finger_depth_m + 0.5 * cfg.tool.gripper.palm_depth_m))
          .cast<float>();
  q.scene_points = &palm;
  q.n_scene_points = 1;
  const GraspVerdict v = check.check(q);
  if (v == GraspVerdict::pass) {
    const robot::GraspMotion& m = check.motion();
    EXPECT_NE(m.turned, first.turned);
    for (int k = 1; k <= 2000; ++k) {
      double qd[6];
      for (int i = 0; i < 6; ++i) qd[i] = q_now[i] + (m.pregrasp[i] - q_now[i]) * k / 2000.0;
      EXPECT_LT(depth_in_gripper(cfg.tool.gripper, pads_at(mc, qd), palm.cast<double>()), 0.0);
    }
  } else {
    EXPECT_EQ(v, GraspVerdict::collision);
    EXPECT_EQ(check.last_path_hit(), PathHit::scene);
    EXPECT_EQ(check.path_hits(), 1u);
  }
  // Off: the same query passes with the first motion.
  cfg.check_path = false;
  check.configure(cfg);
  check.set_current_joints(q_now);
  EXPECT_EQ(check.check(q), GraspVerdict::pass);
}
