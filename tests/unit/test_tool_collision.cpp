// The tool's collision checks (robot/tool_collision.hpp, libccd's GJK) against
// independent oracles: an exact separating-axis test over brute-force hull faces and
// edges for box-vs-point-hull, and constructed scenes with known answers for the
// whole tool (fingers, palm, body swept from the pre-grasp; support plane).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "fg/robot/tool_collision.hpp"

#if FG_ROBOT_WITH_LIBCCD
using fg::Mat3;
using fg::Vec3;
using fg::robot::ToolCollision;
using fg::robot::ToolGeometry;
using fg::robot::ToolHit;
using V3d = Eigen::Vector3d;

namespace {

// Exact for convex polytopes: they are disjoint iff one of these axes separates them:
// the box's face normals, every plane through three of the points (a superset of the
// hull's face normals) and every box edge crossed with every pair of points (a superset
// of the hull's edges).
bool sat_disjoint(const V3d& c, const Eigen::Matrix3d& R, const V3d& h, const std::vector<V3d>& pts) {
  const auto separates = [&](V3d axis) {
    const double len = axis.norm();
    if (len < 1e-12) return false;
    axis /= len;
    const double r = h.x() * std::fabs(axis.dot(R.col(0))) + h.y() * std::fabs(axis.dot(R.col(1))) +
                     h.z() * std::fabs(axis.dot(R.col(2)));
    const double bc = axis.dot(c);
    double lo = 1e300, hi = -1e300;
    for (const V3d& p : pts) {
      lo = std::min(lo, axis.dot(p));
      hi = std::max(hi, axis.dot(p));
    }
    return lo > bc + r + 1e-9 || hi < bc - r - 1e-9;
  };
  for (int k = 0; k < 3; ++k)
    if (separates(R.col(k))) return true;
  const size_t n = pts.size();
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j) {
      for (int k = 0; k < 3; ++k)
        if (separates((pts[j] - pts[i]).cross(R.col(k)))) return true;
      for (size_t l = j + 1; l < n; ++l)
        if (separates((pts[j] - pts[i]).cross(pts[l] - pts[i]))) return true;
    }
  return false;
}

Eigen::Matrix3d random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
  return q.normalized().toRotationMatrix();
}

}  // namespace

TEST(ToolCollision, BoxAgainstPointHullMatchesSeparatingAxes) {
  std::mt19937 rng(20261121);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int hits = 0, misses = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const Eigen::Matrix3d R = random_rotation(rng);
    const V3d h(0.02 + 0.03 * std::fabs(u(rng)), 0.02 + 0.03 * std::fabs(u(rng)), 0.02 + 0.03 * std::fabs(u(rng)));
    const V3d c(0.08 * u(rng), 0.08 * u(rng), 0.08 * u(rng));
    const int n = 1 + trial % 9;  // a point, a segment, a triangle, ... up to 9 points
    std::vector<V3d> pts;
    std::vector<Vec3> ptsf;
    const V3d centre(0.05 * u(rng), 0.05 * u(rng), 0.05 * u(rng));
    for (int i = 0; i < n; ++i) {
      const Vec3 pf = (centre + V3d(0.03 * u(rng), 0.03 * u(rng), 0.03 * u(rng))).cast<float>();
      ptsf.push_back(pf);
      pts.push_back(pf.cast<double>());
    }
    const bool oracle_hit = !sat_disjoint(c, R, h, pts);
    // Keep clear of touching configurations, where float input rounding decides.
    const bool near_touch = !sat_disjoint(c, R, h * 1.0005, pts) != !sat_disjoint(c, R, h * 0.9995, pts);
    if (near_touch) continue;
    const bool gjk_hit = fg::robot::box_intersects_point_hull(c.cast<float>(), R.cast<float>(), h.cast<float>(),
                                                              ptsf.data(), nullptr, static_cast<uint32_t>(n), 100);
    EXPECT_EQ(gjk_hit, oracle_hit) << "trial " << trial << " with " << n << " points";
    (oracle_hit ? hits : misses) += 1;
  }
  EXPECT_GT(hits, 300);  // both answers well represented
  EXPECT_GT(misses, 300);
}

namespace {

// A solid box object sampled on its surface (what the sensors would give), world.
std::vector<Vec3> box_surface(const Vec3& centre, const Vec3& half, float step = 0.004f) {
  std::vector<Vec3> out;
  for (float x = -half.x(); x <= half.x() + 1e-6f; x += step)
    for (float y = -half.y(); y <= half.y() + 1e-6f; y += step)
      for (float z = -half.z(); z <= half.z() + 1e-6f; z += step) {
        const bool surface = std::fabs(std::fabs(x) - half.x()) < step * 0.5f ||
                             std::fabs(std::fabs(y) - half.y()) < step * 0.5f ||
                             std::fabs(std::fabs(z) - half.z()) < step * 0.5f;
        if (surface) out.push_back(centre + Vec3(x, y, z));
      }
  return out;
}

// A top-down grasp at `pos` (approach -z world, closing +x world).
fg::GraspQuery top_down(const Vec3& pos, const fg::Plane* plane, const std::vector<Vec3>& pts) {
  const Vec3 approach(0.f, 0.f, -1.f);
  return fg::GraspQuery{pos,
                        approach,
                        Vec3(1.f, 0.f, 0.f),
                        pos - approach * 0.05f,
                        0.05f,
                        plane,
                        pts.empty() ? nullptr : pts.data(),
                        static_cast<uint32_t>(pts.size())};
}

ToolCollision& scratch() {
  static ToolCollision tc;  // large: not on the stack
  return tc;
}

}  // namespace

