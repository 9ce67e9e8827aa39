// Where a sensor would have to look after a refusal for occlusion (look_advice.hpp).
#include "fg/core/pipeline/look_advice.hpp"

#include <cmath>

namespace fg {

LookAdvice advise_look(const Vec3& hidden, const Vec3& centre, const Vec3& up, const SensorViews& sensors) {
  LookAdvice a;
  // Outwards from the target's centre through the hidden space, along the plane.
  Vec3 out = hidden - centre;
  out -= up * up.dot(out);
  if (!(out.norm() > 1e-6f)) {
    // The hidden space right above or below the centre: from the side opposite the
    // sensors that did not see it.
    Vec3 seen = Vec3::Zero();
    for (uint32_t r = 0; r < kMaxSensors; ++r)
      if (sensors.added[r]) seen += sensors.origin[r] - hidden;
    out = -(seen - up * up.dot(seen));
    if (!(out.norm() > 1e-6f)) out = up.unitOrthogonal();
  }
  const Vec3 dir = out.normalized() * std::cos(kLookElevationRad) + up * std::sin(kLookElevationRad);
  // The sensor whose direction from the hidden space lies nearest the advised one.
  float best = -2.f;
  for (uint32_t r = 0; r < kMaxSensors; ++r) {
    if (!sensors.added[r]) continue;
    const Vec3 to = sensors.origin[r] - hidden;
    const float d = to.norm();
    if (!(d > 1e-6f)) continue;
    const float c = to.dot(dir) / d;
    if (c > best) {
      best = c;
      a.valid = true;
      a.sensor = static_cast<SensorRole>(r);
      a.at = hidden;
      a.from = hidden + dir * d;
    }
  }
  return a;
}

}  // namespace fg
