// Symmetric 3x3 eigen-decomposition by cyclic Jacobi rotations (computed in double,
// at most kMaxSweeps sweeps) and the PCA of a point set built on it.
// Allocation-free, exception-free; every loop has a fixed bound.
#include "fg/core/eigen_sym3.hpp"

#include <cmath>

namespace fg {
namespace {

constexpr int kMaxSweeps = 32;
// Stop when the off-diagonal Frobenius norm is below this fraction of the matrix's.
constexpr double kRelOffTol = 1e-15;

void set_failed(Vec3& evals, Mat3& evecs) {
  evals.setZero();
  evecs.setIdentity();
}

//! Jacobi eigen-decomposition of the symmetric matrix whose upper triangle is
//! u = {a00, a01, a02, a11, a12, a22} (finite). Writes ascending eigenvalues and a
//! right-handed orthonormal eigenvector basis (columns). Returns false only if a
//! result does not fit a float (overflow of huge entries).
bool jacobi_sym3(const double u[6], Vec3& evals, Mat3& evecs) {
  double a[3][3] = {{u[0], u[1], u[2]}, {u[1], u[3], u[4]}, {u[2], u[4], u[5]}};
  double v[3][3] = {{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}};

  double norm2 = 0.0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) norm2 += a[i][j] * a[i][j];
  }
  if (norm2 == 0.0) {
    evals.setZero();
    evecs.setIdentity();
    return true;
  }
  const double stop2 = kRelOffTol * kRelOffTol * norm2;

  static constexpr int kP[3] = {0, 0, 1};
  static constexpr int kQ[3] = {1, 2, 2};
  for (int sweep = 0; sweep < kMaxSweeps; ++sweep) {
    const double off2 = 2.0 * (a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2]);
    if (off2 <= stop2) break;
    for (int r = 0; r < 3; ++r) {
      const int p = kP[r];
      const int q = kQ[r];
      const double apq = a[p][q];
      if (apq == 0.0) continue;
      // Rotation angle that zeroes a[p][q] (Numerical Recipes' jacobi, the smaller root).
      const double theta = (a[q][q] - a[p][p]) / (2.0 * apq);
      double t;
      if (std::fabs(theta) > 1e150) {
        t = 0.5 / theta;  // theta^2 would overflow; t ~ 1 / (2 theta)
      } else {
        t = (theta >= 0.0 ? 1.0 : -1.0) / (std::fabs(theta) + std::sqrt(theta * theta + 1.0));
      }
      const double c = 1.0 / std::sqrt(t * t + 1.0);
      const double s = t * c;
      for (int k = 0; k < 3; ++k) {  // A <- A J (columns p, q)
        const double akp = a[k][p];
        const double akq = a[k][q];
        a[k][p] = c * akp - s * akq;
        a[k][q] = s * akp + c * akq;
      }
      for (int k = 0; k < 3; ++k) {  // A <- J^T A (rows p, q)
        const double apk = a[p][k];
        const double aqk = a[q][k];
        a[p][k] = c * apk - s * aqk;
        a[q][k] = s * apk + c * aqk;
      }
      a[p][q] = 0.0;
      a[q][p] = 0.0;
      for (int k = 0; k < 3; ++k) {  // V <- V J
        const double vkp = v[k][p];
        const double vkq = v[k][q];
        v[k][p] = c * vkp - s * vkq;
        v[k][q] = s * vkp + c * vkq;
      }
    }
  }

  // Ascending order (a stable three-element sort: ties keep their index order).
  int idx[3] = {0, 1, 2};
  const double d[3] = {a[0][0], a[1][1], a[2][2]};
  if (d[idx[1]] < d[idx[0]]) {
    const int tmp = idx[0];
    idx[0] = idx[1];
    idx[1] = tmp;
  }
  if (d[idx[2]] < d[idx[1]]) {
    const int tmp = idx[1];
    idx[1] = idx[2];
    idx[2] = tmp;
  }
  if (d[idx[1]] < d[idx[0]]) {
    const int tmp = idx[0];
    idx[0] = idx[1];
    idx[1] = tmp;
  }

  double e[3][3];  // e[row][col]: sorted eigenvector columns
  for (int col = 0; col < 3; ++col) {
    for (int row = 0; row < 3; ++row) e[row][col] = v[row][idx[col]];
  }
  const double det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                     e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                     e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
  if (det < 0.0) {
    for (int row = 0; row < 3; ++row) e[row][2] = -e[row][2];
  }

  for (int col = 0; col < 3; ++col) {
    const float ev = static_cast<float>(d[idx[col]]);
    if (!std::isfinite(ev)) {  // an eigenvalue beyond the float range
      set_failed(evals, evecs);
      return false;
    }
    evals(col) = ev;
    for (int row = 0; row < 3; ++row) evecs(row, col) = static_cast<float>(e[row][col]);
  }
  return true;
}

}  // namespace

