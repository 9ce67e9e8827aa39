// UR5 inverse kinematics against independent oracles: the forward kinematics (every
// solution must map back onto the target, the generating joints must be among the
// solutions), the URDF file itself (its joint chain parsed here, not the DH table),
// perturbed "calibrated" parameters, and constructed singular / invalid inputs.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "fg/core/constants.hpp"
#include "fg/core/prng.hpp"
#include "fg/robot/ur5.hpp"
#include "fg/robot/ur5_ik.hpp"

using fg::robot::IkChoice;
using fg::robot::IkOptions;
using fg::robot::IkSolutions;
using fg::robot::IkStatus;
using fg::robot::JointLimits;
using fg::robot::PoseD;
using fg::robot::Ur5Params;

namespace {

using fg::kPi;
constexpr double kTwoPi = 2.0 * kPi;

double uniform(fg::Prng& rng, double lo, double hi) {
  const double u = static_cast<double>(rng.next() >> 11) * (1.0 / 9007199254740992.0);
  return lo + (hi - lo) * u;
}

void random_q(fg::Prng& rng, double q[6], double range = kTwoPi) {
  for (int i = 0; i < 6; ++i) q[i] = uniform(rng, -range, range);
}

double rot_angle(const Eigen::Matrix3d& A, const Eigen::Matrix3d& B) {
  return std::fabs(Eigen::AngleAxisd(Eigen::Matrix3d(A.transpose() * B)).angle());
}

struct Err {
  double m;
  double rad;
};

Err pose_err(const PoseD& a, const PoseD& b) { return {(a.t - b.t).norm(), rot_angle(a.R, b.R)}; }

PoseD fk(const Ur5Params& p, const double q[6]) {
  PoseD T;
  EXPECT_TRUE(fg::robot::ur5_forward_d(p, q, T));
  return T;
}

double max_diff_mod_2pi(const double* a, const double* b) {
  double m = 0.0;
  for (int i = 0; i < 6; ++i) m = std::fmax(m, std::fabs(std::remainder(a[i] - b[i], kTwoPi)));
  return m;
}

//! Row index of the solution equal to q modulo 2pi, or -1.
int find_solution(const IkSolutions& s, const double q[6], double tol) {
  for (int r = 0; r < s.count; ++r)
    if (max_diff_mod_2pi(s.q[r], q) <= tol) return r;
  return -1;
}

bool all_finite(const IkSolutions& s) {
  for (int r = 0; r < IkSolutions::kMax; ++r)
    for (int i = 0; i < 6; ++i)
      if (!std::isfinite(s.q[r][i])) return false;
  return true;
}

bool within_limits(const IkSolutions& s, const JointLimits& L) {
  for (int r = 0; r < s.count; ++r)
    for (int i = 0; i < 6; ++i)
      if (s.q[r][i] < L.lower[i] || s.q[r][i] > L.upper[i]) return false;
  return true;
}

//! Every returned solution maps back onto T; returns the worst error.
Err check_all(const Ur5Params& p, const PoseD& T, const IkSolutions& s) {
  Err worst{0.0, 0.0};
  for (int r = 0; r < s.count; ++r) {
    const Err e = pose_err(fk(p, s.q[r]), T);
    worst.m = std::fmax(worst.m, e.m);
    worst.rad = std::fmax(worst.rad, e.rad);
  }
  return worst;
}

//! The wrist centre's distance from the base axis within the arm's plane (nominal UR5,
//! world = base turned by pi): 0 at the shoulder singularity.
double shoulder_inplane(const Ur5Params& p, const double q[6]) {
  const PoseD T = fk(p, q);
  const Eigen::Vector3d p5 = T.t - static_cast<double>(p.d[5]) * T.R.col(2);
  return p5.x() * std::cos(q[0] + kPi) + p5.y() * std::sin(q[0] + kPi);
}

//! How far q is from the nearest singularity (dimensionless, 1 = far): |sin q3|
//! (elbow), |sin q5| (wrist), the shoulder in-plane distance over 0.3 m.
double singularity_distance(const Ur5Params& p, const double q[6]) {
  const double d = std::fmin(std::fabs(std::sin(q[2])), std::fabs(std::sin(q[4])));
  return std::fmin(1.0, std::fmin(d, std::fabs(shoulder_inplane(p, q)) / 0.3));
}

//! The joints are fixed by the pose only as well as the pose is known: a target that
//! is off by eps (another model, float rounding) moves the joints by ~eps / distance
//! near a singularity. Tolerance for "the generating q is among the solutions".
double joint_tolerance(const Ur5Params& p, const double q[6], double floor, double eps) {
  return std::fmax(floor, eps / std::fmax(singularity_distance(p, q), 1e-6));
}

// ---------------------------------------------------------------------------------
// The URDF chain read from shared/data/robots/ur5/urdf/ur5_robot.urdf (a tiny parser
// for this one file's joint elements: origin xyz/rpy, axis, parent, child, limits).
struct UrdfJoint {
  std::string name, type, parent, child;
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero(), rpy = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();
  double lower = 0.0, upper = 0.0;
};

std::string attr(const std::string& tag, const std::string& name) {
  const std::string key = " " + name + "=\"";
  const size_t at = tag.find(key);
  if (at == std::string::npos) return "";
  const size_t from = at + key.size();
  return tag.substr(from, tag.find('"', from) - from);
}

std::string first_tag(const std::string& body, const std::string& name) {
  const size_t at = body.find("<" + name + " ");
  if (at == std::string::npos) return "";
  return body.substr(at, body.find('>', at) - at + 1);
}

Eigen::Vector3d vec3(const std::string& s, const Eigen::Vector3d& dflt) {
  if (s.empty()) return dflt;
  std::istringstream in(s);
  Eigen::Vector3d v;
  in >> v.x() >> v.y() >> v.z();
  return v;
}

//! base_link -> tool0, in chain order; empty if the file is missing.
std::vector<UrdfJoint> load_urdf_chain(const std::string& path) {
  std::ifstream f(path);
  if (!f) return {};
  std::stringstream ss;
  ss << f.rdbuf();
  const std::string xml = ss.str();
  std::map<std::string, UrdfJoint> by_child;
  for (size_t at = xml.find("<joint "); at != std::string::npos; at = xml.find("<joint ", at + 1)) {
    const std::string tag = xml.substr(at, xml.find('>', at) - at + 1);
    UrdfJoint j;
    j.name = attr(tag, "name");
    j.type = attr(tag, "type");
    if (j.type.empty()) continue;  // a <joint> reference inside <transmission>
    const size_t end = xml.find("</joint>", at);
    const std::string body = xml.substr(at, end - at);
    j.parent = attr(first_tag(body, "parent"), "link");
    j.child = attr(first_tag(body, "child"), "link");
    const std::string origin = first_tag(body, "origin");
    j.xyz = vec3(attr(origin, "xyz"), Eigen::Vector3d::Zero());
    j.rpy = vec3(attr(origin, "rpy"), Eigen::Vector3d::Zero());
    j.axis = vec3(attr(first_tag(body, "axis"), "xyz"), Eigen::Vector3d::UnitX());
    const std::string limit = first_tag(body, "limit");
    if (!limit.empty()) {
      j.lower = std::stod(attr(limit, "lower"));
      j.upper = std::stod(attr(limit, "upper"));
    }
    by_child[j.child] = j;
  }
  std::vector<UrdfJoint> chain;
  std::string link = "tool0";
  for (int guard = 0; guard < 64 && link != "base_link"; ++guard) {
    auto it = by_child.find(link);
    if (it == by_child.end()) return {};
    chain.insert(chain.begin(), it->second);
    link = it->second.parent;
  }
  return link == "base_link" ? chain : std::vector<UrdfJoint>{};
}

//! base_link_T_tool0 through the parsed chain; q feeds the revolute joints in order.
PoseD urdf_fk(const std::vector<UrdfJoint>& chain, const double q[6]) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  int k = 0;
  for (const UrdfJoint& j : chain) {
    Eigen::Isometry3d O = Eigen::Isometry3d::Identity();
    O.translation() = j.xyz;
    O.linear() = (Eigen::AngleAxisd(j.rpy.z(), Eigen::Vector3d::UnitZ()) *
                  Eigen::AngleAxisd(j.rpy.y(), Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(j.rpy.x(), Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
    T = T * O;
    if (j.type == "revolute" || j.type == "continuous") {
      Eigen::Isometry3d Rj = Eigen::Isometry3d::Identity();
      Rj.linear() = Eigen::AngleAxisd(q[k++], j.axis.normalized()).toRotationMatrix();
      T = T * Rj;
    }
  }
  PoseD P;
  P.R = T.linear();
  P.t = T.translation();
  return P;
}

const std::string kUrdfPath = std::string(FG_SHARED_DIR) + "/data/robots/ur5/urdf/ur5_robot.urdf";

//! Random calibration-like deviations: 5-15 mm on every a and d, 0.1-0.5 deg on every
//! alpha and joint offset, each with a random sign.
Ur5Params perturbed(fg::Prng& rng) {
  Ur5Params p = fg::robot::ur5_nominal();
  auto signed_in = [&](double lo, double hi) {
    const double v = uniform(rng, lo, hi);
    return (rng.next() & 1u) ? v : -v;
  };
  const double deg = kPi / 180.0;
  for (int i = 0; i < 6; ++i) {
    p.a[i] += static_cast<float>(signed_in(0.005, 0.015));
    p.d[i] += static_cast<float>(signed_in(0.005, 0.015));
    p.alpha[i] += static_cast<float>(signed_in(0.1 * deg, 0.5 * deg));
    p.theta_offset[i] += static_cast<float>(signed_in(0.1 * deg, 0.5 * deg));
  }
  return p;
}

}  // namespace

// ---------------------------------------------------------------------------------

TEST(Ur5Ik, DoubleForwardMatchesFloatForward) {
  const Ur5Params p = fg::robot::ur5_nominal();
  fg::Prng rng(11);
  for (int k = 0; k < 1000; ++k) {
    double qd[6];
    float qf[6];
    random_q(rng, qd);
    for (int i = 0; i < 6; ++i) {
      qf[i] = static_cast<float>(qd[i]);
      qd[i] = qf[i];
    }
    fg::Pose Tf;
    ASSERT_TRUE(fg::robot::ur5_forward(p, qf, Tf));
    const PoseD Td = fk(p, qd);
    EXPECT_LT((Tf.t.cast<double>() - Td.t).norm(), 1e-6);
    EXPECT_LT((Tf.R.cast<double>() - Td.R).cwiseAbs().maxCoeff(), 1e-6);
  }
  const double bad[6] = {0, 0, NAN, 0, 0, 0};
  PoseD T;
  EXPECT_FALSE(fg::robot::ur5_forward_d(p, bad, T));
}

TEST(Ur5Ik, RoundTripOnTenThousandRandomPoses) {
  const Ur5Params p = fg::robot::ur5_nominal();
  fg::Prng rng(2024);
  int histogram[9] = {0};
  int found = 0, singular = 0;
  Err worst{0.0, 0.0};
  double worst_found = 0.0;
  for (int k = 0; k < 10000; ++k) {
    double q[6];
    random_q(rng, q);
    const PoseD T = fk(p, q);
    IkSolutions s;
    const IkStatus st = fg::robot::ur5_inverse(p, T, s);
    ASSERT_TRUE(st == IkStatus::ok || st == IkStatus::singular) << k << " " << to_string(st);
    EXPECT_EQ(st, s.status);
    singular += st == IkStatus::singular;
    ASSERT_GE(s.count, 1);
    ASSERT_LE(s.count, 8);
    ++histogram[s.count];
    EXPECT_TRUE(all_finite(s));
    EXPECT_TRUE(within_limits(s, JointLimits{}));
    const Err e = check_all(p, T, s);
    worst.m = std::fmax(worst.m, e.m);
    worst.rad = std::fmax(worst.rad, e.rad);
    EXPECT_LT(e.m, 1e-6) << k;
    EXPECT_LT(e.rad, 1e-6) << k;
    for (int r = 0; r < s.count; ++r) {
      EXPECT_LE(s.err_m[r], 1e-6);
      for (int r2 = 0; r2 < r; ++r2) EXPECT_GT(max_diff_mod_2pi(s.q[r], s.q[r2]), 1e-6);
    }
    const int at = find_solution(s, q, 1e-6);
    if (at >= 0) {
      ++found;
      worst_found = std::fmax(worst_found, max_diff_mod_2pi(s.q[at], q));
    }
  }
  std::printf("solution counts:");
  for (int c = 1; c <= 8; ++c) std::printf(" %d:%d", c, histogram[c]);
  std::printf("\nworst FK(IK) error %.3g m, %.3g rad; generating q found %d/10000 (worst %.3g rad); singular %d\n",
              worst.m, worst.rad, found, worst_found, singular);
  EXPECT_EQ(found, 10000);
  EXPECT_EQ(singular, 0);
  // Generic poses have 8 solutions; the rest are poses where one shoulder branch
  // cannot reach with its elbow (|c3| > 1): always an even count (4 or 6).
  EXPECT_GT(histogram[8], 5000);
  for (int c = 1; c <= 7; c += 2) EXPECT_EQ(histogram[c], 0) << c;
}

TEST(Ur5Ik, FloatPoseOverloadMeetsFloatTarget) {
  const Ur5Params p = fg::robot::ur5_nominal();
  fg::Prng rng(5);
  for (int k = 0; k < 500; ++k) {
    double q[6];
    float qf[6];
    random_q(rng, q);
    for (int i = 0; i < 6; ++i) qf[i] = static_cast<float>(q[i]);
    fg::Pose T;
    ASSERT_TRUE(fg::robot::ur5_forward(p, qf, T));
    IkSolutions s;
    ASSERT_TRUE(fg::robot::ik_has_solution(fg::robot::ur5_inverse(p, T, s)));
    for (int r = 0; r < s.count; ++r) {
      const PoseD Tq = fk(p, s.q[r]);
      EXPECT_LT((Tq.t - T.t.cast<double>()).norm(), 1e-6);
      EXPECT_LT((Tq.R - T.R.cast<double>()).cwiseAbs().maxCoeff(), 1e-6);
    }
    // The float pose is ~6e-8 m / 1e-7 rad off the exact one.
    for (int i = 0; i < 6; ++i) q[i] = qf[i];
    EXPECT_GE(find_solution(s, q, joint_tolerance(p, q, 1e-5, 2e-6)), 0) << k;
  }
}

TEST(Ur5Ik, ChooseNearestReturnsGeneratingJoints) {
  const Ur5Params p = fg::robot::ur5_nominal();
  fg::Prng rng(99);
  for (int k = 0; k < 10000; ++k) {
    double q[6], current[6];
    random_q(rng, q, kTwoPi - 0.01);
    for (int i = 0; i < 6; ++i) current[i] = q[i] + uniform(rng, -1e-3, 1e-3);
    IkSolutions s;
    ASSERT_TRUE(fg::robot::ik_has_solution(fg::robot::ur5_inverse(p, fk(p, q), s)));
    const IkChoice c = fg::robot::choose_nearest(current, s);
    ASSERT_EQ(c.status, IkStatus::ok);
    ASSERT_LT(c.index, s.count);
    for (int i = 0; i < 6; ++i) EXPECT_NEAR(c.q[i], q[i], 1e-6) << k << " joint " << i;
    EXPECT_LT(c.distance, 3e-3);
  }
}

TEST(Ur5Ik, ChooseNearestPicksRepresentationNearCurrentAndHonoursLimits) {
  IkSolutions s{};
  s.count = 2;
  s.status = IkStatus::ok;
  const double a[6] = {-3.0, 0.5, 1.0, -1.0, 0.2, 6.0};
  const double b[6] = {1.0, -2.0, -1.0, 1.0, -0.2, 0.0};
  for (int i = 0; i < 6; ++i) {
    s.q[0][i] = a[i];
    s.q[1][i] = b[i];
  }
  // Near row 0, with joint 1 across the +-pi seam and joint 6 taken near 0.
  const double cur[6] = {3.2, 0.5, 1.0, -1.0, 0.2, 0.1};
  IkChoice c = fg::robot::choose_nearest(cur, s);
  ASSERT_EQ(c.status, IkStatus::ok);
  EXPECT_EQ(c.index, 0);
  EXPECT_NEAR(c.q[0], -3.0 + kTwoPi, 1e-12);
  EXPECT_NEAR(c.q[5], 6.0 - kTwoPi, 1e-12);

  // Limits that keep joint 1 within [-pi/2, pi/2] leave only row 1 (q1 = 1.0).
  JointLimits L;
  L.lower[0] = -kPi / 2;
  L.upper[0] = kPi / 2;
  c = fg::robot::choose_nearest(cur, s, L);
  ASSERT_EQ(c.status, IkStatus::ok);
  EXPECT_EQ(c.index, 1);
  EXPECT_NEAR(c.q[0], 1.0, 1e-12);

  // Weights: with unit weights row 1 (off only in joint 2) wins; weighting joint 2
  // alone makes row 0 (exact in joint 2) win.
  const double cur2[6] = {1.0, 0.5, -1.0, 1.0, -0.2, 0.0};  // row 1 except joint 2
  const double w_all[6] = {1, 1, 1, 1, 1, 1};
  const double w_j2[6] = {0, 1, 0, 0, 0, 0};
  EXPECT_EQ(fg::robot::choose_nearest(cur2, s, JointLimits{}, w_all).index, 1);
  EXPECT_EQ(fg::robot::choose_nearest(cur2, s, JointLimits{}, w_j2).index, 0);

  // Nothing inside the limits.
  JointLimits none;
  none.lower[4] = 0.3;
  none.upper[4] = 0.4;
  c = fg::robot::choose_nearest(cur, s, none);
  EXPECT_EQ(c.status, IkStatus::unreachable);
  for (double v : c.q) EXPECT_TRUE(std::isfinite(v));

  // Invalid input.
  const double nan_cur[6] = {0, NAN, 0, 0, 0, 0};
  EXPECT_EQ(fg::robot::choose_nearest(nan_cur, s).status, IkStatus::invalid_argument);
  const double neg_w[6] = {1, 1, -1, 1, 1, 1};
  EXPECT_EQ(fg::robot::choose_nearest(cur, s, JointLimits{}, neg_w).status, IkStatus::invalid_argument);
  JointLimits inverted;
  inverted.lower[2] = 1.0;
  inverted.upper[2] = -1.0;
  EXPECT_EQ(fg::robot::choose_nearest(cur, s, inverted).status, IkStatus::invalid_argument);
  IkSolutions empty{};
  EXPECT_EQ(fg::robot::choose_nearest(cur, empty).status, IkStatus::unreachable);
}

TEST(Ur5Ik, RestrictiveJointLimitsAreRespected) {
  const Ur5Params p = fg::robot::ur5_nominal();
  IkOptions opt;
  // A typical table-top configuration space: shoulder lift up, elbow one side.
  opt.limits.lower[0] = -kPi;
  opt.limits.upper[0] = kPi;
  opt.limits.lower[1] = -kPi;
  opt.limits.upper[1] = 0.0;
  opt.limits.lower[2] = 0.0;
  opt.limits.upper[2] = kPi;
  for (int i = 3; i < 6; ++i) {
    opt.limits.lower[i] = -kPi;
    opt.limits.upper[i] = kPi;
  }
  fg::Prng rng(3);
  int with_q = 0, dropped = 0;
  for (int k = 0; k < 2000; ++k) {
    double q[6];
    for (int i = 0; i < 6; ++i) q[i] = uniform(rng, opt.limits.lower[i], opt.limits.upper[i]);
    const PoseD T = fk(p, q);
    IkSolutions s;
    const IkStatus st = fg::robot::ur5_inverse(p, T, s, opt);
    ASSERT_TRUE(fg::robot::ik_has_solution(st));
    EXPECT_TRUE(within_limits(s, opt.limits));
    EXPECT_LT(check_all(p, T, s).m, 1e-6);
    with_q += find_solution(s, q, 1e-6) >= 0;
    dropped += s.dropped_limits;
  }
  EXPECT_EQ(with_q, 2000);
  EXPECT_GT(dropped, 0);

  // Limits that no solution of this pose meets: unreachable, nothing written.
  const double q0[6] = {0.3, -1.0, 1.2, -0.5, 1.0, 0.4};
  IkOptions tight;
  tight.limits.lower[4] = 2.0;
  tight.limits.upper[4] = 2.1;
  IkSolutions s;
  EXPECT_EQ(fg::robot::ur5_inverse(p, fk(p, q0), s, tight), IkStatus::unreachable);
  EXPECT_EQ(s.count, 0);
  EXPECT_GT(s.dropped_limits, 0);
  EXPECT_TRUE(all_finite(s));
}

// --- singularities ----------------------------------------------------------------

TEST(Ur5Ik, WristSingularityGivesStatusAndFreeJointChoice) {
  const Ur5Params p = fg::robot::ur5_nominal();
  fg::Prng rng(17);
  int wrist_rows = 0, kept_zero = 0;
  for (int k = 0; k < 200; ++k) {
    double q[6];
    random_q(rng, q, kPi);
    q[4] = (k % 2 == 0) ? 0.0 : kPi;  // wrist 1 and wrist 3 axes parallel
    const PoseD T = fk(p, q);
    IkOptions opt;
    opt.wrist_free_q6 = q[5];  // the documented choice: the caller's current q6
    IkSolutions s;
    ASSERT_EQ(fg::robot::ur5_inverse(p, T, s, opt), IkStatus::singular) << k;
    EXPECT_TRUE(s.singular & fg::robot::kIkWrist);
    ASSERT_GE(s.count, 1);
    EXPECT_LE(s.count, 6);  // the two wrist branches of the singular shoulder root coincide
    EXPECT_TRUE(all_finite(s));
    const Err e = check_all(p, T, s);
    EXPECT_LT(e.m, 1e-6);
    EXPECT_LT(e.rad, 1e-6);
    int free_rows = 0;
    for (int r = 0; r < s.count; ++r) {
      if (!(s.singular_at[r] & fg::robot::kIkWrist)) continue;  // the other shoulder root
      ++free_rows;
      EXPECT_NEAR(std::remainder(s.q[r][5] - q[5], kTwoPi), 0.0, 1e-9);
    }
    EXPECT_GE(free_rows, 1);
    EXPECT_GE(find_solution(s, q, 1e-6), 0) << k;

    // Default choice q6 = 0: still valid (q2, q3, q4 take up the rest), or, where the
    // arm cannot reach with q6 = 0, another q6 it reaches with.
    IkSolutions s0;
    ASSERT_EQ(fg::robot::ur5_inverse(p, T, s0), IkStatus::singular) << k;
    for (int r = 0; r < s0.count; ++r) {
      if (!(s0.singular_at[r] & fg::robot::kIkWrist)) continue;
      ++wrist_rows;
      kept_zero += std::fabs(s0.q[r][5]) < 1e-12;
    }
    EXPECT_LT(check_all(p, T, s0).m, 1e-6);
    EXPECT_LT(check_all(p, T, s0).rad, 1e-6);
    EXPECT_TRUE(all_finite(s0));
  }
  std::printf("wrist singular, default q6 = 0: kept in %d of %d rows\n", kept_zero, wrist_rows);
  EXPECT_GT(kept_zero, wrist_rows / 2);
}

TEST(Ur5Ik, WristSingularityMovesTheFreeJointWhenTheArmCannotReachWithIt) {
  // Nearly stretched arms with q5 = 0, asked for q6 + pi: that swings the wrist centre's
  // d5 offset about, often beyond the arm's reach; q6 then moves as little as it must.
  const Ur5Params p = fg::robot::ur5_nominal();
  fg::Prng rng(61);
  int moved = 0, rows = 0;
  for (int k = 0; k < 100; ++k) {
    double q[6];
    random_q(rng, q, kPi);
    q[2] = uniform(rng, -0.3, 0.3);
    q[4] = 0.0;
    const PoseD T = fk(p, q);
    IkOptions opt;
    opt.wrist_free_q6 = q[5] + kPi;
    IkSolutions s;
    ASSERT_EQ(fg::robot::ur5_inverse(p, T, s, opt), IkStatus::singular) << k;
    for (int r = 0; r < s.count; ++r) {
      if (!(s.singular_at[r] & fg::robot::kIkWrist)) continue;
      ++rows;
      const double d = std::fabs(std::remainder(s.q[r][5] - opt.wrist_free_q6, kTwoPi));
      if (d > 1e-9) {
        ++moved;
        // The moved q6 is reachable: asking for it returns it unchanged.
        IkOptions again = opt;
        again.wrist_free_q6 = s.q[r][5];
        IkSolutions s2;
        ASSERT_EQ(fg::robot::ur5_inverse(p, T, s2, again), IkStatus::singular);
        EXPECT_GE(find_solution(s2, s.q[r], 1e-9), 0);
      }
    }
    EXPECT_LT(check_all(p, T, s).m, 1e-9);
    EXPECT_LT(check_all(p, T, s).rad, 1e-9);
    EXPECT_TRUE(all_finite(s));
  }
  std::printf("q6 + pi asked: moved in %d of %d wrist-singular rows\n", moved, rows);
  EXPECT_GE(moved, 5);
}

namespace {
// The wrist centre p5 = p - d6 z_tool0; the shoulder singularity is |p5_xy| = d4 (the
// UR's shoulder offset d2 + d3 + d4 = 0.10915 m): within the arm's plane the wrist
// centre lies on the base z-axis. (On the base z-axis itself it is out of reach.)
double shoulder_gap(const Ur5Params& p, const double q[6]) {
  const PoseD T = fk(p, q);
  const Eigen::Vector3d p5 = T.t - static_cast<double>(p.d[5]) * T.R.col(2);
  return std::hypot(p5.x(), p5.y()) - static_cast<double>(p.d[1] + p.d[2] + p.d[3]);
}
}  // namespace

TEST(Ur5Ik, ShoulderSingularityGivesStatusNeverNaN) {
  const Ur5Params p = fg::robot::ur5_nominal();
  fg::Prng rng(23);
  int tested = 0;
  for (int k = 0; k < 400 && tested < 50; ++k) {
    double q[6];
    random_q(rng, q, kPi);
    q[4] = uniform(rng, 0.3, 2.8);
    // Find q2 that puts the wrist centre on the base axis within the arm's plane (a
    // sign change of the in-plane distance over a bracket, then bisection).
    auto inplane = [&](double q2) {
      const double qq[6] = {q[0], q2, q[2], q[3], q[4], q[5]};
      return shoulder_inplane(p, qq);
    };
    double lo = -kPi, hi = 0.0;
    bool bracket = false;
    for (int t = 0; t < 64 && !bracket; ++t) {
      const double x0 = -kPi + t * (kTwoPi / 64), x1 = x0 + kTwoPi / 64;
      if (inplane(x0) * inplane(x1) < 0) {
        lo = x0;
        hi = x1;
        bracket = true;
      }
    }
    if (!bracket) continue;
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      (inplane(lo) * inplane(mid) <= 0 ? hi : lo) = mid;
    }
    q[1] = 0.5 * (lo + hi);
    ASSERT_LT(std::fabs(shoulder_gap(p, q)), 1e-9);
    ++tested;
    const PoseD T = fk(p, q);
    IkSolutions s;
    const IkStatus st = fg::robot::ur5_inverse(p, T, s);
    ASSERT_EQ(st, IkStatus::singular) << k;
    EXPECT_TRUE(s.singular & fg::robot::kIkShoulder);
    EXPECT_LE(s.count, 4);  // the two shoulder roots coincide
    ASSERT_GE(s.count, 1);
    EXPECT_TRUE(all_finite(s));
    const Err e = check_all(p, T, s);
    EXPECT_LT(e.m, 1e-6);
    EXPECT_LT(e.rad, 1e-6);
    EXPECT_GE(find_solution(s, q, 1e-5), 0) << k;
  }
  EXPECT_GE(tested, 20);
}

TEST(Ur5Ik, StretchedArmGivesStatusNeverNaN) {
  const Ur5Params p = fg::robot::ur5_nominal();
  fg::Prng rng(29);
  for (int k = 0; k < 200; ++k) {
    double q[6];
    random_q(rng, q, kPi);
    q[4] = uniform(rng, 0.3, 2.8);
    q[2] = 0.0;  // fully stretched (elbow straight)
    const PoseD T = fk(p, q);
    IkSolutions s;
    const IkStatus st = fg::robot::ur5_inverse(p, T, s);
    ASSERT_EQ(st, IkStatus::singular) << k;
    EXPECT_TRUE(s.singular & fg::robot::kIkElbow);
    ASSERT_GE(s.count, 1);
    EXPECT_TRUE(all_finite(s));
    const Err e = check_all(p, T, s);
    EXPECT_LT(e.m, 1e-6);
    EXPECT_LT(e.rad, 1e-6);
    EXPECT_GE(find_solution(s, q, 1e-5), 0) << k;
  }
  // q = 0: stretched and q5 = 0 at once (the zero pose of the URDF).
  const double zero[6] = {0, 0, 0, 0, 0, 0};
  IkSolutions s;
  ASSERT_EQ(fg::robot::ur5_inverse(p, fk(p, zero), s), IkStatus::singular);
  EXPECT_EQ(s.singular & (fg::robot::kIkElbow | fg::robot::kIkWrist), fg::robot::kIkElbow | fg::robot::kIkWrist);
  EXPECT_TRUE(all_finite(s));
  EXPECT_LT(check_all(p, fk(p, zero), s).m, 1e-6);
  EXPECT_GE(find_solution(s, zero, 1e-5), 0);
}

// --- unreachable and invalid -------------------------------------------------------

TEST(Ur5Ik, UnreachablePosesGiveStatusNeverNaN) {
  const Ur5Params p = fg::robot::ur5_nominal();
  fg::Prng rng(31);
  for (int k = 0; k < 500; ++k) {
    PoseD T;
    const Eigen::Vector3d axis =
        Eigen::Vector3d(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)).normalized();
    T.R = Eigen::AngleAxisd(uniform(rng, -kPi, kPi), axis).toRotationMatrix();
    const Eigen::Vector3d dir =
        Eigen::Vector3d(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)).normalized();
    T.t = 2.0 * dir;  // 2 m away: the UR5 reaches ~0.95 m
    IkSolutions s;
    EXPECT_EQ(fg::robot::ur5_inverse(p, T, s), IkStatus::unreachable);
    EXPECT_EQ(s.count, 0);
    EXPECT_TRUE(all_finite(s));
  }
  // Wrist centre on the base z-axis: inside the shoulder offset cylinder |p5_xy| < d4.
  PoseD T;
  T.R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  T.t = Eigen::Vector3d(0, 0, 0.5) + static_cast<double>(p.d[5]) * T.R.col(2);
  IkSolutions s;
  EXPECT_EQ(fg::robot::ur5_inverse(p, T, s), IkStatus::unreachable);
  EXPECT_TRUE(all_finite(s));
}

