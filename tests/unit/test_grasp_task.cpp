// The grasp task state machine against small test doubles of each HAL interface
// (a clock, two depth sensors replaying rendered images, an arm that moves in a few
// ticks, a gripper that closes onto a set width): the whole task on simulated scenes,
// the kinematics of its targets checked with the forward kinematics, and every way it
// can fail ending in its own failure, never hanging.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "fg/task/grasp_task.hpp"
#include "sim/scene_gen.hpp"

using fg::Status;
using fg::task::GraspTask;
using fg::task::TaskConfig;
using fg::task::TaskFailure;
using fg::task::TaskState;

namespace {

class FakeClock : public fg::hal::Clock {
 public:
  uint64_t t_us = 1000;

 private:
  uint64_t do_now_us() override { return t_us; }
};

class FakeSensor : public fg::hal::DepthSensor {
 public:
  std::vector<uint16_t> image;
  uint16_t width = 0, height = 0;
  fg::PinholeIntrinsics k;
  int latency_polls = 3;
  bool refuse = false, fail = false, never_ready = false;
  int requests = 0;

 private:
  int polls_ = 0;
  Status do_request_capture() override {
    if (refuse) return Status::invalid_argument;
    ++requests;
    polls_ = 0;
    return Status::ok;
  }
  fg::hal::CaptureState do_poll(fg::hal::DepthFrame& out) override {
    if (requests == 0) return fg::hal::CaptureState::idle;
    if (fail) return fg::hal::CaptureState::failed;
    if (never_ready || ++polls_ < latency_polls) return fg::hal::CaptureState::busy;
    out.depth_mm = image.data();
    out.width = width;
    out.height = height;
    out.k = k;
    return fg::hal::CaptureState::ready;
  }
};

class FakeArm : public fg::hal::ArmLink {
 public:
  double q[6] = {0, 0, 0, 0, 0, 0};
  int ticks_per_move = 5;
  bool refuse = false, never_arrive = false;
  int fault_on_move = -1;  // the n-th move (0-based) faults
  int moves = 0, stops = 0;
  std::vector<std::vector<double>> targets;

 private:
  double target_[6] = {};
  int left_ = 0;
  bool fault_ = false;
  Status do_move_joints(const double t[6], double) override {
    if (refuse) return Status::invalid_argument;
    if (moves++ == fault_on_move) fault_ = true;
    for (int i = 0; i < 6; ++i) target_[i] = t[i];
    targets.emplace_back(t, t + 6);
    left_ = ticks_per_move;
    return Status::ok;
  }
  Status do_read_state(fg::hal::ArmState& out) override {
    if (left_ > 0 && !never_arrive && --left_ == 0)
      for (int i = 0; i < 6; ++i) q[i] = target_[i];
    for (int i = 0; i < 6; ++i) out.q[i] = q[i];
    out.moving = left_ > 0;
    out.fault = fault_;
    return Status::ok;
  }
  void do_stop() override {
    left_ = 0;
    ++stops;
  }
};

class FakeGripper : public fg::hal::Gripper {
 public:
  float width = 0.f;
  float contact_width = 0.05f;  // <= 0: closes on nothing
  bool refuse = false;

 private:
  int left_ = 0;
  bool contact_ = false;
  Status do_open_to(float w) override {
    if (refuse) return Status::invalid_argument;
    width = w;
    contact_ = false;
    left_ = 2;
    return Status::ok;
  }
  Status do_close(float) override {
    if (refuse) return Status::invalid_argument;
    contact_ = contact_width > 0.f;
    width = contact_ ? contact_width : 0.f;
    left_ = 2;
    return Status::ok;
  }
  Status do_read_state(fg::hal::GripperState& out) override {
    if (left_ > 0) --left_;
    out.width_m = width;
    out.moving = left_ > 0;
    out.contact = contact_ && left_ == 0;
    return Status::ok;
  }
};

fg::robot::PoseD fk(const double q[6]) {
  fg::robot::PoseD p;
  EXPECT_TRUE(fg::robot::ur5_forward_d(fg::robot::ur5_nominal(), q, p));
  return p;
}

// A rig: a simulated scene rendered once, the arm at a home pose, and the wrist
// sensor's mount chosen so that FK(home) * mount is exactly where the scene's hand
// camera is (so the task's own pose computation reproduces the scene).
struct Rig {
  fg::sim::GeneratedScene scene;
  FakeClock clock;
  FakeSensor head, hand;
  FakeArm arm;
  FakeGripper gripper;
  TaskConfig cfg;
  std::unique_ptr<fg::Planner> planner = std::make_unique<fg::Planner>();