bool eigen_sym3(const Mat3& A, Vec3& evals, Mat3& evecs) {
  const double u[6] = {A(0, 0), A(0, 1), A(0, 2), A(1, 1), A(1, 2), A(2, 2)};
  for (int i = 0; i < 6; ++i) {
    if (!std::isfinite(u[i])) {
      set_failed(evals, evecs);
      return false;
    }
  }
  return jacobi_sym3(u, evals, evecs);
}

bool pca(const Vec3* points, uint32_t n, Vec3& centroid, Vec3& evals, Mat3& evecs) {
  centroid.setZero();
  if (points == nullptr || n == 0) {
    set_failed(evals, evecs);
    return false;
  }
  const double sx = points[0].x();
  const double sy = points[0].y();
  const double sz = points[0].z();
  double s[3] = {0.0, 0.0, 0.0};
  double ss[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};  // xx xy xz yy yz zz
  for (uint32_t i = 0; i < n; ++i) {
    const Vec3& p = points[i];
    if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z())) {
      set_failed(evals, evecs);
      return false;
    }
    const double dx = p.x() - sx;
    const double dy = p.y() - sy;
    const double dz = p.z() - sz;
    s[0] += dx;
    s[1] += dy;
    s[2] += dz;
    ss[0] += dx * dx;
    ss[1] += dx * dy;
    ss[2] += dx * dz;
    ss[3] += dy * dy;
    ss[4] += dy * dz;
    ss[5] += dz * dz;
  }
  const double inv_n = 1.0 / static_cast<double>(n);
  const double m[3] = {s[0] * inv_n, s[1] * inv_n, s[2] * inv_n};
  double cov[6] = {ss[0] * inv_n - m[0] * m[0], ss[1] * inv_n - m[0] * m[1], ss[2] * inv_n - m[0] * m[2],
                   ss[3] * inv_n - m[1] * m[1], ss[4] * inv_n - m[1] * m[2], ss[5] * inv_n - m[2] * m[2]};
  // A variance cannot be negative: clamp cancellation noise on the diagonal.
  if (cov[0] < 0.0) cov[0] = 0.0;
  if (cov[3] < 0.0) cov[3] = 0.0;
  if (cov[5] < 0.0) cov[5] = 0.0;

  const Vec3 c(static_cast<float>(sx + m[0]), static_cast<float>(sy + m[1]), static_cast<float>(sz + m[2]));
  bool finite = std::isfinite(c.x()) && std::isfinite(c.y()) && std::isfinite(c.z());
  for (int i = 0; i < 6; ++i) finite = finite && std::isfinite(cov[i]);
  if (!finite || !jacobi_sym3(cov, evals, evecs)) {
    set_failed(evals, evecs);
    return false;
  }
  // The covariance is positive semi-definite: rounding may leave -tiny eigenvalues.
  for (int i = 0; i < 3; ++i) {
    if (evals(i) < 0.0f) evals(i) = 0.0f;
  }
  centroid = c;
  return true;
}

}  // namespace fg
