// Boolean GJK: do two convex sets, given by support functions, intersect?
// Used with a box (a finger or the palm) against the convex hull of a point set, whose
// support is a scan over the points: no hull is ever built. Bounded iterations.
#pragma once
#include <cstdint>

#include "fg/core/types.hpp"

namespace fg {

struct ConvexSupport {
  //! The point of the set farthest along `dir`.
  Vec3 (*support)(const void* ctx, const Vec3& dir);
  const void* ctx;
  Vec3 centre;  //!< any interior point (seeds the search direction)
};

//! True when the sets intersect (touching counts). When max_iterations is reached
//! without a separating direction the answer is true: callers use it for collision
//! checks, where "maybe" must mean "collides".
bool gjk_intersect(const ConvexSupport& a, const ConvexSupport& b, uint32_t max_iterations = 64);

//! Support helpers: an axis-aligned box and a point array.
struct AabbShape {
  Vec3 lo, hi;
};
Vec3 aabb_support(const void* box, const Vec3& dir);

struct PointSetShape {
  const Vec3* points;
  uint32_t n;
};
Vec3 point_set_support(const void* set, const Vec3& dir);

}  // namespace fg
