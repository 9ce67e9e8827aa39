// Test helper: plans a hal/sim scene as the sensors see it (both cameras' depth images)
// and judges the returned grasp on the scene's TRUE geometry (hal/sim/grasp_judge).
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "fg/core/planner.hpp"
#include "sim/grasp_judge.hpp"
#include "sim/pinhole.hpp"
#include "sim/scene_gen.hpp"

namespace fg::sim {

//! The scene of a box (seeded place, yaw and cameras, no second object) whose target
//! is replaced by a box of half extents `half` standing on the table at the same
//! place, turned about the vertical by `turn` from the box's yaw.
inline GeneratedScene box_target_scene(uint64_t seed, const V3& half, double turn) {
  SceneOptions opt;
  opt.second_object_rate = 0.0;
  GeneratedScene s = make_scene(ObjectKind::box, seed, opt);
  Object& o = s.world.objects[static_cast<size_t>(s.target)];
  Rigid pose = o.parts.at(0).world_T_shape;
  pose.t.z() = s.world.table.height + half.z();
  pose = pose * Rigid::rot_z(turn);
  o.parts.clear();
  o.parts.push_back(Part::box("body", half, pose));
  s.truth = compute_truth(s.world, s.target, s.gripper, s.truth.fit_margin);
  return s;
}

struct JudgedPlan {
  fg::Status status = fg::Status::internal_error;
  std::string message;
  JudgeResult judge;  //!< set when status is ok
  float width = 0.f;  //!< the planned grasp's width, when status is ok
};

//! The sensors a plan is given: both cameras (the normal case) or one of them.
enum class Sensors { both, head, hand };

inline JudgedPlan plan_and_judge(fg::Planner& planner, const GeneratedScene& s, Sensors sensors = Sensors::both) {
  JudgedPlan out;
  const SceneImages img = render_scene(s);
  planner.reset();
  if (sensors != Sensors::hand) {
    EXPECT_EQ(add_rendered(planner, fg::SensorRole::head, img.head, s.head), fg::Status::ok);
  }
  if (sensors != Sensors::head) {
    EXPECT_EQ(add_rendered(planner, fg::SensorRole::hand, img.hand, s.hand), fg::Status::ok);
  }
  fg::PlanResult r;
  out.status = planner.plan(r);
  out.message = r.message;
  out.width = r.grasp.width;
  if (out.status != fg::Status::ok) return out;
  Grasp g;
  g.position = r.grasp.position;
  g.approach = r.grasp.approach;
  g.closing = r.grasp.closing;
  g.width = r.grasp.width;
  out.judge = judge_grasp(s.world, s.target, g, s.gripper);
  return out;
}

//! Seeds 1..n: each scene (make(seed), a target that fits) planned by a default planner
//! and its grasp judged; a plan that is not ok must be no_grasp.
struct JudgedSeeds {
  int grasps = 0, held = 0;
  std::string failures;  //!< " seed N: reason;" for each grasp that does not hold
  //! Of the grasps that do not hold on friction: the larger contact angle of each (deg).
  std::vector<double> friction_deg;
};
template <class MakeScene>
JudgedSeeds judge_seeds(uint64_t n, MakeScene make) {
  JudgedSeeds out;
  auto planner = std::make_unique<fg::Planner>();
  EXPECT_EQ(planner->configure(fg::PlannerConfig{}), fg::Status::ok);
  std::ostringstream failures;
  for (uint64_t seed = 1; seed <= n; ++seed) {
    const GeneratedScene s = make(seed);
    EXPECT_TRUE(s.truth.target_fits) << "seed " << seed;
    const JudgedPlan jp = plan_and_judge(*planner, s);
    if (jp.status != fg::Status::ok) {
      EXPECT_EQ(jp.status, fg::Status::no_grasp) << "seed " << seed << ": " << jp.message;
      continue;
    }
    ++out.grasps;
    if (jp.judge.success)
      ++out.held;
    else
      failures << " seed " << seed << ": " << jp.judge.reason << ";";
    if (!jp.judge.success && jp.judge.reason.rfind("friction", 0) == 0)
      out.friction_deg.push_back(std::max(jp.judge.angle_left, jp.judge.angle_right) * 180.0 / 3.14159265358979);
  }
  out.failures = failures.str();
  return out;
}

}  // namespace fg::sim
