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

// An arm pose over the table, and a grasp in front of it that the UR5 reaches from there.
const double kInFront[6] = {0.0, -1.9, 1.9, -1.57, -1.57, 0.0};
GraspQuery reachable_grasp() {
  const Vec3 pos(0.0f, -0.45f, 0.10f), approach(0.f, -0.6f, -0.8f);
  GraspQuery q{};
  q.position = pos;
  q.approach = approach;
  q.closing = Vec3(1.f, 0.f, 0.f);
  q.pregrasp = pos - approach * 0.06f;
  q.width = 0.05f;
  return q;
}
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
  const Vec3 palm =
      (mid.centre - mid.R.col(2) * (0.5 * tool.gripper.finger_depth_m + 0.5 * tool.gripper.palm_depth_m)).cast<float>();
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
  const double* q_now = kInFront;
  check.set_current_joints(q_now);
  GraspQuery q = reachable_grasp();
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

namespace {

// A motion from kQa: a free move to a random pre-grasp, then six short approach steps.
robot::GraspMotion random_motion(std::mt19937& rng) {
  std::uniform_real_distribution<double> uq(-0.6, 0.6), us(-0.03, 0.03);
  robot::GraspMotion m{};
  for (int i = 0; i < 6; ++i) m.pregrasp[i] = kQa[i] + uq(rng);
  const double* prev = m.pregrasp;
  for (auto& step : m.approach) {
    for (int i = 0; i < 6; ++i) step[i] = prev[i] + us(rng);
    prev = step;
  }
  return m;
}

// The samples grasp_path_hit takes on a clear path, from the header's rules: each
// segment ceil(span / step_rad) samples (at least 1, at most max_samples), and the
// free move's start once (the tool may be leaving a contact there).
uint32_t samples_of(const robot::PathCheckConfig& cfg, const double q_now[6], const robot::GraspMotion& m) {
  uint32_t n = 1;
  const double* from = q_now;
  const double* to = m.pregrasp;
  for (int s = 0; s <= robot::GraspMotion::kApproachSteps; ++s) {
    double span = 0.0;
    for (int i = 0; i < 6; ++i) span = std::max(span, std::fabs(to[i] - from[i]));
    const double want = std::ceil(span / cfg.step_rad);
    n += want < 1.0 ? 1u : std::min<uint32_t>(static_cast<uint32_t>(want), cfg.max_samples);
    if (s == robot::GraspMotion::kApproachSteps) break;
    from = to;
    to = m.approach[s];
  }
  return n;
}

}  // namespace

TEST(PathCheck, TheColumnIndexAnswersAsScanningEveryPoint) {
  // The oracle is the same check without the index (every kept point against every
  // box at every sample): random motions, points scattered about the tool along them
  // (some inside it), far points over several metres (the columns wrap round), and
  // points flagged as the support plane's.
  const robot::ToolGeometry tool;  // with the body behind the palm
  robot::MotionConfig mc;
  mc.tcp_offset_m = tool.tcp_offset_m;
  const robot::PathCheckConfig cfg;
  static robot::PathSceneScratch scratch;  // 68 KB: not on the test's stack
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> uf(0.0, 1.0), un(-0.12, 0.12), ufar(-4.0, 4.0);
  int hits = 0, clear = 0;
  for (int trial = 0; trial < 80; ++trial) {
    const robot::GraspMotion m = random_motion(rng);
    std::vector<Vec3> pts;
    std::vector<uint8_t> keep;
    for (int k = 0; k < 300; ++k) {
      double qs[6];
      const double f = uf(rng);
      for (int i = 0; i < 6; ++i) qs[i] = kQa[i] + f * (m.pregrasp[i] - kQa[i]);
      const Pads p = pads_at(mc, qs);
      // Mostly outside the fingers' and palm's boxes, a few trials with points inside.
      const double spread = 1.0 + 1.5 * (trial % 4);
      pts.push_back((p.centre + V3d(un(rng), un(rng), un(rng)) * spread).cast<float>());
      keep.push_back(static_cast<uint8_t>(k % 7 != 0));
    }
    for (int k = 0; k < 200; ++k) {
      pts.push_back(Vec3(static_cast<float>(ufar(rng)), static_cast<float>(ufar(rng)), static_cast<float>(uf(rng))));
      keep.push_back(1);
    }
    GraspQuery q{};
    q.scene_points = pts.data();
    q.scene_keep = keep.data();
    q.n_scene_points = static_cast<uint32_t>(pts.size());
    const robot::PathScene indexed = robot::prepare_path_scene(q, &scratch);
    const robot::PathScene plain = robot::prepare_path_scene(q, nullptr);
    ASSERT_NE(indexed.idx, nullptr);
    ASSERT_EQ(plain.idx, nullptr);
    int seg_a = -1, seg_b = -1;
    const PathHit a = robot::grasp_path_hit(mc, tool, cfg, kQa, m, indexed, q, &seg_a);
    const PathHit b = robot::grasp_path_hit(mc, tool, cfg, kQa, m, plain, q, &seg_b);
    EXPECT_EQ(a, b) << "trial " << trial;
    EXPECT_EQ(seg_a, seg_b) << "trial " << trial;
    (a == PathHit::scene ? hits : clear) += 1;
  }
  EXPECT_GE(hits, 10);
  EXPECT_GE(clear, 10);
}

