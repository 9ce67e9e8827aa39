// Symmetric 3x3 eigen-decomposition (own routine, cyclic Jacobi, bounded sweeps) and
// PCA of a point set built on it.
#pragma once
#include <cstdint>

#include "fg/core/types.hpp"

namespace fg {

//! Eigen-decomposition of a symmetric 3x3 matrix A (only its upper triangle is read).
//! evals ascending; evecs columns are the matching unit eigenvectors, forming a
//! right-handed orthonormal basis (the last column is flipped if needed). Computed in
//! double. The zero matrix gives zero eigenvalues and the identity. Returns false
//! (evals zero, evecs identity) if A has a non-finite entry or an eigenvalue
//! overflows float. At most 32 Jacobi sweeps: bounded time. No sign convention for
//! the eigenvectors beyond det = +1.
[[nodiscard]] bool eigen_sym3(const Mat3& A, Vec3& evals, Mat3& evecs);

//! PCA of n points: centroid, covariance (divided by n) eigenvalues (ascending,
//! clamped at >= 0) and eigenvectors (columns, as eigen_sym3). Accumulates in double
//! about a first-point shift for accuracy. Returns false for n == 0, a null pointer
//! or any non-finite point (centroid and evals zero, evecs identity).
[[nodiscard]] bool pca(const Vec3* points, uint32_t n, Vec3& centroid, Vec3& evals, Mat3& evecs);

}  // namespace fg