TEST(ToolCollision, TopDownOnANarrowBoxIsClearAndOnAWideOneHitsIt) {
  const ToolGeometry tool;  // 2F-85-like: 0.085 opening
  const fg::Plane table{Vec3::UnitZ(), 0.f};
  // A 0.05 x 0.05 x 0.10 box on the table; the grasp 0.02 below its top.
  const std::vector<Vec3> narrow = box_surface(Vec3(0.5f, 0.f, 0.05f), Vec3(0.025f, 0.025f, 0.05f));
  EXPECT_EQ(scratch().check(tool, top_down(Vec3(0.5f, 0.f, 0.08f), &table, narrow)), ToolHit::none);
  EXPECT_GT(scratch().gjk_calls(), 0u);
  // 0.10 wide along the closing direction: the open fingers (at +-0.0425) cut into it.
  const std::vector<Vec3> wide = box_surface(Vec3(0.5f, 0.f, 0.05f), Vec3(0.05f, 0.025f, 0.05f));
  EXPECT_EQ(scratch().check(tool, top_down(Vec3(0.5f, 0.f, 0.08f), &table, wide)), ToolHit::object);
  // The same wide box turned a quarter turn: it is 0.05 along the closing direction
  // now, and 0.10 across, where only the palm and body (above it) could meet it.
  const std::vector<Vec3> turned = box_surface(Vec3(0.5f, 0.f, 0.05f), Vec3(0.025f, 0.05f, 0.05f));
  EXPECT_EQ(scratch().check(tool, top_down(Vec3(0.5f, 0.f, 0.08f), &table, turned)), ToolHit::none);
}

TEST(ToolCollision, PalmOrBodyDrivenIntoTheObjectIsAHit) {
  const ToolGeometry tool;
  const std::vector<Vec3> narrow = box_surface(Vec3(0.5f, 0.f, 0.05f), Vec3(0.025f, 0.025f, 0.05f));
  // The pads' centre 0.05 below the top: the palm (0.02..0.06 behind it) sits in the box.
  EXPECT_EQ(scratch().check(tool, top_down(Vec3(0.5f, 0.f, 0.05f), nullptr, narrow)), ToolHit::object);
}

TEST(ToolCollision, TheSupportPlaneStopsLowGrasps) {
  const ToolGeometry tool;
  const fg::Plane table{Vec3::UnitZ(), 0.f};
  const std::vector<Vec3> none;
  // Fingertips reach 0.02 past the pads' centre: at 0.03 they clear the table by 0.01,
  // at 0.015 they are in it.
  EXPECT_EQ(scratch().check(tool, top_down(Vec3(0.5f, 0.f, 0.03f), &table, none)), ToolHit::none);
  EXPECT_EQ(scratch().check(tool, top_down(Vec3(0.5f, 0.f, 0.015f), &table, none)), ToolHit::support_plane);
  // A side grasp 0.02 above the table: the palm (0.025 half width) reaches below it.
  const Vec3 side_pos(0.5f, 0.f, 0.02f);
  const fg::GraspQuery side{
      side_pos, Vec3(1.f, 0.f, 0.f), Vec3(0.f, 1.f, 0.f), side_pos - Vec3(0.05f, 0.f, 0.f), 0.05f, &table, nullptr, 0};
  EXPECT_EQ(scratch().check(tool, side), ToolHit::support_plane);
  // A tilted table (10 deg) is still a table.
  const Vec3 n = Vec3(std::sin(0.1745f), 0.f, std::cos(0.1745f));
  const fg::Plane tilted{n, -n.dot(Vec3(0.5f, 0.f, 0.03f))};
  EXPECT_EQ(scratch().check(tool, top_down(Vec3(0.5f, 0.f, 0.03f), &tilted, none)), ToolHit::support_plane);
}

TEST(ToolCollision, NonFiniteQueriesAreInvalidNotCrashes) {
  const ToolGeometry tool;
  const std::vector<Vec3> none;
  fg::GraspQuery q = top_down(Vec3(0.5f, 0.f, 0.1f), nullptr, none);
  q.approach = Vec3(NAN, 0.f, 0.f);
  EXPECT_EQ(scratch().check(tool, q), ToolHit::invalid);
  q = top_down(Vec3(0.5f, 0.f, 0.1f), nullptr, none);
  q.closing = q.approach;  // degenerate frame: closing along the approach
  EXPECT_NE(scratch().check(tool, q), ToolHit::none);
}
#else
TEST(ToolCollision, NotInThisBuild) { GTEST_SKIP() << "built without libccd"; }
#endif
