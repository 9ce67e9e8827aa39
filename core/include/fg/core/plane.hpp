// RANSAC support plane with the core's own seeded PRNG, then a least-squares refit.
#pragma once
#include <cstdint>

#include "fg/core/types.hpp"

namespace fg {

//! n . p + d = 0 with |n| = 1 and n pointing up (n.z > 0): n . p + d is the height.
struct Plane {
  Vec3 n = Vec3::UnitZ();
  float d = 0.f;
  float height(const Vec3& p) const { return n.dot(p) + d; }
};

struct PlaneParams {
  float distance_m = 0.01f;   //!< inlier distance
  uint32_t iterations = 200;  //!< upper bound; stops earlier once 99% confident
  uint32_t seed = 42;
  float max_tilt_rad = 0.349f;  //!< only planes whose normal is this close to world z
  float min_inlier_fraction = 0.10f;
  uint32_t min_inliers = 50;
};

//! Finds the dominant near-horizontal plane of `pts`. Hypotheses are scored on an
//! evenly strided subset of at most 4096 points (bounded time for any n); the winner
//! is refitted by PCA on all its inliers. Returns false when no plane has enough inliers.
[[nodiscard]] bool ransac_plane(const Vec3* pts, uint32_t n, const PlaneParams& params, Plane& out, uint32_t& inliers);

//! The points within `thr` of the plane (nrm, d) (|n . p + d| <= thr; NaN points are
//! never in): ransac_plane's final count.
uint32_t count_plane_inliers(const Vec3* pts, uint32_t n, const Vec3& nrm, float d, float thr);

//! Replaces (nrm, d) by the least-squares plane through its inliers (PCA, smallest
//! axis, nrm pointing up): ransac_plane's refit. False, leaving them unchanged, when
//! fewer than 3 points are inliers or the fit is not finite.
[[nodiscard]] bool refit_plane(const Vec3* pts, uint32_t n, float thr, Vec3& nrm, float& d);

}  // namespace fg
