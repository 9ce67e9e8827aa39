// The pads' reach past the first contact (docs/method.md, executability check 5): a pad
// whose contact points all lie within a few millimetres of its fingertip may land its
// tip on the face beyond the edge it was meant to squeeze. Low slabs lying on the table
// (the gripper is raised off the table, so on a tilted approach one pad only just
// reaches the slab's top edge), rendered two-sensor by hal/sim and judged on their TRUE
// geometry (hal/sim/grasp_judge): every grasp the planner returns must hold (both pads
// on the slab's sides, inside the friction cone); no_grasp is the other right answer.
#include <gtest/gtest.h>

#include <cstdint>
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
  const JudgedSeeds r = judge_seeds(24, [](uint64_t seed) {
    const double height = 0.012 + 0.0005 * static_cast<double>(seed % 13);  // 1.2 to 1.8 cm
    return slab_scene(seed, height);
  });
  EXPECT_EQ(r.held, r.grasps) << "grasps that do not hold:" << r.failures;
  // The slabs fit the gripper across their narrow side: most get a grasp.
  EXPECT_GE(r.grasps, 12);
}