TEST(Ur5Ik, InvalidPosesAndParametersGiveStatus) {
  const Ur5Params p = fg::robot::ur5_nominal();
  const double q[6] = {0.3, -1.0, 1.2, -0.5, 1.0, 0.4};
  const PoseD good = fk(p, q);
  IkSolutions s;
  ASSERT_EQ(fg::robot::ur5_inverse(p, good, s), IkStatus::ok);
  EXPECT_EQ(s.count, 8);

  auto expect_invalid = [&](const PoseD& T, const Ur5Params& pp, const IkOptions& opt) {
    IkSolutions out;
    EXPECT_EQ(fg::robot::ur5_inverse(pp, T, out, opt), IkStatus::invalid_argument);
    EXPECT_EQ(out.count, 0);
    EXPECT_EQ(out.status, IkStatus::invalid_argument);
    EXPECT_TRUE(all_finite(out));
  };
  const IkOptions dflt;
  PoseD T = good;
  T.t.x() = NAN;
  expect_invalid(T, p, dflt);
  T = good;
  T.t.z() = INFINITY;
  expect_invalid(T, p, dflt);
  T = good;
  T.R(1, 2) = NAN;
  expect_invalid(T, p, dflt);
  T = good;
  T.R(0, 0) = -INFINITY;
  expect_invalid(T, p, dflt);
  T = good;
  T.R *= 1.01;  // scaled
  expect_invalid(T, p, dflt);
  T = good;
  T.R.col(0) += 0.01 * T.R.col(1);  // sheared
  expect_invalid(T, p, dflt);
  T = good;
  T.R.col(2) = -T.R.col(2);  // a reflection, det = -1
  expect_invalid(T, p, dflt);
  T = good;
  T.R.setZero();
  expect_invalid(T, p, dflt);

  Ur5Params bad = p;
  bad.d[3] = NAN;
  expect_invalid(good, bad, dflt);
  bad = p;
  bad.alpha[1] = 1.0f;  // not the UR structure
  expect_invalid(good, bad, dflt);
  bad = p;
  bad.world_T_base.R(0, 0) = 2.0f;
  expect_invalid(good, bad, dflt);
  bad = p;
  bad.a[1] = 0.0f;  // no upper arm
  expect_invalid(good, bad, dflt);

  IkOptions opt;
  opt.limits.lower[0] = 1.0;
  opt.limits.upper[0] = -1.0;
  expect_invalid(good, p, opt);
  opt = IkOptions{};
  opt.limits.upper[3] = INFINITY;
  expect_invalid(good, p, opt);
  opt = IkOptions{};
  opt.wrist_free_q6 = NAN;
  expect_invalid(good, p, opt);
  opt = IkOptions{};
  opt.accept_m = -1.0;
  expect_invalid(good, p, opt);
}

