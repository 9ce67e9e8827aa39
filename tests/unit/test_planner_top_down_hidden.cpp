// A finger hidden beside a tall box's far face (docs/method.md, executability check 4):
// tall boxes standing on the table, rendered two-sensor by hal/sim and judged on their
// TRUE geometry (hal/sim/grasp_judge).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <string>

#include "fg/core/planner.hpp"
#include "sim_plan_judge.hpp"

using namespace fg::sim;

// A box 6.0-7.2 cm by 14.0-16.1 cm, 20-24 cm tall (a cracker box standing), turned about
// the vertical by 0-1.4 rad from the seeded box's yaw: only its narrow width fits the
// 8.5 cm opening, and both sensors see it from one side, so one of the two faces the
// pads would close on is seen by none. The finger beside it is hidden by the box itself
// at every approach; straight down it lies beside the top's far edge. Every grasp the
// planner returns must hold on the TRUE geometry; no_grasp is the other right answer
// but the box is graspable from above.
TEST(PlannerTopDownHidden, TallBoxesAreGraspedFromAboveAndTheGraspsHold) {
  const JudgedSeeds r = judge_seeds(40, [](uint64_t seed) {
    const double w = 0.060 + 0.0012 * static_cast<double>(seed % 11);
    const double l = 0.140 + 0.0030 * static_cast<double>(seed % 8);
    const double h = 0.20 + 0.01 * static_cast<double>(seed % 5);
    const double turn = 0.1 * static_cast<double>(seed % 15);
    return box_target_scene(seed, V3(0.5 * w, 0.5 * l, 0.5 * h), turn);
  });
  std::printf("grasps %d held %d:%s\n", r.grasps, r.held, r.failures.c_str());
  // Measured: 35 of 36 grasps hold (seed 32: an open finger 1 mm into the box on a
  // tilted approach, as before the rule). Without the top-down deferral: 32 of 33, the
  // other 7 no_grasp with every candidate's far finger in hidden space. Since the seen
  // side under a partly hidden finger counts only where no hidden space lies beyond it
  // (check 4): 33 of 34 hold, 2 tilted grasps that held became no_grasp (their far
  // side's profile had been the near face's points, seen through the box).
  EXPECT_LE(r.grasps - r.held, 1) << "grasps that do not hold:" << r.failures;
  EXPECT_GE(r.held, 33) << "grasps that do not hold:" << r.failures;
}