  explicit Rig(fg::sim::ObjectKind kind, uint64_t seed, const fg::sim::Rigid& world_T_base = {}) {
    scene = fg::sim::make_scene(kind, seed);
    const fg::sim::SceneImages img = fg::sim::render_scene(scene);
    fill(head, img.head, scene.head.K);
    fill(hand, img.hand, scene.hand.K);
    const double home[6] = {0.0, -1.9, 1.9, -1.57, -1.57, 0.0};
    for (int i = 0; i < 6; ++i) arm.q[i] = home[i];
    const fg::robot::PoseD base_T_tool0 = fk(home);
    const fg::sim::Rigid tool0 = world_T_base * fg::sim::Rigid{base_T_tool0.R, base_T_tool0.t};
    cfg.world_T_base = world_T_base.to_pose();
    cfg.world_T_head = scene.head.world_T_sensor.to_pose();
    cfg.tool0_T_hand = (tool0.inverse() * scene.hand.world_T_sensor).to_pose();
    EXPECT_EQ(planner->configure(fg::PlannerConfig{}), Status::ok);
  }
  static void fill(FakeSensor& s, const fg::sim::DepthImage& d, const fg::sim::Intrinsics& K) {
    s.image = d.mm;
    s.width = static_cast<uint16_t>(d.width);
    s.height = static_cast<uint16_t>(d.height);
    s.k.fx = static_cast<float>(K.fx);
    s.k.fy = static_cast<float>(K.fy);
    s.k.cx = static_cast<float>(K.cx);
    s.k.cy = static_cast<float>(K.cy);
  }
  fg::task::TaskHal hal() { return fg::task::TaskHal{clock, &head, &hand, arm, gripper}; }
  // Ticks at 125 Hz until the task ends; the tick count is bounded by the timeouts.
  TaskState run(GraspTask& task, int max_ticks = 100000) {
    const fg::task::TaskHal h = hal();
    TaskState s = task.state();
    for (int i = 0; i < max_ticks; ++i) {
      s = task.step(*planner, h);
      if (s == TaskState::succeeded || s == TaskState::failed) return s;
      clock.t_us += 8000;
    }
    ADD_FAILURE() << "the task did not end in " << max_ticks << " ticks (state " << to_string(s) << ")";
    return s;
  }
};

// Tool0 at q, pushed tcp_offset along its z, is the grasp position; its z the approach.
void expect_tool_at(const double q[6], const fg::Vec3& position, const fg::Vec3& approach, float tcp) {
  const fg::robot::PoseD t = fk(q);
  const Eigen::Vector3d tcp_point = t.t + t.R.col(2) * static_cast<double>(tcp);
  EXPECT_LT((tcp_point - position.cast<double>()).norm(), 1e-4);
  EXPECT_GT(t.R.col(2).dot(approach.cast<double>()), 0.9999);
}

class GraspTaskScenes : public ::testing::TestWithParam<uint64_t> {};

TEST_P(GraspTaskScenes, GraspsAnUprightBox) {
  Rig rig(fg::sim::ObjectKind::box, GetParam());
  GraspTask task;
  ASSERT_EQ(task.start(rig.cfg), Status::ok);
  EXPECT_EQ(task.state(), TaskState::capturing);
  const TaskState end = rig.run(task);
  ASSERT_EQ(end, TaskState::succeeded) << to_string(task.failure()) << ": " << task.message();
  EXPECT_EQ(task.failure(), TaskFailure::none);
  EXPECT_EQ(rig.head.requests, 1);
  EXPECT_EQ(rig.hand.requests, 1);
  // The motions, in order: the start of the approach line (standoff behind the
  // pre-grasp), the steps along it (the last one the grasp), the lift.
  constexpr int kSteps = fg::robot::GraspMotion::kApproachSteps;
  ASSERT_EQ(rig.arm.targets.size(), static_cast<size_t>(kSteps + 2));
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(rig.arm.targets[0][static_cast<size_t>(i)], task.pregrasp_joints()[i]);
    EXPECT_EQ(rig.arm.targets[kSteps][static_cast<size_t>(i)], task.grasp_joints()[i]);
    EXPECT_EQ(rig.arm.q[i], task.lift_joints()[i]);
  }
  const fg::Grasp& g = task.plan_result().grasp;
  const float standoff = fg::robot::MotionConfig{}.standoff_m;
  const fg::Vec3 start = g.pregrasp - g.approach * standoff;
  expect_tool_at(task.grasp_joints(), g.position, g.approach, rig.cfg.tcp_offset_m);
  expect_tool_at(task.pregrasp_joints(), start, g.approach, rig.cfg.tcp_offset_m);
  for (int k = 1; k <= kSteps; ++k) {  // equal steps on the line (an oracle of its own)
    const fg::Vec3 on_line = start + (g.position - start) * (static_cast<float>(k) / kSteps);
    double q[6];
    for (int i = 0; i < 6; ++i) q[i] = rig.arm.targets[static_cast<size_t>(k)][static_cast<size_t>(i)];
    expect_tool_at(q, on_line, g.approach, rig.cfg.tcp_offset_m);
  }
  fg::Vec3 lifted = g.position;
  lifted.z() += rig.cfg.lift_m;
  expect_tool_at(task.lift_joints(), lifted, g.approach, rig.cfg.tcp_offset_m);
  // The closing direction is the tool's x, one way or the other.
  const fg::robot::PoseD t = fk(task.grasp_joints());
  EXPECT_GT(std::fabs(t.R.col(0).dot(g.closing.cast<double>())), 0.9999);
  // Joint moves stay small: the nearest solutions were taken, not a wrist flip.
  for (int i = 0; i < 6; ++i)
    EXPECT_LT(std::fabs(task.grasp_joints()[i] - task.pregrasp_joints()[i]), 0.5) << "joint " << i;
}

