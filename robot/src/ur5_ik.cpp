// UR5 analytic inverse kinematics (see ur5_ik.hpp and docs/robot.md).
//
// Closed form (Hawkins 2013, as in ur_kinematics' inverse()), written on the DH chain
// T06 = base_T_world * world_T_tool0 with theta_i = q_i + theta_offset_i:
//   p5 = p - d6 z6 (wrist centre, on the wrist 2 and wrist 3 axes);
//   z1 = (sin t1, -cos t1, 0) and p5 . z1 = d2 + d3 + d4  -> two shoulder roots t1;
//   cos t5 = z6 . z1, |sin t5| = |(x6 . z1, y6 . z1)|       -> two wrist roots t5;
//   t6 = atan2(-(y6 . z1) / s5, (x6 . z1) / s5);
//   T14 = A1^-1 T06 A6^-1 A5^-1 = Rz(t2 + t3 + t4) with origin (x, y, d4)
//     -> planar two-link problem for t2, t3 (two elbow roots), then t4.
// Every branch is then checked (and, off the nominal structure, refined) on the full
// forward kinematics, so no answer is returned that FK does not confirm.
#include "fg/robot/ur5_ik.hpp"

#include <Eigen/Cholesky>
#include <cmath>

#include "fg/core/constants.hpp"

