// After a refusal as occluded, the plan says which sensor would have to look where
// (docs/method.md, "The report": look): scenes rendered by hal/sim for the head sensor
// alone (the cell distribution), whose advice is checked against the scenes' TRUE
// geometry. Round bodies seen from one side leave the far finger of many grasps in
// space no sensor saw; of 60 such scenes a few are refused for it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include "fg/core/planner.hpp"
#include "sim_plan_judge.hpp"

using namespace fg::sim;

TEST(PlannerLookAdvice, TheAdvisedViewSeesTheHiddenSpacePastTheTarget) {
  auto planner = std::make_unique<fg::Planner>();
  ASSERT_EQ(planner->configure(fg::PlannerConfig{}), fg::Status::ok);
  int occluded = 0;
  for (const ObjectKind kind : {ObjectKind::bottle, ObjectKind::sphere, ObjectKind::ellipsoid})
    for (uint64_t seed = 1; seed <= 20; ++seed) {
      SCOPED_TRACE(std::string(kind_name(kind)) + " seed " + std::to_string(seed));
      SceneOptions opt = SceneOptions::of(Distribution::cell);
      const GeneratedScene s = make_scene(kind, seed, opt);
      const SceneImages img = render_scene(s);
      planner->reset();
      ASSERT_EQ(add_rendered(*planner, fg::SensorRole::head, img.head, s.head), fg::Status::ok);
      fg::PlanResult r;
      const fg::Status st = planner->plan(r);
      if (st != fg::Status::no_grasp || r.reason != fg::NoGraspReason::occluded) {
        EXPECT_FALSE(r.look.valid);
        continue;
      }
      ++occluded;
      ASSERT_TRUE(r.look.valid);
      // One sensor: it is the one to move.
      EXPECT_EQ(r.look.sensor, fg::SensorRole::head);
      const Object& target = s.world.objects[static_cast<size_t>(s.target)];
      const V3 at(r.look.at.x(), r.look.at.y(), r.look.at.z());
      const V3 from(r.look.from.x(), r.look.from.y(), r.look.from.z());
      // The hidden space lies by the target, within a finger's reach of it.
      EXPECT_LT(target.sdf(at), 0.06);
      // The target does not stand between the advised viewpoint and that space: the
      // segment stays outside the true target up to a centimetre short of its end.
      const double len = (at - from).norm();
      for (int k = 0; k <= 100; ++k) {
        const double t = (len - 0.01) * k / 100.0;
        EXPECT_GT(target.sdf(from + (at - from) * (t / len)), 0.0) << "at " << t << " m of " << len;
      }
      // From above, at the head's distance.
      EXPECT_GT(from.z(), at.z());
      EXPECT_NEAR(len, (s.head.world_T_sensor.t - at).norm(), 1e-4);
    }
  EXPECT_GT(occluded, 0) << "no scene was refused as occluded: the test shows nothing";
}