TEST(Ur5Ik, SlightlyNonOrthonormalRotationWithinToleranceIsAccepted) {
  const Ur5Params p = fg::robot::ur5_nominal();
  const double q[6] = {-0.8, -1.9, 1.4, 0.7, -1.2, 2.0};
  PoseD T = fk(p, q);
  PoseD noisy = T;
  noisy.R(0, 1) += 1e-7;  // float-like noise, re-orthonormalised inside
  IkSolutions s;
  ASSERT_EQ(fg::robot::ur5_inverse(p, noisy, s), IkStatus::ok);
  EXPECT_EQ(s.count, 8);
  EXPECT_LT(check_all(p, T, s).m, 1e-6);
  EXPECT_LT(check_all(p, T, s).rad, 1e-6);
  EXPECT_GE(find_solution(s, q, 1e-6), 0);
}

TEST(Ur5Ik, DeterministicAndRowsBeyondCountZero) {
  const Ur5Params p = fg::robot::ur5_nominal();
  fg::Prng rng(41);
  for (int k = 0; k < 200; ++k) {
    double q[6];
    random_q(rng, q);
    const PoseD T = fk(p, q);
    IkSolutions a, b;
    const fg::robot::IkStatus sa = fg::robot::ur5_inverse(p, T, a);
    const fg::robot::IkStatus sb = fg::robot::ur5_inverse(p, T, b);
    ASSERT_EQ(sa, sb);
    ASSERT_EQ(a.count, b.count);
    for (int r = 0; r < IkSolutions::kMax; ++r)
      for (int i = 0; i < 6; ++i) {
        EXPECT_EQ(a.q[r][i], b.q[r][i]);
        if (r >= a.count) {
          EXPECT_EQ(a.q[r][i], 0.0);
        }
      }
  }
}

