// Small fixed-size math types shared by every layer (Eigen, fixed size only).
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products
#include <Eigen/LU>        // 3x3 determinant
#include <cstdint>

namespace fg {

using Vec3 = Eigen::Vector3f;
using Mat3 = Eigen::Matrix3f;

//! A 2D point in a silhouette plane (metres).
struct Vec2 {
  float x;
  float y;
};

//! Rigid transform a_T_b: a point p in frame b is R p + t in frame a.
struct Pose {
  Mat3 R = Mat3::Identity();
  Vec3 t = Vec3::Zero();
  Vec3 apply(const Vec3& p) const { return R * p + t; }
};

}  // namespace fg
