// Stage A.1, the units of a sensor's points (units.hpp).
#include "fg/core/pipeline/units.hpp"

namespace fg {

namespace {
struct Unit {
  float metres;
  const char* message;
};
// The units clouds are written in, each with what the caller is told.
constexpr Unit kUnits[] = {
    {0.001f,
     "every finite point lies outside the depth range, and read as millimetres most lie within it: the cloud is "
     "likely in millimetres (give metres, or the sensor's units: mm)"},
    {0.01f,
     "every finite point lies outside the depth range, and read as centimetres most lie within it: the cloud is "
     "likely in centimetres (give metres, or the sensor's units: cm)"},
    {1.f,
     "every finite point lies outside the depth range, and read as metres most lie within it: the cloud is likely in "
     "metres (give the sensor's units: m)"},
    {1000.f,
     "every finite point lies outside the depth range, and read as kilometres most lie within it: the cloud's "
     "coordinates are likely 1000 times too small"},
};
}  // namespace

const char* units_mistake(const float* depth, uint32_t n, float range_min_m, float range_max_m, float metres_per_unit) {
  if (depth == nullptr || n < kUnitSamplesNeeded) return nullptr;
  const float n_f = static_cast<float>(n);
  for (const Unit& u : kUnits) {
    const float ratio = u.metres / metres_per_unit;
    if (ratio > 0.5f && ratio < 2.f) continue;  // the units given
    uint32_t inside = 0;
    for (uint32_t i = 0; i < n; ++i) {
      const float m = depth[i] * u.metres;
      inside += m >= range_min_m && m <= range_max_m ? 1u : 0u;
    }
    if (2.f * static_cast<float>(inside) >= n_f) return u.message;
  }
  uint32_t far = 0, near = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const float m = depth[i] * metres_per_unit;
    far += m > 100.f * range_max_m ? 1u : 0u;
    near += m < 0.01f * range_min_m ? 1u : 0u;
  }
  if (far == n || near == n)
    return "every finite point's depth lies more than 100 times outside the depth range: the cloud's units or scale "
           "are wrong (metres expected)";
  return nullptr;
}

}  // namespace fg
