// 2D hull routines over caller memory: the convex hull (Andrew's monotone chain)
// and a raster concave hull (the outer boundary of the occupied cells of a closed
// silhouette raster). Both are bounded by their capacities; neither allocates.
#pragma once
#include <cstdint>
#include "fg/core/limits.hpp"
#include "fg/core/status.hpp"
#include "fg/core/types.hpp"

namespace fg {

//! Convex hull of n points, counter-clockwise, no repeated first vertex, collinear
//! points on edges dropped. `scratch` must hold n points (it receives a sorted copy).
//! Non-finite points are skipped. out_n = 0 for n = 0; 1 or 2 vertices for
//! degenerate inputs (all identical / all collinear).
//! Returns capacity_exceeded if the hull has more than out_capacity vertices.
Status convex_hull_2d(const Vec2* points, uint32_t n, Vec2* scratch, Vec2* out,
                      uint32_t out_capacity, uint32_t& out_n);

//! Work memory of the concave hull (a silhouette raster). Large: keep it in a workspace.
struct ConcaveHullScratch {
  uint8_t cells[kHullGridDim * kHullGridDim];
  uint8_t temp[kHullGridDim * kHullGridDim];
};

//! Parameters of the raster concave hull.
struct ConcaveHullParams {
  float cell_m = 0.0025f;     //!< raster cell size; grown automatically to fit the grid
  uint32_t closing_cells = 2; //!< morphological closing radius (bridges sampling gaps)
};

//! Concave hull of n points: the boundary of the outer component of the union of
//! occupied raster cells after a closing, traced counter-clockwise (Moore
//! neighbour tracing), vertices at cell corners with collinear runs merged.
//! Guarantees: every finite input point lies inside or on the polygon; holes are
//! filled (a ring gives its outer circle); concavities wider than about
//! 2 * closing_cells cells are followed (L and U shapes). When the points form
//! several components after the closing, the component holding the most points is
//! traced and `all_inside` reports false.
//! out_cell_m receives the cell size actually used.
Status concave_hull_2d(const Vec2* points, uint32_t n, const ConcaveHullParams& params,
                       ConcaveHullScratch& scratch, Vec2* out, uint32_t out_capacity,
                       uint32_t& out_n, float& out_cell_m, bool& all_inside);

//! Signed area of a polygon (positive when counter-clockwise).
float polygon_area(const Vec2* poly, uint32_t n);

//! Point-in-polygon (even-odd rule); points on an edge count as inside.
bool polygon_contains(const Vec2* poly, uint32_t n, Vec2 p, float edge_tol_m = 1e-6f);

//! Leftmost and rightmost x where the horizontal line y = y_line crosses the polygon
//! boundary. Returns false when the line misses the polygon.
bool polygon_span_at_y(const Vec2* poly, uint32_t n, float y_line, float& x_left, float& x_right);

}  // namespace fg
