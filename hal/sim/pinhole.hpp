// The simulated camera's intrinsics as the planner takes them (add_depth_image).
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

}  // namespace fg::sim
