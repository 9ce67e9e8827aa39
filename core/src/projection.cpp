#include "fg/core/projection.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "fg/core/vec4.hpp"

namespace fg {

void project_to_view(const Vec3* p, uint32_t n, const Vec3& origin, const Vec3& X, const Vec3& Y, Vec2* out,
                     ConcaveHullParams& hull) {
  hull.bounds_given = false;
  if (n == 0) return;
  static_assert(sizeof(Vec3) == 3 * sizeof(float) && sizeof(Vec2) == 2 * sizeof(float), "packed points");
  // Four points per step, a coordinate per vector; every coordinate (lanes and tail) is
  // X.x d.x + (X.y d.y + X.z d.z) in float, on every target: the order of Eigen's
  // Vector3f dot on x86-64 (on aarch64 Eigen sums (X.x d.x + X.y d.y) + X.z d.z), so
  // host plans are what they were with X.dot(d).
  const V4f cx = V4f{} + origin.x(), cy = V4f{} + origin.y(), cz = V4f{} + origin.z();
  const V4f xx = V4f{} + X.x(), xy = V4f{} + X.y(), xz = V4f{} + X.z();
  const V4f yx = V4f{} + Y.x(), yy = V4f{} + Y.y(), yz = V4f{} + Y.z();
  // The bounds over the stored (x, y, x, y) pairs: min and max are the same in any
  // order (a zero's sign aside, which moves no raster cell), so they are the hull's
  // own. Finite points in a finite frame project to finite values or overflow to an
  // infinity, which the box then shows.
  auto dot = [](const Vec3& a, const Vec3& d) { return a.x() * d.x() + (a.y() * d.y() + a.z() * d.z()); };
  const Vec3 d0 = p[0] - origin;
  const V4f first{dot(X, d0), dot(Y, d0), dot(X, d0), dot(Y, d0)};
  V4f lo_xy = first, hi_xy = first;
  uint32_t i = 0;
  for (; i + 4 <= n; i += 4) {
    V4f a, b, c;  // x0 y0 z0 x1 | y1 z1 x2 y2 | z2 x3 y3 z3
    const float* q = p[i].data();
    std::memcpy(&a, q, sizeof a);
    std::memcpy(&b, q + 4, sizeof b);
    std::memcpy(&c, q + 8, sizeof c);
    // Five shuffles of two lanes from each source (one SSE shufps each).
    const V4f t0 = __builtin_shufflevector(b, c, 2, 3, 5, 6);  // x2 y2 x3 y3
    const V4f t1 = __builtin_shufflevector(a, b, 1, 2, 4, 5);  // y0 z0 y1 z1
    const V4f dx = __builtin_shufflevector(a, t0, 0, 3, 4, 6) - cx;
    const V4f dy = __builtin_shufflevector(t1, t0, 0, 2, 5, 7) - cy;
    const V4f dz = __builtin_shufflevector(t1, c, 1, 3, 4, 7) - cz;
    const V4f px = xx * dx + (xy * dy + xz * dz);
    const V4f py = yx * dx + (yy * dy + yz * dz);
    const V4f lo = __builtin_shufflevector(px, py, 0, 4, 1, 5), hi = __builtin_shufflevector(px, py, 2, 6, 3, 7);
    std::memcpy(&out[i], &lo, sizeof lo);
    std::memcpy(&out[i + 2], &hi, sizeof hi);
    const V4f lo_2 = lo < hi ? lo : hi, hi_2 = lo > hi ? lo : hi;
    lo_xy = lo_2 < lo_xy ? lo_2 : lo_xy;
    hi_xy = hi_2 > hi_xy ? hi_2 : hi_xy;
  }
  float bx[2] = {std::min(lo_xy[0], lo_xy[2]), std::max(hi_xy[0], hi_xy[2])};
  float by[2] = {std::min(lo_xy[1], lo_xy[3]), std::max(hi_xy[1], hi_xy[3])};
  for (; i < n; ++i) {
    const Vec3 d = p[i] - origin;
    const Vec2 q{dot(X, d), dot(Y, d)};
    out[i] = q;
    bx[0] = std::min(bx[0], q.x);
    bx[1] = std::max(bx[1], q.x);
    by[0] = std::min(by[0], q.y);
    by[1] = std::max(by[1], q.y);
  }
  if (!(X.allFinite() && Y.allFinite() && origin.allFinite() && std::isfinite(bx[0]) && std::isfinite(bx[1]) &&
        std::isfinite(by[0]) && std::isfinite(by[1])))
    return;
  hull.bounds_given = true;
  hull.xmin = bx[0];
  hull.xmax = bx[1];
  hull.ymin = by[0];
  hull.ymax = by[1];
}

}  // namespace fg
