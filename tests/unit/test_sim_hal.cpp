// hal/sim simulated hardware: SimClock, SimArm (joint-space motion, limits, faults, FK),
// SimGripper with the SDF contact model, SimDepthSensor (latency, failures, rendering,
// a wrist sensor following the arm). All in simulated time.
#include <gtest/gtest.h>

#include <cmath>

#include "fg/core/constants.hpp"
#include "fg/robot/ur5.hpp"
#include "fg/robot/ur5_ik.hpp"
#include "sim/sim_hal.hpp"

using namespace fg::sim;
using fg::Status;

namespace {

using fg::kPi;

// Advances the clock and ticks the devices together, in steps of dt_us, for total_us.
void run(SimClock& clock, SimArm* arm, SimGripper* gripper, uint64_t total_us, uint64_t dt_us = 1000) {
  for (uint64_t t = 0; t < total_us; t += dt_us) {
    clock.advance_us(dt_us);
    if (arm) arm->tick(dt_us * 1e-6);
    if (gripper) gripper->tick(dt_us * 1e-6);
  }
}

double max_abs_diff(const Rigid& a, const Rigid& b) {
  return std::max((a.R - b.R).cwiseAbs().maxCoeff(), (a.t - b.t).cwiseAbs().maxCoeff());
}

// An arm pose above the table with tool0 +z pointing (nearly) straight down.
const double kHomeDown[6] = {0.0, -kPi / 2, kPi / 2, -kPi / 2, -kPi / 2, 0.0};

}  // namespace

// ---------------------------------------------------------------------------------------
TEST(SimClock, StartsAtZeroAndAdvances) {
  SimClock clock;
  fg::hal::Clock& c = clock;
  EXPECT_EQ(c.now_us(), 0u);
  clock.advance_us(1500);
  clock.advance_us(2500);
  EXPECT_EQ(c.now_us(), 4000u);
  EXPECT_EQ(clock.time_us(), 4000u);
}

// ---------------------------------------------------------------------------------------
TEST(SimArm, ReachesTargetAtExpectedTime) {
  SimClock clock;
  SimArm arm(nullptr, SimArmConfig{}, &clock);
  // Joint 2 has the largest move: 1.575 rad at 0.5 x 3.15 rad/s = 1.0 s.
  const double target[6] = {0.5, -1.575, 0.3, 0.0, 1.0, -0.2};
  ASSERT_EQ(arm.move_joints(target, 0.5), Status::ok);
  EXPECT_NEAR(arm.motion_duration_s(), 1.0, 1e-12);
  fg::hal::ArmState st;
  ASSERT_EQ(arm.read_state(st), Status::ok);
  EXPECT_TRUE(st.moving);

  run(clock, &arm, nullptr, 500000);  // half way: the slowest joint at its commanded speed
  EXPECT_NEAR(arm.q_rad()[1], -0.7875, 1e-9);
  EXPECT_TRUE(arm.moving());
  run(clock, &arm, nullptr, 498000);  // 0.998 s
  EXPECT_TRUE(arm.moving());
  run(clock, &arm, nullptr, 2000);  // 1.000 s
  ASSERT_EQ(arm.read_state(st), Status::ok);
  EXPECT_FALSE(st.moving);
  EXPECT_EQ(st.stamp_us, 1000000u);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(st.q[i], target[i]) << i;

  // The speed scales with the fraction: the same move back at full speed takes 0.5 s.
  const double zero[6] = {0, 0, 0, 0, 0, 0};
  ASSERT_EQ(arm.move_joints(zero, 1.0), Status::ok);
  EXPECT_NEAR(arm.motion_duration_s(), 0.5, 1e-12);
  run(clock, &arm, nullptr, 499000);
  EXPECT_TRUE(arm.moving());
  run(clock, &arm, nullptr, 1000);
  EXPECT_FALSE(arm.moving());
}