TEST(PathCheck, ABudgetThatCannotPayForThePathAnswersBudget) {
  const robot::ToolGeometry tool = no_body_tool();
  const robot::MotionConfig mc = motion_for(tool);
  const robot::PathCheckConfig cfg;
  std::mt19937 rng(5);
  const robot::GraspMotion m = random_motion(rng);
  Plane far_below;
  far_below.n = Vec3::UnitZ();
  far_below.d = 5.f;  // z = -5 m
  GraspQuery q{};
  q.support = &far_below;
  const robot::PathScene scene = robot::prepare_path_scene(q, nullptr);
  const uint32_t need = samples_of(cfg, kQa, m);
  robot::PathBudget enough{need, 0};
  EXPECT_EQ(robot::grasp_path_hit(mc, tool, cfg, kQa, m, scene, q, nullptr, &enough), PathHit::none);
  EXPECT_EQ(enough.samples, 0u);
  robot::PathBudget short_one{need - 1, 0};
  EXPECT_EQ(robot::grasp_path_hit(mc, tool, cfg, kQa, m, scene, q, nullptr, &short_one), PathHit::budget);

  // Point tests: one point beside the start of the path, inside the tool's bounds at
  // the first sample, so that sample scans it (charged 1 test per box whose columns
  // hold it), never inside a box. A budget of no tests cannot pay for that scan.
  const Pads start = pads_at(mc, kQa);
  const Vec3 beside = (start.centre + start.R * V3d(0.0, 0.0, 0.02)).cast<float>();  // between the open fingers
  q.scene_points = &beside;
  q.n_scene_points = 1;
  const robot::PathScene one = robot::prepare_path_scene(q, nullptr);
  robot::PathBudget plenty = robot::PathBudget::of(cfg);
  EXPECT_EQ(robot::grasp_path_hit(mc, tool, cfg, kQa, m, one, q, nullptr, &plenty), PathHit::none);
  EXPECT_LT(plenty.point_tests, cfg.plan_point_tests);
  robot::PathBudget no_tests{need, 0};
  EXPECT_EQ(robot::grasp_path_hit(mc, tool, cfg, kQa, m, one, q, nullptr, &no_tests), PathHit::budget);
}

TEST(PathCheck, TheUr5CheckSpendsOneBudgetPerPlan) {
  // The same reachable grasp as above: what one check spends, measured; a plan's budget
  // of exactly that passes the first check and turns down the second as unchecked
  // (a collision verdict, counted as a budget hit) until the next plan begins.
  robot::Ur5GraspCheck check;
  robot::GraspCheckConfig cfg;
  check.configure(cfg);
  const double* q_now = kInFront;
  check.set_current_joints(q_now);
  GraspQuery q = reachable_grasp();
  ASSERT_EQ(check.check(q), GraspVerdict::pass);
  const uint32_t used = cfg.path.plan_samples - check.path_budget().samples;
  ASSERT_GT(used, 10u);

  cfg.path.plan_samples = used;
  check.configure(cfg);
  check.set_current_joints(q_now);
  EXPECT_EQ(check.check(q), GraspVerdict::pass);
  EXPECT_EQ(check.path_budget().samples, 0u);
  EXPECT_EQ(check.check(q), GraspVerdict::collision);
  EXPECT_EQ(check.last_path_hit(), PathHit::budget);
  EXPECT_EQ(check.path_budget_hits(), 1u);
  check.begin_plan();
  EXPECT_EQ(check.check(q), GraspVerdict::pass);
  EXPECT_EQ(check.path_budget_hits(), 1u);
}
