#include "fg/core/status.hpp"

namespace fg {

const char* to_string(Status s) {
  switch (s) {
    case Status::ok:
      return "ok";
    case Status::no_grasp:
      return "no_grasp";
    case Status::invalid_argument:
      return "invalid_argument";
    case Status::non_finite:
      return "non_finite";
    case Status::invalid_pose:
      return "invalid_pose";
    case Status::invalid_config:
      return "invalid_config";
    case Status::no_input:
      return "no_input";
    case Status::invalid_sensor:
      return "invalid_sensor";
    case Status::invalid_sequence:
      return "invalid_sequence";
    case Status::sensor_disagreement:
      return "sensor_disagreement";
    case Status::capacity_exceeded:
      return "capacity_exceeded";
    case Status::numeric_failure:
      return "numeric_failure";
    case Status::internal_error:
      return "internal_error";
  }
  return "unknown_status";
}

const char* to_string(NoGraspReason r) {
  switch (r) {
    case NoGraspReason::none:
      return "none";
    case NoGraspReason::no_points:
      return "no_points";
    case NoGraspReason::no_plane:
      return "no_plane";
    case NoGraspReason::no_object:
      return "no_object";
    case NoGraspReason::too_few_points:
      return "too_few_points";
    case NoGraspReason::too_wide:
      return "too_wide";
    case NoGraspReason::no_candidate:
      return "no_candidate";
    case NoGraspReason::collision:
      return "collision";
    case NoGraspReason::unreachable:
      return "unreachable";
    case NoGraspReason::friction:
      return "friction";
    case NoGraspReason::degenerate:
      return "degenerate";
    case NoGraspReason::occluded:
      return "occluded";
  }
  return "unknown_reason";
}

}  // namespace fg
