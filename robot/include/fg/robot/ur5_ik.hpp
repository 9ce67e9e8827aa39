// UR5 analytic inverse kinematics for the embedded side (no heap, no exceptions, no
// RTTI, every loop bounded by a constant). Same frames and the same parameter struct
// as the forward kinematics of ur5.hpp: the target is world_T_tool0 (world = URDF
// base_link), and the solutions are the joint angles q (shoulder_pan .. wrist_3) that
// ur5_forward() maps onto it.
//
// Arithmetic: double throughout (the float Ur5Params are read as double; see
// ur5_forward_d() for the one rounding it undoes). For the nominal UR5 the answers
// meet the target to ~1e-15 m; see docs/robot.md.
//
// Closed form: Hawkins, "Analytic Inverse Kinematics for the Universal Robots
// UR-5/UR-10 Arms" (2013), the same branches as ur_kinematics' inverse(). It assumes the
// nominal UR structure: joints 2-4 parallel (alpha = pi/2, 0, 0, pi/2, -pi/2, 0) and
// a1 = a4 = a5 = a6 = 0 (d2 + d3 fold into d4). Calibrated parameters that deviate from
// that structure (a few mm on a1/a4/a5/a6, a fraction of a degree on alpha) make the
// closed form a starting point only: every branch is then refined, in a bounded number
// of steps, on the full forward kinematics (one virtual-target step, then Gauss-Newton
// with a line search). Every answer is checked on the full FK before it is returned.
#pragma once
#include <cstdint>

#include "fg/core/types.hpp"
#include "fg/robot/ur5.hpp"

