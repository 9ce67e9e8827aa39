// Host-only: the Python values plan() and Planner() take, read into what the planner
// takes. Every problem is refused here, with the Python exception and a message naming
// it, before the core sees the input (TypeError: a wrong kind of value; ValueError: a
// wrong shape, a non-finite or non-rigid pose, an empty array, an unknown key...).
#pragma once
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <cstdint>

#include "fg/core/config.hpp"
#include "fg/core/planner.hpp"

namespace fg::python {
namespace py = pybind11;

const char* role_name(SensorRole role);

//! One sensor's input, read while the GIL is held and handed to the planner while it is
//! released: `held` keeps the array the pointers point into alive (the caller's own
//! array, or the one converted copy).
struct SensorInput {
  SensorRole role = SensorRole::head;
  Pose pose;
  py::array held;
  // Points: point i's x, y, z are floats at xyz + i * stride bytes.
  const float* xyz = nullptr;
  uint32_t count = 0;
  uint32_t stride = 0;
  // Or a depth image: row-major uint16 millimetres, 0 = no return.
  const uint16_t* depth = nullptr;
  uint16_t width = 0, height = 0;
  PinholeIntrinsics intrinsics;
  float units_m = 1.f;  // metres per unit of the points ("units": m, cm, mm)
};

//! A sensor as plan() takes it: a (points, pose) tuple, or a dict {"points" or "depth",
//! "pose", "intrinsics" (depth only), "units" (points only: "m", "cm" or "mm")}.
SensorInput read_sensor(SensorRole role, const py::handle& spec);

//! The arm's current joints: six finite angles (radians, URDF order).
std::array<double, 6> read_joints(const py::handle& joints);

//! The target of plan(target=(x, y, z)) or plan(target_box=(xmin, ymin, zmin, xmax, ymax,
//! zmax)), world frame, metres; both None: the configured rule. TypeError for
//! non-numbers, ValueError (with the status's name) for a wrong count, NaN or Inf, an
//! inverted box, or both given.
TargetSpec read_target(const py::handle& target, const py::handle& target_box);

//! The gripper dict {max_opening, finger_width, finger_depth} over the scene file's
//! defaults, with the scene file's ranges.
void apply_gripper(PlannerConfig& cfg, const py::handle& gripper);

//! The config dict: each option through set_config_option, its value as the text the
//! command line's --set would take.
void apply_config(PlannerConfig& cfg, const py::handle& config);

}  // namespace fg::python