namespace fg::robot {

namespace {
constexpr double kTwoPi = 2.0 * kPi;
constexpr double kHalfPi = 0.5 * kPi;
constexpr double kLimitAbsMax = 1000.0;  // rad: bounds the 2pi-shift arithmetic

using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;

struct Tf {
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
};

Tf mul(const Tf& a, const Tf& b) { return Tf{a.R * b.R, a.R * b.t + a.t}; }

Tf inverse(const Tf& a) {
  const Eigen::Matrix3d Rt = a.R.transpose();
  return Tf{Rt, -(Rt * a.t)};
}

//! T = Rz(theta) Tz(d) Tx(a) Rx(alpha), the convention of ur5_forward().
Tf dh(double theta, double d, double a, double alpha) {
  const double ct = std::cos(theta), st = std::sin(theta);
  const double ca = std::cos(alpha), sa = std::sin(alpha);
  Tf T;
  T.R << ct, -st * ca, st * sa, st, ct * ca, -ct * sa, 0.0, sa, ca;
  T.t = Eigen::Vector3d(a * ct, a * st, d);
  return T;
}

double max_abs_off_identity(const Eigen::Matrix3d& R) {
  return (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
}

//! Two Bjorck steps R <- R (3 I - R^T R) / 2: the nearest rotation for a matrix that is
//! already orthonormal to ~1e-5 (quadratic convergence).
Eigen::Matrix3d orthonormalize(Eigen::Matrix3d R) {
  for (int k = 0; k < 2; ++k) R = R * (1.5 * Eigen::Matrix3d::Identity() - 0.5 * (R.transpose() * R));
  return R;
}

bool finite3(const Eigen::Matrix3d& R) { return R.allFinite(); }

bool rotation_ok(const Eigen::Matrix3d& R, double tol) {
  if (!finite3(R)) return false;
  if (!(max_abs_off_identity(R) <= tol)) return false;
  return R.determinant() > 0.0;
}

//! The representation x + 2 pi k inside [lo, hi] nearest to c. False if none.
bool nearest_rep(double x, double c, double lo, double hi, double& out) {
  const double cc = c < lo ? lo : (c > hi ? hi : c);
  double y = x + kTwoPi * std::nearbyint((cc - x) / kTwoPi);
  if (y > hi) y -= kTwoPi;
  if (y < lo) y += kTwoPi;
  if (!(y >= lo && y <= hi)) return false;
  out = y;
  return true;
}

//! x - 2 pi k in [-pi, pi] (|x| is at most a few thousand here; std::remainder is exact
//! but slow in glibc).
double wrap_pi(double x) { return x - kTwoPi * std::nearbyint(x / kTwoPi); }

double angle_diff(double a, double b) { return std::fabs(wrap_pi(a - b)); }

bool limits_ok(const JointLimits& L) {
  for (int i = 0; i < 6; ++i) {
    const double lo = L.lower[i], hi = L.upper[i];
    if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo <= hi)) return false;
    if (std::fabs(lo) > kLimitAbsMax || std::fabs(hi) > kLimitAbsMax) return false;
  }
  return true;
}

bool nonneg_finite(double v) { return std::isfinite(v) && v >= 0.0; }

bool options_ok(const IkOptions& o) {
  return limits_ok(o.limits) && nonneg_finite(o.reach_tol) && o.reach_tol < 0.1 && nonneg_finite(o.singular_tol) &&
         nonneg_finite(o.wrist_singular_tol) && std::isfinite(o.wrist_free_q6) &&
         std::fabs(o.wrist_free_q6) <= kLimitAbsMax && nonneg_finite(o.duplicate_tol) &&
         nonneg_finite(o.orthonormal_tol) && o.orthonormal_tol < 0.1 && nonneg_finite(o.refine_above_m) &&
         nonneg_finite(o.refine_above_rad) && nonneg_finite(o.refine_stop_m) && nonneg_finite(o.refine_stop_rad) &&
         nonneg_finite(o.accept_m) && nonneg_finite(o.accept_rad);
}

//! Ur5Params read as double. A twist within kSnapRad of a multiple of pi/2 is taken as
//! exactly that multiple: float cannot hold pi/2 (the nearest float is 4.4e-8 rad off)
//! and the URDF means pi/2 (it writes 1.570796325). The base rotation is
//! re-orthonormalised the same way. This is the model the IK solves and checks.
constexpr double kSnapRad = 1e-6;

struct Model {
  double d[6], a[6], alpha[6], off[6];
  double ca[6], sa[6];  //!< cos, sin of alpha
  Tf base;
};

void load_model(const Ur5Params& p, Model& m) {
  for (int i = 0; i < 6; ++i) {
    m.d[i] = p.d[i];
    m.a[i] = p.a[i];
    m.off[i] = p.theta_offset[i];
    const double al = p.alpha[i];
    const double snapped = kHalfPi * std::nearbyint(al / kHalfPi);
    m.alpha[i] = std::fabs(al - snapped) <= kSnapRad ? snapped : al;
    m.ca[i] = std::cos(m.alpha[i]);
    m.sa[i] = std::sin(m.alpha[i]);
  }
  const Eigen::Matrix3d Rb = p.world_T_base.R.cast<double>();
  m.base.R = (Rb.allFinite() && max_abs_off_identity(Rb) <= 1e-5) ? orthonormalize(Rb) : Rb;
  m.base.t = p.world_T_base.t.cast<double>();
}

//! The model is finite and has the UR structure the closed form relies on, within the
//! deviations a calibration brings (0.1 rad on alpha, 5 cm on a1/a4/a5/a6).
//! deviation_m: a rough bound on how far the full model can put the tool from the
//! closed form's nominal-structure model (the ignored offsets, plus the twist errors
//! times the arm's length); exactly 0 for the nominal structure.
bool ur_structure_ok(const Model& m, double& deviation_m) {
  const double nominal_alpha[6] = {kHalfPi, 0.0, 0.0, kHalfPi, -kHalfPi, 0.0};
  double reach = 0.0;
  for (int i = 0; i < 6; ++i) {
    if (!std::isfinite(m.d[i]) || !std::isfinite(m.a[i]) || !std::isfinite(m.alpha[i]) || !std::isfinite(m.off[i]))
      return false;
    if (std::fabs(m.alpha[i] - nominal_alpha[i]) > 0.1) return false;
    if (std::fabs(m.off[i]) > 10.0 || std::fabs(m.d[i]) > 10.0 || std::fabs(m.a[i]) > 10.0) return false;
    reach += std::fabs(m.a[i]) + std::fabs(m.d[i]);
  }
  const int offset_free[4] = {0, 3, 4, 5};
  double dev = 0.0;
  for (int k = 0; k < 4; ++k) {
    if (std::fabs(m.a[offset_free[k]]) > 0.05) return false;
    dev += std::fabs(m.a[offset_free[k]]);
  }
  for (int i = 0; i < 6; ++i) dev += std::fabs(m.alpha[i] - nominal_alpha[i]) * reach;
  if (std::fabs(m.a[1]) < 1e-3 || std::fabs(m.a[2]) < 1e-3) return false;
  if (std::fabs(m.d[1] + m.d[2] + m.d[3]) < 1e-3) return false;
  if (!m.base.t.allFinite() || !rotation_ok(m.base.R, 1e-9)) return false;
  deviation_m = dev;
  return true;
}

//! FK of the model, with the geometric Jacobian (world frame; rows: linear velocity,
//! angular velocity). The chain and arithmetic of ur5_forward(), in double.
void forward_jacobian(const Model& m, const double q[6], Tf& T, Mat6* J) {
  Eigen::Matrix3d R = m.base.R;
  Eigen::Vector3d t = m.base.t;
  Eigen::Vector3d z[6], o[6];
  for (int i = 0; i < 6; ++i) {
    z[i] = R.col(2);
    o[i] = t;
    const double th = q[i] + m.off[i];
    const double ct = std::cos(th), st = std::sin(th);
    const double ca = m.ca[i], sa = m.sa[i];
    Eigen::Matrix3d Ri;
    Ri << ct, -st * ca, st * sa, st, ct * ca, -ct * sa, 0, sa, ca;
    const Eigen::Vector3d ti(m.a[i] * ct, m.a[i] * st, m.d[i]);
    t = t + R * ti;
    R = R * Ri;
  }
  T.R = R;
  T.t = t;
  if (J != nullptr) {
    for (int i = 0; i < 6; ++i) {
      J->block<3, 1>(0, i) = z[i].cross(t - o[i]);
      J->block<3, 1>(3, i) = z[i];
    }
  }
}

//! Distance of T from the target: |dt| and the rotation angle, from
//! |R_target - R|_F = 2 sqrt(2) sin(angle / 2) (no cancellation at small angles).
void pose_error(const Tf& T, const Tf& target, double& err_m, double& err_rad) {
  err_m = (target.t - T.t).norm();
  const double s = (target.R - T.R).norm() / (2.0 * std::sqrt(2.0));
  err_rad = 2.0 * std::asin(s < 1.0 ? s : 1.0);
}

//! Residual of T against the target: e = (dt, rotation vector of R_target R^T).
void residual(const Tf& T, const Tf& target, Vec6& e, double& err_m, double& err_rad) {
  const Eigen::Vector3d dt = target.t - T.t;
  const Eigen::AngleAxisd aa(Eigen::Matrix3d(target.R * T.R.transpose()));
  e.head<3>() = dt;
  e.tail<3>() = aa.angle() * aa.axis();
  err_m = dt.norm();
  err_rad = std::fabs(aa.angle());
}

// ---- the closed form ------------------------------------------------------------

//! The closed form's nominal structure: d2 + d3 fold into d4 (joints 2-4 parallel),
//! a1 = a4 = a5 = a6 = 0, alpha = (pi/2, 0, 0, pi/2, -pi/2, 0).
struct Nominal {
  double d1, a2, a3, d4, d5, d6;
  double off[6];
  double slack_m;  //!< how far beyond a fold an argument is still clamped (model mismatch)
  bool exact;      //!< the model has exactly the nominal structure
};

Nominal nominal_of(const Model& m, double deviation_m) {
  Nominal nm;
  nm.d1 = m.d[0];
  nm.a2 = m.a[1];
  nm.a3 = m.a[2];
  nm.d4 = m.d[1] + m.d[2] + m.d[3];
  nm.d5 = m.d[4];
  nm.d6 = m.d[5];
  for (int i = 0; i < 6; ++i) nm.off[i] = m.off[i];
  nm.exact = deviation_m == 0.0;
  nm.slack_m = 2.0 * deviation_m;
  return nm;
}

// Off the nominal structure a double root is started a little apart, so that the
// refinement has a slope to follow.
constexpr double kFoldNudge = 1e-3;

//! The two shoulder roots t1 = phi + atan2(s, +-h) of p5 . z1 = d4.
struct Shoulder {
  double s, h, phi;
  bool singular;
};

bool shoulder_roots(const Nominal& nm, const Tf& T06, const IkOptions& opt, Shoulder& sh) {
  const Eigen::Vector3d p5 = T06.t - nm.d6 * T06.R.col(2);  // wrist centre
  // z1 = (s1, -c1, 0): |p5_xy| sin(t1 - phi) = d4.
  const double rxy = std::hypot(p5.x(), p5.y());
  if (!(rxy > 0.0) || std::fabs(nm.d4) > rxy * (1.0 + opt.reach_tol) + nm.slack_m) return false;
  double s = nm.d4 / rxy;
  if (s > 1.0) s = 1.0;
  if (s < -1.0) s = -1.0;
  double h = std::sqrt(std::fmax(0.0, 1.0 - s * s));
  sh.singular = std::atan2(h, std::fabs(s)) < opt.singular_tol;
  if (!nm.exact && h < std::sin(kFoldNudge)) h = std::sin(kFoldNudge);
  sh.s = s;
  sh.h = h;
  sh.phi = std::atan2(p5.y(), p5.x());
  return true;
}

struct Candidate {
  double q[6];   //!< joint angles (theta - offset), in (-pi, pi]
  uint8_t sing;  //!< IkSingularity bits
  bool valid;
};

//! The free joint at the wrist singularity. There q6 turns the wrist centre's offset d5
//! about the wrist 3 axis, so the planar arm's target moves on a circle: its squared
//! distance is exactly r2(t6) = A + B cos t6 + C sin t6 (three samples fix A, B, C).
//! t6 = the caller's choice (IkOptions::wrist_free_q6) when the planar arm reaches with
//! it; else the nearest t6 that it reaches with, kept 10% of the reachable range inside
//! (away from the elbow fold). False if no t6 reaches.
template <typename Planar>
bool free_q6(Planar& planar, const Nominal& nm, const IkOptions& opt, double ra, double rb, double& t6) {
  double r2s[3];
  for (int k = 0; k < 3; ++k) {
    double x = 0.0, y = 0.0, t234 = 0.0;
    planar(k * kHalfPi, x, y, t234);
    r2s[k] = x * x + y * y;
  }
  const double A = 0.5 * (r2s[0] + r2s[2]), B = 0.5 * (r2s[0] - r2s[2]), C = r2s[1] - A;
  const double R = std::hypot(B, C), phi = std::atan2(C, B);
  const double slack = nm.slack_m + opt.reach_tol * (ra + rb);
  const double rmin = std::fmax(0.0, std::fabs(ra - rb) - slack), rmax = ra + rb + slack;
  const double hint = opt.wrist_free_q6 + nm.off[5];
  if (R <= 1e-12 * (1.0 + A)) {  // r2 does not depend on q6
    t6 = hint;
    return A >= rmin * rmin && A <= rmax * rmax;
  }
  double lo = (rmin * rmin - A) / R, hi = (rmax * rmax - A) / R;  // bounds on cos(t6 - phi)
  if (lo > 1.0 || hi < -1.0) return false;
  lo = std::fmax(lo, -1.0);
  hi = std::fmin(hi, 1.0);
  const double umin = std::acos(hi), umax = std::acos(lo);  // allowed |t6 - phi|
  const double uh = wrap_pi(hint - phi);
  const double au = std::fabs(uh);
  if (au >= umin && au <= umax) {
    t6 = hint;
    return true;
  }
  const double margin = 0.1 * (umax - umin);
  const double target = au < umin ? umin + margin : umax - margin;
  t6 = phi + (uh < 0.0 ? -target : target);
  return true;
}

//! Shoulder root ib, wrist root jb: both elbow roots (out[0], out[1]). Returns false
//! when the arm cannot reach with this pair (out[*].valid false). wrist_sing tells
//! whether sin q5 = 0 here (then jb = 1 repeats jb = 0).
bool solve_pair(const Nominal& nm, const Tf& T06, const Shoulder& sh, int ib, int jb, const IkOptions& opt,
                Candidate out[2], bool& wrist_sing) {
  out[0].valid = out[1].valid = false;
  const double t1 = sh.phi + std::atan2(sh.s, ib == 0 ? sh.h : -sh.h);
  const double s1 = std::sin(t1), c1 = std::cos(t1);
  const Eigen::Vector3d n = T06.R.col(0), o = T06.R.col(1), a = T06.R.col(2);
  // Tool axes along z1: x6.z1 = s5 c6, y6.z1 = -s5 s6, z6.z1 = c5.
  const double nw = n.x() * s1 - n.y() * c1;
  const double ow = o.x() * s1 - o.y() * c1;
  const double aw = a.x() * s1 - a.y() * c1;
  const double s5_abs = std::hypot(nw, ow);
  wrist_sing = s5_abs < opt.wrist_singular_tol;
  const double sg = jb == 0 ? 1.0 : -1.0;
  const double t5 = std::atan2(sg * s5_abs, aw);
  const Tf A1inv = inverse(dh(t1, nm.d1, 0.0, kHalfPi));
  const Tf A5inv = inverse(dh(t5, nm.d5, 0.0, -kHalfPi));
  const Tf T05 = mul(A1inv, T06);

  // T14 = A1^-1 T06 A6^-1 A5^-1 = A2 A3 A4: a rotation about z1 by t2 + t3 + t4 and the
  // origin (x, y, d4) of a planar two-link arm.
  auto planar = [&](double t6_, double& x_, double& y_, double& t234_) {
    const Tf T14 = mul(mul(T05, inverse(dh(t6_, nm.d6, 0.0, 0.0))), A5inv);
    x_ = T14.t.x();
    y_ = T14.t.y();
    t234_ = std::atan2(T14.R(1, 0), T14.R(0, 0));
  };
  const double ra = std::fabs(nm.a2), rb = std::fabs(nm.a3);
  double t6 = std::atan2(-sg * ow, sg * nw);
  if (wrist_sing && !free_q6(planar, nm, opt, ra, rb, t6)) return false;
  double x = 0.0, y = 0.0, t234 = 0.0;
  planar(t6, x, y, t234);
  const double r2 = x * x + y * y;
  double c3 = (r2 - nm.a2 * nm.a2 - nm.a3 * nm.a3) / (2.0 * nm.a2 * nm.a3);
  const double c3_slack = nm.slack_m * std::sqrt(r2) / (ra * rb);
  if (!std::isfinite(c3) || std::fabs(c3) > 1.0 + opt.reach_tol + c3_slack) return false;
  if (c3 > 1.0) c3 = 1.0;
  if (c3 < -1.0) c3 = -1.0;
  double s3_abs = std::sqrt(std::fmax(0.0, 1.0 - c3 * c3));
  const bool elbow_sing = std::atan2(s3_abs, std::fabs(c3)) < opt.singular_tol;
  if (!nm.exact && s3_abs < std::sin(kFoldNudge)) s3_abs = std::sin(kFoldNudge);

  uint8_t sing = 0;
  if (sh.singular) sing = static_cast<uint8_t>(sing | kIkShoulder);
  if (elbow_sing) sing = static_cast<uint8_t>(sing | kIkElbow);
  if (wrist_sing) sing = static_cast<uint8_t>(sing | kIkWrist);
  for (int kb = 0; kb < 2; ++kb) {
    const double s3 = kb == 0 ? s3_abs : -s3_abs;
    const double t3 = std::atan2(s3, c3);
    const double t2 = std::atan2(y, x) - std::atan2(nm.a3 * s3, nm.a2 + nm.a3 * c3);
    const double t4 = t234 - t2 - t3;
    const double th[6] = {t1, t2, t3, t4, t5, t6};
    for (int i = 0; i < 6; ++i) out[kb].q[i] = wrap_pi(th[i] - nm.off[i]);
    out[kb].sing = sing;
    out[kb].valid = true;
  }
  return true;
}

// ---- refinement on the full model --------------------------------------------------

constexpr double kVtGain = 0.1;   // the virtual-target step must cut the squared error 10x
constexpr double kMaxStep = 0.5;  // rad per joint and Newton step
constexpr int kLineSearch = 6;    // trials per Newton step (full, 1/2, ..., 1/32)

//! One branch (ib, jb, kb) of the closed form brought onto the target on the full
//! model, in at most opt.refine_iterations steps:
//!  1. one virtual-target step: the same branch of the closed form solved for
//!     Tv = T FK(q)^-1 T, which removes most of the (nearly constant) offset between
//!     the two models at once, also beside a fold where Newton steps crawl; kept only if
//!     it cuts the squared error 10x;
//!  2. Gauss-Newton steps on the full FK (6x6 LDLT, a 1e-12 relative ridge), each with
//!     a backtracking line search of at most kLineSearch trials. At a fold the gradient
//!     has no component along the fold, so damping (which turns a step toward the
//!     gradient) stalls there, while the Newton direction, shortened, crosses it.
//! Worst case per branch: 2 + kLineSearch * refine_iterations FK (+ Jacobian) evaluations.
void refine(const Model& m, const Nominal& nm, const Tf& target, int ib, int jb, int kb, const IkOptions& opt, Tf T,
            Vec6 e, double q[6], double& err_m, double& err_rad) {
  const int iterations = opt.refine_iterations;
  const double stop_m = opt.refine_stop_m, stop_rad = opt.refine_stop_rad;
  double cost = e.squaredNorm();
  if (iterations < 1 || (err_m <= stop_m && err_rad <= stop_rad)) return;

  {  // 1. virtual target
    const Tf Tv = mul(mul(target, inverse(T)), target);
    const Tf T06v = mul(inverse(m.base), Tv);
    Shoulder sh;
    Candidate c[2];
    bool ws = false;
    if (shoulder_roots(nm, T06v, opt, sh) && solve_pair(nm, T06v, sh, ib, jb, opt, c, ws) && c[kb].valid) {
      Tf Tn;
      Vec6 en;
      double em = 0.0, er = 0.0;
      forward_jacobian(m, c[kb].q, Tn, nullptr);
      residual(Tn, target, en, em, er);
      const double cost_n = en.squaredNorm();
      if (cost_n < kVtGain * cost) {
        for (int i = 0; i < 6; ++i) q[i] = c[kb].q[i];
        e = en;
        cost = cost_n;
        err_m = em;
        err_rad = er;
      }
    }
  }

  // 2. Gauss-Newton with a line search.
  Mat6 J;
  forward_jacobian(m, q, T, &J);
  for (int it = 1; it < iterations; ++it) {
    if (err_m <= stop_m && err_rad <= stop_rad) return;
    const Mat6 JtJ = J.transpose() * J;
    const Vec6 g = J.transpose() * e;
    const Mat6 A = JtJ + (1e-12 * JtJ.diagonal().maxCoeff()) * Mat6::Identity();
    Vec6 dq = A.ldlt().solve(g);
    if (!dq.allFinite()) return;
    const double step = dq.cwiseAbs().maxCoeff();
    if (step > kMaxStep) dq *= kMaxStep / step;
    bool improved = false;
    for (int ls = 0; ls < kLineSearch && !improved; ++ls, dq *= 0.5) {
      double qn[6];
      for (int i = 0; i < 6; ++i) qn[i] = q[i] + dq[i];
      Tf Tn;
      Mat6 Jn;
      Vec6 en;
      double em = 0.0, er = 0.0;
      forward_jacobian(m, qn, Tn, &Jn);
      residual(Tn, target, en, em, er);
      const double cost_n = en.squaredNorm();
      if (std::isfinite(cost_n) && cost_n < cost) {
        improved = true;
        for (int i = 0; i < 6; ++i) q[i] = qn[i];
        J = Jn;
        e = en;
        cost = cost_n;
        err_m = em;
        err_rad = er;
      }
    }
    if (!improved) return;
  }
}

void clear(IkSolutions& out) {
  for (int r = 0; r < IkSolutions::kMax; ++r) {
    for (int j = 0; j < 6; ++j) out.q[r][j] = 0.0;
    out.branch[r] = 0;
    out.singular_at[r] = 0;
    out.err_m[r] = 0.0;
    out.err_rad[r] = 0.0;
  }
  out.count = 0;
  out.status = IkStatus::invalid_argument;
  out.singular = 0;
  out.dropped_limits = 0;
  out.dropped_accept = 0;
}

[[nodiscard]] IkStatus finish(IkSolutions& out, IkStatus s) {
  out.status = s;
  return s;
}

}  // namespace

