// Check 5's round flanks (core/src/grazed_round.cpp) on constructed cans: a camera in
// front of an upright can at table height sees its wall only within `half` of its own
// line of sight (a depth sensor drops the grazing rest), and the grasp across that line
// closes on the unseen tangents. Noise-free points on a 2 mm grid, the head role with an
// identity pose (the sensor at the origin, looking along +x at the can); the oracle is
// the construction's own diameter and the gripper's opening.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
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
using fg::test::kPi;
using fg::test::v3;

constexpr double kStep = 0.002;

// The table in front of and beside the can (what a camera at the origin sees of it) and
// the can's wall within `half` of -x: radius r, height h, centre (cx, 0).
std::vector<Vec3> can_seen_from_the_front(double cx, double r, double h, double half) {
  std::vector<Vec3> pts;
  for (double x = 0.3; x <= 0.7; x += kStep)
    for (double y = -0.2; y <= 0.2; y += kStep)
      if (std::hypot(x - cx, y) > r && !(x > cx && std::fabs(y) < r)) pts.push_back(v3(x, y, 0.0));
  fg::test::add_can_wall_facing_minus_x(pts, cx, 0.0, r, h, half, kStep);
  return pts;
}

struct Planned {
  Status status;
  float width;
};

Planned plan(const std::vector<Vec3>& pts, bool round_flanks) {
  PlannerConfig cfg;
  cfg.range_min_m = 0.f;  // the identity pose: sensor depth is world z, the table at 0
  cfg.round_flanks = round_flanks;
  auto pl = std::make_unique<fg::Planner>();
  EXPECT_EQ(pl->configure(cfg), Status::ok);
  EXPECT_EQ(
      pl->add_points(SensorRole::head, pts.front().data(), static_cast<uint32_t>(pts.size()), sizeof(Vec3), Pose{}),
      Status::ok);
  PlanResult r;
  const Status st = pl->plan(r);
  EXPECT_TRUE(st == Status::ok || st == Status::no_grasp) << r.message;
  return {st, st == Status::ok ? r.grasp.width : 0.f};
}

// Cans up to the opening less width_margin (0.085 - 0.004 m): the rule measures their
// diameter, whose seen chord alone (2 r sin(half)) is a centimetre or more short.
TEST(GrazedRound, WideCansCloseOnTheirTangents) {
  const PlannerConfig defaults;
  for (double d : {0.060, 0.070, 0.078}) {
    SCOPED_TRACE(d);
    const std::vector<Vec3> can = can_seen_from_the_front(0.5, 0.5 * d, 0.12, 50.0 * kPi / 180.0);
    const Planned with = plan(can, true), without = plan(can, false);
    std::printf("can %.0f mm: %s %.1f mm with the rule, %s %.1f mm without\n", d * 1e3, fg::to_string(with.status),
                with.width * 1e3, fg::to_string(without.status), without.width * 1e3);
    ASSERT_EQ(with.status, Status::ok);
    EXPECT_NEAR(with.width, d, 0.004);
    EXPECT_LE(with.width, defaults.gripper.max_opening_m - defaults.width_margin_m);
    if (without.status == Status::ok) {
      EXPECT_LT(without.width, d - 0.008);
    }
  }
}

// A can the opening cannot clear with width_margin to spare gets no grasp on its
// tangents: whatever the planner answers is narrower than the opening allows.
TEST(GrazedRound, CansWiderThanTheOpeningLessItsMarginGetNoTangentGrasp) {
  const PlannerConfig defaults;
  const std::vector<Vec3> can = can_seen_from_the_front(0.5, 0.042, 0.12, 50.0 * kPi / 180.0);
  const Planned with = plan(can, true);
  if (with.status == Status::ok) {
    EXPECT_LT(with.width, defaults.gripper.max_opening_m - defaults.width_margin_m);
  }
}

}  // namespace