TEST(SimArm, JointsMoveOnALineAndArriveTogether) {
  SimArm arm;
  const double target[6] = {0.4, -1.2, 2.0, -0.1, 0.8, 3.0};
  ASSERT_EQ(arm.move_joints(target, 0.25), Status::ok);
  const double duration_s = 3.0 / (0.25 * 3.15);  // joint 6 moves furthest
  EXPECT_NEAR(arm.motion_duration_s(), duration_s, 1e-12);
  int ticks = 0;
  while (arm.moving() && ticks < 100000) {
    arm.tick(0.01);
    ++ticks;
    if (!arm.moving()) break;
    // Every joint has covered the same fraction of its way.
    const double f = arm.q_rad()[5] / target[5];
    for (int i = 0; i < 5; ++i) EXPECT_NEAR(arm.q_rad()[i] / target[i], f, 1e-12) << i;
  }
  EXPECT_EQ(ticks, static_cast<int>(std::ceil(duration_s / 0.01)));
  for (int i = 0; i < 6; ++i) EXPECT_EQ(arm.q_rad()[i], target[i]);
  // The sampled tool0 path: start, one pose per tick, the last at the target.
  ASSERT_EQ(arm.tool0_path().size(), static_cast<size_t>(ticks) + 1);
  EXPECT_LT(max_abs_diff(arm.tool0_path().back(), arm.world_T_tool0()), 1e-15);
}

TEST(SimArm, RefusesTargetsOutsideLimitsAndNonFinite) {
  SimArm arm;
  fg::hal::ArmLink& link = arm;  // through the interface, as the task calls it
  const double beyond[6] = {0, 0, 6.3, 0, 0, 0};
  EXPECT_EQ(link.move_joints(beyond, 0.5), Status::invalid_argument);
  EXPECT_FALSE(arm.moving());
  arm.tick(1.0);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(arm.q_rad()[i], 0.0);

  const double nan_target[6] = {0, 0, NAN, 0, 0, 0};
  const double inf_target[6] = {0, 0, 0, 0, 0, -INFINITY};
  EXPECT_EQ(link.move_joints(nan_target, 0.5), Status::invalid_argument);
  EXPECT_EQ(link.move_joints(inf_target, 0.5), Status::invalid_argument);
  const double ok_target[6] = {0.1, 0, 0, 0, 0, 0};
  EXPECT_EQ(link.move_joints(ok_target, 0.0), Status::invalid_argument);
  EXPECT_EQ(link.move_joints(ok_target, 1.5), Status::invalid_argument);
  EXPECT_EQ(link.move_joints(ok_target, NAN), Status::invalid_argument);
  EXPECT_FALSE(arm.moving());

  // Configured limits.
  SimArmConfig cfg;
  cfg.lower_rad[1] = -kPi;
  cfg.upper_rad[1] = 0.0;
  SimArm arm2(nullptr, cfg);
  const double up[6] = {0, 0.2, 0, 0, 0, 0};
  const double down[6] = {0, -0.2, 0, 0, 0, 0};
  EXPECT_EQ(arm2.move_joints(up, 1.0), Status::invalid_argument);
  EXPECT_EQ(arm2.move_joints(down, 1.0), Status::ok);

  // A refused target leaves a motion under way alone.
  EXPECT_EQ(arm2.move_joints(up, 1.0), Status::invalid_argument);
  EXPECT_TRUE(arm2.moving());
  for (int i = 0; i < 6; ++i) EXPECT_EQ(arm2.target_rad()[i], down[i]);
}

TEST(SimArm, FaultStopsAndRefusesMovesUntilCleared) {
  SimArm arm;
  const double target[6] = {1.0, 0, 0, 0, 0, 0};
  ASSERT_EQ(arm.move_joints(target, 1.0), Status::ok);
  arm.tick(0.1);
  const double q_at_fault = arm.q_rad()[0];
  EXPECT_GT(q_at_fault, 0.0);
  arm.inject_fault();
  fg::hal::ArmState st;
  ASSERT_EQ(arm.read_state(st), Status::ok);
  EXPECT_TRUE(st.fault);
  EXPECT_FALSE(st.moving);
  arm.tick(1.0);
  EXPECT_EQ(arm.q_rad()[0], q_at_fault);
  EXPECT_EQ(arm.move_joints(target, 1.0), Status::invalid_sequence);
  EXPECT_FALSE(arm.moving());

  arm.clear_fault();
  ASSERT_EQ(arm.read_state(st), Status::ok);
  EXPECT_FALSE(st.fault);
  ASSERT_EQ(arm.move_joints(target, 1.0), Status::ok);
  arm.tick(1.0);
  EXPECT_FALSE(arm.moving());
  EXPECT_EQ(arm.q_rad()[0], 1.0);
}

