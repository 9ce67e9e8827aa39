// Stage B: the object frame (object_frame.hpp).
#include "fg/core/pipeline/object_frame.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "fg/core/eigen_sym3.hpp"
#include "fg/core/hull.hpp"
#include "fg/core/limits.hpp"

namespace fg {
namespace {
// A body whose middle PCA eigenvalue is below this many times the smallest is round
// (cans, bottles: 1.4-2.6 as seen from above) rather than a plate (standing bats: 16.5
// and more), and its axis snaps to vertical within vertical_snap_round.
constexpr float kRoundBodyFlatness = 6.f;
// The footprint's rectangle is searched over at most this many hull vertices (h^2
// work); a larger hull keeps the covariance axes.
constexpr uint32_t kMaxFootprintHull = 256;
}  // namespace

Vec3 orthogonal_from(const Vec3& axis, const Vec3& hint) {
  const Vec3 cands[3] = {hint, Vec3::UnitZ(), Vec3::UnitX()};
  for (const Vec3& h : cands) {
    const Vec3 v = h.cross(axis);  // orthogonal to the axis
    const float n = v.norm();
    if (n > 1e-3f * (h.norm() + 1e-12f)) return v / n;
  }
  return Vec3::UnitY();
}

bool build_object_frame(const PointSpan& pts, const SensorViews& sensors, const PlannerConfig& cfg, ObjectFrame& out) {
  Vec3 evals;
  Mat3 evecs;
  if (!pca(pts.data(), pts.size(), out.centroid, evals, evecs)) return false;
  if (!(evals[2] > 1e-12f)) return false;
  Vec3 Y = evecs.col(2);
  const float up = std::fabs(Y.z());
  const bool ill_defined = evals[2] < cfg.axis_ratio_min * evals[1];
  // Seen from above, a round body's top and the wall one sensor faced form an L whose
  // axis leans 20-25 deg; a plate's lean (kRoundBodyFlatness) is real.
  const bool round_body = evals[1] < kRoundBodyFlatness * evals[0];
  const float snap = round_body ? cfg.vertical_snap_round_rad : cfg.vertical_snap_rad;
  if (ill_defined || up > std::cos(snap)) {
    Y = Vec3::UnitZ();  // gravity is the better axis for upright or round objects
  } else if (up > 0.05f) {
    if (Y.z() < 0) Y = -Y;
  } else if (Y.x() < 0) {
    Y = -Y;
  }
  out.axes[0] = Y;
  // The other two axes: PCA's, made orthogonal to Y.
  Vec3 m = evecs.col(1) - Y * Y.dot(evecs.col(1));
  if (m.norm() < 1e-3f) m = orthogonal_from(Y, evecs.col(0));
  out.axes[1] = m.normalized();
  out.axes[2] = Y.cross(out.axes[1]).normalized();
  // Paper eq. (2): X = normalize(Sp x Y) with Sp the hand sensor relative to c;
  // then the head sensor, then world z.
  const uint32_t first = sensors.added[1] ? 1u : 0u;
  Vec3 hint = sensors.origin[first] - out.centroid;
  if (hint.cross(Y).norm() < 1e-3f * (hint.norm() + 1e-12f) && sensors.added[1 - first])
    hint = sensors.origin[1 - first] - out.centroid;
  out.X0 = orthogonal_from(Y, hint);  // normalize(Sp x Y), with fallbacks
  return out.X0.allFinite() && Y.allFinite();
}

bool support_axes(const PointSpan& pts, const Vec3& centroid, const SupportPlane& support, Vec3 axes[3]) {
  if (!support.found || pts.size() < 3) return false;
  Vec3 n = support.plane.n;
  if (!(n.norm() > 0.5f)) return false;
  n.normalize();
  if (n.z() < 0.f) n = -n;
  const Vec3 a = std::fabs(n.x()) < 0.9f ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 u = (a - n * n.dot(a)).normalized(), v = n.cross(u);
  double suu = 0.0, suv = 0.0, svv = 0.0, su = 0.0, sv = 0.0;
  const uint32_t m = pts.size();
  for (uint32_t i = 0; i < m; ++i) {
    const Vec3 d = pts[i] - centroid;
    const double x = u.dot(d), y = v.dot(d);
    su += x;
    sv += y;
    suu += x * x;
    suv += x * y;
    svv += y * y;
  }
  const double k = static_cast<double>(m);
  const double cxx = suu / k - (su / k) * (su / k), cxy = suv / k - (su / k) * (sv / k),
               cyy = svv / k - (sv / k) * (sv / k);
  // Major direction of the 2x2 covariance: angle 0.5 atan2(2 cxy, cxx - cyy).
  if (!(std::fabs(cxy) + std::fabs(cxx - cyy) > 1e-12)) return false;
  const double phi = 0.5 * std::atan2(2.0 * cxy, cxx - cyy);
  const Vec3 major = (u * static_cast<float>(std::cos(phi)) + v * static_cast<float>(std::sin(phi))).normalized();
  axes[0] = n;
  axes[1] = major;
  axes[2] = n.cross(major).normalized();
  return axes[1].allFinite() && axes[2].allFinite();
}

bool footprint_axes(const PointSpan& pts, const Vec3& centroid, const Vec3 sup[3], Vec2* proj, Vec2* hull,
                    Vec3 foot[3]) {
  // The target's points on the plane's (major, minor) axes, then their convex hull;
  // the hull overwrites the projection (its scratch).
  const uint32_t m = pts.size();
  for (uint32_t i = 0; i < m; ++i) {
    const Vec3 d = pts[i] - centroid;
    proj[i] = Vec2{sup[1].dot(d), sup[2].dot(d)};
  }
  uint32_t h = 0;
  if (convex_hull_2d(proj, m, proj, hull, kMaxContourVertices, h) != Status::ok || h < 3 || h > kMaxFootprintHull)
    return false;
  float major_x = 0.f, major_y = 0.f;
  if (!(min_area_rectangle(hull, h, major_x, major_y) < std::numeric_limits<float>::infinity())) return false;
  foot[0] = sup[0];
  foot[1] = (sup[1] * major_x + sup[2] * major_y).normalized();
  foot[2] = sup[0].cross(foot[1]).normalized();
  return foot[1].allFinite() && foot[2].allFinite();
}

}  // namespace fg
