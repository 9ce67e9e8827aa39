// hal/sim grasp judge: hand-made grasps on boxes and cans accepted or rejected for the
// right reason; the "fits the gripper" test.
#include <gtest/gtest.h>

#include <cmath>

#include "fg/core/constants.hpp"
#include "sim/grasp_judge.hpp"
#include "sim/scene_gen.hpp"

using namespace fg::sim;

namespace {

using fg::kPi;

World world_with(const Object& target) {
  World w;
  w.objects.push_back(target);
  return w;
}

Object box_object(const V3& half, const V3& centre, double yaw = 0.0) {
  Object o;
  o.name = "target";
  o.kind = "box";
  o.parts.push_back(Part::box("body", half, Rigid::translation(centre) * Rigid::rot_z(yaw)));
  return o;
}

Grasp make_grasp(const V3& position, const V3& approach, const V3& closing, double width) {
  Grasp g;
  g.position = position.cast<float>();
  g.approach = approach.normalized().cast<float>();
  g.closing = closing.normalized().cast<float>();
  g.width = static_cast<float>(width);
  return g;
}

bool starts_with(const std::string& s, const std::string& p) { return s.rfind(p, 0) == 0; }

// A 0.06 x 0.12 x 0.16 box standing at (0.5, 0, 0); a side grasp across its narrow faces at
// mid-height, approaching along +y with the palm just outside the box.
const Object kBox = box_object(V3(0.03, 0.06, 0.08), V3(0.5, 0, 0.08));
Grasp side_grasp_on_box(double width = 0.06) {
  return make_grasp(V3(0.5, -0.045, 0.08), V3(0, 1, 0), V3(1, 0, 0), width);
}

}  // namespace

TEST(SimJudge, AcceptsSideGraspAcrossNarrowFaces) {
  const fg::GripperGeometry g;
  const JudgeResult r = judge_grasp(world_with(kBox), 0, side_grasp_on_box(), g);
  EXPECT_TRUE(r.success) << r.reason;
  EXPECT_EQ(r.reason, "success");
  EXPECT_NEAR(r.true_width, 0.06f, 1e-5f);
  EXPECT_NEAR(r.angle_left, 0.0f, 1e-3f);
  EXPECT_NEAR(r.angle_right, 0.0f, 1e-3f);
  EXPECT_NEAR(r.contact_left.x(), 0.47f, 1e-5f);
  EXPECT_NEAR(r.contact_right.x(), 0.53f, 1e-5f);
}

TEST(SimJudge, AcceptsTopDownGraspOnBox) {
  const fg::GripperGeometry g;
  const Grasp grasp = make_grasp(V3(0.5, 0.0, 0.175), V3(0, 0, -1), V3(1, 0, 0), 0.061);
  const JudgeResult r = judge_grasp(world_with(kBox), 0, grasp, g);
  EXPECT_TRUE(r.success) << r.reason;
  // Closing the other way round is the same grasp.
  const Grasp flipped = make_grasp(V3(0.5, 0.0, 0.175), V3(0, 0, -1), V3(-1, 0, 0), 0.06);
  EXPECT_TRUE(judge_grasp(world_with(kBox), 0, flipped, g).success);
}

TEST(SimJudge, AcceptsSlightlyRotatedBox) {
  // A 3 degree yaw: the pads meet the faces (not the edges), inside the friction cone.
  const Object box = box_object(V3(0.03, 0.06, 0.08), V3(0.5, 0, 0.08), 3.0 * kPi / 180.0);
  const JudgeResult r = judge_grasp(world_with(box), 0, side_grasp_on_box(0.062), fg::GripperGeometry{});
  EXPECT_TRUE(r.success) << r.reason;
  EXPECT_NEAR(r.angle_left, 3.0 * kPi / 180.0, 1e-3);
}

