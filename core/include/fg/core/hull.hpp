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
//! points on edges dropped, starting at the lexicographically smallest (x, then y)
//! point. `scratch` must hold n points (it receives a sorted copy; it must not alias
//! `out`). Non-finite points are skipped. out_n = 0 for n = 0 (or no finite point);
//! 1 or 2 vertices for degenerate inputs (all identical / all collinear: the two
//! extreme points). Orientation tests are done in double on the float inputs.
//! Returns capacity_exceeded if the hull has more than out_capacity vertices, and
//! invalid_argument for a null points / scratch with n > 0 or a null out with
//! out_capacity > 0. out_n = 0 whenever the status is not ok.
[[nodiscard]] Status convex_hull_2d(const Vec2* points, uint32_t n, Vec2* scratch, Vec2* out, uint32_t out_capacity,
                                    uint32_t& out_n);

//! A run of foreground cells in one raster row (the concave hull's component labels).
struct HullRun {
  uint32_t parent;  //!< union-find link: a run index (itself at a root)
  uint32_t points;  //!< points in its cells (saturated per-cell counts); bit 31: a count saturated
  uint16_t x0, x1;  //!< its first and last cell
};

//! Work memory of the concave hull (a silhouette raster). Large: keep it in a workspace.
struct ConcaveHullScratch {
  // The cell flags, then the per-cell point counts.
  static constexpr uint32_t kRasterCells = kHullGridDim * kHullGridDim;
  uint8_t raster[2 * kRasterCells];
  float corner_x[kHullGridDim + 1];  // the raster's cell corners
  float corner_y[kHullGridDim + 1];
  // The closing works on rows as bit sets (64 cells per word): two images. The
  // component labelling then reuses that memory for runs (a raster with more runs than
  // fit is labelled by flooding instead).
  static constexpr uint32_t kRowWords = (kHullGridDim + 63) / 64;
  static constexpr uint32_t kMaxRuns =
      static_cast<uint32_t>(size_t{2} * kHullGridDim * kRowWords * sizeof(uint64_t) / sizeof(HullRun));
  union {
    uint64_t rows[2][kHullGridDim * kRowWords];
    HullRun runs[kMaxRuns];
  };
  // Cells holding more than 254 points (their count in `temp` stays at 255) keep
  // their exact count here, so a component is counted without another pass over the
  // points. Room for every full cell of kMaxObjectPoints points; a larger input that
  // fills more cells falls back to that pass.
  static constexpr uint32_t kMaxFullCells =
      kMaxObjectPoints / 255 + 1 < 127 ? kMaxObjectPoints / 255 + 1 : 127;  // slot + 1 fits 7 bits
  struct FullCell {
    uint32_t cell;    //!< raster index
    uint32_t points;  //!< exact count (at least 255)
  };
  FullCell full[kMaxFullCells];
};

//! Parameters of the raster concave hull.
struct ConcaveHullParams {
  float cell_m = 0.0025f;      //!< raster cell size (> 0, finite); grown automatically to fit the grid
  uint32_t closing_cells = 2;  //!< closing radius in cells, at most (kHullGridDim - 5) / 2
  //! Optional: the caller states that every point is finite and gives their bounding
  //! box (the planner's projection computes it in passing), so the hull skips its own
  //! pass over the points. With the exact box the result is the one without it;
  //! with a wrong one it is undefined but memory-safe (cells are clamped).
  bool bounds_given = false;
  float xmin = 0.f, ymin = 0.f, xmax = 0.f, ymax = 0.f;
};

//! Concave hull of n points: the outer boundary of one 8-connected component of the
//! occupied raster cells after a closing and hole filling, traced counter-clockwise
//! along cell edges (vertices at cell corners, collinear runs merged, no repeated
//! first vertex; the first vertex is the lower-left corner of the component's lowest,
//! then leftmost cell).
//! Steps: bounding box of the finite points; cell = max(cell_m, extent /
//! (kHullGridDim - 2 * closing_cells - 4), two float ulps of the largest |coordinate|),
//! so the occupied span plus a margin of closing_cells + 1 empty cells fits the
//! raster and the float cell corners stay distinct; closing (dilate then erode, square
//! of radius closing_cells); holes filled (background not 4-connected to the border);
//! the component holding the most points (exact count; ties: the component whose
//! first cell comes first in row-major order from the smallest y) is traced.
//! Guarantees: every finite point of the traced component lies inside or on the
//! polygon (a point's cell is one whose float corners, the polygon's vertices,
//! enclose it); holes are filled (a ring gives its outer circle);
//! concavities wider than about 2 * closing_cells cells are followed (L and U
//! shapes). Where two cells of the component touch only diagonally the polygon
//! touches itself at that corner (weakly simple). `all_inside` is false when some
//! finite points lie in other components.
//! out_cell_m receives the cell size actually used (0 when there is no finite point).
//! Statuses: ok (out_n = 0 when there is no finite point); invalid_argument (null
//! points with n > 0, null out with out_capacity > 0, cell_m not a finite value > 0,
//! closing_cells too large, given bounds not finite or min above max); capacity_exceeded (more than out_capacity
//! vertices); numeric_failure (the raster's corners overflow float: coordinates near FLT_MAX). out_n = 0 whenever the
//! status is not ok. Time: O(n + raster cells) (the raster is at most kHullGridDim^2 cells). Cells with more than 254
//! points keep an exact count in the scratch (up to ConcaveHullScratch::kMaxFullCells of them: every input of
//! kMaxObjectPoints points); only beyond that does a component holding such an uncounted cell cost one extra pass over
//! the points and the raster.
[[nodiscard]] Status concave_hull_2d(const Vec2* points, uint32_t n, const ConcaveHullParams& params,
                                     ConcaveHullScratch& scratch, Vec2* out, uint32_t out_capacity, uint32_t& out_n,
                                     float& out_cell_m, bool& all_inside);

//! The smallest-area rectangle about a convex polygon (`hull`, h vertices): it has a
//! side along a hull edge (Freeman and Shapira), so each edge's direction is tried
//! (h^2 work). Its area, and the unit direction of its longer side in (major_x,
//! major_y); infinity when no edge has a length.
float min_area_rectangle(const Vec2* hull, uint32_t h, float& major_x, float& major_y);

//! Signed area of a polygon (positive when counter-clockwise).
float polygon_area(const Vec2* poly, uint32_t n);

//! Point-in-polygon (even-odd rule); points within edge_tol_m of an edge count as
//! inside. False for a null / empty polygon or a non-finite point.
[[nodiscard]] bool polygon_contains(const Vec2* poly, uint32_t n, Vec2 p, float edge_tol_m = 1e-6f);

//! Leftmost and rightmost x where the horizontal line y = y_line meets the polygon
//! boundary: every edge is intersected; a line through a vertex counts that vertex,
//! a line along a horizontal edge counts both its endpoints. Returns false (and
//! zeros) when the line misses the polygon or y_line is not finite.
[[nodiscard]] bool polygon_span_at_y(const Vec2* poly, uint32_t n, float y_line, float& x_left, float& x_right);

//! What polygon_span_at_y takes from the edge a-b for the line y = y_line: the x of
//! each meeting (both ends of an edge along the line, the vertex a line passes through,
//! else the interpolated crossing), written to x[]; returns how many (0, 1 or 2). An
//! edge with a non-finite end meets nothing; callers skip non-finite x.
uint32_t edge_meets_line(const Vec2& a, const Vec2& b, double y_line, double x[2]);

}  // namespace fg
