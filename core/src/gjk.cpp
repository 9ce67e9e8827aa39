// GJK after Gilbert, Johnson and Keerthi (1988), in the simplex-update form of
// Muratori's "Implementing GJK" (2006): the origin lies in the Minkowski difference
// B - A exactly when the sets intersect.
#include "fg/core/gjk.hpp"

namespace fg {
namespace {
Vec3 minkowski(const ConvexSupport& a, const ConvexSupport& b, const Vec3& d) {
  return b.support(b.ctx, d) - a.support(a.ctx, -d);
}

// Keeps the feature of triangle (a newest, b, c) closest to the origin.
void update_triangle(Vec3& a, Vec3& b, Vec3& c, Vec3& d, int& dim, Vec3& dir) {
  const Vec3 n = (b - a).cross(c - a);
  const Vec3 ao = -a;
  dim = 2;
  if ((b - a).cross(n).dot(ao) > 0) {  // edge AB
    c = a;
    dir = (b - a).cross(ao).cross(b - a);
    return;
  }
  if (n.cross(c - a).dot(ao) > 0) {  // edge AC
    b = a;
    dir = (c - a).cross(ao).cross(c - a);
    return;
  }
  dim = 3;
  if (n.dot(ao) > 0) {  // above the triangle
    d = c;
    c = b;
    b = a;
    dir = n;
    return;
  }
  d = b;  // below
  b = a;
  dir = -n;
}

// Tetrahedron with apex a over base bcd: true when it encloses the origin.
bool update_tetrahedron(Vec3& a, Vec3& b, Vec3& c, Vec3& d, int& dim, Vec3& dir) {
  const Vec3 abc = (b - a).cross(c - a);
  const Vec3 acd = (c - a).cross(d - a);
  const Vec3 adb = (d - a).cross(b - a);
  const Vec3 ao = -a;
  dim = 3;
  if (abc.dot(ao) > 0) {
    d = c;
    c = b;
    b = a;
    dir = abc;
    return false;
  }
  if (acd.dot(ao) > 0) {
    b = a;
    dir = acd;
    return false;
  }
  if (adb.dot(ao) > 0) {
    c = d;
    d = b;
    b = a;
    dir = adb;
    return false;
  }
  return true;
}

bool tiny(const Vec3& v) { return v.squaredNorm() < 1e-20f; }
}  // namespace

bool gjk_intersect(const ConvexSupport& A, const ConvexSupport& B, uint32_t max_iterations) {
  Vec3 dir = A.centre - B.centre;
  if (tiny(dir)) dir = Vec3::UnitX();
  Vec3 c = minkowski(A, B, dir);
  dir = -c;
  if (tiny(dir)) return true;  // the origin is a support point: touching
  Vec3 b = minkowski(A, B, dir);
  if (b.dot(dir) < 0) return false;
  dir = (c - b).cross(-b).cross(c - b);
  if (tiny(dir)) {  // the origin lies on segment bc
    dir = (c - b).cross(Vec3::UnitX());
    if (tiny(dir)) dir = (c - b).cross(Vec3::UnitZ());
    if (tiny(dir)) return true;
  }
  Vec3 a, d = Vec3::Zero();
  int dim = 2;
  for (uint32_t it = 0; it < max_iterations; ++it) {
    if (tiny(dir)) return true;  // the origin is on the current simplex
    a = minkowski(A, B, dir);
    if (a.dot(dir) < 0) return false;  // a separating direction: disjoint
    ++dim;
    if (dim == 3) {
      update_triangle(a, b, c, d, dim, dir);
    } else if (update_tetrahedron(a, b, c, d, dim, dir)) {
      return true;
    }
  }
  return true;
}

Vec3 aabb_support(const void* box, const Vec3& dir) {
  const AabbShape& s = *static_cast<const AabbShape*>(box);
  return Vec3(dir.x() >= 0 ? s.hi.x() : s.lo.x(), dir.y() >= 0 ? s.hi.y() : s.lo.y(),
              dir.z() >= 0 ? s.hi.z() : s.lo.z());
}

Vec3 point_set_support(const void* set, const Vec3& dir) {
  const PointSetShape& s = *static_cast<const PointSetShape*>(set);
  uint32_t best = 0;
  float best_dot = s.points[0].dot(dir);
  for (uint32_t i = 1; i < s.n; ++i) {
    const float v = s.points[i].dot(dir);
    if (v > best_dot) {
      best_dot = v;
      best = i;
    }
  }
  return s.points[best];
}

}  // namespace fg