const char* to_string(IkStatus s) {
  switch (s) {
    case IkStatus::ok:
      return "ok";
    case IkStatus::singular:
      return "singular";
    case IkStatus::unreachable:
      return "unreachable";
    case IkStatus::invalid_argument:
      return "invalid_argument";
  }
  return "unknown";
}

JointLimits ur5_joint_limits() { return JointLimits{}; }

bool ur5_forward_d(const Ur5Params& p, const double q[6], PoseD& world_T_tool0) {
  for (int i = 0; i < 6; ++i)
    if (!std::isfinite(q[i])) return false;
  Model m;
  load_model(p, m);
  Tf T;
  forward_jacobian(m, q, T, nullptr);
  world_T_tool0.R = T.R;
  world_T_tool0.t = T.t;
  return true;
}

IkStatus ur5_inverse(const Ur5Params& p, const Pose& world_T_tool0, IkSolutions& out, const IkOptions& opt) {
  PoseD T;
  T.R = world_T_tool0.R.cast<double>();
  T.t = world_T_tool0.t.cast<double>();
  return ur5_inverse(p, T, out, opt);
}

IkStatus ur5_inverse(const Ur5Params& p, const PoseD& world_T_tool0, IkSolutions& out, const IkOptions& opt) {
  clear(out);
  Model m;
  load_model(p, m);
  double deviation_m = 0.0;
  if (!options_ok(opt) || !ur_structure_ok(m, deviation_m)) return finish(out, IkStatus::invalid_argument);
  if (!world_T_tool0.t.allFinite() || !rotation_ok(world_T_tool0.R, opt.orthonormal_tol))
    return finish(out, IkStatus::invalid_argument);

  const Tf target{orthonormalize(world_T_tool0.R), world_T_tool0.t};
  const Tf T06 = mul(inverse(m.base), target);
  const Nominal nm = nominal_of(m, deviation_m);

  Shoulder sh;
  if (!shoulder_roots(nm, T06, opt, sh)) return finish(out, IkStatus::unreachable);

  for (int ib = 0; ib < 2; ++ib) {    // shoulder
    for (int jb = 0; jb < 2; ++jb) {  // wrist
      Candidate c[2];
      bool wrist_sing = false;
      const bool reach = solve_pair(nm, T06, sh, ib, jb, opt, c, wrist_sing);
      if (wrist_sing && jb == 1) break;  // the same solution family as jb = 0
      if (!reach) continue;
      for (int kb = 0; kb < 2; ++kb) {  // elbow
        double q[6];
        for (int i = 0; i < 6; ++i) q[i] = c[kb].q[i];
        // Check on the full model; refine where the closed form is not exact for it.
        Tf T;
        double em = 0.0, er = 0.0;
        forward_jacobian(m, q, T, nullptr);
        pose_error(T, target, em, er);
        if (opt.refine_iterations > 0 && (em > opt.refine_above_m || er > opt.refine_above_rad)) {
          Vec6 e;
          residual(T, target, e, em, er);
          refine(m, nm, target, ib, jb, kb, opt, T, e, q, em, er);
        }
        bool finite = std::isfinite(em) && std::isfinite(er);
        for (int i = 0; i < 6; ++i) finite = finite && std::isfinite(q[i]);
        if (!finite || em > opt.accept_m || er > opt.accept_rad) {
          ++out.dropped_accept;
          continue;
        }
        double qw[6];
        bool inside = true;
        for (int i = 0; i < 6; ++i)
          inside = inside && nearest_rep(q[i], 0.0, opt.limits.lower[i], opt.limits.upper[i], qw[i]);
        if (!inside) {
          ++out.dropped_limits;
          continue;
        }
        bool duplicate = false;
        for (int r = 0; r < out.count && !duplicate; ++r) {
          bool same = true;
          for (int i = 0; i < 6; ++i) same = same && angle_diff(out.q[r][i], qw[i]) <= opt.duplicate_tol;
          duplicate = same;
        }
        if (duplicate) continue;
        const int r = out.count;
        for (int i = 0; i < 6; ++i) out.q[r][i] = qw[i];
        out.branch[r] = static_cast<uint8_t>(ib | (jb << 1) | (kb << 2));
        out.err_m[r] = em;
        out.err_rad[r] = er;
        out.singular_at[r] = c[kb].sing;
        out.singular = static_cast<uint8_t>(out.singular | c[kb].sing);
        ++out.count;
      }
    }
  }
  if (out.count == 0) return finish(out, IkStatus::unreachable);
  return finish(out, out.singular != 0 ? IkStatus::singular : IkStatus::ok);
}

