// Stage B, the object frame: the target's centroid and principal axes (paper eq. 2),
// and the support plane's frame about it (the extension's families, algorithm.md G).
#pragma once
#include <cstdint>

#include "fg/core/config.hpp"
#include "fg/core/pipeline/sensor_views.hpp"
#include "fg/core/pipeline/support_plane.hpp"
#include "fg/core/point_buffer.hpp"
#include "fg/core/types.hpp"

namespace fg {

struct ObjectFrame {
  Vec3 centroid = Vec3::Zero();
  //! Y (the principal axis, snapped to vertical for upright and round bodies), then
  //! the middle and minor PCA axes made orthogonal to it.
  Vec3 axes[3];
  Vec3 X0;  //!< the paper's X = normalize(Sp x Y): closing of the hand sensor's view
};

//! False when the points have no defined principal axis (all identical, too few).
[[nodiscard]] bool build_object_frame(const PointSpan& pts, const SensorViews& sensors, const PlannerConfig& cfg,
                                      ObjectFrame& out);

//! The support plane's frame: its upward normal, then the object's major and minor
//! directions along it (PCA of the points projected onto the plane), right-handed.
//! False without a plane or when the projection is round to float precision.
[[nodiscard]] bool support_axes(const PointSpan& pts, const Vec3& centroid, const SupportPlane& support, Vec3 axes[3]);

//! The sides of the smallest-area rectangle about the target's footprint on the plane
//! (Freeman and Shapira: it has a side along a hull edge): foot[0] the normal, foot[1]
//! along the longer side. `proj` (pts.size() entries) and `hull` (kMaxContourVertices)
//! are scratch. False when the hull is degenerate or too large to search.
[[nodiscard]] bool footprint_axes(const PointSpan& pts, const Vec3& centroid, const Vec3 sup[3], Vec2* proj, Vec2* hull,
                                  Vec3 foot[3]);

//! A unit vector orthogonal to `axis`, from `hint` (hint x axis), with fall-backs.
Vec3 orthogonal_from(const Vec3& axis, const Vec3& hint);

}  // namespace fg
