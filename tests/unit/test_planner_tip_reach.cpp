// The pads' reach past the first contact (docs/method.md, executability check 5): a pad
// whose contact points all lie within a few millimetres of its fingertip may land its
// tip on the face beyond the edge it was meant to squeeze. Low slabs lying on the table
// (the gripper is raised off the table, so on a tilted approach one pad only just
// reaches the slab's top edge), rendered two-sensor by hal/sim and judged on their TRUE
// geometry (hal/sim/grasp_judge): every grasp the planner returns must hold (both pads
// on the slab's sides, inside the friction cone); no_grasp is the other right answer.
#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <sstream>
#include <string>

#include "fg/core/planner.hpp"
#include "sim_plan_judge.hpp"

using namespace fg::sim;

namespace {

// The scene of a box (seeded place, yaw and cameras) whose target is replaced by a slab
// 2.6 cm across, 12 cm long and `height` tall, lying at the same place and yaw.
GeneratedScene slab_scene(uint64_t seed, double height) {
  return box_target_scene(seed, V3(0.013, 0.06, 0.5 * height), 0.0);
}

}  // namespace

TEST(PlannerTipReach, GraspsOnLowSlabsHoldOnTheTrueGeometry) {
  auto planner = std::make_unique<fg::Planner>();
  ASSERT_EQ(planner->configure(fg::PlannerConfig{}), fg::Status::ok);
  int grasps = 0, held = 0;
  std::ostringstream failures;
  for (uint64_t seed = 1; seed <= 24; ++seed) {
    const double height = 0.012 + 0.0005 * static_cast<double>(seed % 13);  // 1.2 to 1.8 cm
    const GeneratedScene s = slab_scene(seed, height);
    ASSERT_TRUE(s.truth.target_fits);
    const JudgedPlan jp = plan_and_judge(*planner, s);
    if (jp.status != fg::Status::ok) {
      EXPECT_EQ(jp.status, fg::Status::no_grasp) << "seed " << seed << ": " << jp.message;
      continue;
    }
    ++grasps;
    const JudgeResult& j = jp.judge;
    if (j.success) ++held;
    else failures << " seed " << seed << " (height " << height << "): " << j.reason << ";";
  }
  EXPECT_EQ(held, grasps) << "grasps that do not hold:" << failures.str();
  // The slabs fit the gripper across their narrow side: most get a grasp.
  EXPECT_GE(grasps, 12);
}
