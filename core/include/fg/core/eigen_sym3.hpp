// Symmetric 3x3 eigen-decomposition (own routine, cyclic Jacobi, bounded sweeps) and
// PCA of a point set built on it.
#pragma once
#include <cstdint>
#include "fg/core/types.hpp"

namespace fg {

//! Eigen-decomposition of a symmetric 3x3 matrix A (only its upper triangle is read).
//! evals ascending; evecs columns are the matching unit eigenvectors, forming a
//! right-handed orthonormal basis. Returns false (outputs set to identity / zero) if
//! A has a non-finite entry. At most 32 Jacobi sweeps: bounded time.
bool eigen_sym3(const Mat3& A, Vec3& evals, Mat3& evecs);

//! PCA of n points: centroid, covariance eigenvalues (ascending) and eigenvectors
//! (columns). Accumulates in double about a first-point shift for accuracy.
//! Returns false for n == 0 or non-finite input.
bool pca(const Vec3* points, uint32_t n, Vec3& centroid, Vec3& evals, Mat3& evecs);

}  // namespace fg
