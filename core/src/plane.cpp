#include "fg/core/plane.hpp"

#include <cmath>
#include "fg/core/eigen_sym3.hpp"
#include "fg/core/prng.hpp"

namespace fg {
namespace {
constexpr uint32_t kScoreSamples = 4096;

uint32_t count_inliers(const Vec3* pts, uint32_t n, uint32_t step, const Vec3& nrm, float d,
                       float thr) {
  uint32_t c = 0;
  for (uint32_t i = 0; i < n; i += step) c += std::fabs(nrm.dot(pts[i]) + d) <= thr ? 1u : 0u;
  return c;
}

// Least-squares plane through the inliers of (nrm, d): PCA, smallest axis.
bool refit(const Vec3* pts, uint32_t n, float thr, Vec3& nrm, float& d) {
  double sx = 0, sy = 0, sz = 0, sxx = 0, sxy = 0, sxz = 0, syy = 0, syz = 0, szz = 0;
  uint32_t c = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const Vec3& p = pts[i];
    if (!(std::fabs(nrm.dot(p) + d) <= thr)) continue;  // also skips NaN points
    const double x = p.x(), y = p.y(), z = p.z();
    sx += x; sy += y; sz += z;
    sxx += x * x; sxy += x * y; sxz += x * z; syy += y * y; syz += y * z; szz += z * z;
    ++c;
  }
  if (c < 3) return false;
  const double inv = 1.0 / c, mx = sx * inv, my = sy * inv, mz = sz * inv;
  Mat3 C;
  C(0, 0) = static_cast<float>(sxx * inv - mx * mx);
  C(0, 1) = static_cast<float>(sxy * inv - mx * my);
  C(0, 2) = static_cast<float>(sxz * inv - mx * mz);
  C(1, 1) = static_cast<float>(syy * inv - my * my);
  C(1, 2) = static_cast<float>(syz * inv - my * mz);
  C(2, 2) = static_cast<float>(szz * inv - mz * mz);
  C(1, 0) = C(0, 1); C(2, 0) = C(0, 2); C(2, 1) = C(1, 2);
  Vec3 evals;
  Mat3 evecs;
  if (!eigen_sym3(C, evals, evecs)) return false;
  Vec3 nn = evecs.col(0);
  if (nn.z() < 0) nn = -nn;
  const Vec3 m(static_cast<float>(mx), static_cast<float>(my), static_cast<float>(mz));
  if (!nn.allFinite()) return false;
  nrm = nn;
  d = -nn.dot(m);
  return true;
}
}  // namespace

bool ransac_plane(const Vec3* pts, uint32_t n, const PlaneParams& prm, Plane& out,
                  uint32_t& inliers) {
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
    if (!refit(pts, n, prm.distance_m, nrm, d)) return false;
  }
  if (nrm.z() < cos_tilt) return false;
  const uint32_t total = count_inliers(pts, n, 1, nrm, d, prm.distance_m);
  if (total < prm.min_inliers || static_cast<float>(total) < prm.min_inlier_fraction * static_cast<float>(n))
    return false;
  out.n = nrm;
  out.d = d;
  inliers = total;
  return true;
}

}  // namespace fg
