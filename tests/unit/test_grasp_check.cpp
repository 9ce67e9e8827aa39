// The planner's hook for the robot's checks (core/grasp_check.hpp) and the UR5's
// implementation (robot/ur5_grasp_check.hpp): the next candidate is tried when one is
// turned down, every refusal is counted and named, and the joints of an accepted grasp
// put the pads where the planner said (forward kinematics as the oracle).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "fg/core/planner.hpp"
#include "fg/robot/ur5_grasp_check.hpp"
#include "sim/pinhole.hpp"
#include "sim/scene_gen.hpp"

using namespace fg;

namespace {

Planner& planner() {
  static std::unique_ptr<Planner> p = [] {
    auto q = std::make_unique<Planner>();
    EXPECT_EQ(q->configure(PlannerConfig{}), Status::ok);
    return q;
  }();
  return *p;
}

// Adds a rendered scene to the planner (after reset).
void add_scene(const sim::GeneratedScene& scene) {
  const sim::SceneImages img = sim::render_scene(scene);
  Planner& p = planner();
  p.reset();
  ASSERT_EQ(p.add_depth_image(SensorRole::head, img.head.mm.data(), static_cast<uint16_t>(img.head.width),
                              static_cast<uint16_t>(img.head.height), fg::sim::to_pinhole(scene.head.K),
                              scene.head.world_T_sensor.to_pose()),
            Status::ok);
  ASSERT_EQ(p.add_depth_image(SensorRole::hand, img.hand.mm.data(), static_cast<uint16_t>(img.hand.width),
                              static_cast<uint16_t>(img.hand.height), fg::sim::to_pinhole(scene.hand.K),
                              scene.hand.world_T_sensor.to_pose()),
            Status::ok);
}

// Turns down the first `refuse` candidates it is asked about, recording each.
class RefuseFirst final : public GraspCheck {
 public:
  uint32_t refuse = 0;
  GraspVerdict verdict = GraspVerdict::unreachable;
  std::vector<Vec3> seen;

 private:
  GraspVerdict do_check(const GraspQuery& q) override {
    EXPECT_TRUE(q.position.allFinite());
    EXPECT_NEAR(q.approach.norm(), 1.f, 1e-4f);
    EXPECT_NEAR(q.approach.dot(q.closing), 0.f, 1e-4f);
    EXPECT_GT(q.n_object_points, 0u);
    EXPECT_NE(q.support, nullptr);
    seen.push_back(q.position);
    return seen.size() <= refuse ? verdict : GraspVerdict::pass;
  }
};

}  // namespace

TEST(GraspCheckHook, TheNextCandidateIsTriedWhenOneIsTurnedDown) {
  // A scene with at least three candidates that pass the core's own checks: refusing
  // every one of them counts them.
  sim::GeneratedScene scene;
  size_t passing = 0;
  for (uint64_t seed = 1; seed <= 20 && passing < 3; ++seed) {
    scene = sim::make_scene(sim::ObjectKind::can, seed);
    add_scene(scene);
    RefuseFirst all;
    all.refuse = 1000000;
    planner().set_grasp_check(&all);
    PlanResult r;
    EXPECT_EQ(planner().plan(r), Status::no_grasp);  // the check refuses every candidate
    passing = all.seen.size();
  }
  ASSERT_GE(passing, 3u);

  add_scene(scene);
  RefuseFirst none;
  planner().set_grasp_check(&none);
  PlanResult first;
  ASSERT_EQ(planner().plan(first), Status::ok);
  ASSERT_EQ(none.seen.size(), 1u);
  EXPECT_TRUE(none.seen[0].isApprox(first.grasp.position));

  add_scene(scene);
  RefuseFirst two;
  two.refuse = 2;
  planner().set_grasp_check(&two);
  PlanResult third;
  ASSERT_EQ(planner().plan(third), Status::ok);
  planner().set_grasp_check(nullptr);
  ASSERT_EQ(two.seen.size(), 3u);
  EXPECT_EQ(third.rejected.unreachable, 2u);
  EXPECT_TRUE(two.seen[0].isApprox(first.grasp.position));  // the same ranking
  EXPECT_TRUE(two.seen[2].isApprox(third.grasp.position));
}

TEST(GraspCheckHook, RefusingEveryCandidateNamesTheReason) {
  const sim::GeneratedScene scene = sim::make_scene(sim::ObjectKind::can, 5);
  for (const GraspVerdict v : {GraspVerdict::unreachable, GraspVerdict::collision}) {
    add_scene(scene);
    RefuseFirst all;
    all.refuse = 1000000;
    all.verdict = v;
    planner().set_grasp_check(&all);
    PlanResult r;
    EXPECT_EQ(planner().plan(r), Status::no_grasp);
    planner().set_grasp_check(nullptr);
    EXPECT_GT(all.seen.size(), 0u);
    EXPECT_LE(all.seen.size(), static_cast<size_t>(kMaxCheckedCandidates));
    EXPECT_EQ(r.reason, v == GraspVerdict::unreachable ? NoGraspReason::unreachable : NoGraspReason::collision);
  }
}

