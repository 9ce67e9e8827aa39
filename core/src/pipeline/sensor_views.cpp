// What each sensor saw: the visibility test of sensor_views.hpp.
#include "fg/core/pipeline/sensor_views.hpp"

namespace fg {

void SensorViews::clear() {
  for (uint32_t r = 0; r < kMaxSensors; ++r) {
    added[r] = false;
    origin[r] = Vec3::Zero();
  }
}

void SensorViews::begin(uint32_t r, const Pose& world_T_sensor) {
  added[r] = true;
  origin[r] = world_T_sensor.t;
  pose[r] = world_T_sensor;
  for (uint32_t i = 0; i < kSightBins * kSightBins; ++i) sight_mm[r][i] = 0xFFFFu;
}

bool SensorViews::any() const {
  for (uint32_t r = 0; r < kMaxSensors; ++r)
    if (added[r]) return true;
  return false;
}

bool SensorViews::hidden_by(uint32_t r, const Vec3& q, Vec3& hit) const {
  if (r >= kMaxSensors || !added[r]) return false;
  const float half = 0.5f * static_cast<float>(kSightBins);
  const Vec3 p = pose[r].R.transpose() * (q - pose[r].t);
  if (!(p.z() > 0.05f)) return false;
  const float bu = (p.x() / p.z() + 1.f) * half, bv = (p.y() / p.z() + 1.f) * half;
  if (!(bu >= 0.f && bv >= 0.f && bu < 2.f * half && bv < 2.f * half)) return false;
  const uint16_t d = sight_mm[r][static_cast<uint32_t>(bv) * kSightBins + static_cast<uint32_t>(bu)];
  if (d == 0xFFFFu) return false;
  const float seen_m = static_cast<float>(d) * 0.001f;
  if (!(seen_m < p.z() - kSightMargin)) return false;
  hit = pose[r].apply(p * (seen_m / p.z()));
  return true;
}

Sight SensorViews::visibility(const Vec3& q) const {
  Sight result = Sight::unknown;
  const float half = 0.5f * static_cast<float>(kSightBins);
  for (uint32_t r = 0; r < kMaxSensors; ++r) {
    if (!added[r]) continue;
    const Vec3 p = pose[r].R.transpose() * (q - pose[r].t);
    if (!(p.z() > 0.05f)) continue;
    const float bu = (p.x() / p.z() + 1.f) * half, bv = (p.y() / p.z() + 1.f) * half;
    if (!(bu >= 0.f && bv >= 0.f && bu < 2.f * half && bv < 2.f * half)) continue;
    const uint16_t d = sight_mm[r][static_cast<uint32_t>(bv) * kSightBins + static_cast<uint32_t>(bu)];
    if (d == 0xFFFFu) continue;
    const float seen_m = static_cast<float>(d) * 0.001f;
    if (seen_m > p.z() + kSightMargin) return Sight::seen_free;
    if (seen_m < p.z() - kSightMargin) result = Sight::hidden;
  }
  return result;
}

}  // namespace fg
