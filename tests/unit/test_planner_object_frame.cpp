// The object frame's axis (docs/method.md B/C): a round body seen from above leans its
// principal axis towards the wall a sensor saw, and snaps to vertical within
// vertical_snap_round; a plate that leans for real keeps its axis (vertical_snap).
// Constructed, noise-free point sets on a table at z = 0 (2 mm grid), given to the head
// role with an identity pose; the oracle is the construction's own axis.
#include <gtest/gtest.h>

#include <cmath>
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

// The table around (0.5, 0), without the points within `hole` of (cx, cy).
void add_table(std::vector<Vec3>& pts, double cx, double cy, double hole) {
  for (int i = 0; i <= 200; ++i)
    for (int j = 0; j <= 200; ++j) {
      const double x = 0.3 + i * kStep, y = -0.2 + j * kStep;
      if (std::hypot(x - cx, y - cy) > hole) pts.push_back(v3(x, y, 0.0));
    }
}

// An upright can (radius r, height h, centre (cx, cy)) as cameras above it see it:
// the whole top disc and the wall within `half` of -x (a head camera in front of it
// drops the grazing rest).
std::vector<Vec3> can_seen_from_above(double cx, double cy, double r, double h, double half) {
  std::vector<Vec3> pts;
  add_table(pts, cx, cy, r);
  fg::test::add_can_wall_facing_minus_x(pts, cx, cy, r, h, half, kStep);
  for (double x = -r; x <= r; x += kStep)
    for (double y = -r; y <= r; y += kStep)
      if (x * x + y * y < r * r) pts.push_back(v3(cx + x, cy + y, h));
  return pts;
}

// A plate (length L along its axis, width w, thickness t) standing on its short edge at
// (cx, cy), its axis leaning `lean` from vertical towards +x: all its faces.
std::vector<Vec3> leaning_plate(double cx, double cy, double L, double w, double t, double lean) {
  std::vector<Vec3> pts;
  add_table(pts, cx, cy, 0.5 * w + L * std::sin(lean) + 0.01);
  const double ax = std::sin(lean), az = std::cos(lean);   // the axis
  const double nx = std::cos(lean), nz = -std::sin(lean);  // the thickness direction
  for (double s = 0.0; s <= L; s += kStep)
    for (double u = -0.5 * w; u <= 0.5 * w; u += kStep)
      for (double v : {-0.5 * t, 0.5 * t}) pts.push_back(v3(cx + s * ax + v * nx, cy + u, s * az + v * nz + 0.5 * t));
  return pts;
}

// The axis of the first viewpoint (the sensor arc's Y) after planning `pts`.
Vec3 planned_axis(const std::vector<Vec3>& pts, const PlannerConfig& cfg) {
  auto pl = std::make_unique<fg::Planner>();
  EXPECT_EQ(pl->configure(cfg), Status::ok);
  EXPECT_EQ(
      pl->add_points(SensorRole::head, pts.front().data(), static_cast<uint32_t>(pts.size()), sizeof(Vec3), Pose{}),
      Status::ok);
  Pose hand;
  hand.t = v3(0.5, 0.0, 0.7);
  EXPECT_EQ(pl->add_points(SensorRole::hand, nullptr, 0, 12, hand), Status::ok);
  PlanResult r;
  const Status st = pl->plan(r);
  EXPECT_TRUE(st == Status::ok || st == Status::no_grasp) << r.message;
  EXPECT_GT(pl->view_count(), 0u);
  if (pl->view_count() == 0) return Vec3::Zero();
  return pl->view(0).Y.normalized();
}

// The defaults, but for the range filter: with the identity pose the sensor-frame depth
// is world z, and the table lies at z = 0.
PlannerConfig defaults() {
  PlannerConfig c;
  c.range_min_m = 0.f;
  return c;
}

double tilt_deg(const Vec3& y) { return std::acos(std::fabs(static_cast<double>(y.z()))) * 180.0 / kPi; }

TEST(PlannerObjectFrame, RoundBodySeenFromAboveSnapsToVertical) {
  // A can 10 cm high, its wall seen within 69 deg of the head's side: the L's axis
  // leans 20 deg (printed), as the steep-wrist scenes' cans did (README).
  const std::vector<Vec3> can = can_seen_from_above(0.5, 0.0, 0.035, 0.10, 1.2);
  PlannerConfig lean = defaults();
  lean.vertical_snap_round_rad = lean.vertical_snap_rad;
  const double leaning = tilt_deg(planned_axis(can, lean));
  std::printf("can seen from above: axis %.1f deg from vertical without the round snap\n", leaning);
  // The construction is the case the rule is for: an L whose axis leans past 15 deg.
  EXPECT_GT(leaning, 15.0);
  EXPECT_LT(leaning, 30.0);
  EXPECT_LT(tilt_deg(planned_axis(can, defaults())), 0.01);
}

TEST(PlannerObjectFrame, LeaningPlateKeepsItsAxis) {
  for (double lean_deg : {10.0, 20.0, 28.0}) {
    SCOPED_TRACE(lean_deg);
    const std::vector<Vec3> plate = leaning_plate(0.5, 0.0, 0.16, 0.06, 0.012, lean_deg * kPi / 180.0);
    const double t = tilt_deg(planned_axis(plate, defaults()));
    std::printf("plate leaning %.0f deg: axis %.1f deg from vertical\n", lean_deg, t);
    if (lean_deg < 15.0)
      EXPECT_LT(t, 0.01);  // vertical_snap: within 15 deg every body snaps
    else
      EXPECT_NEAR(t, lean_deg, 2.0);
  }
}

}  // namespace
