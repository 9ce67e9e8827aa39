// Every object on a simulated table (Planner::plan_object after plan(): `forcegrasp plan
// --objects all`): scenes of the cell distribution with 2 to 6 objects apart, rendered
// by both cameras with the structured-light noise. Each object the plan lists is
// identified with the true object most of its voxels lie on; a grasp planned for it is
// judged on that object's TRUE geometry (hal/sim/grasp_judge: each pad's first contact
// on it, inside the friction cone, no collision with the table or the other objects).
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <memory>
#include <string>

#include "fg/core/planner.hpp"
#include "sim/grasp_judge.hpp"
#include "sim/pinhole.hpp"
#include "sim/scene_gen.hpp"

namespace {
using namespace fg::sim;

// The true object most of the listed object's voxel centroids lie on (within 1 cm of its
// surface), or -1.
int identify(const World& world, const fg::PointSpan& pts) {
  std::map<int, int> votes;
  for (uint32_t i = 0; i < pts.size(); ++i) {
    const V3 p = pts[i].cast<double>();
    int best = -1;
    double best_d = 0.01;
    for (size_t j = 0; j < world.objects.size(); ++j) {
      const double d = std::abs(world.objects[j].sdf(p));
      if (d < best_d) best_d = d, best = static_cast<int>(j);
    }
    ++votes[best];
  }
  int id = -1, most = 0;
  for (const auto& [j, n] : votes)
    if (j >= 0 && n > most) most = n, id = j;
  return id;
}

struct Tally {
  int scenes = 0, objects = 0, listed = 0, fitting_seen = 0, fitting_held = 0, grasps = 0, held = 0;
  int target_grasps = 0, target_held = 0;  // of the scene's target (the cameras aim at it)
  std::map<int, int> by_count;             // scenes by their number of objects
  std::string failures;
};

Tally plan_every_object(uint64_t first_seed, int n_scenes) {
  SceneOptions opt = SceneOptions::of(Distribution::cell);
  opt.cell.others_min = 1;
  opt.cell.others_max = 5;
  auto planner = std::make_unique<fg::Planner>();
  EXPECT_EQ(planner->configure(fg::PlannerConfig{}), fg::Status::ok);
  Tally t;
  for (int i = 0; i < n_scenes; ++i) {
    const uint64_t seed = first_seed + static_cast<uint64_t>(i);
    const ObjectKind kind = all_kinds()[seed % all_kinds().size()];
    const GeneratedScene s = make_scene(kind, seed, opt);
    const int m = static_cast<int>(s.world.objects.size());
    ++t.scenes;
    ++t.by_count[m];
    t.objects += m;
    const SceneImages img = render_scene(s);
    planner->reset();
    EXPECT_EQ(add_rendered(*planner, fg::SensorRole::head, img.head, s.head), fg::Status::ok);
    EXPECT_EQ(add_rendered(*planner, fg::SensorRole::hand, img.hand, s.hand), fg::Status::ok);
    fg::PlanResult res;
    const fg::Status st = planner->plan(res);
    EXPECT_TRUE(st == fg::Status::ok || st == fg::Status::no_grasp) << "seed " << seed << ": " << res.message;
    const uint32_t n = planner->object_count();
    t.listed += static_cast<int>(n);
    std::map<int, bool> seen, held;
    for (uint32_t k = 0; k < n; ++k) {
      fg::PlanResult r;
      const fg::Status sk = planner->plan_object(k, r);
      EXPECT_TRUE(sk == fg::Status::ok || sk == fg::Status::no_grasp) << "seed " << seed << ": " << r.message;
      const int id = identify(s.world, planner->object_points());
      if (id < 0) continue;  // a cluster of no object (noise, a veil of mixed pixels)
      seen[id] = true;
      if (sk != fg::Status::ok) continue;
      ++t.grasps;
      Grasp g;
      g.position = r.grasp.position;
      g.approach = r.grasp.approach;
      g.closing = r.grasp.closing;
      g.width = r.grasp.width;
      const JudgeResult j = judge_grasp(s.world, id, g, s.gripper);
      t.target_grasps += id == s.target ? 1 : 0;
      t.target_held += id == s.target && j.success ? 1 : 0;
      if (j.success) {
        ++t.held;
        held[id] = true;
      } else {
        t.failures += " " + std::to_string(seed) + "/" + s.world.objects[static_cast<size_t>(id)].kind + ":" +
                      j.reason.substr(0, j.reason.find(' '));
      }
    }
    for (int j = 0; j < m; ++j) {
      if (!seen[j] || !target_fit(s.world.objects[static_cast<size_t>(j)], s.gripper).fits) continue;
      ++t.fitting_seen;
      t.fitting_held += held[j] ? 1 : 0;
    }
  }
  std::printf("%d scenes (objects per scene:", t.scenes);
  for (const auto& [count, scenes] : t.by_count) std::printf(" %d x%d", count, scenes);
  std::printf("), %d objects, %d listed; %d grasps, %d hold their object; %d of %d fitting objects seen are held\n",
              t.objects, t.listed, t.grasps, t.held, t.fitting_held, t.fitting_seen);
  std::printf("of them on the targets the cameras aim at: %d grasps, %d hold\n", t.target_grasps, t.target_held);
  std::printf("grasps that do not hold:%s\n", t.failures.c_str());
  return t;
}
}  // namespace

// Measured: on these 40 scenes 95 of 117 grasps hold their object (81%), and 90 of 119
// fitting objects are held; on 120 scenes of other seeds (93000-93119) 277 of 355 (78%),
// the targets the cameras aim at 78 of 101, the other objects 199 of 254: an object off
// the cameras' aim is grasped as well as the target. The bounds sit some three standard
// deviations below: grasps landing on the wrong object, or on none, fail them.
TEST(SimObjects, EveryObjectOnTheTableIsGraspedOnItself) {
  const Tally t = plan_every_object(81000, 40);
  EXPECT_GE(t.by_count.begin()->first, 2);
  EXPECT_GT(t.by_count.rbegin()->first, 4);
  EXPECT_GE(t.listed, t.objects * 8 / 10) << "most objects are seen and listed";
  EXPECT_GT(t.grasps, t.objects / 2);
  EXPECT_GE(t.held * 100, t.grasps * 70) << "fewer than 70% of the grasps hold their object";
  EXPECT_GE(t.fitting_held * 100, t.fitting_seen * 65) << "fewer than 65% of the fitting objects are held";
}
