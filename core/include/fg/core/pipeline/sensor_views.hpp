// What each depth sensor saw (the ingest stage's record, read by the viewpoints and
// the checks): its pose and, per direction bin, its nearest return. A point of space
// is then seen free (a return lies behind it), hidden (a return lies in front of it
// and no sensor saw through) or unknown (no sensor looked there).
#pragma once
#include <cstdint>

#include "fg/core/limits.hpp"
#include "fg/core/types.hpp"

namespace fg {

enum class SensorRole : uint8_t { head = 0, hand = 1 };

//! Visibility of a point of space (SensorViews::visibility).
enum class Sight : int8_t { hidden = -1, unknown = 0, seen_free = 1 };

struct SensorViews {
  bool added[kMaxSensors] = {};
  Vec3 origin[kMaxSensors];  //!< world
  Pose pose[kMaxSensors];    //!< world_T_sensor
  //! The nearest return (mm) per direction bin over x/z, y/z in [-1, 1) (a 90 deg
  //! cone), kSightBins x kSightBins row by row, 0xFFFF where nothing returned.
  uint16_t sight_mm[kMaxSensors][kSightBins * kSightBins];

  //! No sensor added.
  void clear();
  //! Sensor r starts its view from `world_T_sensor` (its sight map emptied).
  void begin(uint32_t r, const Pose& world_T_sensor);
  bool any() const;
  bool both() const { return added[0] && added[1]; }
  //! Returns within kSightMargin of q neither free nor hide it.
  Sight visibility(const Vec3& q) const;
  //! Sensor r saw a return more than kSightMargin in front of q, along q's ray: true,
  //! with that return's point (world) in `hit`.
  [[nodiscard]] bool hidden_by(uint32_t r, const Vec3& q, Vec3& hit) const;

  //! Metres: a return this close to a point neither frees nor hides it (voxel
  //! centroids and sensor noise).
  static constexpr float kSightMargin = 0.01f;
};

}  // namespace fg