namespace fg::robot {

//! Outcome of an IK call. fg::Status (core/status.hpp) has no `unreachable` or
//! `singular`, hence this small enum.
enum class IkStatus : uint8_t {
  ok = 0,                //!< count >= 1 solutions, none at a singularity
  singular = 1,          //!< count >= 1 valid solutions, at least one of them at a wrist,
                         //!< shoulder or elbow singularity (IkSolutions::singular_at)
  unreachable = 2,       //!< count == 0: outside the workspace, or no solution within
                         //!< the joint limits / the acceptance tolerance
  invalid_argument = 3,  //!< non-finite pose, non-orthonormal or reflected rotation,
                         //!< bad parameters (non-finite, not UR-like), bad limits/options
};
const char* to_string(IkStatus s);

//! Solutions carry usable joints for ok and singular.
inline bool ik_has_solution(IkStatus s) { return s == IkStatus::ok || s == IkStatus::singular; }

constexpr double kUr5TwoPi = 6.283185307179586;

//! Joint limits in radians (lower <= upper, finite). Default: the URDF's +-2pi.
struct JointLimits {
  double lower[6] = {-kUr5TwoPi, -kUr5TwoPi, -kUr5TwoPi, -kUr5TwoPi, -kUr5TwoPi, -kUr5TwoPi};
  double upper[6] = {kUr5TwoPi, kUr5TwoPi, kUr5TwoPi, kUr5TwoPi, kUr5TwoPi, kUr5TwoPi};
};

//! The URDF limits of ur_description's ur5_robot.urdf (+-2pi on every joint).
JointLimits ur5_joint_limits();

//! Rigid transform in double (a_T_b: p_a = R p_b + t).
struct PoseD {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
};

//! Bits of IkSolutions::singular and singular_at.
enum IkSingularity : uint8_t {
  kIkShoulder = 1,  //!< wrist centre p5 on the cylinder |p5_xy| = d2 + d3 + d4 about the
                    //!< base axis (in the arm's plane: on the base axis): the two q1
                    //!< roots coincide (double root, duplicates removed)
  kIkElbow = 2,     //!< arm fully stretched or folded (q3 = 0 or pi): elbow branches coincide
  kIkWrist = 4,     //!< sin q5 = 0: wrist 1 and wrist 3 parallel, q6 free: set to
                    //!< IkOptions::wrist_free_q6, or, where the arm cannot reach with
                    //!< that, to the nearest q6 it reaches with (10% of the reachable
                    //!< range inside); q2, q3, q4 absorb the rest
};

struct IkOptions {
  JointLimits limits{};
  //! acos/asin arguments (shoulder, elbow) may exceed +-1 by this much and are clamped;
  //! beyond it the branch does not exist (unreachable).
  double reach_tol = 1e-9;
  //! Two shoulder or elbow roots closer than this (rad, half their distance) are a
  //! double root: a shoulder / elbow singularity. (acos-type roots carry ~1e-7 rad of
  //! rounding at the fold, hence not smaller.)
  double singular_tol = 1e-6;
  //! |sin q5| below this is the wrist singularity (q5 comes from an atan2 of the
  //! orientation and is accurate to ~1e-15 there).
  double wrist_singular_tol = 1e-9;
  //! q6 at the wrist singularity (the free joint). Pass the current q6 so the wrist
  //! does not spin. Used as given (then wrapped into the limits) when the arm reaches
  //! with it; see kIkWrist.
  double wrist_free_q6 = 0.0;
  //! Two solutions within this (rad, on every joint, modulo 2pi) are one.
  double duplicate_tol = 1e-6;
  //! Max |(R^T R - I)_ij| accepted for the target rotation; det must be > 0.
  double orthonormal_tol = 1e-5;
  //! Refinement on the full FK: a branch whose residual exceeds refine_above_m (m) or
  //! refine_above_rad (rad) gets at most refine_iterations steps (0 = closed form
  //! only; step 1 is a virtual-target step, the rest Gauss-Newton with a line search of
  //! at most 6 trials: a branch costs at most 3 + 6 (refine_iterations - 1) FK
  //! evaluations, 45 for 8, so a call at most 360),
  //! stopping once both errors are below refine_stop_m / refine_stop_rad. The closed
  //! form is exact (~1e-15) for the nominal structure, so that is never refined.
  uint8_t refine_iterations = 8;
  double refine_above_m = 1e-10;
  double refine_above_rad = 1e-10;
  double refine_stop_m = 1e-12;
  double refine_stop_rad = 1e-12;
  //! A solution is returned only if FK(q) meets the target within these.
  double accept_m = 1e-6;
  double accept_rad = 1e-6;
};

//! Up to 8 solutions in branch order, each joint wrapped into the joint limits (the
//! value in [-pi, pi], or, if that lies outside the limits, the nearest value
//! +- 2pi k inside; choose_nearest() picks the representation near the current joint).
//! Rows [count, 8) are zero.
struct IkSolutions {
  static constexpr uint8_t kMax = 8;
  double q[kMax][6];
  uint8_t count;
  IkStatus status;
  uint8_t singular;           //!< IkSingularity bits of all returned solutions
  uint8_t singular_at[kMax];  //!< IkSingularity bits of each solution
  uint8_t branch[kMax];       //!< bit 0: second q1 root, bit 1: q5 < 0 root,
                              //!< bit 2: q3 < 0 root (of the closed form)
  double err_m[kMax];         //!< |t_FK(q) - t_target| (m), after refinement
  double err_rad[kMax];       //!< rotation angle of R_target^T R_FK(q) (rad)
  uint8_t dropped_limits;     //!< branches found but with a joint outside the limits
  uint8_t dropped_accept;     //!< branches that did not meet accept_m / accept_rad
};

//! All solutions for world_T_tool0 (out.status is the return value). Never writes NaN;
//! deterministic. Stack: about 5 KB deep (gcc -fstack-usage, x86-64, -O3).
[[nodiscard]] IkStatus ur5_inverse(const Ur5Params& p, const PoseD& world_T_tool0, IkSolutions& out,
                                   const IkOptions& opt = IkOptions{});
//! Same, from the float pose of fg::Pose (its rotation is re-orthonormalised in double).
[[nodiscard]] IkStatus ur5_inverse(const Ur5Params& p, const Pose& world_T_tool0, IkSolutions& out,
                                   const IkOptions& opt = IkOptions{});

//! world_T_tool0 in double for double joints: the chain of ur5_forward(), and the model
//! the IK solves. One difference: a twist alpha within 1e-6 rad of a multiple of pi/2
//! is taken as exactly that (float cannot hold pi/2: ur5_nominal()'s alphas are
//! 4.4e-8 rad off, the URDF's 1.570796325 is 1.8e-9 off), and a base rotation within
//! 1e-5 of orthonormal is re-orthonormalised; for the nominal UR5 the two differ by
//! <= 5e-8 m and 1.3e-7 rad. Returns false (out untouched) if any q is non-finite.
[[nodiscard]] bool ur5_forward_d(const Ur5Params& p, const double q[6], PoseD& world_T_tool0);

struct IkChoice {
  IkStatus status;  //!< ok, unreachable (no solution inside the limits) or invalid_argument
  uint8_t index;    //!< row of the chosen solution in IkSolutions
  double q[6];      //!< the chosen solution, each joint the representation q + 2pi k
                    //!< inside the limits nearest the current joint
  double distance;  //!< sqrt(sum w_i (q_i - current_i)^2)
};

//! The solution nearest `current` in weighted joint space (weights null: all 1),
//! every joint taken in its representation (+- 2pi k) nearest the current joint that
//! lies inside `limits`. Ties go to the lower row. Never NaN.
IkChoice choose_nearest(const double current[6], const IkSolutions& solutions, const JointLimits& limits,
                        const double* weights = nullptr);
//! Same with ur5_joint_limits() and unit weights.
IkChoice choose_nearest(const double current[6], const IkSolutions& solutions);

}  // namespace fg::robot