TEST(SimArm, StopHoldsTheCurrentJoints) {
  SimArm arm;
  const double target[6] = {0, 0, 0, 0, 0, -2.0};
  ASSERT_EQ(arm.move_joints(target, 1.0), Status::ok);
  arm.tick(0.2);
  const double q = arm.q_rad()[5];
  EXPECT_NEAR(q, -0.63, 1e-12);
  fg::hal::ArmLink& link = arm;
  link.stop();
  EXPECT_FALSE(arm.moving());
  arm.tick(1.0);
  EXPECT_EQ(arm.q_rad()[5], q);
  EXPECT_FALSE(arm.fault());
}

TEST(SimArm, MoveToWhereItIsEndsAtOnce) {
  const double q[6] = {0.1, -0.2, 0.3, -0.4, 0.5, -0.6};
  SimArm arm(q);
  ASSERT_EQ(arm.move_joints(q, 0.3), Status::ok);
  EXPECT_FALSE(arm.moving());
  EXPECT_EQ(arm.tool0_path().size(), 1u);
}

TEST(SimArm, Tool0IsTheForwardKinematics) {
  const double q[6] = {0.3, -1.1, 1.4, -0.9, -1.6, 0.7};
  SimArm arm(q);
  fg::robot::PoseD fk;
  ASSERT_TRUE(fg::robot::ur5_forward_d(fg::robot::ur5_nominal(), q, fk));
  const Rigid t0 = arm.tool0();
  EXPECT_LT((t0.R - fk.R).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((t0.t - fk.t).cwiseAbs().maxCoeff(), 1e-15);
  // And the float FK of the embedded side agrees to its precision.
  const float qf[6] = {0.3f, -1.1f, 1.4f, -0.9f, -1.6f, 0.7f};
  fg::Pose pf;
  ASSERT_TRUE(fg::robot::ur5_forward(fg::robot::ur5_nominal(), qf, pf));
  EXPECT_LT(max_abs_diff(t0, Rigid::from_pose(pf)), 1e-5);

  // The base at identity unless set; then world_T_tool0 = world_T_base * base_T_tool0.
  EXPECT_LT(max_abs_diff(arm.world_T_tool0(), t0), 1e-15);
  const Rigid world_T_base = Rigid::translation(V3(0.2, -0.1, 0.75)) * Rigid::rot_z(0.4);
  arm.set_world_T_base(world_T_base);
  EXPECT_LT(max_abs_diff(arm.world_T_tool0(), world_T_base * t0), 1e-15);
  EXPECT_LT(max_abs_diff(arm.tool0(), t0), 1e-15);
}

// ---------------------------------------------------------------------------------------
namespace {

// Grasp frame at `centre`, closing along world x, approaching downwards (-z).
Rigid grasp_down_at(const V3& centre) {
  Rigid G;
  G.R.col(0) = V3(1, 0, 0);
  G.R.col(2) = V3(0, 0, -1);
  G.R.col(1) = G.R.col(2).cross(G.R.col(0));
  G.t = centre;
  return G;
}

World world_with_box(const V3& centre, const V3& half_extents) {
  World w;
  w.objects.push_back({"box", "box", {Part::box("box", half_extents, Rigid::translation(centre))}});
  return w;
}

// Ticks the gripper until it stops (bounded).
void settle(SimGripper& g) {
  for (int i = 0; i < 100000 && g.moving(); ++i) g.tick(0.001);
}

}  // namespace

TEST(SimGripper, OpensAndClosesAtItsSpeed) {
  SimGripper g;  // starts open at 0.085 m, no contact model: nothing to touch
  fg::hal::Gripper& grip = g;
  ASSERT_EQ(grip.close(20.f), Status::ok);
  EXPECT_DOUBLE_EQ(g.last_force_n(), 20.0);
  for (int i = 0; i < 200; ++i) g.tick(0.001);  // 0.2 s at 0.15 m/s: 30 mm
  EXPECT_NEAR(g.width_m(), 0.055, 1e-9);
  EXPECT_TRUE(g.moving());
  for (int i = 0; i < 366; ++i) g.tick(0.001);  // 0.566 s: 84.9 mm
  EXPECT_TRUE(g.moving());
  g.tick(0.001);
  fg::hal::GripperState st;
  ASSERT_EQ(grip.read_state(st), Status::ok);
  EXPECT_FALSE(st.moving);
  EXPECT_FALSE(st.contact);
  EXPECT_EQ(st.width_m, 0.f);

  ASSERT_EQ(grip.open_to(0.06f), Status::ok);  // 0.4 s
  for (int i = 0; i < 399; ++i) g.tick(0.001);
  EXPECT_TRUE(g.moving());
  g.tick(0.001);
  EXPECT_FALSE(g.moving());
  EXPECT_NEAR(g.width_m(), 0.06, 1e-7);

  // Beyond the opening is clamped; negative and non-finite widths are refused.
  ASSERT_EQ(grip.open_to(0.5f), Status::ok);
  settle(g);
  EXPECT_NEAR(g.width_m(), 0.085, 1e-7);
  EXPECT_EQ(grip.open_to(-0.01f), Status::invalid_argument);
  EXPECT_EQ(grip.open_to(NAN), Status::invalid_argument);
  EXPECT_EQ(grip.close(0.f), Status::invalid_argument);
}

TEST(SimGripper, FaultStopsAndRefusesCommandsUntilCleared) {
  SimGripper g;
  ASSERT_EQ(g.close(10.f), Status::ok);
  g.tick(0.1);
  const double w = g.width_m();
  g.inject_fault();
  fg::hal::GripperState st;
  ASSERT_EQ(g.read_state(st), Status::ok);
  EXPECT_TRUE(st.fault);
  EXPECT_FALSE(st.moving);
  g.tick(0.1);
  EXPECT_EQ(g.width_m(), w);
  EXPECT_EQ(g.open_to(0.08f), Status::invalid_sequence);
  EXPECT_EQ(g.close(10.f), Status::invalid_sequence);
  g.clear_fault();
  EXPECT_EQ(g.open_to(0.08f), Status::ok);
}

TEST(SimGripper, StopsOnACentredBoxAtItsWidth) {
  const V3 centre(0.5, 0.0, 0.3);
  const World w = world_with_box(centre, V3(0.02, 0.05, 0.04));  // 40 mm across x
  const SdfContactModel model(w, [&] { return grasp_down_at(centre); });
  EXPECT_NEAR(model.contact_width(0.085), 0.040, 1e-6);

  SimGripper g(SimGripperConfig{}, &model);
  ASSERT_EQ(g.close(40.f), Status::ok);
  EXPECT_FALSE(g.contact());  // not yet: the pads are still travelling
  settle(g);
  fg::hal::GripperState st;
  ASSERT_EQ(g.read_state(st), Status::ok);
  EXPECT_TRUE(st.contact);
  EXPECT_FALSE(st.moving);
  EXPECT_NEAR(st.width_m, 0.040, 1e-3);

  // Opening again clears the contact.
  ASSERT_EQ(g.open_to(0.085f), Status::ok);
  EXPECT_FALSE(g.contact());
}

TEST(SimGripper, ClosesToZeroWithNothingBetweenThePads) {
  const World w = world_with_box(V3(0.5, 0.3, 0.3), V3(0.02, 0.05, 0.04));  // beside, not between
  const SdfContactModel model(w, [] { return grasp_down_at(V3(0.5, 0.0, 0.3)); });
  EXPECT_EQ(model.contact_width(0.085), -1.0);
  SimGripper g(SimGripperConfig{}, &model);
  ASSERT_EQ(g.close(40.f), Status::ok);
  settle(g);
  fg::hal::GripperState st;
  ASSERT_EQ(g.read_state(st), Status::ok);
  EXPECT_FALSE(st.contact);
  EXPECT_EQ(st.width_m, 0.f);
}

TEST(SimGripper, OffCentreBoxStillGivesItsWidth) {
  const V3 grasp_centre(0.5, 0.0, 0.3);
  // 30 mm wide, its centre 20 mm towards the right pad (spans +5..+35 mm; pads at +-42.5).
  const World w = world_with_box(grasp_centre + V3(0.02, 0.0, 0.0), V3(0.015, 0.05, 0.04));
  const SdfContactModel model(w, [&] { return grasp_down_at(grasp_centre); });
  const Rigid G = grasp_down_at(grasp_centre);
  EXPECT_NEAR(model.pad_travel(G, 0.085, 0, 0.085), 0.0425 + 0.005, 1e-6);
  EXPECT_NEAR(model.pad_travel(G, 0.085, 1, 0.085), 0.0425 - 0.035, 1e-6);
  SimGripper g(SimGripperConfig{}, &model);
  ASSERT_EQ(g.close(40.f), Status::ok);
  settle(g);
  EXPECT_TRUE(g.contact());
  EXPECT_NEAR(g.width_m(), 0.030, 1e-3);

  // Only partly between the pads (the pad edge overlaps it by 5 mm along y): still touched.
  const World w2 = world_with_box(grasp_centre + V3(0.0, 0.011 + 0.02 - 0.005, 0.0), V3(0.015, 0.02, 0.04));
  const SdfContactModel model2(w2, [&] { return G; });
  EXPECT_NEAR(model2.contact_width(0.085), 0.030, 1e-6);
}

TEST(SimGripper, TouchesAThinPartUnderTheFingertips) {
  // A 2 mm slat (30 mm across the closing direction) 14-16 mm past the pads' centre
  // along the approach: between the rows of a coarse 5 x 5 pad grid (every 10 mm along
  // the pad), as a flat pair of scissors lies under the fingertips. A pad touches it.
  const V3 grasp_centre(0.5, 0.0, 0.3);
  const World w = world_with_box(grasp_centre - V3(0.0, 0.0, 0.015), V3(0.015, 0.02, 0.001));
  const SdfContactModel model(w, [&] { return grasp_down_at(grasp_centre); });
  EXPECT_NEAR(model.contact_width(0.085), 0.030, 1e-6);
  // The same slat narrower than the pad across it (3 mm along grasp y, off the centre
  // line): touched as well.
  const World w2 = world_with_box(grasp_centre + V3(0.0, 0.004, -0.015), V3(0.015, 0.0015, 0.001));
  const SdfContactModel model2(w2, [&] { return grasp_down_at(grasp_centre); });
  EXPECT_NEAR(model2.contact_width(0.085), 0.030, 1e-6);
}

TEST(SimGripper, FollowsTheArmThroughAMountedGraspFrame) {
  // The grasp frame 0.15 m in front of tool0; the box sits there for the start pose only.
  SimArm arm(kHomeDown);
  const Rigid tool0_T_grasp = Rigid::translation(V3(0, 0, 0.15));
  const V3 centre = (arm.world_T_tool0() * tool0_T_grasp).t;
  const World w = world_with_box(centre, V3(0.025, 0.025, 0.025));
  const SdfContactModel model(w, mounted_on_tool0(arm, tool0_T_grasp));
  EXPECT_NEAR(model.contact_width(0.085), 0.050, 1e-6);
  double q[6];
  for (int i = 0; i < 6; ++i) q[i] = kHomeDown[i];
  q[0] += 0.5;  // swing the base away
  ASSERT_EQ(arm.move_joints(q, 1.0), Status::ok);
  arm.tick(1.0);
  EXPECT_EQ(model.contact_width(0.085), -1.0);
}

// ---------------------------------------------------------------------------------------
namespace {

World table_with_box() {
  World w;
  w.table.height = 0.0;
  w.table.x_min = -1.5;
  w.table.x_max = 1.5;
  w.table.y_min = -1.5;
  w.table.y_max = 1.5;
  // 60 x 60 x 100 mm box standing at (0.5, 0): top at z = 0.1.
  w.objects.push_back({"box", "box", {Part::box("box", V3(0.03, 0.03, 0.05), Rigid::translation(V3(0.5, 0, 0.05)))}});
  return w;
}

SimDepthSensorConfig noise_free() {
  SimDepthSensorConfig c;
  c.noise = NoiseModel::none();
  return c;
}

uint16_t pixel(const fg::hal::DepthFrame& f, int u, int v) { return f.depth_mm[static_cast<size_t>(v) * f.width + u]; }

}  // namespace

TEST(SimDepthSensor, ReadyOnlyAfterItsLatency) {
  const World w = table_with_box();
  SimClock clock;
  clock.advance_us(5000);
  const Rigid above = look_at(V3(0.5, 0, 1.0), V3(0.5, 0, 0), V3(1, 0, 0));
  SimDepthSensor sensor(
      w, clock, [&] { return above; }, noise_free());
  fg::hal::DepthSensor& s = sensor;
  fg::hal::DepthFrame f;
  EXPECT_EQ(s.poll(f), fg::hal::CaptureState::idle);
  ASSERT_EQ(s.request_capture(), Status::ok);
  EXPECT_EQ(s.poll(f), fg::hal::CaptureState::busy);
  clock.advance_us(32999);
  EXPECT_EQ(s.poll(f), fg::hal::CaptureState::busy);
  EXPECT_EQ(f.depth_mm, nullptr);
  clock.advance_us(1);
  ASSERT_EQ(s.poll(f), fg::hal::CaptureState::ready);
  EXPECT_EQ(f.stamp_us, 5000u);  // taken at the request
  EXPECT_EQ(f.width, 640);
  EXPECT_EQ(f.height, 480);
  EXPECT_FLOAT_EQ(f.k.fx, 525.f);
  EXPECT_FLOAT_EQ(f.k.cx, 319.5f);
  // It stays ready until the next request.
  clock.advance_us(100000);
  EXPECT_EQ(s.poll(f), fg::hal::CaptureState::ready);
  EXPECT_EQ(sensor.captures(), 1u);
}

TEST(SimDepthSensor, FailedCaptureReportsFailed) {
  const World w = table_with_box();
  SimClock clock;
  const Rigid above = look_at(V3(0.5, 0, 1.0), V3(0.5, 0, 0), V3(1, 0, 0));
  SimDepthSensor sensor(
      w, clock, [&] { return above; }, noise_free());
  sensor.set_fail_next();
  fg::hal::DepthFrame f;
  ASSERT_EQ(sensor.request_capture(), Status::ok);
  EXPECT_EQ(sensor.poll(f), fg::hal::CaptureState::busy);
  clock.advance_us(33000);
  EXPECT_EQ(sensor.poll(f), fg::hal::CaptureState::failed);
  EXPECT_EQ(f.depth_mm, nullptr);
  // Only the next one.
  ASSERT_EQ(sensor.request_capture(), Status::ok);
  clock.advance_us(33000);
  EXPECT_EQ(sensor.poll(f), fg::hal::CaptureState::ready);
}

TEST(SimDepthSensor, NonFinitePoseIsAFailedCapture) {
  const World w = table_with_box();
  SimClock clock;
  Rigid pose = look_at(V3(0.5, 0, 1.0), V3(0.5, 0, 0), V3(1, 0, 0));
  SimDepthSensor sensor(
      w, clock, [&] { return pose; }, noise_free());
  pose.t.x() = NAN;
  fg::hal::DepthFrame f;
  ASSERT_EQ(sensor.request_capture(), Status::ok);
  clock.advance_us(33000);
  EXPECT_EQ(sensor.poll(f), fg::hal::CaptureState::failed);
}

TEST(SimDepthSensor, BoxSeenFromAboveHasItsTopAtTheRightDepth) {
  const World w = table_with_box();
  SimClock clock;
  const Rigid above = look_at(V3(0.5, 0, 1.0), V3(0.5, 0, 0), V3(1, 0, 0));
  SimDepthSensor sensor(
      w, clock, [&] { return above; }, noise_free());
  fg::hal::DepthFrame f;
  ASSERT_EQ(sensor.request_capture(), Status::ok);
  clock.advance_us(33000);
  ASSERT_EQ(sensor.poll(f), fg::hal::CaptureState::ready);
  // The box top (z = 0.1) fills the centre: 0.9 m away; the table around it: 1.0 m.
  EXPECT_NEAR(pixel(f, 320, 240), 900, 1);
  EXPECT_NEAR(pixel(f, 310, 230), 900, 1);
  EXPECT_NEAR(pixel(f, 40, 240), 1000, 1);
  EXPECT_NEAR(pixel(f, 320, 30), 1000, 1);
  // The top is 60 mm at 0.9 m: 35 pixels across.
  int top = 0;
  for (int u = 0; u < f.width; ++u) top += pixel(f, u, 240) == 900;
  EXPECT_NEAR(top, 0.06 / 0.9 * 525, 2);
}

TEST(SimDepthSensor, NoisyCapturesAreSeededPerCapture) {
  const World w = table_with_box();
  SimClock clock;
  const Rigid above = look_at(V3(0.5, 0, 1.0), V3(0.5, 0, 0), V3(1, 0, 0));
  SimDepthSensorConfig cfg;  // default noise
  cfg.seed = 7;
  SimDepthSensor a(
      w, clock, [&] { return above; }, cfg);
  SimDepthSensor b(
      w, clock, [&] { return above; }, cfg);
  ASSERT_EQ(a.request_capture(), Status::ok);
  ASSERT_EQ(b.request_capture(), Status::ok);
  EXPECT_EQ(a.last_image().mm, b.last_image().mm);  // same seed, same capture: same image
  const std::vector<uint16_t> first = a.last_image().mm;
  ASSERT_EQ(a.request_capture(), Status::ok);
  EXPECT_NE(a.last_image().mm, first);  // the next capture has its own noise
}

TEST(SimDepthSensor, WristSensorFollowsTheArm) {
  SimClock clock;
  SimArm arm(kHomeDown, SimArmConfig{}, &clock);
  // The tool looks down (tool0 +z), so the wrist camera sees the table.
  ASSERT_LT(arm.world_T_tool0().R.col(2).z(), -0.99);
  const Rigid tool0_T_sensor = Rigid::from_pose(fg::robot::default_hand_eye());
  const V3 eye = (arm.world_T_tool0() * tool0_T_sensor).t;
  // The table 0.7 m below the camera, the box (top 0.6 m below) right under it.
  World w = table_with_box();
  w.table.height = eye.z() - 0.7;
  w.objects[0].parts[0].world_T_shape = Rigid::translation(V3(eye.x(), eye.y(), w.table.height + 0.05));
  SimDepthSensor sensor(w, clock, mounted_on_tool0(arm, tool0_T_sensor), noise_free());
  fg::hal::DepthFrame f;

  ASSERT_EQ(sensor.request_capture(), Status::ok);
  run(clock, &arm, nullptr, 33000);
  ASSERT_EQ(sensor.poll(f), fg::hal::CaptureState::ready);
  const std::vector<uint16_t> before(f.depth_mm, f.depth_mm + size_t(f.width) * f.height);
  EXPECT_LT(max_abs_diff(sensor.last_camera().world_T_sensor, arm.world_T_tool0() * tool0_T_sensor), 1e-12);
  EXPECT_NEAR(pixel(f, 320, 240), 600, 3);  // the box top, straight below

  // Swing the base (the camera moves ~0.15 m sideways); capture again.
  double q[6];
  for (int i = 0; i < 6; ++i) q[i] = kHomeDown[i];
  q[0] += 0.3;
  ASSERT_EQ(arm.move_joints(q, 0.5), Status::ok);
  run(clock, &arm, nullptr, 1000000);
  ASSERT_FALSE(arm.moving());
  ASSERT_EQ(sensor.request_capture(), Status::ok);
  run(clock, &arm, nullptr, 33000);
  ASSERT_EQ(sensor.poll(f), fg::hal::CaptureState::ready);
  const Rigid expected_pose = arm.world_T_tool0() * tool0_T_sensor;
  EXPECT_LT(max_abs_diff(sensor.last_camera().world_T_sensor, expected_pose), 1e-12);
  // The image is the one a camera at the new pose sees, and not the old one.
  Camera cam;
  cam.world_T_sensor = expected_pose;
  const DepthImage expected = render_depth(w, cam, NoiseModel::none(), 1);
  const std::vector<uint16_t> after(f.depth_mm, f.depth_mm + size_t(f.width) * f.height);
  EXPECT_EQ(after, expected.mm);
  EXPECT_NE(after, before);
}