IkChoice choose_nearest(const double current[6], const IkSolutions& solutions, const JointLimits& limits,
                        const double* weights) {
  IkChoice best{};
  best.status = IkStatus::invalid_argument;
  best.index = 0;
  for (int i = 0; i < 6; ++i) best.q[i] = 0.0;
  best.distance = 0.0;
  if (current == nullptr || !limits_ok(limits)) return best;
  double w[6];
  for (int i = 0; i < 6; ++i) {
    w[i] = weights != nullptr ? weights[i] : 1.0;
    if (!std::isfinite(current[i]) || !nonneg_finite(w[i])) return best;
  }
  best.status = IkStatus::unreachable;
  const int count = solutions.count < IkSolutions::kMax ? solutions.count : IkSolutions::kMax;
  double best_d2 = 0.0;
  for (int r = 0; r < count; ++r) {
    double q[6];
    double d2 = 0.0;
    bool inside = true;
    for (int i = 0; i < 6 && inside; ++i) {
      const double x = solutions.q[r][i];
      inside = std::isfinite(x) && nearest_rep(x, current[i], limits.lower[i], limits.upper[i], q[i]);
      if (inside) d2 += w[i] * (q[i] - current[i]) * (q[i] - current[i]);
    }
    if (!inside) continue;
    if (best.status != IkStatus::ok || d2 < best_d2) {
      best.status = IkStatus::ok;
      best.index = static_cast<uint8_t>(r);
      for (int i = 0; i < 6; ++i) best.q[i] = q[i];
      best_d2 = d2;
    }
  }
  best.distance = std::sqrt(best_d2);
  return best;
}

IkChoice choose_nearest(const double current[6], const IkSolutions& solutions) {
  return choose_nearest(current, solutions, ur5_joint_limits(), nullptr);
}

}  // namespace fg::robot
