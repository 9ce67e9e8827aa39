// The simulator's calibration error (hal/sim/calibration_error.hpp): exactly the size
// asked for, measured from the relative transform with Eigen's angle-axis; the same for
// a seed, other directions for other seeds; none when none is asked. The kinematic
// error: every DH length and joint zero within its bound, spread over it, and the arm's
// tool0 moved by it as the FK of the perturbed table says (an independent DH chain
// written out in the test).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "fg/core/constants.hpp"
#include "fg/robot/ur5.hpp"
#include "sim/calibration_error.hpp"
#include "sim/sim_hal.hpp"

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

TEST(SimKinematicError, EveryParameterWithinItsBound) {
  const fg::robot::Ur5Params nominal = fg::robot::ur5_nominal();
  double max_len = 0.0, max_zero = 0.0;
  for (uint64_t seed = 1; seed <= 50; ++seed) {
    const fg::robot::Ur5Params p = fg::sim::with_kinematic_error(nominal, 5.0, 0.5, seed);
    for (int i = 0; i < 6; ++i) {
      const double dd = std::fabs(static_cast<double>(p.d[i]) - nominal.d[i]);
      const double da = std::fabs(static_cast<double>(p.a[i]) - nominal.a[i]);
      const double dz = std::fabs(static_cast<double>(p.theta_offset[i]) - nominal.theta_offset[i]);
      EXPECT_LE(dd, 5e-3 + 1e-7);
      EXPECT_LE(da, 5e-3 + 1e-7);
      EXPECT_LE(dz, 0.5 * fg::kPi / 180.0 + 1e-7);
      EXPECT_EQ(p.alpha[i], nominal.alpha[i]);
      max_len = std::fmax(max_len, std::fmax(dd, da));
      max_zero = std::fmax(max_zero, dz);
    }
    const fg::robot::Ur5Params again = fg::sim::with_kinematic_error(nominal, 5.0, 0.5, seed);
    for (int i = 0; i < 6; ++i) EXPECT_EQ(again.d[i], p.d[i]);
  }
  // Spread over the bound, not stuck near zero.
  EXPECT_GT(max_len, 4e-3);
  EXPECT_GT(max_zero, 0.4 * fg::kPi / 180.0);
  const fg::robot::Ur5Params none = fg::sim::with_kinematic_error(nominal, 0.0, 0.0, 3);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(none.d[i], nominal.d[i]);
}

// base_T_tool0 of a DH table, written out: T_i = Rz(theta_i + offset_i) Tz(d_i) Tx(a_i) Rx(alpha_i).
Rigid dh_chain(const fg::robot::Ur5Params& p, const double q[6]) {
  Rigid T;
  for (int i = 0; i < 6; ++i) {
    Rigid step;
    step.R = (Eigen::AngleAxisd(q[i] + p.theta_offset[i], V3::UnitZ()) *
              Eigen::AngleAxisd(static_cast<double>(p.alpha[i]), V3::UnitX()))
                 .toRotationMatrix();
    step.t = Eigen::AngleAxisd(q[i] + p.theta_offset[i], V3::UnitZ()) * V3(p.a[i], 0.0, p.d[i]);
    T = T * step;
  }
  return T;
}

TEST(SimKinematicError, TheArmMovesByItsTrueKinematics) {
  const double q[6] = {0.3, -1.2, 1.4, -1.6, -1.5, 0.2};
  const fg::robot::Ur5Params nominal = fg::robot::ur5_nominal();
  fg::sim::SimArmConfig cfg;
  cfg.kinematics = fg::sim::with_kinematic_error(nominal, 5.0, 0.5, 11);
  const fg::sim::SimArm true_arm(q, cfg), nominal_arm(q);
  // Both as their own DH chains say (the same mounting of the DH base in both).
  const Rigid d_true = dh_chain(cfg.kinematics, q), d_nominal = dh_chain(nominal, q);
  const V3 moved = true_arm.tool0().t - nominal_arm.tool0().t;
  const V3 moved_dh = nominal_arm.tool0().R * (d_nominal.R.transpose() * (d_true.t - d_nominal.t));
  EXPECT_NEAR((moved - moved_dh).norm(), 0.0, 1e-5) << moved.transpose() << " / " << moved_dh.transpose();
  // An uncalibrated arm: millimetres to a few centimetres at the flange.
  EXPECT_GT(moved.norm(), 1e-3);
  EXPECT_LT(moved.norm(), 0.05);
}
}  // namespace