INSTANTIATE_TEST_SUITE_P(Seeds, GraspTaskScenes, ::testing::Values(1u, 2u, 4u));

// The same with the robot's base turned and moved in the world: every target is
// expressed in the base frame.
TEST(GraspTask, BaseAwayFromTheWorldOrigin) {
  const fg::sim::Rigid base = fg::sim::Rigid::translation(fg::sim::V3(0.1, -0.3, 0.0)) * fg::sim::Rigid::rot_z(0.5);
  Rig rig(fg::sim::ObjectKind::box, 1, base);
  GraspTask task;
  ASSERT_EQ(task.start(rig.cfg), Status::ok);
  ASSERT_EQ(rig.run(task), TaskState::succeeded) << to_string(task.failure()) << ": " << task.message();
  const fg::Grasp& g = task.plan_result().grasp;
  const fg::robot::PoseD t = fk(task.grasp_joints());
  const Eigen::Vector3d tcp_world = base.apply(t.t + t.R.col(2) * static_cast<double>(rig.cfg.tcp_offset_m));
  EXPECT_LT((tcp_world - g.position.cast<double>()).norm(), 1e-4);
  EXPECT_GT((base.R * t.R.col(2)).dot(g.approach.cast<double>()), 0.9999);
}

TEST(GraspTask, WideBoxEndsInNoGrasp) {
  Rig rig(fg::sim::ObjectKind::wide_box, 1);
  GraspTask task;
  ASSERT_EQ(task.start(rig.cfg), Status::ok);
  EXPECT_EQ(rig.run(task), TaskState::failed);
  EXPECT_EQ(task.failure(), TaskFailure::no_grasp);
  EXPECT_EQ(task.plan_result().status, Status::no_grasp);
  EXPECT_TRUE(rig.arm.targets.empty()) << "the arm must not move without a grasp";
}

