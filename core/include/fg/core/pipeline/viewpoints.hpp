// Stage C, viewpoints: virtual object frames turned about an axis through the
// centroid, in families (the paper's arc between the sensors, then the extension's
// circles, algorithm.md C and G). A viewpoint's Z is its approach, X its closing.
#pragma once
#include <cstdint>

#include "fg/core/config.hpp"
#include "fg/core/limits.hpp"
#include "fg/core/pipeline/sensor_views.hpp"
#include "fg/core/pipeline/support_plane.hpp"
#include "fg/core/types.hpp"

namespace fg {

//! Viewpoint families: the paper's arc between the sensors, then (extend_search)
//! the rest of the circle about the principal axis and circles about the other axes,
//! then circles about the support plane's axes (its normal, and the object's major
//! and minor directions along the plane).
enum class ViewFamily : uint8_t {
  sensor_arc = 0,
  full_circle = 1,
  middle_axis = 2,
  minor_axis = 3,
  support_normal = 4,
  support_major = 5,
  support_minor = 6,
};
inline constexpr int kViewFamilies = 7;
//! "sensor_arc", "full_circle", "middle_axis", "minor_axis", "support_normal",
//! "support_major", "support_minor".
const char* to_string(ViewFamily f);

//! One viewpoint, and the summary of its best candidate kept for reports and pictures.
struct ViewRecord {
  ViewFamily family;
  float theta;   //!< rad about the family's axis
  Vec3 X, Y, Z;  //!< the virtual object frame (closing, axis, approach)
  bool has_candidate;
  float beta;  //!< best candidate's beta (when has_candidate)
  float dz;    //!< best candidate's dz
};

struct ViewList {
  ViewRecord views[kMaxViewpoints];
  uint32_t n = 0;
};

//! What the viewpoints are turned about and kept by.
struct ViewContext {
  const PlannerConfig& cfg;
  const SupportPlane& support;
  const SensorViews& sensors;
  const Vec3& centroid;
};

//! One family's circle (or, for sensor_arc, arc) of viewpoints about `axis`, from X0
//! turned by `from` to `to` (rad); with skip_arc, the steps within [arc_from, arc_to]
//! (the arc already searched) are left out. Viewpoints approaching from below, closing
//! too steeply about the support plane's axes, or seen from no sensor are skipped.
//! Appends to `views` while it has room; returns how many were added.
struct FamilySpec {
  ViewFamily family;
  Vec3 axis, X0;
  float from, to;
  bool skip_arc = false;
  float arc_from = 0.f, arc_to = 0.f;
};
uint32_t add_view_family(const ViewContext& ctx, const FamilySpec& spec, ViewList& views);

//! The paper's arc (C): from the hand sensor's direction about Y (theta 0) to the
//! head sensor's, or +-single_sensor_arc with one sensor; from <= to.
void sensor_arc(const ViewContext& ctx, const Vec3& Y, const Vec3& X0, float& from, float& to);

//! The angle, on the circle of viewpoints about `axis` that add_view_family turns from
//! X0, of the circle's steepest approach (straight down the support plane's normal `n`
//! when the axis lies along the plane); false when the circle passes farther than 60 deg
//! from straight down, or one of its steps of `step` lies within half a degree of it.
[[nodiscard]] bool steepest_theta(const Vec3& axis, const Vec3& X0, const Vec3& n, float step, float& theta);

//! Rodrigues: v turned by theta about the unit axis.
Vec3 rotate_about(const Vec3& v, const Vec3& axis_unit, float theta);

}  // namespace fg
