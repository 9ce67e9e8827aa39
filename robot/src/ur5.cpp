#include "fg/robot/ur5.hpp"

#include <cmath>

#include "fg/core/constants.hpp"

namespace fg::robot {

Ur5Params ur5_nominal() {
  Ur5Params p{};
  const float d[6] = {0.089159f, 0.f, 0.f, 0.10915f, 0.09465f, 0.0823f};
  const float a[6] = {0.f, -0.425f, -0.39225f, 0.f, 0.f, 0.f};
  const float alpha[6] = {kPiF / 2, 0.f, 0.f, kPiF / 2, -kPiF / 2, 0.f};
  for (int i = 0; i < 6; ++i) {
    p.d[i] = d[i];
    p.a[i] = a[i];
    p.alpha[i] = alpha[i];
    p.theta_offset[i] = 0.f;
  }
  p.world_T_base.R << -1.f, 0.f, 0.f, 0.f, -1.f, 0.f, 0.f, 0.f, 1.f;
  p.world_T_base.t.setZero();
  return p;
}

bool ur5_forward(const Ur5Params& p, const float q[6], Pose& world_T_tool0) {
  for (int i = 0; i < 6; ++i)
    if (!std::isfinite(q[i])) return false;
  // Accumulate in double: the chain is long and we want ~1e-6 m agreement with the URDF.
  Eigen::Matrix3d R = p.world_T_base.R.cast<double>();
  Eigen::Vector3d t = p.world_T_base.t.cast<double>();
  for (int i = 0; i < 6; ++i) {
    const double th = static_cast<double>(q[i]) + p.theta_offset[i];
    const double ct = std::cos(th), st = std::sin(th);
    const double ca = std::cos(static_cast<double>(p.alpha[i]));
    const double sa = std::sin(static_cast<double>(p.alpha[i]));
    Eigen::Matrix3d Ri;
    Ri << ct, -st * ca, st * sa, st, ct * ca, -ct * sa, 0, sa, ca;
    const Eigen::Vector3d ti(p.a[i] * ct, p.a[i] * st, p.d[i]);
    t = t + R * ti;
    R = R * Ri;
  }
  world_T_tool0.R = R.cast<float>();
  world_T_tool0.t = t.cast<float>();
  return true;
}

Pose default_hand_eye() {
  Pose p;
  p.R.setIdentity();
  p.t = Vec3(0.f, 0.08f, 0.03f);
  return p;
}

}  // namespace fg::robot
