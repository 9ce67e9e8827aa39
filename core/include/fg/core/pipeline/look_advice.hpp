// After a refusal for occlusion: which sensor would have to look where. The hidden
// space that turned the first candidate refused for occlusion down (its open fingers'
// samples no sensor saw, where the target could be solid) is seen from beyond it, looking back
// at it over the target: from above and from the far side of that space, away from the
// target's centre, so that the target itself does not stand in the way.
#pragma once

#include "fg/core/pipeline/sensor_views.hpp"
#include "fg/core/types.hpp"

namespace fg {

struct LookAdvice {
  bool valid = false;
  SensorRole sensor = SensorRole::hand;  //!< the sensor that turns least to get there
  Vec3 at = Vec3::Zero();                //!< the hidden space's centre (world)
  Vec3 from = Vec3::Zero();              //!< where that sensor would look from (world)
};

//! The elevation of the advised view above the support plane: a sensor looks down on a
//! table-top scene, and from 45 deg the ray to a point beside the target passes above
//! the target's near side rather than through it.
inline constexpr float kLookElevationRad = 0.7853982f;

//! hidden: the hidden space's centre; centre: the target's centroid; up: the support
//! plane's upward unit normal. The view keeps the chosen sensor's distance to `hidden`.
//! Invalid without a sensor.
[[nodiscard]] LookAdvice advise_look(const Vec3& hidden, const Vec3& centre, const Vec3& up,
                                     const SensorViews& sensors);

}  // namespace fg
