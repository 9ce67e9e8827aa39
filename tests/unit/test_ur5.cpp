// UR5 forward kinematics against the URDF facts published in shared/data/README.md
// (tool0 at q = 0) and against an independent chain built from the URDF joint origins.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "fg/robot/ur5.hpp"

namespace {
// The URDF chain written out joint by joint (origin xyz, rpy, axis) from
// ur5_robot.urdf: an oracle independent of the DH table.
Eigen::Isometry3d urdf_tool0(const double q[6]) {
  auto origin = [](double x, double y, double z, double r, double p, double yw) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(x, y, z);
    T.linear() = (Eigen::AngleAxisd(yw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(p, Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(r, Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
    return T;
  };
  auto rot = [](const Eigen::Vector3d& axis, double a) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(a, axis).toRotationMatrix();
    return T;
  };
  const double pi2 = M_PI / 2;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T = T * origin(0, 0, 0.089159, 0, 0, 0) * rot(Eigen::Vector3d::UnitZ(), q[0]);
  T = T * origin(0, 0.13585, 0, 0, pi2, 0) * rot(Eigen::Vector3d::UnitY(), q[1]);
  T = T * origin(0, -0.1197, 0.425, 0, 0, 0) * rot(Eigen::Vector3d::UnitY(), q[2]);
  T = T * origin(0, 0, 0.39225, 0, pi2, 0) * rot(Eigen::Vector3d::UnitY(), q[3]);
  T = T * origin(0, 0.093, 0, 0, 0, 0) * rot(Eigen::Vector3d::UnitZ(), q[4]);
  T = T * origin(0, 0, 0.09465, 0, 0, 0) * rot(Eigen::Vector3d::UnitY(), q[5]);
  T = T * origin(0, 0.0823, 0, -pi2, 0, 0);  // tool0, child of wrist_3_link
  return T;
}
}  // namespace

TEST(Ur5Forward, MatchesPublishedPoseAtZero) {
  const float q[6] = {0, 0, 0, 0, 0, 0};
  fg::Pose T;
  ASSERT_TRUE(fg::robot::ur5_forward(fg::robot::ur5_nominal(), q, T));
  EXPECT_NEAR(T.t.x(), 0.81725f, 1e-5f);
  EXPECT_NEAR(T.t.y(), 0.19145f, 1e-5f);
  EXPECT_NEAR(T.t.z(), -0.005491f, 1e-5f);
}

TEST(Ur5Forward, MatchesUrdfChainOnRandomJoints) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-M_PI, M_PI);
  for (int k = 0; k < 500; ++k) {
    double qd[6];
    float qf[6];
    for (int i = 0; i < 6; ++i) {
      qd[i] = U(rng);
      qf[i] = static_cast<float>(qd[i]);
    }
    fg::Pose T;
    ASSERT_TRUE(fg::robot::ur5_forward(fg::robot::ur5_nominal(), qf, T));
    // Compare with the URDF chain at the same (float-rounded) angles.
    for (int i = 0; i < 6; ++i) qd[i] = qf[i];
    const Eigen::Isometry3d ref = urdf_tool0(qd);
    EXPECT_LT((T.t.cast<double>() - ref.translation()).norm(), 2e-6);
    EXPECT_LT((T.R.cast<double>() - ref.linear()).cwiseAbs().maxCoeff(), 2e-6);
  }
}

TEST(Ur5Forward, RejectsNonFiniteJoints) {
  const float q[6] = {0, NAN, 0, 0, 0, 0};
  fg::Pose T;
  EXPECT_FALSE(fg::robot::ur5_forward(fg::robot::ur5_nominal(), q, T));
}
