// Every outcome of the embedded side as a value: 0 is ok, positive values are
// ordinary non-error outcomes, negative values are errors grouped by cause.
// Values are explicit and never reused.
#pragma once
#include <cstdint>

namespace fg {

enum class Status : int32_t {
  ok = 0,
  no_grasp = 1,  //!< valid input, but no grasp fits; see NoGraspReason

  // -100..-199: the caller's input
  invalid_argument = -100,  //!< null pointer, zero size, bad stride, bad enum
  non_finite = -101,        //!< NaN or Inf where a finite number is required
  invalid_pose = -102,      //!< rotation not orthonormal / not right-handed, absurd translation
  invalid_config = -103,    //!< a configuration value out of its documented range
  no_input = -104,          //!< plan() called before any sensor data was added
  invalid_sensor = -105,    //!< unknown sensor role, or the same role added twice
  invalid_sequence = -106,  //!< a call out of order (sensor data added after plan() without reset())
  //! the two sensors' clouds disagree after the registration (RegistrationMode::strict)
  sensor_disagreement = -107,

  // -200..-299: capacity
  capacity_exceeded = -200,  //!< more data than the build configuration holds

  // -300..-399: numerics
  numeric_failure = -300,  //!< a computation produced a non-finite result

  // -900: bugs
  internal_error = -900,
};

//! Why a valid input produced no grasp.
enum class NoGraspReason : int32_t {
  none = 0,
  no_points = 1,       //!< nothing left after the range filter and crop box
  no_plane = 2,        //!< no support plane was found
  no_object = 3,       //!< nothing stands on the support plane
  too_few_points = 4,  //!< the target cluster is too small to analyse
  too_wide = 5,        //!< the object is wider than the opening from every viewpoint
  no_candidate = 6,    //!< no candidate passed the force-balance filters
  collision = 7,       //!< every candidate hit the support plane or another object
  unreachable = 8,     //!< every candidate failed inverse kinematics
  friction = 9,        //!< every candidate's contact normals lay outside the friction cone
  degenerate = 10,     //!< the object cloud has no defined principal axis
  occluded = 11,       //!< every candidate put a finger where no sensor looked (see the object from elsewhere)
};

const char* to_string(Status s);
const char* to_string(NoGraspReason r);

}  // namespace fg
