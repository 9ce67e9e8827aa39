// A depth camera's pinhole model: what a depth image needs to become points, shared
// by the planner's ingest and the HAL's depth frames.
#pragma once

namespace fg {

//! Focal lengths and principal point in pixels (defaults: a 640x480 Kinect-class sensor).
struct PinholeIntrinsics {
  float fx = 525.f, fy = 525.f, cx = 319.5f, cy = 239.5f;
};

}  // namespace fg
