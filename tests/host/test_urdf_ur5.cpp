// The UR5 read from its URDF through urdfdom (platform/host/urdf): the parameters equal
// the published DH table, the forward kinematics with them equals the URDF's own joint
// chain composed from urdfdom's transforms (the oracle), and files that are missing,
// malformed or of another layout are refused with a message naming the problem.
#include <gtest/gtest.h>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>

#include "fg/robot/ur5.hpp"
#include "urdf/urdf_ur5.hpp"

namespace {

const std::string kUrdf = std::string(FG_SHARED_DIR) + "/data/robots/ur5/urdf/ur5_robot.urdf";

Eigen::Isometry3d to_iso(const urdf::Pose& p) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z).toRotationMatrix();
  t.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  return t;
}

// base_link -> tool0 through urdfdom's joints, each origin then a turn about its axis.
Eigen::Isometry3d chain(const urdf::ModelInterface& m, const double q[6]) {
  const char* names[6] = {"shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint",
                          "wrist_1_joint",      "wrist_2_joint",       "wrist_3_joint"};
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 6; ++i) {
    const urdf::JointConstSharedPtr j = m.getJoint(names[i]);
    const Eigen::Vector3d axis(j->axis.x, j->axis.y, j->axis.z);
    t = t * to_iso(j->parent_to_joint_origin_transform) * Eigen::AngleAxisd(q[i], axis.normalized());
  }
  return t * to_iso(m.getJoint("wrist_3_link-tool0_fixed_joint")->parent_to_joint_origin_transform);
}

TEST(UrdfUr5, ParametersAreThePublishedTable) {
  fg::robot::Ur5Params p;
  std::string err;
  ASSERT_TRUE(fg::host::read_ur5_urdf(kUrdf, p, err)) << err;
  const fg::robot::Ur5Params n = fg::robot::ur5_nominal();
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(p.d[i], n.d[i], 1e-6) << "d" << i + 1;
    EXPECT_NEAR(p.a[i], n.a[i], 1e-6) << "a" << i + 1;
    EXPECT_EQ(p.alpha[i], n.alpha[i]);
  }
}

TEST(UrdfUr5, ForwardKinematicsEqualsTheUrdfChain) {
  fg::robot::Ur5Params p;
  std::string err;
  ASSERT_TRUE(fg::host::read_ur5_urdf(kUrdf, p, err)) << err;
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDFFile(kUrdf);
  ASSERT_TRUE(model);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-3.1, 3.1);
  for (int k = 0; k < 500; ++k) {
    double q[6];
    float qf[6];
    for (int i = 0; i < 6; ++i) qf[i] = static_cast<float>(q[i] = u(rng));
    for (int i = 0; i < 6; ++i) q[i] = qf[i];
    fg::Pose fk;
    ASSERT_TRUE(fg::robot::ur5_forward(p, qf, fk));
    const Eigen::Isometry3d ref = chain(*model, q);
    EXPECT_LT((fk.t.cast<double>() - ref.translation()).norm(), 2e-6) << "pose " << k;
    EXPECT_LT((fk.R.cast<double>() - ref.linear()).cwiseAbs().maxCoeff(), 2e-6) << "pose " << k;
  }
}

TEST(UrdfUr5, RefusesWhatItCannotRead) {
  fg::robot::Ur5Params p = fg::robot::ur5_nominal();
  std::string err;
  EXPECT_FALSE(fg::host::read_ur5_urdf("/nonexistent/ur5.urdf", p, err));
  EXPECT_NE(err.find("/nonexistent/ur5.urdf"), std::string::npos) << err;

  const std::string dir = ::testing::TempDir();
  const std::string bad_xml = dir + "/fg_bad.urdf";
  std::ofstream(bad_xml) << "<robot name='x'><link name='a'/><joint";
  err.clear();
  EXPECT_FALSE(fg::host::read_ur5_urdf(bad_xml, p, err));
  EXPECT_NE(err.find(bad_xml), std::string::npos) << err;

  // Another layout: the elbow turned about x instead of y.
  std::ifstream in(kUrdf);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string elbow = "<joint name=\"elbow_joint\" type=\"revolute\">";
  const size_t at = text.find(elbow);
  ASSERT_NE(at, std::string::npos);
  const size_t axis = text.find("<axis xyz=\"0 1 0\"/>", at);
  ASSERT_NE(axis, std::string::npos);
  text.replace(axis, 19, "<axis xyz=\"1 0 0\"/>");
  const std::string other = dir + "/fg_other_layout.urdf";
  std::ofstream(other) << text;
  err.clear();
  EXPECT_FALSE(fg::host::read_ur5_urdf(other, p, err));
  EXPECT_NE(err.find("elbow_joint"), std::string::npos) << err;
  // Nothing of a refused file reaches the output.
  const fg::robot::Ur5Params n = fg::robot::ur5_nominal();
  for (int i = 0; i < 6; ++i) EXPECT_EQ(p.d[i], n.d[i]);
}

}  // namespace
