// XOY force balance on one silhouette (algorithm.md D): scan lines across the
// concave hull, the width filter, the discontinuity split, sliding candidate windows
// and the least-squares sides with their angle beta.
#pragma once
#include <cstdint>

#include "fg/core/types.hpp"

namespace fg {

struct ScanLine {
  float y;      //!< line position in the viewpoint frame (m)
  float left;   //!< leftmost contour x on the line (L_j)
  float right;  //!< rightmost contour x on the line (R_j)
  bool hit;     //!< the line crosses the contour
  bool kept;    //!< graspable: min_width <= right - left < max_width
};

//! One candidate window of k consecutive kept lines and its fitted sides
//! (x = a * y + b for the left and the right side).
struct SideFit {
  uint32_t first = 0;  //!< index of the first line of the window
  uint32_t count = 0;  //!< k
  float a_left = 0.f, b_left = 0.f, a_right = 0.f, b_right = 0.f;
  float beta = 0.f;      //!< |atan(a_left) - atan(a_right)|
  float y_centre = 0.f;  //!< window centre along Y
  float x_centre = 0.f;  //!< mean of (L + R) / 2 over the window
  float width = 0.f;     //!< mean R - L over the window
  float rank = 0.f;      //!< beta + centre_weight * |y_centre - y_ref| (smaller is better)
};

//! Scan lines y_j = y_min + j * delta over [y_min, y_max]. When the span needs more
//! than `capacity` lines, delta grows to fit (reported in used_delta). Returns the count.
uint32_t build_scan_lines(const Vec2* contour, uint32_t n_contour, float y_min, float y_max, float delta,
                          ScanLine* lines, uint32_t capacity, float& used_delta);

//! Marks the lines whose width lies in [min_width, max_width).
void mark_graspable(ScanLine* lines, uint32_t n, float min_width, float max_width);

//! Least squares x = a * y + b (paper eq. 6 in the well-conditioned form). false when
//! n < 2 or the y values are all equal.
[[nodiscard]] bool fit_x_of_y(const float* y, const float* x, uint32_t n, float& a, float& b);

//! beta = |atan(a_left) - atan(a_right)|, the angle between the two fitted sides.
float side_angle(float a_left, float a_right);

//! Splits the kept lines into continuous regions (a dropped line, or |dL| or |dR|
//! above dx_threshold between neighbours ends a region), slides windows of k lines
//! over each region and returns the best `max_out` windows by rank (beta plus
//! centre_weight times the distance of the window centre from y_ref), best first.
uint32_t best_windows(const ScanLine* lines, uint32_t n, float dx_threshold, uint32_t k, float y_ref,
                      float centre_weight, SideFit* out, uint32_t max_out);

}  // namespace fg
