#include "sim/calibration_error.hpp"

#include <Eigen/Geometry>

#include "fg/core/constants.hpp"
#include "sim/sim_rng.hpp"

namespace fg::sim {
namespace {
// A unit vector uniform on the sphere; each draw a statement of its own, so the draws
// come in the same order on every compiler (sim_rng.hpp).
V3 random_direction(Rng& rng) {
  for (;;) {  // a zero vector (never drawn in practice) is drawn again
    const double x = rng.normal();
    const double y = rng.normal();
    const double z = rng.normal();
    const V3 v(x, y, z);
    if (v.norm() > 1e-9) return v.normalized();
  }
}
}  // namespace

Rigid with_calibration_error(const Rigid& a_T_b, double mm, double deg, uint64_t seed) {
  if (mm <= 0.0 && deg <= 0.0) return a_T_b;
  Rng rng(seed ^ 0xC0FFEE5EEDull);  // a stream of its own: a scene drawn from the same seed stays as it is
  const V3 shift = random_direction(rng) * (mm * 1e-3);
  const V3 axis = random_direction(rng);
  Rigid error;
  error.R = Eigen::AngleAxisd(deg * kPi / 180.0, axis).toRotationMatrix();
  error.t = shift;
  return a_T_b * error;
}

fg::robot::Ur5Params with_kinematic_error(const fg::robot::Ur5Params& nominal, double mm, double deg, uint64_t seed) {
  if (mm <= 0.0 && deg <= 0.0) return nominal;
  Rng rng(seed ^ 0x4B1E3A7105EEDull);  // a stream of its own, like the hand-eye error's
  fg::robot::Ur5Params p = nominal;
  for (int i = 0; i < 6; ++i) {
    const double dd = rng.uniform(-mm, mm) * 1e-3;
    const double da = rng.uniform(-mm, mm) * 1e-3;
    const double dtheta = rng.uniform(-deg, deg) * kPi / 180.0;
    p.d[i] += static_cast<float>(dd);
    p.a[i] += static_cast<float>(da);
    p.theta_offset[i] += static_cast<float>(dtheta);
  }
  return p;
}

}  // namespace fg::sim
