// The pads' edges (docs/method.md E/F): a surface just beyond a pad's footprint that
// stands out past the contact meets the pad's corner before the pad meets its contact.
// A table-tennis bat lying flat: a grasp across the handle next to the blade puts the
// corner of one finger on the blade's rim, whose normal points along the handle (75-80
// deg outside the friction cone). Such grasps wait until no other grasp is found.
// Scenes rendered two-sensor by hal/sim and judged on their TRUE geometry
// (hal/sim/grasp_judge): every grasp the planner returns must hold; no_grasp is the
// other right answer.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "fg/core/planner.hpp"
#include "sim_plan_judge.hpp"

using namespace fg::sim;

namespace {
GeneratedScene lying_bat(uint64_t seed) {
  return make_scene(ObjectKind::bat_lying, seed, SceneOptions{});  // as `forcegrasp sim` makes it
}
}  // namespace

// The scenes of `forcegrasp sim` trials whose grasp met the blade with a finger's
// corner before the rule (seeds 2000, 9000, 12000, 47000 and 61000, 380 trials each),
// here seen by the cameras at the scene's poses (the sim's wrist camera may be turned
// about its axis).
TEST(PlannerPadCorner, BatsWhoseBladeMetAFingerCornerGetGraspsThatHold) {
  const uint64_t seeds[] = {2009, 2294, 9237, 12142, 47085, 61275};
  // judge_seeds numbers the scenes 1..6; a failure names that number.
  const JudgedSeeds r =
      judge_seeds(sizeof(seeds) / sizeof(seeds[0]), [&](uint64_t k) { return lying_bat(seeds[k - 1]); });
  EXPECT_EQ(r.held, r.grasps) << "grasps that do not hold (scene k of the list):" << r.failures;
  EXPECT_GE(r.grasps, 5);
}

// Sixty more lying bats: the rule costs them nothing.
TEST(PlannerPadCorner, GraspsOnLyingBatsHoldOnTheTrueGeometry) {
  const JudgedSeeds r = judge_seeds(60, [](uint64_t seed) {
    SceneOptions opt;
    opt.second_object_rate = 0.0;
    return make_scene(ObjectKind::bat_lying, seed, opt);
  });
  EXPECT_LE(r.grasps - r.held, 1) << "grasps that do not hold:" << r.failures;
  EXPECT_GE(r.grasps, 50);
}