TEST(SimJudge, AcceptsSideGraspOnCan) {
  Object can;
  can.name = "target";
  can.parts.push_back(Part::cylinder("body", 0.035, 0.06, Rigid::translation(V3(0.4, 0.1, 0.06))));
  const Grasp grasp = make_grasp(V3(0.4, 0.082, 0.06), V3(0, 1, 0), V3(1, 0, 0), 0.07);
  const JudgeResult r = judge_grasp(world_with(can), 0, grasp, fg::GripperGeometry{});
  EXPECT_TRUE(r.success) << r.reason;
  EXPECT_NEAR(r.true_width, 0.07f, 1e-4f);
  // And top-down.
  const Grasp top = make_grasp(V3(0.4, 0.1, 0.135), V3(0, 0, -1), V3(0, 1, 0), 0.07);
  const JudgeResult rt = judge_grasp(world_with(can), 0, top, fg::GripperGeometry{});
  EXPECT_TRUE(rt.success) << rt.reason;
}

TEST(SimJudge, RejectsClosingAcrossTheDiagonal) {
  const Object box = box_object(V3(0.02, 0.025, 0.06), V3(0.5, 0, 0.06));
  const double diag = 2.0 * std::hypot(0.02, 0.025);
  const Grasp grasp = make_grasp(V3(0.5, 0, 0.135), V3(0, 0, -1), V3(0.04, 0.05, 0), diag);
  const JudgeResult r = judge_grasp(world_with(box), 0, grasp, fg::GripperGeometry{});
  EXPECT_FALSE(r.success);
  EXPECT_TRUE(starts_with(r.reason, "friction_")) << r.reason;
  EXPECT_NEAR(r.true_width, diag, 2e-3);
  // With enough friction a corner grasp would hold.
  JudgeOptions sticky;
  sticky.mu = 2.0;
  EXPECT_TRUE(judge_grasp(world_with(box), 0, grasp, fg::GripperGeometry{}, sticky).success);
}

TEST(SimJudge, RejectsPalmThroughTheTable) {
  // The same side grasp lowered: the palm (0.05 wide across the closing plane) goes below
  // z = 0 while the fingers (0.022 wide) stay above it.
  Grasp grasp = side_grasp_on_box();
  grasp.position.z() = 0.015f;
  const JudgeResult r = judge_grasp(world_with(kBox), 0, grasp, fg::GripperGeometry{});
  EXPECT_FALSE(r.success);
  EXPECT_TRUE(starts_with(r.reason, "collision_open_pose:table palm")) << r.reason;
  EXPECT_NEAR(r.max_penetration, 0.01f, 1e-4f);
  // A grasp from below the table.
  const Grasp below = make_grasp(V3(0.5, 0, 0.01), V3(0, 0, 1), V3(1, 0, 0), 0.06);
  EXPECT_TRUE(
      starts_with(judge_grasp(world_with(kBox), 0, below, fg::GripperGeometry{}).reason, "collision_open_pose:table"));
}

TEST(SimJudge, RejectsPalmInsideTheObject) {
  // Top-down with the pads' centre 5 cm below the box top: the palm enters the box.
  const Grasp grasp = make_grasp(V3(0.5, 0.0, 0.11), V3(0, 0, -1), V3(1, 0, 0), 0.06);
  const JudgeResult r = judge_grasp(world_with(kBox), 0, grasp, fg::GripperGeometry{});
  EXPECT_FALSE(r.success);
  EXPECT_TRUE(starts_with(r.reason, "collision_open_pose:target palm")) << r.reason;
  // Closing across the wide faces (0.12 > 0.085): the fingers are inside the box.
  const Grasp wide = make_grasp(V3(0.5, 0.0, 0.175), V3(0, 0, -1), V3(0, 1, 0), 0.085);
  const JudgeResult rw = judge_grasp(world_with(kBox), 0, wide, fg::GripperGeometry{});
  EXPECT_TRUE(starts_with(rw.reason, "collision_open_pose:target")) << rw.reason;
}

TEST(SimJudge, RejectsWidthOffByTwoCentimetres) {
  const JudgeResult r = judge_grasp(world_with(kBox), 0, side_grasp_on_box(0.08), fg::GripperGeometry{});
  EXPECT_FALSE(r.success);
  EXPECT_EQ(r.reason, "width_error 0.020");
  // 9 mm off is tolerated.
  EXPECT_TRUE(judge_grasp(world_with(kBox), 0, side_grasp_on_box(0.069), fg::GripperGeometry{}).success);
}

