// UR URDF -> DH parameters (urdf_ur5.hpp). The ur_description layout: every joint
// frame keeps the base orientation except the shoulder_lift and wrist_1 origins,
// turned +90 deg about y; the arm's lengths sit on single axes of the joint origins.
#include "urdf/urdf_ur5.hpp"

#include <urdf_parser/urdf_parser.h>

#include <cmath>
#include <exception>

namespace fg::host {
namespace {

constexpr double kTol = 1e-6;
constexpr double kHalfPi = 1.5707963267948966;

struct Expect {
  const char* name;
  double axis[3];
  double rpy[3];
};

// The six joints in order, with the axis and origin rotation the layout gives them.
const Expect kJoints[6] = {
    {"shoulder_pan_joint", {0, 0, 1}, {0, 0, 0}}, {"shoulder_lift_joint", {0, 1, 0}, {0, kHalfPi, 0}},
    {"elbow_joint", {0, 1, 0}, {0, 0, 0}},        {"wrist_1_joint", {0, 1, 0}, {0, kHalfPi, 0}},
    {"wrist_2_joint", {0, 0, 1}, {0, 0, 0}},      {"wrist_3_joint", {0, 1, 0}, {0, 0, 0}},
};

bool near(double a, double b) { return std::fabs(a - b) <= kTol; }

}  // namespace

bool read_ur5_urdf(const std::string& path, robot::Ur5Params& out, std::string& error) {
  urdf::ModelInterfaceSharedPtr model;
  try {
    model = urdf::parseURDFFile(path);
  } catch (const std::exception& e) {
    error = path + ": " + e.what();
    return false;
  }
  if (!model) {
    error = path + ": not a readable URDF (missing file or malformed XML)";
    return false;
  }
  urdf::Vector3 origin[6];
  for (int i = 0; i < 6; ++i) {
    const urdf::JointConstSharedPtr j = model->getJoint(kJoints[i].name);
    if (!j) {
      error = path + ": no joint '" + kJoints[i].name + "' (not a UR arm in the ur_description layout)";
      return false;
    }
    if (j->type != urdf::Joint::REVOLUTE && j->type != urdf::Joint::CONTINUOUS) {
      error = path + ": joint '" + kJoints[i].name + "' is not revolute";
      return false;
    }
    double r = 0, p = 0, y = 0;
    j->parent_to_joint_origin_transform.rotation.getRPY(r, p, y);
    const urdf::Vector3& ax = j->axis;
    if (!near(ax.x, kJoints[i].axis[0]) || !near(ax.y, kJoints[i].axis[1]) || !near(ax.z, kJoints[i].axis[2]) ||
        !near(r, kJoints[i].rpy[0]) || !near(p, kJoints[i].rpy[1]) || !near(y, kJoints[i].rpy[2])) {
      error =
          path + ": joint '" + kJoints[i].name + "' has another axis or origin rotation than the ur_description layout";
      return false;
    }
    origin[i] = j->parent_to_joint_origin_transform.position;
  }
  const urdf::JointConstSharedPtr tool = model->getJoint("wrist_3_link-tool0_fixed_joint");
  if (!tool) {
    error = path + ": no joint 'wrist_3_link-tool0_fixed_joint' (the flange frame tool0)";
    return false;
  }
  const urdf::Vector3& t = tool->parent_to_joint_origin_transform.position;
  // Offsets the DH table cannot hold must be zero.
  const bool zeros = near(origin[0].x, 0) && near(origin[0].y, 0) && near(origin[1].x, 0) && near(origin[1].z, 0) &&
                     near(origin[2].x, 0) && near(origin[3].x, 0) && near(origin[3].y, 0) && near(origin[4].x, 0) &&
                     near(origin[4].z, 0) && near(origin[5].x, 0) && near(origin[5].y, 0) && near(t.x, 0) &&
                     near(t.z, 0);
  if (!zeros) {
    error = path + ": a joint origin has an offset the DH table of the layout cannot express";
    return false;
  }
  robot::Ur5Params p = robot::ur5_nominal();  // twists, zero offsets and the base turn
  const double d[6] = {origin[0].z, 0, 0, origin[1].y + origin[2].y + origin[4].y, origin[5].z, t.y};
  const double a[6] = {0, -origin[2].z, -origin[3].z, 0, 0, 0};
  for (int i = 0; i < 6; ++i) {
    p.d[i] = static_cast<float>(d[i]);
    p.a[i] = static_cast<float>(a[i]);
  }
  out = p;
  return true;
}

}  // namespace fg::host