// --- calibrated parameters --------------------------------------------------------

TEST(Ur5Ik, PerturbedParametersAreRefinedOnTheFullForwardKinematics) {
  // 200 "calibrated" robots x 50 poses made by their own FK. A perturbed UR is a
  // general 6R arm: no closed form, possibly other solution counts; each closed-form
  // branch is refined on the full model (8 steps at most).
  fg::Prng rng(1234);
  int poses = 0, solved = 0, found = 0, sols = 0, sols_1e9 = 0;
  double worst_m = 0.0, worst_rad = 0.0;
  for (int robot = 0; robot < 200; ++robot) {
    const Ur5Params p = perturbed(rng);
    for (int k = 0; k < 50; ++k) {
      double q[6];
      random_q(rng, q);
      const PoseD T = fk(p, q);
      IkSolutions s;
      const IkStatus st = fg::robot::ur5_inverse(p, T, s);
      ++poses;
      solved += fg::robot::ik_has_solution(st);
      EXPECT_TRUE(all_finite(s));
      for (int r = 0; r < s.count; ++r) {
        const Err e = pose_err(fk(p, s.q[r]), T);
        worst_m = std::fmax(worst_m, e.m);
        worst_rad = std::fmax(worst_rad, e.rad);
        EXPECT_LT(e.m, 1e-6);  // the acceptance tolerance
        EXPECT_LT(e.rad, 1e-6);
        EXPECT_NEAR(e.m, s.err_m[r], 1e-12);
        sols_1e9 += e.m < 1e-9 && e.rad < 1e-9;
      }
      sols += s.count;
      found += find_solution(s, q, 1e-6) >= 0;
    }
  }
  std::printf(
      "perturbed: %d poses, solved %d, generating q found %d; %d solutions (mean %.2f), "
      "%d of them < 1e-9 m and rad; worst %.3g m %.3g rad\n",
      poses, solved, found, sols, static_cast<double>(sols) / poses, sols_1e9, worst_m, worst_rad);
  EXPECT_GE(solved, poses * 995 / 1000);
  EXPECT_GE(found, poses * 95 / 100);
  EXPECT_GE(sols_1e9, sols * 998 / 1000);

  // Without refinement the closed form alone misses such a robot by millimetres:
  // nothing meets the 1e-6 acceptance, so the call says unreachable.
  const Ur5Params p = perturbed(rng);
  const double q[6] = {0.3, -1.0, 1.2, -0.5, 1.0, 0.4};
  IkOptions opt;
  opt.refine_iterations = 0;
  IkSolutions s;
  EXPECT_EQ(fg::robot::ur5_inverse(p, fk(p, q), s, opt), IkStatus::unreachable);
  EXPECT_EQ(s.dropped_accept, 8);
  // With it, this generic pose gets all 8, each to < 1e-9 m.
  ASSERT_EQ(fg::robot::ur5_inverse(p, fk(p, q), s), IkStatus::ok);
  EXPECT_EQ(s.count, 8);
  EXPECT_LT(check_all(p, fk(p, q), s).m, 1e-9);
  EXPECT_GE(find_solution(s, q, 1e-9), 0);
}