TEST(GraspTask, EachFailureEndsInItsOwnState) {
  struct Case {
    const char* name;
    void (*setup)(Rig&);
    TaskFailure expected;
  };
  const Case cases[] = {
      {"head refuses", [](Rig& r) { r.head.refuse = true; }, TaskFailure::sensor_failed},
      {"hand fails", [](Rig& r) { r.hand.fail = true; }, TaskFailure::sensor_failed},
      {"head never ready", [](Rig& r) { r.head.never_ready = true; }, TaskFailure::sensor_timeout},
      {"arm refuses", [](Rig& r) { r.arm.refuse = true; }, TaskFailure::arm_refused},
      {"arm faults on the approach", [](Rig& r) { r.arm.fault_on_move = 1; }, TaskFailure::arm_fault},
      {"arm never arrives", [](Rig& r) { r.arm.never_arrive = true; }, TaskFailure::arm_timeout},
      {"gripper refuses", [](Rig& r) { r.gripper.refuse = true; }, TaskFailure::gripper_refused},
      {"gripper closes on nothing", [](Rig& r) { r.gripper.contact_width = 0.f; }, TaskFailure::missed},
      {"joint limits exclude every solution",
       [](Rig& r) {
         for (int i = 0; i < 6; ++i) {
           r.cfg.ik.limits.lower[i] = 3.0;
           r.cfg.ik.limits.upper[i] = 3.01;
         }
       },
       TaskFailure::unreachable},
  };
  for (const Case& c : cases) {
    Rig rig(fg::sim::ObjectKind::box, 1);
    c.setup(rig);
    GraspTask task;
    ASSERT_EQ(task.start(rig.cfg), Status::ok) << c.name;
    EXPECT_EQ(rig.run(task), TaskState::failed) << c.name;
    EXPECT_EQ(task.failure(), c.expected)
        << c.name << ": got " << to_string(task.failure()) << " (" << task.message() << ")";
    EXPECT_NE(task.message()[0], '\0') << c.name;
  }
}

TEST(GraspTask, TimeoutStopsTheArm) {
  Rig rig(fg::sim::ObjectKind::box, 1);
  rig.arm.never_arrive = true;
  GraspTask task;
  ASSERT_EQ(task.start(rig.cfg), Status::ok);
  rig.run(task);
  EXPECT_EQ(task.failure(), TaskFailure::arm_timeout);
  EXPECT_EQ(rig.arm.stops, 1);
}

TEST(GraspTask, RefusesBadConfigurationsAndIdles) {
  Rig rig(fg::sim::ObjectKind::box, 1);
  TaskConfig bad = rig.cfg;
  bad.world_T_head.t.x() = NAN;
  GraspTask task;
  EXPECT_EQ(task.start(bad), Status::invalid_config);
  EXPECT_EQ(task.state(), TaskState::failed);
  EXPECT_EQ(task.failure(), TaskFailure::invalid_config);
  bad = rig.cfg;
  bad.use_head = bad.use_hand = false;
  EXPECT_EQ(task.start(bad), Status::invalid_config);
  bad = rig.cfg;
  bad.speed_fraction = 0.0;
  EXPECT_EQ(task.start(bad), Status::invalid_config);
  // A task never started does nothing when stepped.
  GraspTask idle;
  EXPECT_EQ(idle.step(*rig.planner, rig.hal()), TaskState::idle);
  EXPECT_EQ(rig.head.requests, 0);
}

