// UR5 kinematic parameters and forward kinematics for the embedded side.
// The numbers are the classic UR5 DH table; tests check them against the URDF in
// shared/data/robots/ur5 (world = URDF base_link = DH base turned 180 deg about z).
#pragma once
#include "fg/core/types.hpp"

namespace fg::robot {

//! Standard DH parameters (T_i = Rz(theta_i + offset_i) Tz(d_i) Tx(a_i) Rx(alpha_i)),
//! plus the mounting of the DH base in `world`. A calibrated robot replaces the
//! nominal values with its own (real UR arms differ from nominal by 5-15 mm).
struct Ur5Params {
  float d[6];
  float a[6];
  float alpha[6];
  float theta_offset[6];
  Pose world_T_base;  //!< DH base in world (nominal: Rz(pi))
};

//! The nominal UR5 (ur_description, 2015).
Ur5Params ur5_nominal();

//! world_T_tool0 for joint angles q (radians, shoulder_pan .. wrist_3).
//! Returns false (and leaves out untouched) if any q is non-finite.
[[nodiscard]] bool ur5_forward(const Ur5Params& p, const float q[6], Pose& world_T_tool0);

//! The default wrist-sensor mount (tool0_T_sensor) used when a scene gives joints
//! without "hand_eye": optical axis along tool0 +z, 0.08 m off the flange axis along
//! tool0 +y and 0.03 m forward along tool0 +z.
Pose default_hand_eye();

}  // namespace fg::robot
