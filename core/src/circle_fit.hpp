// A circle through points of a plane section, by least squares on
// x^2 + z^2 + D x + E z + F = 0 (Kasa's algebraic fit): the normal equations a s = r,
// solved by Eigen's closed-form 3x3 determinant and inverse (fixed size, no heap).
// Callers pass coordinates about a point near the arc's centre or mean, which keeps
// the equations well conditioned. Used by the unseen side's round front
// (pipeline/grasp_checks.cpp) and the round flanks' repair (pipeline/grazed_round.cpp).
#pragma once
#include <Eigen/Core>
#include <Eigen/LU>
#include <cmath>

namespace fg {

struct CircleFit {
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  Eigen::Vector3d r = Eigen::Vector3d::Zero();

  void add(double x, double z) {
    const Eigen::Vector3d v(x, z, 1.0);
    a += v * v.transpose();
    r -= (v[0] * v[0] + v[1] * v[1]) * v;
  }
  // The centre and the squared radius; false when the points are collinear (a flat
  // section) or give no real circle.
  [[nodiscard]] bool solve(double& xc, double& zc, double& rr) const {
    if (!(std::fabs(a.determinant()) > 1e-18)) return false;
    const Eigen::Vector3d sol = a.inverse() * r;
    xc = -0.5 * sol[0];
    zc = -0.5 * sol[1];
    rr = xc * xc + zc * zc - sol[2];
    return rr > 0.0;
  }
};

}  // namespace fg
