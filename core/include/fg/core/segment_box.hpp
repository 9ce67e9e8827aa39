// Does a segment meet an axis-aligned box? The slab test: the segment's parameter
// interval is cut by each axis's pair of planes. Used by the planner to ask whether the
// space under a target point (a vertical segment down to the support plane, in the
// grasp frame) reaches into a finger's sweep.
#pragma once

#include <algorithm>
#include <cmath>

namespace fg {

//! True when some point q - u * dir with u in [u0, u1] lies in the box [lo, hi]
//! (touching counts). An axis along which dir is below 1e-6 in magnitude is tested as
//! parallel: q itself must lie within that axis's slab. False when u0 > u1.
inline bool segment_meets_box(const float q[3], const float dir[3], float u0, float u1, const float lo[3],
                              const float hi[3]) {
  for (int a = 0; a < 3 && u0 <= u1; ++a) {
    if (std::fabs(dir[a]) < 1e-6f) {
      if (q[a] < lo[a] || q[a] > hi[a]) return false;
      continue;
    }
    const float ua = (q[a] - hi[a]) / dir[a], ub = (q[a] - lo[a]) / dir[a];
    u0 = std::max(u0, std::min(ua, ub));
    u1 = std::min(u1, std::max(ua, ub));
  }
  return u0 <= u1;
}

}  // namespace fg
