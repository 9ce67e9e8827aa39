// The simulated camera as the planner takes it (add_depth_image).
#pragma once
#include "fg/core/planner.hpp"
#include "sim/depth_render.hpp"

namespace fg::sim {

inline fg::PinholeIntrinsics to_pinhole(const Intrinsics& k) {
  fg::PinholeIntrinsics p;
  p.fx = static_cast<float>(k.fx);
  p.fy = static_cast<float>(k.fy);
  p.cx = static_cast<float>(k.cx);
  p.cy = static_cast<float>(k.cy);
  return p;
}

//! One rendered camera's depth image handed to the planner as `role`.
[[nodiscard]] inline fg::Status add_rendered(fg::Planner& planner, fg::SensorRole role, const DepthImage& img,
                                             const Camera& cam) {
  return planner.add_depth_image(role, img.mm.data(), static_cast<uint16_t>(img.width),
                                 static_cast<uint16_t>(img.height), to_pinhole(cam.K), cam.world_T_sensor.to_pose());
}

}  // namespace fg::sim
