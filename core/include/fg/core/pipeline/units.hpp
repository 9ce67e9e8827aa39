// Stage A.1, the units of a sensor's points: a cloud whose every point failed the range
// filter is read at the other units a cloud is written in (millimetres, centimetres,
// metres, kilometres); where most of its depths lie within the range read so, the cloud
// was given in those units and the caller hears so, instead of "no points". Depth
// images carry their millimetres explicitly and are not asked.
#pragma once
#include <cstdint>

namespace fg {

//! Depths (the sensor frame's z) of a sample of the points that failed the range filter,
//! spread over the whole cloud: at most kUnitSamples, and no verdict on fewer than
//! kUnitSamplesNeeded (a handful of stray points say nothing of a cloud's units).
inline constexpr uint32_t kUnitSamples = 64;
inline constexpr uint32_t kUnitSamplesNeeded = 16;

//! When none of a sensor's points passed the range filter: a static message naming the
//! units the sampled depths `depth` (n of them, in the units given, `metres_per_unit`)
//! were likely written in, or naming an absurd scale; null when they say nothing of
//! units (the sensor saw only what lies beyond its range), or when n < kUnitSamplesNeeded.
//! Another unit is named when
//! at least half the depths lie within [range_min_m, range_max_m] read in it; an absurd
//! scale when every depth lies more than 100 times beyond the range, or 100 times under it.
const char* units_mistake(const float* depth, uint32_t n, float range_min_m, float range_max_m, float metres_per_unit);

}  // namespace fg