// Refused as occluded, the task moves the wrist sensor to the view the plan advises,
// captures and plans once more (the fake sensors give the same images again, so the plan
// refuses again): the arm's one motion puts the camera on the advised line through the
// hidden space, at the camera's distance from it, looking at it. With max_relooks 0, or a
// refusal for another reason, the arm does not move. Big spheres, too wide: some of their
// refusals are for occlusion.
TEST(GraspTask, RefusedAsOccludedItLooksAgainFromTheAdvisedView) {
  int looked = 0;
  for (uint64_t seed = 1; seed <= 12 && looked == 0; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    Rig rig(fg::sim::ObjectKind::big_sphere, seed);
    GraspTask task;
    ASSERT_EQ(task.start(rig.cfg), Status::ok);
    EXPECT_EQ(rig.run(task), TaskState::failed);
    if (task.relooks() == 0) {
      EXPECT_NE(task.plan_result().reason, fg::NoGraspReason::occluded);
      EXPECT_TRUE(rig.arm.targets.empty());
      continue;
    }
    ++looked;
    EXPECT_EQ(task.relooks(), 1u);
    EXPECT_EQ(task.failure(), TaskFailure::no_grasp);
    EXPECT_EQ(rig.hand.requests, 2);
    EXPECT_EQ(rig.head.requests, 2);
    ASSERT_EQ(rig.arm.targets.size(), 1u);
    const fg::LookAdvice& look = task.followed_advice();
    ASSERT_TRUE(look.valid);
    // The camera before: the scene's (the rig's mount makes FK(home) put it there).
    const Eigen::Vector3d before = rig.scene.hand.world_T_sensor.t;
    const fg::robot::PoseD after =
        fg::robot::compose(fk(rig.arm.targets[0].data()), fg::robot::to_d(rig.cfg.tool0_T_hand));
    const Eigen::Vector3d at = look.at.cast<double>();
    const Eigen::Vector3d line = (look.from - look.at).cast<double>().normalized();
    EXPECT_NEAR((after.t - at).norm(), (before - at).norm(), 1e-5);
    EXPECT_GT((after.t - at).normalized().dot(line), 1.0 - 1e-6);
    EXPECT_GT(after.R.col(2).dot(-line), 1.0 - 1e-6);
    // Configured not to look again: refused at once, the arm still.
    Rig still(fg::sim::ObjectKind::big_sphere, seed);
    still.cfg.max_relooks = 0;
    GraspTask once;
    ASSERT_EQ(once.start(still.cfg), Status::ok);
    EXPECT_EQ(still.run(once), TaskState::failed);
    EXPECT_EQ(once.relooks(), 0u);
    EXPECT_EQ(once.plan_result().reason, fg::NoGraspReason::occluded);
    EXPECT_EQ(still.hand.requests, 1);
    EXPECT_TRUE(still.arm.targets.empty());
  }
  EXPECT_GT(looked, 0) << "no plan was refused as occluded: the test shows nothing";
}

TEST(GraspTask, OneSensorIsEnough) {
  Rig rig(fg::sim::ObjectKind::box, 1);
  rig.cfg.use_hand = false;
  GraspTask task;
  ASSERT_EQ(task.start(rig.cfg), Status::ok);
  const fg::task::TaskHal h{rig.clock, &rig.head, nullptr, rig.arm, rig.gripper};
  TaskState s = TaskState::capturing;
  for (int i = 0; i < 100000 && s != TaskState::succeeded && s != TaskState::failed; ++i) {
    s = task.step(*rig.planner, h);
    rig.clock.t_us += 8000;
  }
  EXPECT_TRUE(s == TaskState::succeeded || task.failure() == TaskFailure::no_grasp)
      << to_string(task.failure()) << ": " << task.message();
  EXPECT_EQ(rig.hand.requests, 0);
}

}  // namespace
