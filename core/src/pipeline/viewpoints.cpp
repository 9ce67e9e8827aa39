// Stage C: viewpoints (viewpoints.hpp).
#include "fg/core/pipeline/viewpoints.hpp"

#include <algorithm>
#include <cmath>

#include "fg/core/constants.hpp"
#include "fg/core/pipeline/object_frame.hpp"

namespace fg {
namespace {
// Approaches pointing up more steeply than this come from below the object: skipped.
constexpr float kMaxApproachUp = 0.5f;
// The families about the support plane's horizontal axes close within 30 deg of it.
constexpr float kSupportClosingSin = 0.5f;
// A circle passing within 60 deg of straight down gets its steepest approach as a
// viewpoint of its own, unless one of its steps lies within half a degree of it.
constexpr float kSteepestReach = 0.5f;  // sin 30 deg: the down vector's part across the axis
constexpr float kSameViewRad = 0.0087f;

// The partial cloud only shows the sides the sensors faced: an approach is allowed
// when it comes from within approach_view_max of some sensor's line of sight, so the
// surfaces the palm and fingers move through were observed.
bool seen_from_a_sensor(const ViewContext& ctx, const Vec3& approach) {
  const float min_cos = std::cos(ctx.cfg.approach_view_max_rad);
  for (uint32_t r = 0; r < kMaxSensors; ++r) {
    if (!ctx.sensors.added[r]) continue;
    const Vec3 sight = ctx.centroid - ctx.sensors.origin[r];
    const float len = sight.norm();
    if (!(len > 1e-6f) || approach.dot(sight) >= min_cos * len) return true;
  }
  return false;
}
}  // namespace

const char* to_string(ViewFamily f) {
  switch (f) {
    case ViewFamily::sensor_arc:
      return "sensor_arc";
    case ViewFamily::full_circle:
      return "full_circle";
    case ViewFamily::middle_axis:
      return "middle_axis";
    case ViewFamily::minor_axis:
      return "minor_axis";
    case ViewFamily::support_normal:
      return "support_normal";
    case ViewFamily::support_major:
      return "support_major";
    case ViewFamily::support_minor:
      return "support_minor";
  }
  return "unknown";
}

Vec3 rotate_about(const Vec3& v, const Vec3& axis_unit, float theta) {
  // Rodrigues for a vector orthogonal or not to the axis.
  const float c = std::cos(theta), s = std::sin(theta);
  return v * c + axis_unit.cross(v) * s + axis_unit * axis_unit.dot(v) * (1.f - c);
}

bool steepest_theta(const Vec3& axis, const Vec3& X0, const Vec3& n, float step, float& theta) {
  const Vec3 down = -n;
  const Vec3 across = down - axis * axis.dot(down);
  if (across.norm() <= kSteepestReach) return false;
  const Vec3 Z0 = X0.cross(axis);
  float th = std::atan2(across.dot(axis.cross(Z0)), across.dot(Z0));
  if (th < 0.f) th += 2.f * kPiF;
  if (std::fabs(std::remainder(th, step)) <= kSameViewRad || th >= 2.f * kPiF - kSameViewRad) return false;
  theta = th;
  return true;
}

void sensor_arc(const ViewContext& ctx, const Vec3& Y, const Vec3& X0, float& from, float& to) {
  if (ctx.sensors.both()) {
    // theta_1: the head sensor's direction about Y, measured from the hand's.
    const Vec3 Z0 = X0.cross(Y);
    const Vec3 zh = orthogonal_from(Y, ctx.sensors.origin[0] - ctx.centroid).cross(Y);
    to = std::atan2(zh.dot(X0), zh.dot(Z0));
    from = 0.f;
  } else {
    from = -ctx.cfg.single_sensor_arc_rad;
    to = ctx.cfg.single_sensor_arc_rad;
  }
  if (to < from) std::swap(from, to);
}

uint32_t add_view_family(const ViewContext& ctx, const FamilySpec& spec, ViewList& views) {
  const ViewFamily fam = spec.family;
  const Vec3& axis = spec.axis;
  const float from = spec.from, to = spec.to;
  const Vec3 Z0 = spec.X0.cross(axis);
  const Plane& plane = ctx.support.plane;
  // The paper's arc at dtheta; the wider families of the extension at their own step.
  const float step = fam == ViewFamily::sensor_arc ? ctx.cfg.dtheta_rad : ctx.cfg.extension_dtheta_rad;
  const uint32_t steps = static_cast<uint32_t>((to - from) / step + 1e-4f);
  const bool circle = fam != ViewFamily::sensor_arc;
  // The arc runs from `from` to exactly `to` (theta_1); circles stop short of 2 pi.
  const bool add_end = !circle && (to - from) - static_cast<float>(steps) * step > 1e-4f;
  uint32_t added = 0;
  for (uint32_t s = 0; s <= steps + (add_end ? 1u : 0u) && views.n < kMaxViewpoints; ++s) {
    const float th = s > steps ? to : from + static_cast<float>(s) * step;
    if (circle && th >= 2.f * kPiF - 1e-4f) break;
    if (spec.skip_arc) {
      const float wrapped = th > kPiF ? th - 2.f * kPiF : th;
      if (wrapped >= spec.arc_from - 1e-4f && wrapped <= spec.arc_to + 1e-4f) continue;
    }
    ViewRecord& v = views.views[views.n];
    v.family = fam;
    v.theta = th;
    v.Y = axis;
    v.X = rotate_about(spec.X0, axis, th);
    v.Z = rotate_about(Z0, axis, th);
    if (v.Z.z() > kMaxApproachUp) continue;  // from below the object
    // About the support plane's horizontal axes: closing within 30 deg of the plane
    // (approaches within 30 deg of top-down). A steeper closing needs a finger under
    // the object, which stands on the plane.
    if ((fam == ViewFamily::support_major || fam == ViewFamily::support_minor) &&
        std::fabs(v.X.dot(plane.n)) > kSupportClosingSin * plane.n.norm())
      continue;
    if (!seen_from_a_sensor(ctx, v.Z)) continue;
    v.has_candidate = false;
    v.beta = v.dz = 0.f;
    ++views.n;
    ++added;
  }
  return added;
}

}  // namespace fg
