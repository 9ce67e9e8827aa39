// Host-only simulation: a calibration error of a known size in a direction drawn from a
// seed (`forcegrasp sim --calibration-error MM,DEG`): the pose a robot believes a sensor
// has when its hand-eye calibration is off.
#pragma once
#include <cstdint>

#include "fg/robot/ur5.hpp"
#include "sim/sim_world.hpp"

namespace fg::sim {

//! a_T_b off by `mm` millimetres along a direction and `deg` degrees about an axis through
//! b's origin, both uniform on the sphere and drawn from `seed` (the same on every
//! compiler): a_T_b * error, in b's frame. a_T_b itself when both are 0.
Rigid with_calibration_error(const Rigid& a_T_b, double mm, double deg, uint64_t seed);

//! An arm whose kinematics differ from `nominal` as an uncalibrated UR5's do (its links
//! machined and assembled within tolerance, its joint encoders zeroed by hand): every
//! DH length d_i and a_i off by a value uniform in [-mm, mm], every joint's zero
//! (theta_offset_i) by one uniform in [-deg, deg], drawn from `seed` on a stream of its
//! own. `nominal` itself when both are 0.
fg::robot::Ur5Params with_kinematic_error(const fg::robot::Ur5Params& nominal, double mm, double deg, uint64_t seed);

}  // namespace fg::sim