namespace {
robot::Ur5GraspCheck& ur5_check() {
  static robot::Ur5GraspCheck c;  // large scratch: not on the stack
  return c;
}
const double kHome[6] = {0.0, -1.9, 1.9, -1.57, -1.57, 0.0};

// Plans the scene added last with the UR5 check (cfg, the planner's gripper, from home).
Status plan_with_ur5_check(robot::GraspCheckConfig cfg, PlanResult& r) {
  cfg.tool.gripper = planner().config().gripper;
  ur5_check().configure(cfg);
  ur5_check().set_current_joints(kHome);
  planner().set_grasp_check(&ur5_check());
  const Status st = planner().plan(r);
  planner().set_grasp_check(nullptr);
  return st;
}
}  // namespace

TEST(Ur5GraspCheck, JointsOfTheAcceptedGraspPutThePadsOnIt) {
  int planned = 0;
  for (const sim::ObjectKind kind : {sim::ObjectKind::box, sim::ObjectKind::can, sim::ObjectKind::bottle,
                                     sim::ObjectKind::lying_cylinder, sim::ObjectKind::ellipsoid}) {
    for (uint64_t seed = 1; seed <= 3; ++seed) {
      add_scene(sim::make_scene(kind, seed));
      PlanResult r;
      if (plan_with_ur5_check(robot::GraspCheckConfig{}, r) != Status::ok) continue;
      ++planned;
      ASSERT_TRUE(ur5_check().has_motion());
      const robot::GraspMotion& m = ur5_check().motion();
      const robot::MotionConfig& mc = ur5_check().config().motion;
      // Oracle: forward kinematics of the joints, the pads tcp_offset along tool0 z.
      const auto pads = [&](const double q[6], Vec3& centre, Vec3& z, Vec3& x) {
        robot::PoseD tool0;
        ASSERT_TRUE(robot::ur5_forward_d(mc.robot, q, tool0));
        const robot::PoseD w = robot::compose(robot::to_d(mc.world_T_base), tool0);
        z = w.R.col(2).cast<float>();
        x = w.R.col(0).cast<float>();
        centre = (w.t + w.R.col(2) * static_cast<double>(mc.tcp_offset_m)).cast<float>();
      };
      Vec3 c = Vec3::Zero(), z = Vec3::Zero(), x = Vec3::Zero();
      pads(m.grasp, c, z, x);
      EXPECT_LT((c - r.grasp.position).norm(), 1e-4f);
      EXPECT_GT(z.dot(r.grasp.approach), 0.9999f);
      EXPECT_GT(std::fabs(x.dot(r.grasp.closing)), 0.9999f);
      pads(m.pregrasp, c, z, x);  // the free move ends standoff behind the pre-grasp
      EXPECT_LT((c - (r.grasp.pregrasp - r.grasp.approach * mc.standoff_m)).norm(), 1e-4f);
      pads(m.lift, c, z, x);
      EXPECT_LT((c - (r.grasp.position + Vec3(0.f, 0.f, mc.lift_m))).norm(), 1e-4f);
      for (int i = 0; i < 6; ++i) {
        EXPECT_GE(m.grasp[i], mc.ik.limits.lower[i]);
        EXPECT_LE(m.grasp[i], mc.ik.limits.upper[i]);
      }
    }
  }
  EXPECT_GE(planned, 12);
}

TEST(Ur5GraspCheck, AnArmOutOfReachGivesUnreachable) {
  add_scene(sim::make_scene(sim::ObjectKind::box, 2));
  robot::GraspCheckConfig cfg;
  cfg.motion.world_T_base.t = Vec3(3.f, 0.f, 0.f);  // the arm stands 3 m away (reach ~0.85 m)
  PlanResult r;
  EXPECT_EQ(plan_with_ur5_check(cfg, r), Status::no_grasp);
  EXPECT_EQ(r.reason, NoGraspReason::unreachable);
  EXPECT_GT(ur5_check().unreachable(), 0u);
  EXPECT_FALSE(ur5_check().has_motion());
}

TEST(Ur5GraspCheck, TightJointLimitsSendThePlannerToAnotherCandidateOrNone) {
  // Wrist 3 held within +-0.05 rad of zero: only grasps whose closing direction the
  // arm can turn to with that wrist survive; the check never returns joints outside.
  add_scene(sim::make_scene(sim::ObjectKind::box, 4));
  robot::GraspCheckConfig cfg;
  cfg.motion.ik.limits.lower[5] = -0.05;
  cfg.motion.ik.limits.upper[5] = 0.05;
  PlanResult r;
  const Status st = plan_with_ur5_check(cfg, r);
  if (st == Status::ok) {
    const robot::GraspMotion& m = ur5_check().motion();
    for (const double* q : {m.pregrasp, m.grasp, m.lift}) {
      EXPECT_GE(q[5], -0.05 - 1e-12);
      EXPECT_LE(q[5], 0.05 + 1e-12);
    }
  } else {
    EXPECT_EQ(r.reason, NoGraspReason::unreachable);
  }
  EXPECT_GT(ur5_check().asked(), 0u);
}
