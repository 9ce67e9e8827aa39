// Ranked grasps (Planner::more_grasps, `forcegrasp plan --top N`): after a plan, more
// grasps on the same target that pass every check, each distinct from the returned one
// and from the others by the definition of selection.hpp, checked here against that
// definition written out from the vectors; nothing before a plan or after a refusal.
#include <gtest/gtest.h>

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
using fg::RankedGrasp;
using fg::SensorRole;
using fg::Status;
using fg::Vec3;

// A 5 x 7 x 12 cm box on the table at (0.5, 0), seen by a head sensor in front and
// above and a wrist sensor from the side: enough sides for grasps from several
// directions.
std::unique_ptr<fg::Planner> planned_box(PlanResult& r, uint32_t seed = 4) {
  std::mt19937 rng(seed);
  std::vector<Vec3> world;
  fg::test::add_table(world, rng, 0.004f, 0.475f, 0.525f, -0.035f, 0.035f);
  fg::test::add_box(world, rng, 0.5f, 0.f, 0.05f, 0.07f, 0.12f, 0.0025f);
  auto pl = std::make_unique<fg::Planner>();
  EXPECT_EQ(pl->configure(fg::PlannerConfig{}), Status::ok);
  const Pose poses[2] = {look_at(Vec3(-0.2f, -0.1f, 0.6f), Vec3(0.5f, 0.f, 0.06f)),
                         look_at(Vec3(0.55f, -0.45f, 0.35f), Vec3(0.5f, 0.f, 0.06f))};
  for (int s = 0; s < 2; ++s) {
    std::vector<float> xyz;
    for (const Vec3& w : world) {
      const Vec3 p = poses[s].R.transpose() * (w - poses[s].t);
      xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
    }
    EXPECT_EQ(pl->add_points(s == 0 ? SensorRole::head : SensorRole::hand, xyz.data(),
                             static_cast<uint32_t>(world.size()), 12, poses[s]),
              Status::ok);
  }
  EXPECT_EQ(pl->plan(r), r.status);
  return pl;
}

// The definition, from the vectors: closing lines or approaches 15 deg apart, or
// centres 1 cm apart.
bool distinct(const fg::Grasp& a, const fg::Grasp& b) {
  const double line = std::acos(std::min(1.0, std::fabs(static_cast<double>(a.closing.dot(b.closing)))));
  const double appr = std::acos(std::max(-1.0, std::min(1.0, static_cast<double>(a.approach.dot(b.approach)))));
  const double deg = 180.0 / fg::kPi;
  return line * deg >= 15.0 || appr * deg >= 15.0 || (a.position - b.position).norm() >= 0.01f;
}

TEST(RankedGrasps, DistinctGraspsFollowTheDefinition) {
  const Vec3 p(0.5f, 0.f, 0.1f), x = Vec3::UnitX(), z = -Vec3::UnitZ();
  const auto turned = [](const Vec3& v, double deg) {  // about the vertical
    const double a = deg * fg::kPi / 180.0;
    return Vec3(static_cast<float>(std::cos(a) * v.x() - std::sin(a) * v.y()),
                static_cast<float>(std::sin(a) * v.x() + std::cos(a) * v.y()), v.z());
  };
  EXPECT_FALSE(fg::distinct_grasps(p, x, z, p, x, z));
  EXPECT_FALSE(fg::distinct_grasps(p, x, z, p, -x, z));  // the same closing line
  EXPECT_FALSE(fg::distinct_grasps(p, x, z, p, turned(x, 14.0), z));
  EXPECT_TRUE(fg::distinct_grasps(p, x, z, p, turned(x, 16.0), z));
  EXPECT_TRUE(fg::distinct_grasps(p, x, z, p, turned(x, 180.0 - 16.0), z));
  EXPECT_FALSE(fg::distinct_grasps(p, x, z, p + Vec3(0.009f, 0.f, 0.f), x, z));
  EXPECT_TRUE(fg::distinct_grasps(p, x, z, p + Vec3(0.f, 0.011f, 0.f), x, z));
  const Vec3 tilted = Vec3(std::sin(0.3f), 0.f, -std::cos(0.3f));  // 17 deg off straight down
  EXPECT_TRUE(fg::distinct_grasps(p, Vec3::UnitY(), z, p, Vec3::UnitY(), tilted));
}

