// D.1, the projection into a viewpoint's XOY plane: every coordinate within float
// rounding of the dot in double (the oracle) and, bit for bit, the float formula of the
// header for every count (the four-point steps and the tail alike, on every target);
// on x86-64 also Eigen's Vector3f dot bit for bit (the planner's projection before it
// had its own file, so host plans are unchanged); and the bounding box the hull would
// find itself.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "fg/core/projection.hpp"

namespace {

using fg::Vec2;
using fg::Vec3;

TEST(Projection, EveryCoordinateIsEigensDotBitForBit) {
  std::mt19937 rng(2024u);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (uint32_t n : {1u, 2u, 3u, 4u, 5u, 7u, 8u, 9u, 63u, 1000u, 4099u}) {
    for (int trial = 0; trial < 6; ++trial) {
      const Vec3 origin(0.5f + 0.1f * u(rng), 0.1f * u(rng), 0.05f + 0.1f * u(rng));
      const Vec3 X = Vec3(u(rng), u(rng), u(rng)).normalized();
      const Vec3 Y = X.cross(Vec3(u(rng), u(rng), u(rng))).normalized();
      std::vector<Vec3> pts(n);
      for (Vec3& p : pts) p = origin + 0.15f * Vec3(u(rng), u(rng), u(rng));
      std::vector<Vec2> out(n);
      fg::ConcaveHullParams hp;
      fg::project_to_view(pts.data(), n, origin, X, Y, out.data(), hp);
      float xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
      for (uint32_t i = 0; i < n; ++i) {
        const Vec3 d = pts[i] - origin;
        const float ex = X.x() * d.x() + (X.y() * d.y() + X.z() * d.z());
        const float ey = Y.x() * d.x() + (Y.y() * d.y() + Y.z() * d.z());
        ASSERT_EQ(std::memcmp(&out[i].x, &ex, sizeof ex), 0) << "n " << n << " point " << i;
        ASSERT_EQ(std::memcmp(&out[i].y, &ey, sizeof ey), 0) << "n " << n << " point " << i;
#if defined(__x86_64__)
        const float eigen_x = X.dot(d), eigen_y = Y.dot(d);
        ASSERT_EQ(std::memcmp(&out[i].x, &eigen_x, sizeof ex), 0) << "n " << n << " point " << i;
        ASSERT_EQ(std::memcmp(&out[i].y, &eigen_y, sizeof ey), 0) << "n " << n << " point " << i;
#endif
        // The exact dot of the float inputs: three products and two sums, each off by
        // at most half an ulp of its own magnitude (|d| < 0.3, |X| = 1).
        const Eigen::Vector3d dd = d.cast<double>();
        EXPECT_NEAR(out[i].x, X.cast<double>().dot(dd), 4 * 0.3 * std::ldexp(1.0, -24));
        EXPECT_NEAR(out[i].y, Y.cast<double>().dot(dd), 4 * 0.3 * std::ldexp(1.0, -24));
        xmin = std::fmin(xmin, ex), xmax = std::fmax(xmax, ex), ymin = std::fmin(ymin, ey), ymax = std::fmax(ymax, ey);
      }
      ASSERT_TRUE(hp.bounds_given);
      EXPECT_EQ(hp.xmin, xmin);
      EXPECT_EQ(hp.xmax, xmax);
      EXPECT_EQ(hp.ymin, ymin);
      EXPECT_EQ(hp.ymax, ymax);
    }
  }
}

// No box where it would not be the hull's: a non-finite frame, or projections that
// overflow the float range.
TEST(Projection, NoBoundsForANonFiniteFrameOrOverflow) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<Vec3> pts = {Vec3(0.f, 0.f, 0.f), Vec3(1.f, 2.f, 3.f), Vec3(-1.f, 0.5f, 2.f), Vec3(3.f, 1.f, 0.f),
                           Vec3(0.2f, 0.1f, 0.f)};
  std::vector<Vec2> out(pts.size());
  fg::ConcaveHullParams hp;
  fg::project_to_view(pts.data(), 5, Vec3::Zero(), Vec3(1.f, 0.f, 0.f), Vec3(0.f, 1.f, 0.f), out.data(), hp);
  EXPECT_TRUE(hp.bounds_given);
  EXPECT_EQ(hp.xmin, -1.f);
  EXPECT_EQ(hp.ymax, 2.f);
  fg::project_to_view(pts.data(), 5, Vec3::Zero(), Vec3(nan, 0.f, 0.f), Vec3(0.f, 1.f, 0.f), out.data(), hp);
  EXPECT_FALSE(hp.bounds_given);
  fg::project_to_view(pts.data(), 5, Vec3(0.f, nan, 0.f), Vec3(1.f, 0.f, 0.f), Vec3(0.f, 1.f, 0.f), out.data(), hp);
  EXPECT_FALSE(hp.bounds_given);
  pts[3] = Vec3(3e38f, 0.f, 0.f);
  fg::project_to_view(pts.data(), 5, Vec3(-3e38f, 0.f, 0.f), Vec3(1.f, 0.f, 0.f), Vec3(0.f, 1.f, 0.f), out.data(), hp);
  EXPECT_FALSE(hp.bounds_given);
  fg::project_to_view(pts.data(), 0, Vec3::Zero(), Vec3(1.f, 0.f, 0.f), Vec3(0.f, 1.f, 0.f), out.data(), hp);
  EXPECT_FALSE(hp.bounds_given);
}

}  // namespace
