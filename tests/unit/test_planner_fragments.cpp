// Fragments of one object joined (docs/method.md A.6, pipeline/fragments.hpp). Two
// sensors look at an upright can from opposite sides; each loses the returns of the
// wall it sees steeper than 60 deg, so each sees the 120 deg of wall facing it and the
// two bands of 60 deg between the patches are seen by neither: two clusters, one can.
// Two boxes 25 mm apart, their gap seen down to the table, stay two objects. The
// scenes are constructed here, noise-free, world frame: the table top at z = 0.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "fg/core/planner.hpp"
#include "synthetic_scene.hpp"

namespace {

using fg::PlannerConfig;
using fg::PlanResult;
using fg::Pose;
using fg::SensorRole;
using fg::Status;
using fg::Vec3;
using fg::test::look_at;

constexpr double kCx = 0.5, kCy = 0.0, kR = 0.035, kH = 0.12;
constexpr double kStep = 0.002;

// The can (kCx, kCy, radius kR, height kH) as a solid for the rays: true when the
// segment from `eye` to `p` passes through it before reaching p (p itself outside it).
// In x-y the segment is inside the can's circle for t in [t0, t1] (a quadratic in t);
// its height is linear in t, so it meets the solid when that stretch, within the
// segment, spans some height between 0 and kH.
bool can_blocks(const Vec3& eye, const Vec3& p) {
  const double ex = eye.x() - kCx, ey = eye.y() - kCy;
  const double dx = p.x() - eye.x(), dy = p.y() - eye.y(), dz = p.z() - eye.z();
  const double a = dx * dx + dy * dy, b = 2.0 * (ex * dx + ey * dy), c = ex * ex + ey * ey - kR * kR;
  const double disc = b * b - 4.0 * a * c;
  if (a <= 0.0 || disc <= 0.0) return false;
  const double t0 = std::max(0.0, (-b - std::sqrt(disc)) / (2.0 * a));
  const double t1 = std::min(1.0, (-b + std::sqrt(disc)) / (2.0 * a));
  if (t0 >= t1) return false;
  const double z0 = eye.z() + t0 * dz, z1 = eye.z() + t1 * dz;
  return std::min(z0, z1) < kH && std::max(z0, z1) > 0.0;
}

// What a sensor at `eye` returns of the table (0.8 x 0.8 about (0.5, 0)) and of the
// can's wall: the table where the can does not shadow it, the wall within 60 deg of
// the direction (in x-y) towards the sensor (steeper, a structured-light sensor gets
// no return; the can's top is left out, as a dark lid would be).
std::vector<Vec3> seen_by(const Vec3& eye) {
  std::vector<Vec3> pts;
  for (double x = 0.1; x < 0.9; x += kStep)
    for (double y = -0.4; y < 0.4; y += kStep) {
      const Vec3 p = fg::test::v3(x, y, 0.0);
      const double dx = x - kCx, dy = y - kCy;
      if (dx * dx + dy * dy <= kR * kR) continue;  // under the can
      if (can_blocks(eye, p)) continue;
      pts.push_back(p);
    }
  const double facing = std::atan2(eye.y() - kCy, eye.x() - kCx);
  const double half = 60.0 * fg::kPi / 180.0;
  const int na = static_cast<int>(std::lround(2.0 * half * kR / kStep));
  for (int k = 0; k <= na; ++k) {
    const double a = facing - half + 2.0 * half * k / na;
    for (double z = 0.0; z <= kH; z += kStep)
      pts.push_back(fg::test::v3(kCx + kR * std::cos(a), kCy + kR * std::sin(a), z));
  }
  return pts;
}

// The world points in the sensor's frame, as x y z triples.
std::vector<float> in_frame(const std::vector<Vec3>& world, const Pose& pose) {
  std::vector<float> xyz;
  for (const Vec3& p : world) {
    const Vec3 s = pose.R.transpose() * (p - pose.t);
    xyz.push_back(s.x());
    xyz.push_back(s.y());
    xyz.push_back(s.z());
  }
  return xyz;
}

std::unique_ptr<fg::Planner> make_planner() {
  auto p = std::make_unique<fg::Planner>();
  const char* field = nullptr;
  EXPECT_EQ(p->configure(PlannerConfig{}, &field), Status::ok) << (field ? field : "");
  // Exact poses: the test is of the clustering, not of the registration.
  p->set_registration(fg::RegistrationMode::off);
  return p;
}

void add(fg::Planner& pl, SensorRole role, const Vec3& eye, const std::vector<Vec3>& world) {
  const Pose pose = look_at(eye, fg::test::v3(kCx, kCy, 0.5 * kH));
  const std::vector<float> xyz = in_frame(world, pose);
  ASSERT_EQ(pl.add_points(role, xyz.data(), static_cast<uint32_t>(xyz.size() / 3), 12, pose), Status::ok);
}

const Vec3 kHeadEye = fg::test::v3(kCx - 0.6, kCy, 0.1);
const Vec3 kHandEye = fg::test::v3(kCx + 0.35, kCy, 0.1);

TEST(Fragments, TwoPatchesOfACanAreOneObject) {
  // One sensor alone: its patch is the whole can it knows of.
  {
    auto pl = make_planner();
    add(*pl, SensorRole::head, kHeadEye, seen_by(kHeadEye));
    PlanResult r;
    (void)pl->plan(r);
    ASSERT_EQ(pl->object_count(), 1u);
  }
  auto pl = make_planner();
  add(*pl, SensorRole::head, kHeadEye, seen_by(kHeadEye));
  add(*pl, SensorRole::hand, kHandEye, seen_by(kHandEye));
  PlanResult r;
  (void)pl->plan(r);
  // The patches are 35 mm apart (the chord across 60 deg of arc, the radius): beyond
  // the clustering's reach, within the fragments' gap, and every segment between them
  // runs inside the can, behind a patch for each sensor.
  ASSERT_EQ(pl->object_count(), 1u);
  const fg::ObjectSummary& o = pl->object(0);
  EXPECT_EQ(o.fragments, 1u);
  EXPECT_LT(o.box_min.x(), kCx - 0.9 * kR);
  EXPECT_GT(o.box_max.x(), kCx + 0.9 * kR);
  EXPECT_NEAR(o.centroid.x(), kCx, 0.005);
  // Planned as one object, whichever of plan() and plan_object() asks.
  EXPECT_EQ(r.points.object, o.voxels);
  PlanResult again;
  (void)pl->plan_object(0, again);
  EXPECT_EQ(again.points.object, o.voxels);
}

TEST(Fragments, TwoBoxesWithTheirGapSeenStayTwo) {
  // Two 40 mm boxes, 100 mm tall, 25 mm apart along y: within the fragments' gap, but
  // both sensors look down into the gap and see the table through it.
  std::mt19937 rng(7);
  std::vector<Vec3> world;
  fg::test::add_table(world, rng, 0.003f, 0.48f, 0.52f, -0.0525f, 0.0525f);
  fg::test::add_box(world, rng, 0.5f, -0.0325f, 0.04f, 0.04f, 0.1f, 0.002f);
  fg::test::add_box(world, rng, 0.5f, 0.0325f, 0.04f, 0.04f, 0.1f, 0.002f);
  auto pl = make_planner();
  const Vec3 above_head = fg::test::v3(0.2, 0.0, 0.6), above_hand = fg::test::v3(0.75, 0.0, 0.45);
  const Pose head = look_at(above_head, fg::test::v3(0.5, 0.0, 0.05));
  const Pose hand = look_at(above_hand, fg::test::v3(0.5, 0.0, 0.05));
  const std::vector<float> a = in_frame(world, head), b = in_frame(world, hand);
  ASSERT_EQ(pl->add_points(SensorRole::head, a.data(), static_cast<uint32_t>(a.size() / 3), 12, head), Status::ok);
  ASSERT_EQ(pl->add_points(SensorRole::hand, b.data(), static_cast<uint32_t>(b.size() / 3), 12, hand), Status::ok);
  PlanResult r;
  (void)pl->plan(r);
  ASSERT_EQ(pl->object_count(), 2u);
  EXPECT_EQ(pl->object(0).fragments, 0u);
  EXPECT_EQ(pl->object(1).fragments, 0u);
}

}  // namespace
