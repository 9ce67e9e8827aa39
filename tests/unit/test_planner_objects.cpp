// Every object on the table and a chosen target (Planner::set_target, object_count,
// plan_object): boxes standing apart on a table, seen by a head and a wrist sensor. The
// object list is checked against the boxes placed; each object's grasp against its own
// box; the calls out of order and the bad targets against their statuses.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <random>
#include <vector>

#include "fg/core/planner.hpp"
#include "synthetic_scene.hpp"

namespace {

using fg::test::look_at;

using fg::PlanResult;
using fg::Pose;
using fg::SensorRole;
using fg::Status;
using fg::Vec3;

struct Box {
  float cx, cy, sx, sy, sz;
  bool holds(const Vec3& p, float grow) const {
    return std::fabs(p.x() - cx) <= 0.5f * sx + grow && std::fabs(p.y() - cy) <= 0.5f * sy + grow && p.z() >= -grow &&
           p.z() <= sz + grow;
  }
};

// The boxes on the table (no table under them), both sensors looking at (0.5, 0).
void add_scene(fg::Planner& pl, const std::vector<Box>& boxes, uint32_t seed = 3) {
  std::mt19937 rng(seed);
  std::vector<Vec3> world;
  fg::test::add_table(world, rng, 0.004f);
  world.erase(std::remove_if(world.begin(), world.end(),
                             [&](const Vec3& p) {
                               for (const Box& b : boxes)
                                 if (b.holds(p, 0.f)) return true;
                               return false;
                             }),
              world.end());
  for (const Box& b : boxes) fg::test::add_box(world, rng, b.cx, b.cy, b.sx, b.sy, b.sz, 0.0025f);
  const Pose poses[2] = {look_at(Vec3(-0.2f, -0.1f, 0.7f), Vec3(0.5f, 0.f, 0.05f)),
                         look_at(Vec3(0.55f, -0.45f, 0.4f), Vec3(0.5f, 0.f, 0.05f))};
  for (int s = 0; s < 2; ++s) {
    std::vector<float> xyz;
    for (const Vec3& w : world) {
      const Vec3 p = poses[s].R.transpose() * (w - poses[s].t);
      xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
    }
    ASSERT_EQ(pl.add_points(s == 0 ? SensorRole::head : SensorRole::hand, xyz.data(),
                            static_cast<uint32_t>(world.size()), 12, poses[s]),
              Status::ok);
  }
}

const std::vector<Box> kThree = {
    {0.5f, 0.f, 0.05f, 0.07f, 0.12f}, {0.52f, 0.2f, 0.06f, 0.05f, 0.09f}, {0.34f, -0.18f, 0.04f, 0.06f, 0.08f}};

std::unique_ptr<fg::Planner> planner() {
  auto pl = std::make_unique<fg::Planner>();
  EXPECT_EQ(pl->configure(fg::PlannerConfig{}), Status::ok);
  return pl;
}

bool same_grasp(const fg::Grasp& a, const fg::Grasp& b) {
  return std::memcmp(a.position.data(), b.position.data(), sizeof(float) * 3) == 0 &&
         std::memcmp(a.closing.data(), b.closing.data(), sizeof(float) * 3) == 0 &&
         std::memcmp(a.approach.data(), b.approach.data(), sizeof(float) * 3) == 0 && a.width == b.width;
}

TEST(PlannerObjects, EveryBoxIsListedAndGraspedOnItself) {
  auto pl = planner();
  add_scene(*pl, kThree);
  PlanResult r;
  ASSERT_EQ(pl->plan(r), Status::ok) << r.message;
  ASSERT_EQ(pl->object_count(), 3u);
  EXPECT_EQ(pl->objects_dropped(), 0u);
  EXPECT_EQ(pl->target_object(), 0);
  float last = -1.f;
  std::vector<bool> grasped(kThree.size(), false);
  for (uint32_t k = 0; k < 3; ++k) {
    const fg::ObjectSummary o = pl->object(k);
    const float d = std::hypot(o.centroid.x() - 0.5f, o.centroid.y());
    EXPECT_GE(d, last) << "nearest the workspace centre first";
    last = d;
    size_t b = kThree.size();
    for (size_t j = 0; j < kThree.size(); ++j)
      if (kThree[j].holds(o.centroid, 0.f)) b = j;
    ASSERT_LT(b, kThree.size()) << "object " << k << " is none of the boxes";
    // Its box: the box's cells, within a voxel.
    EXPECT_TRUE(kThree[b].holds(o.box_min, 0.006f) && kThree[b].holds(o.box_max, 0.006f));
    EXPECT_GT(o.box_max.z(), kThree[b].sz - 0.006f);
    PlanResult rk;
    ASSERT_EQ(pl->plan_object(k, rk), Status::ok) << rk.message;
    EXPECT_EQ(pl->target_object(), static_cast<int32_t>(k));
    EXPECT_EQ(rk.points.object, o.voxels);
    EXPECT_TRUE(kThree[b].holds(rk.grasp.position, 0.005f)) << "object " << k << "'s grasp is not on its box";
    const Box& x = kThree[b];  // the width of a side of its box
    EXPECT_LT(std::min({std::fabs(rk.grasp.width - x.sx), std::fabs(rk.grasp.width - x.sy),
                        std::fabs(rk.grasp.width - x.sz)}),
              0.01f);
    grasped[b] = true;
    // The ranked grasps then are this object's too.
    fg::RankedGrasp more[4];
    const uint32_t n = pl->more_grasps(more, 4);
    for (uint32_t i = 0; i < n; ++i) EXPECT_TRUE(kThree[b].holds(more[i].grasp.position, 0.005f));
  }
  EXPECT_EQ(std::count(grasped.begin(), grasped.end(), true), 3);
  // The plan's target planned again as an object: the plan's grasp, bit for bit.
  PlanResult again;
  ASSERT_EQ(pl->plan_object(0, again), Status::ok);
  EXPECT_TRUE(same_grasp(again.grasp, r.grasp));
}

TEST(PlannerObjects, ATargetPointOrBoxPicksItsBox) {
  auto pl = planner();
  for (size_t b = 0; b < kThree.size(); ++b) {
    const Box& x = kThree[b];
    fg::TargetSpec by_point;
    by_point.kind = fg::TargetKind::nearest_point;
    by_point.point = Vec3(x.cx + 0.5f * x.sx + 0.02f, x.cy, 0.5f * x.sz);  // 2 cm beside its +x face
    fg::TargetSpec by_box;
    by_box.kind = fg::TargetKind::inside_box;
    by_box.box_min = Vec3(x.cx - 0.5f * x.sx, x.cy - 0.5f * x.sy, 0.f);
    by_box.box_max = Vec3(x.cx + 0.5f * x.sx, x.cy + 0.5f * x.sy, x.sz);
    for (const fg::TargetSpec& t : {by_point, by_box}) {
      ASSERT_EQ(pl->set_target(t), Status::ok);
      pl->reset();  // the target stays
      add_scene(*pl, kThree);
      PlanResult r;
      ASSERT_EQ(pl->plan(r), Status::ok) << r.message;
      EXPECT_TRUE(x.holds(r.grasp.position, 0.005f)) << "box " << b << " kind " << static_cast<int>(t.kind);
      EXPECT_TRUE(x.holds(pl->object(static_cast<uint32_t>(pl->target_object())).centroid, 0.f));
    }
  }
}

TEST(PlannerObjects, TargetsOutsideOrEmptyAndBadSpecs) {
  auto pl = planner();
  fg::TargetSpec t;
  t.kind = fg::TargetKind::nearest_point;
  t.point = Vec3(2.f, 0.f, 0.f);  // the crop box is 0.5 +- 0.6 in x
  ASSERT_EQ(pl->set_target(t), Status::ok);
  add_scene(*pl, kThree);
  PlanResult r;
  EXPECT_EQ(pl->plan(r), Status::invalid_argument);
  EXPECT_STREQ(r.message, "the target point lies outside the workspace crop box");
  EXPECT_EQ(pl->object_count(), 0u);
  // A box partly inside is fine; one wholly outside is not.
  t.kind = fg::TargetKind::inside_box;
  t.box_min = Vec3(1.2f, -0.1f, 0.f);
  t.box_max = Vec3(1.3f, 0.1f, 0.2f);
  ASSERT_EQ(pl->set_target(t), Status::ok);
  pl->reset();
  add_scene(*pl, kThree);
  EXPECT_EQ(pl->plan(r), Status::invalid_argument);
  EXPECT_STREQ(r.message, "the target box does not overlap the workspace crop box");
  // Inside the workspace, but on bare table: no object, every object still listed.
  t.box_min = Vec3(0.7f, 0.25f, 0.f);
  t.box_max = Vec3(0.8f, 0.35f, 0.2f);
  ASSERT_EQ(pl->set_target(t), Status::ok);
  pl->reset();
  add_scene(*pl, kThree);
  EXPECT_EQ(pl->plan(r), Status::no_grasp);
  EXPECT_EQ(r.reason, fg::NoGraspReason::no_object);
  EXPECT_STREQ(r.message, "no object has a voxel inside the target box");
  EXPECT_EQ(pl->object_count(), 3u);
  EXPECT_EQ(pl->target_object(), -1);
  // A bad spec is refused and the one before stays.
  fg::TargetSpec bad = t;
  bad.box_min.x() = 0.9f;
  EXPECT_EQ(pl->set_target(bad), Status::invalid_argument);
  EXPECT_STREQ(pl->last_message(), "target box: a minimum is above its maximum");
  EXPECT_EQ(pl->target().box_min.x(), 0.7f);
  bad.box_min.x() = NAN;
  EXPECT_EQ(pl->set_target(bad), Status::non_finite);
  ASSERT_EQ(pl->set_target(fg::TargetSpec{}), Status::ok);
}

TEST(PlannerObjects, PlanObjectNeedsAPlan) {
  auto pl = planner();
  PlanResult r;
  EXPECT_EQ(pl->plan_object(0, r), Status::invalid_sequence);
  EXPECT_EQ(pl->object_count(), 0u);
  add_scene(*pl, kThree);
  EXPECT_EQ(pl->plan_object(0, r), Status::invalid_sequence);  // added, not planned
  ASSERT_EQ(pl->plan(r), Status::ok);
  EXPECT_EQ(pl->plan_object(3, r), Status::invalid_argument);
  EXPECT_EQ(r.status, Status::invalid_argument);
  EXPECT_EQ(pl->plan_object(0xFFFFFFFFu, r), Status::invalid_argument);
  EXPECT_EQ(pl->plan_object(2, r), Status::ok);
  pl->reset();
  EXPECT_EQ(pl->object_count(), 0u);
  EXPECT_EQ(pl->plan_object(0, r), Status::invalid_sequence);
}

// More boxes than the build lists: the kMaxObjects nearest the workspace centre, the
// rest counted. A grid of small cubes 5 cm apart.
TEST(PlannerObjects, MoreObjectsThanTheListHolds) {
  std::vector<Box> cubes;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      cubes.push_back(
          Box{0.38f + 0.06f * static_cast<float>(i), -0.12f + 0.06f * static_cast<float>(j), 0.02f, 0.02f, 0.03f});
  ASSERT_GT(cubes.size(), fg::kMaxObjects);
  auto pl = planner();
  add_scene(*pl, cubes);
  PlanResult r;
  const Status st = pl->plan(r);
  ASSERT_TRUE(st == Status::ok || st == Status::no_grasp) << r.message;
  ASSERT_EQ(pl->object_count(), fg::kMaxObjects);
  EXPECT_EQ(pl->object_count() + pl->objects_dropped(), cubes.size());
  // The listed ones are the nearest: no dropped cube lies nearer than the last listed.
  std::vector<float> d;
  for (const Box& c : cubes) d.push_back(std::hypot(c.cx - 0.5f, c.cy));
  std::sort(d.begin(), d.end());
  const fg::ObjectSummary& last = pl->object(fg::kMaxObjects - 1);
  EXPECT_LE(std::hypot(last.centroid.x() - 0.5f, last.centroid.y()), d[fg::kMaxObjects - 1] + 0.005f);
}

}  // namespace
