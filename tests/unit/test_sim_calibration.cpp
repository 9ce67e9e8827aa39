// The simulator's calibration error (hal/sim/calibration_error.hpp): exactly the size
// asked for, measured from the relative transform with Eigen's angle-axis; the same for
// a seed, other directions for other seeds; none when none is asked.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "fg/core/constants.hpp"
#include "sim/calibration_error.hpp"

namespace {
using fg::sim::Rigid;
using fg::sim::V3;

Rigid mount() {
  Rigid m;
  m.R = Eigen::AngleAxisd(0.3, V3(0.2, 0.9, -0.1).normalized()).toRotationMatrix();
  m.t = V3(0.0, 0.08, 0.03);
  return m;
}

TEST(SimCalibrationError, HasTheSizeAskedFor) {
  const Rigid m = mount();
  V3 first_shift = V3::Zero();
  for (uint64_t seed = 1; seed <= 40; ++seed) {
    for (const auto& [mm, deg] : {std::pair{5.0, 0.0}, std::pair{0.0, 1.0}, std::pair{20.0, 2.0}}) {
      const Rigid b = fg::sim::with_calibration_error(m, mm, deg, seed);
      const Rigid rel = m.inverse() * b;  // the error in the mount's frame
      EXPECT_NEAR(rel.t.norm(), mm * 1e-3, 1e-12);
      const Eigen::AngleAxisd aa(rel.R);
      EXPECT_NEAR(std::fabs(aa.angle()) * 180.0 / fg::kPi, deg, 1e-9);
      EXPECT_NEAR((rel.R * rel.R.transpose() - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-12);
      // The same for the same seed.
      const Rigid again = fg::sim::with_calibration_error(m, mm, deg, seed);
      EXPECT_EQ((again.t - b.t).norm(), 0.0);
      if (mm == 20.0 && seed == 1) first_shift = rel.t;
      if (mm == 20.0 && seed > 1) {
        EXPECT_GT((rel.t - first_shift).norm(), 1e-6) << "seed " << seed;
      }
    }
  }
  const Rigid none = fg::sim::with_calibration_error(m, 0.0, 0.0, 7);
  EXPECT_EQ((none.t - m.t).norm(), 0.0);
  EXPECT_EQ((none.R - m.R).norm(), 0.0);
}
}  // namespace