TEST(RankedGrasps, MoreGraspsPassTheChecksAndAreDistinctFromEachOther) {
  PlanResult r;
  auto pl = planned_box(r);
  ASSERT_EQ(r.status, Status::ok) << r.message;
  RankedGrasp more[fg::kMaxRankedGrasps];
  const uint32_t n = pl->more_grasps(more, fg::kMaxRankedGrasps - 1);
  ASSERT_GE(n, 2u) << "a box seen on three sides has more than one way to be held";
  const float opening = fg::PlannerConfig{}.gripper.max_opening_m;
  for (uint32_t i = 0; i < n; ++i) {
    SCOPED_TRACE(i);
    const fg::Grasp& g = more[i].grasp;
    EXPECT_TRUE(distinct(g, r.grasp));
    for (uint32_t k = 0; k < i; ++k) EXPECT_TRUE(distinct(g, more[k].grasp)) << "against " << k;
    EXPECT_NEAR(g.approach.norm(), 1.f, 1e-5f);
    EXPECT_NEAR(g.closing.norm(), 1.f, 1e-5f);
    EXPECT_NEAR(g.approach.dot(g.closing), 0.f, 1e-4f);
    EXPECT_GT(g.width, 0.f);
    EXPECT_LT(g.width, opening);
    // On the box: its centre inside the box's extent (a margin for the contact depth).
    EXPECT_NEAR(g.position.x(), 0.5f, 0.035f);
    EXPECT_NEAR(g.position.y(), 0.f, 0.045f);
    EXPECT_GT(g.position.z(), 0.f);
    EXPECT_LT(g.position.z(), 0.13f);
    // Passed the friction cone: its margin was measured and is inside it.
    EXPECT_TRUE(std::isfinite(more[i].margins[fg::CheckId::friction_cone]));
    EXPECT_GE(more[i].margins[fg::CheckId::friction_cone], 0.f);
  }
}

TEST(RankedGrasps, TheSameSceneGivesTheSameListAndMaxBoundsIt) {
  PlanResult ra, rb;
  auto a = planned_box(ra, 9);
  auto b = planned_box(rb, 9);
  ASSERT_EQ(ra.status, Status::ok);
  RankedGrasp ma[fg::kMaxRankedGrasps], mb[fg::kMaxRankedGrasps], one[1];
  const uint32_t na = a->more_grasps(ma, 4), nb = b->more_grasps(mb, 4);
  ASSERT_EQ(na, nb);
  EXPECT_LE(na, 4u);
  for (uint32_t i = 0; i < na; ++i) {
    EXPECT_EQ(std::memcmp(ma[i].grasp.position.data(), mb[i].grasp.position.data(), 12), 0);
    EXPECT_EQ(std::memcmp(ma[i].grasp.closing.data(), mb[i].grasp.closing.data(), 12), 0);
  }
  // Asking again goes on from where the first call stopped: nothing it returned comes
  // back, and the returned grasp is never among the alternates.
  const uint32_t again = a->more_grasps(one, 1);
  for (uint32_t i = 0; i < again; ++i) {
    EXPECT_TRUE(distinct(one[i].grasp, ra.grasp));
    for (uint32_t k = 0; k < na; ++k) EXPECT_TRUE(distinct(one[i].grasp, ma[k].grasp));
  }
  EXPECT_EQ(a->more_grasps(nullptr, 3), 0u);
  EXPECT_EQ(a->more_grasps(ma, 0), 0u);
}

TEST(RankedGrasps, NothingBeforeAPlanOrAfterARefusal) {
  auto pl = std::make_unique<fg::Planner>();
  ASSERT_EQ(pl->configure(fg::PlannerConfig{}), Status::ok);
  RankedGrasp more[4];
  EXPECT_EQ(pl->more_grasps(more, 4), 0u);  // no plan yet
  // Only a table: no_grasp.
  std::mt19937 rng(1);
  std::vector<Vec3> world;
  fg::test::add_table(world, rng, 0.005f);
  std::vector<float> xyz;
  const Pose pose = look_at(Vec3(0.2f, 0.f, 0.7f), Vec3(0.5f, 0.f, 0.f));
  for (const Vec3& w : world) {
    const Vec3 p = pose.R.transpose() * (w - pose.t);
    xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
  }
  ASSERT_EQ(pl->add_points(SensorRole::head, xyz.data(), static_cast<uint32_t>(world.size()), 12, pose), Status::ok);
  PlanResult r;
  EXPECT_EQ(pl->plan(r), Status::no_grasp);
  EXPECT_EQ(pl->more_grasps(more, 4), 0u);
  // After reset() the last plan's grasps are gone too.
  PlanResult rb;
  auto box = planned_box(rb);
  ASSERT_EQ(rb.status, Status::ok);
  box->reset();
  EXPECT_EQ(box->more_grasps(more, 4), 0u);
}

}  // namespace
