// D.1: the object's points in a viewpoint's XOY plane, the silhouette's input.
#pragma once
#include <cstdint>

#include "fg/core/hull.hpp"
#include "fg/core/types.hpp"

namespace fg {

//! out[i] = (X . (p_i - origin), Y . (p_i - origin)) for n finite points, each dot
//! a.x d.x + (a.y d.y + a.z d.z) in float on every target. In passing, the projections'
//! bounding box into `hull` (bounds_given, xmin .. ymax: concave_hull_2d then skips its
//! own pass) when the box and the frame are finite; bounds_given = false otherwise.
void project_to_view(const Vec3* points, uint32_t n, const Vec3& origin, const Vec3& X, const Vec3& Y, Vec2* out,
                     ConcaveHullParams& hull);

}  // namespace fg