TEST(SimJudge, RejectsGraspBesideTheObject) {
  Grasp grasp = side_grasp_on_box();
  grasp.position.x() += 0.1f;
  const JudgeResult r = judge_grasp(world_with(kBox), 0, grasp, fg::GripperGeometry{});
  EXPECT_FALSE(r.success);
  EXPECT_EQ(r.reason, "miss_left");
  // Pads above the object: nothing between them either.
  const Grasp above = make_grasp(V3(0.5, 0.0, 0.25), V3(0, 0, -1), V3(1, 0, 0), 0.06);
  EXPECT_EQ(judge_grasp(world_with(kBox), 0, above, fg::GripperGeometry{}).reason, "miss_left");
}

TEST(SimJudge, RejectsAnotherObjectBetweenTheFingers) {
  World w = world_with(box_object(V3(0.015, 0.06, 0.08), V3(0.5, 0, 0.08)));
  Object pebble;
  pebble.name = "pebble";
  pebble.parts.push_back(Part::sphere("s", 0.008, V3(0.47, -0.04, 0.08)));
  w.objects.push_back(pebble);
  const JudgeResult r = judge_grasp(w, 0, side_grasp_on_box(0.03), fg::GripperGeometry{});
  EXPECT_FALSE(r.success);
  EXPECT_EQ(r.reason, "collision_closing:pebble left");
  // Target index 1 (the pebble) with a grasp that never reaches it: a miss.
  EXPECT_TRUE(starts_with(
      judge_grasp(w, 1, make_grasp(V3(0.8, 0, 0.1), V3(0, 0, -1), V3(1, 0, 0), 0.02), fg::GripperGeometry{}).reason,
      "miss"));
}

TEST(SimJudge, RejectsMalformedGrasps) {
  const fg::GripperGeometry g;
  EXPECT_TRUE(
      starts_with(judge_grasp(world_with(kBox), 0, side_grasp_on_box(0.09), g).reason, "width_exceeds_opening"));
  Grasp skew = side_grasp_on_box();
  skew.closing = fg::Vec3(1, 1, 0).normalized();
  EXPECT_TRUE(starts_with(judge_grasp(world_with(kBox), 0, skew, g).reason, "invalid_grasp"));
  Grasp nan = side_grasp_on_box();
  nan.position.x() = std::nanf("");
  EXPECT_TRUE(starts_with(judge_grasp(world_with(kBox), 0, nan, g).reason, "invalid_grasp"));
  EXPECT_EQ(judge_grasp(world_with(kBox), 3, side_grasp_on_box(), g).reason, "invalid_target");
}

TEST(SimJudge, FitsTheGripper) {
  const fg::GripperGeometry g;
  const FitReport box = target_fit(box_object(V3(0.03, 0.06, 0.08), V3(0.5, 0, 0.08), 0.7), g);
  EXPECT_TRUE(box.fits);
  EXPECT_NEAR(box.min_width, 0.06, 1e-9);
  EXPECT_NEAR(std::abs(box.direction.dot(V3(std::cos(0.7), std::sin(0.7), 0))), 1.0, 1e-9);
  EXPECT_FALSE(target_fit(box_object(V3(0.055, 0.06, 0.03), V3(0.5, 0, 0.03)), g).fits);
  // Expected answers of the generated kinds, over a few seeds.
  for (ObjectKind k : all_kinds()) {
    const bool expect = !(k == ObjectKind::wide_box || k == ObjectKind::big_sphere);
    for (uint64_t seed = 0; seed < 20; ++seed) {
      const FitReport f = target_fit(make_object(k, seed), g);
      EXPECT_EQ(f.fits, expect) << kind_name(k) << " seed " << seed << " min width " << f.min_width;
    }
  }
  // A lying bat fits by its handle, a standing bat by its blade's thickness.
  const Object lying = make_object(ObjectKind::bat_lying, 4);
  const FitReport fl = target_fit(lying, g);
  ASSERT_GE(fl.part, 0);
  EXPECT_EQ(lying.parts[static_cast<size_t>(fl.part)].name, "handle");
  const Object standing = make_object(ObjectKind::bat_standing, 4);
  const FitReport fs = target_fit(standing, g);
  ASSERT_GE(fs.part, 0);
  EXPECT_EQ(standing.parts[static_cast<size_t>(fs.part)].name, "blade");
  EXPECT_LT(fs.min_width, 0.015);
}