TEST(Ur5Ik, NominalAnalyticAloneMeetsTheTarget) {
  // The closed form is exact for the nominal structure: no refinement needed.
  const Ur5Params p = fg::robot::ur5_nominal();
  IkOptions opt;
  opt.refine_iterations = 0;
  fg::Prng rng(77);
  for (int k = 0; k < 1000; ++k) {
    double q[6];
    random_q(rng, q);
    const PoseD T = fk(p, q);
    IkSolutions s;
    ASSERT_TRUE(fg::robot::ik_has_solution(fg::robot::ur5_inverse(p, T, s, opt)));
    const Err e = check_all(p, T, s);
    EXPECT_LT(e.m, 1e-12);
    EXPECT_LT(e.rad, 1e-12);
    EXPECT_GE(find_solution(s, q, 1e-6), 0);
  }
}

// --- the URDF file ------------------------------------------------------------------

TEST(Ur5Ik, SolutionsDriveTheUrdfChainOntoTheTarget) {
  const std::vector<UrdfJoint> chain = load_urdf_chain(kUrdfPath);
  if (chain.empty()) GTEST_SKIP() << "no URDF at " << kUrdfPath;
  int revolute = 0;
  for (const UrdfJoint& j : chain) revolute += j.type == "revolute";
  ASSERT_EQ(revolute, 6);
  const JointLimits L = fg::robot::ur5_joint_limits();
  {
    int k = 0;
    for (const UrdfJoint& j : chain) {
      if (j.type != "revolute") continue;
      EXPECT_NEAR(L.lower[k], j.lower, 1e-7) << j.name;
      EXPECT_NEAR(L.upper[k], j.upper, 1e-7) << j.name;
      ++k;
    }
  }
  const Ur5Params p = fg::robot::ur5_nominal();
  fg::Prng rng(555);
  double worst_m = 0.0, worst_rad = 0.0;
  for (int k = 0; k < 300; ++k) {
    double q[6];
    random_q(rng, q);
    const PoseD T = urdf_fk(chain, q);  // the target comes from the URDF, not the DH table
    IkSolutions s;
    ASSERT_TRUE(fg::robot::ik_has_solution(fg::robot::ur5_inverse(p, T, s))) << k;
    for (int r = 0; r < s.count; ++r) {
      const Err e = pose_err(urdf_fk(chain, s.q[r]), T);
      worst_m = std::fmax(worst_m, e.m);
      worst_rad = std::fmax(worst_rad, e.rad);
      EXPECT_LT(e.m, 1e-6);
      EXPECT_LT(e.rad, 1e-6);
    }
    // The URDF writes pi/2 as 1.570796325: its chain is ~2e-8 m off the DH model.
    EXPECT_GE(find_solution(s, q, joint_tolerance(p, q, 1e-6, 2e-7)), 0) << k;
  }
  std::printf("URDF chain: worst %.3g m, %.3g rad over 300 poses\n", worst_m, worst_rad);
}
