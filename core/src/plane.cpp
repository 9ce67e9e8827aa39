#include "fg/core/plane.hpp"

#include <cmath>

#include "fg/core/eigen_sym3.hpp"
#include "fg/core/prng.hpp"
#include "fg/core/vec4.hpp"

namespace fg {
namespace {
constexpr uint32_t kScoreSamples = 4096;

uint32_t count_inliers(const Vec3* pts, uint32_t n, uint32_t step, const Vec3& nrm, float d, float thr) {
  uint32_t c = 0;
  for (uint32_t i = 0; i < n; i += step) c += std::fabs(nrm.dot(pts[i]) + d) <= thr ? 1u : 0u;
  return c;
}

// The inliers of (nrm, d) over all n points, four per step: their count and, with
// kSums, the sums of their offsets from `ref` and of the offsets' products (xx xy xz yy
// yz zz). Lanes sum in float over at most kFlushGroups steps, then into double, so the
// precision does not fall with n; offsets from an inlier keep the squares small. A NaN
// point fails the distance test and adds nothing.
struct InlierSums {
  uint32_t count = 0;
  double s[3] = {0, 0, 0};
  double ss[6] = {0, 0, 0, 0, 0, 0};
};

constexpr uint32_t kFlushGroups = 64;

inline V4f splat4(float v) { return V4f{v, v, v, v}; }
inline V4f select_or_zero(V4i m, V4f v) { return reinterpret_cast<V4f>(reinterpret_cast<V4i>(v) & m); }
inline double lane_sum(V4f v) {
  return (static_cast<double>(v[0]) + static_cast<double>(v[1])) +
         (static_cast<double>(v[2]) + static_cast<double>(v[3]));
}

template <bool kSums>
void inlier_sums(const Vec3* pts, uint32_t n, const Vec3& nrm, float d, float thr, const Vec3& ref, InlierSums& out) {
  static_assert(sizeof(Vec3) == 12, "Vec3 arrays are packed xyz triples");
  const auto* bytes = reinterpret_cast<const uint8_t*>(pts);
  const V4f nx = splat4(nrm.x()), ny = splat4(nrm.y()), nz = splat4(nrm.z()), dd = splat4(d);
  const V4f hi = splat4(thr), lo = splat4(-thr);
  const V4f rx = splat4(ref.x()), ry = splat4(ref.y()), rz = splat4(ref.z());
  const uint32_t whole = n / 4;
  for (uint32_t g0 = 0; g0 < whole; g0 += kFlushGroups) {
    const uint32_t g1 = whole - g0 < kFlushGroups ? whole : g0 + kFlushGroups;
    V4i cnt = {0, 0, 0, 0};
    V4f sx = splat4(0.f), sy = sx, sz = sx, sxx = sx, sxy = sx, sxz = sx, syy = sx, syz = sx, szz = sx;
    for (uint32_t g = g0; g < g1; ++g) {
      const uint8_t* p = bytes + static_cast<size_t>(g) * 48;
      V4f x, y, z;
      deinterleave_xyz(load4(p), load4(p + 16), load4(p + 32), x, y, z);
      const V4f h = ((x * nx + y * ny) + z * nz) + dd;  // the order of Vec3::dot, then + d
      const V4i in = (h <= hi) & (h >= lo);
      cnt -= in;
      if (kSums) {
        const V4f ox = select_or_zero(in, x - rx), oy = select_or_zero(in, y - ry), oz = select_or_zero(in, z - rz);
        sx += ox;
        sy += oy;
        sz += oz;
        sxx += ox * ox;
        sxy += ox * oy;
        sxz += ox * oz;
        syy += oy * oy;
        syz += oy * oz;
        szz += oz * oz;
      }
    }
    out.count += static_cast<uint32_t>(cnt[0] + cnt[1] + cnt[2] + cnt[3]);
    if (kSums) {
      out.s[0] += lane_sum(sx);
      out.s[1] += lane_sum(sy);
      out.s[2] += lane_sum(sz);
      out.ss[0] += lane_sum(sxx);
      out.ss[1] += lane_sum(sxy);
      out.ss[2] += lane_sum(sxz);
      out.ss[3] += lane_sum(syy);
      out.ss[4] += lane_sum(syz);
      out.ss[5] += lane_sum(szz);
    }
  }
  for (uint32_t i = 4 * whole; i < n; ++i) {
    const Vec3& p = pts[i];
    const float h = ((p.x() * nrm.x() + p.y() * nrm.y()) + p.z() * nrm.z()) + d;
    if (!(h <= thr && h >= -thr)) continue;
    ++out.count;
    if (kSums) {
      const double ox = p.x() - ref.x(), oy = p.y() - ref.y(), oz = p.z() - ref.z();
      out.s[0] += ox;
      out.s[1] += oy;
      out.s[2] += oz;
      out.ss[0] += ox * ox;
      out.ss[1] += ox * oy;
      out.ss[2] += ox * oz;
      out.ss[3] += oy * oy;
      out.ss[4] += oy * oz;
      out.ss[5] += oz * oz;
    }
  }
}

}  // namespace

bool refit_plane(const Vec3* pts, uint32_t n, float thr, Vec3& nrm, float& d) {
  if (pts == nullptr || n == 0) return false;
  // Offsets from the first inlier: the others lie within the cloud's extent of it.
  uint32_t first = 0;
  while (first < n && !(std::fabs(nrm.dot(pts[first]) + d) <= thr)) ++first;
  if (first == n) return false;
  InlierSums m;
  const Vec3 ref = pts[first];
  inlier_sums<true>(pts, n, nrm, d, thr, ref, m);
  if (m.count < 3) return false;
  const double inv = 1.0 / m.count, mx = m.s[0] * inv, my = m.s[1] * inv, mz = m.s[2] * inv;
  Mat3 C;
  C(0, 0) = static_cast<float>(m.ss[0] * inv - mx * mx);
  C(0, 1) = static_cast<float>(m.ss[1] * inv - mx * my);
  C(0, 2) = static_cast<float>(m.ss[2] * inv - mx * mz);
  C(1, 1) = static_cast<float>(m.ss[3] * inv - my * my);
  C(1, 2) = static_cast<float>(m.ss[4] * inv - my * mz);
  C(2, 2) = static_cast<float>(m.ss[5] * inv - mz * mz);
  C(1, 0) = C(0, 1);
  C(2, 0) = C(0, 2);
  C(2, 1) = C(1, 2);
  Vec3 evals;
  Mat3 evecs;
  if (!eigen_sym3(C, evals, evecs)) return false;
  Vec3 nn = evecs.col(0);
  if (nn.z() < 0) nn = -nn;
  if (!nn.allFinite()) return false;
  const Vec3 m0(static_cast<float>(ref.x() + mx), static_cast<float>(ref.y() + my), static_cast<float>(ref.z() + mz));
  nrm = nn;
  d = -nn.dot(m0);
  return true;
}

uint32_t count_plane_inliers(const Vec3* pts, uint32_t n, const Vec3& nrm, float d, float thr) {
  if (pts == nullptr) return 0;
  InlierSums m;
  inlier_sums<false>(pts, n, nrm, d, thr, Vec3::Zero(), m);
  return m.count;
}

bool ransac_plane(const Vec3* pts, uint32_t n, const PlaneParams& prm, Plane& out, uint32_t& inliers) {
  inliers = 0;
  if (pts == nullptr || n < 3) return false;
  const uint32_t step = n > kScoreSamples ? (n + kScoreSamples - 1) / kScoreSamples : 1u;
  const uint32_t scored = (n + step - 1) / step;
  const float cos_tilt = std::cos(prm.max_tilt_rad);
  Prng rng(prm.seed);

  uint32_t best = 0;
  Vec3 best_n = Vec3::UnitZ();
  float best_d = 0.f;
  uint32_t needed = prm.iterations;
  for (uint32_t it = 0; it < prm.iterations && it < needed; ++it) {
    const Vec3& a = pts[rng.below(n)];
    const Vec3& b = pts[rng.below(n)];
    const Vec3& c = pts[rng.below(n)];
    Vec3 nn = (b - a).cross(c - a);
    const float len = nn.norm();
    if (!(len > 1e-9f)) continue;  // collinear, duplicate or non-finite sample
    nn /= len;
    if (nn.z() < 0) nn = -nn;
    if (nn.z() < cos_tilt) continue;  // not a support-plane candidate
    const float d = -nn.dot(a);
    const uint32_t cnt = count_inliers(pts, n, step, nn, d, prm.distance_m);
    if (cnt > best) {
      best = cnt;
      best_n = nn;
      best_d = d;
      // Iterations for 99% confidence of one all-inlier sample at this inlier ratio.
      const double w = static_cast<double>(cnt) / scored;
      const double p_bad = 1.0 - w * w * w;
      if (p_bad <= 1e-12) {
        needed = it + 1;
      } else {
        const double k = std::log(0.01) / std::log(p_bad);
        if (k < static_cast<double>(prm.iterations)) needed = static_cast<uint32_t>(k) + 1;
      }
    }
  }
  if (best == 0) return false;
  Vec3 nrm = best_n;
  float d = best_d;
  // Two refits: the second uses the inliers of the least-squares plane.
  for (int r = 0; r < 2; ++r) {
    if (!refit_plane(pts, n, prm.distance_m, nrm, d)) return false;
  }
  if (nrm.z() < cos_tilt) return false;
  const uint32_t total = count_plane_inliers(pts, n, nrm, d, prm.distance_m);
  if (total < prm.min_inliers || static_cast<float>(total) < prm.min_inlier_fraction * static_cast<float>(n))
    return false;
  out.n = nrm;
  out.d = d;
  inliers = total;
  return true;
}

}  // namespace fg
