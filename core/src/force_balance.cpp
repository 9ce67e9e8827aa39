#include "fg/core/force_balance.hpp"

#include <algorithm>
#include <cmath>

#include "fg/core/hull.hpp"

namespace fg {

uint32_t build_scan_lines(const Vec2* contour, uint32_t n_contour, float y_min, float y_max, float delta,
                          ScanLine* lines, uint32_t capacity, float& used_delta) {
  used_delta = delta;
  if (contour == nullptr || n_contour < 3 || capacity == 0 || !(y_max >= y_min) || !(delta > 0.f)) return 0;
  const float span = y_max - y_min;
  // In double and clamped first: span / delta can exceed any integer type. A span
  // within 0.1% of a whole number of steps keeps its last line at y_max.
  const double wanted = static_cast<double>(span) / static_cast<double>(delta) + 1.001;
  uint32_t n = wanted >= static_cast<double>(capacity) ? capacity + 1u : static_cast<uint32_t>(wanted);
  if (n > capacity) {
    n = capacity;
    used_delta = capacity > 1 ? span / static_cast<float>(capacity - 1) : span;
  }
  bool finite = true;
  for (uint32_t j = 0; j < n; ++j) {
    ScanLine& l = lines[j];
    l.y = y_min + static_cast<float>(j) * used_delta;
    l.left = l.right = 0.f;
    l.hit = false;
    l.kept = false;
    finite = finite && std::isfinite(l.y);
  }
  if (!finite) {  // lines beyond the float range: each one on its own (they meet nothing)
    for (uint32_t j = 0; j < n; ++j)
      lines[j].hit = polygon_span_at_y(contour, n_contour, lines[j].y, lines[j].left, lines[j].right);
    return n;
  }
  // One pass over the edges: the lines' y do not decrease with j, so an edge meets the
  // run of lines from the first at or above its lower end (bisection) to its upper end,
  // and gives each exactly what polygon_span_at_y takes from it. The spans are kept in
  // float: rounding is monotonic, so the float of the extreme double is the extreme
  // of the floats.
  for (uint32_t i = 0; i < n_contour; ++i) {
    const Vec2& a = contour[i];
    const Vec2& b = contour[(i + 1 == n_contour) ? 0 : i + 1];
    const double lo = std::min<double>(a.y, b.y), hi = std::max<double>(a.y, b.y);
    if (!(lo <= hi)) continue;     // a NaN end: the edge meets nothing
    uint32_t first = 0, last = n;  // the first line with y >= lo, by bisection
    for (uint32_t guard = 0; first < last && guard < 32; ++guard) {
      const uint32_t mid = first + (last - first) / 2;
      if (static_cast<double>(lines[mid].y) < lo) {
        first = mid + 1;
      } else {
        last = mid;
      }
    }
    const auto meet = [](ScanLine& l, double x) {
      if (!std::isfinite(x)) return;
      const float xf = static_cast<float>(x);
      if (!l.hit) {
        l.left = l.right = xf;
        l.hit = true;
      } else {
        l.left = std::min(l.left, xf);
        l.right = std::max(l.right, xf);
      }
    };
    // edge_meets_line() for each line of the run, its per-edge tests taken out of the
    // loop (the same operations on the same values for each line): an edge with a
    // non-finite end meets nothing; a horizontal one gives the lines along it both
    // ends; else a line through an end takes that end, the others the clamped crossing.
    if (!std::isfinite(a.x) || !std::isfinite(a.y) || !std::isfinite(b.x) || !std::isfinite(b.y)) continue;
    const double ax = a.x, ay = a.y, bx = b.x, by = b.y;
    if (ay == by) {
      for (uint32_t j = first; j < n && static_cast<double>(lines[j].y) <= hi; ++j) {
        meet(lines[j], ax);
        meet(lines[j], bx);
      }
      continue;
    }
    const double dx = bx - ax, dy = by - ay, x_lo = std::min(ax, bx), x_hi = std::max(ax, bx);
    for (uint32_t j = first; j < n && static_cast<double>(lines[j].y) <= hi; ++j) {
      const double yl = lines[j].y;
      if (yl == ay) {
        meet(lines[j], ax);
      } else if (yl == by) {
        meet(lines[j], bx);
      } else {
        const double t = (yl - ay) / dy;
        meet(lines[j], std::min(std::max(ax + t * dx, x_lo), x_hi));
      }
    }
  }
  return n;
}

void mark_graspable(ScanLine* lines, uint32_t n, float min_width, float max_width) {
  for (uint32_t j = 0; j < n; ++j) {
    const float w = lines[j].right - lines[j].left;
    lines[j].kept = lines[j].hit && w >= min_width && w < max_width;
  }
}

bool fit_x_of_y(const float* y, const float* x, uint32_t n, float& a, float& b) {
  if (n < 2) return false;
  double sy = 0, sx = 0;
  for (uint32_t i = 0; i < n; ++i) {
    sy += y[i];
    sx += x[i];
  }
  const double my = sy / n, mx = sx / n;
  double syy = 0, sxy = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const double dy = y[i] - my;
    syy += dy * dy;
    sxy += dy * (x[i] - mx);
  }
  if (!(syy > 1e-18)) return false;
  const double aa = sxy / syy;
  a = static_cast<float>(aa);
  b = static_cast<float>(mx - aa * my);
  return std::isfinite(a) && std::isfinite(b);
}

float side_angle(float a_left, float a_right) { return std::fabs(std::atan(a_left) - std::atan(a_right)); }

namespace {
// Inserts c into the sorted list out[0, n) of at most cap entries.
void insert_best(SideFit* out, uint32_t& n, uint32_t cap, const SideFit& c) {
  uint32_t pos = n;
  while (pos > 0 && c.rank < out[pos - 1].rank) --pos;
  if (pos >= cap) return;
  const uint32_t last = n < cap ? n : cap - 1;
  for (uint32_t i = last; i > pos; --i) out[i] = out[i - 1];
  out[pos] = c;
  if (n < cap) ++n;
}
}  // namespace

uint32_t best_windows(const ScanLine* lines, uint32_t n, float dx_threshold, uint32_t k, float y_ref,
                      float centre_weight, SideFit* out, uint32_t max_out) {
  if (lines == nullptr || out == nullptr || max_out == 0 || k < 2 || n < k) return 0;
  uint32_t found = 0;
  uint32_t j = 0;
  while (j < n) {
    if (!lines[j].kept || !std::isfinite(lines[j].y)) {
      ++j;
      continue;
    }
    // Region [j, e): consecutive kept lines without a jump on either side (a NaN or
    // infinite side is a jump; so is a line without a finite y, which would spoil the
    // running sums of the windows after it).
    uint32_t e = j + 1;
    while (e < n && lines[e].kept && std::isfinite(lines[e].y) &&
           std::fabs(lines[e].left - lines[e - 1].left) <= dx_threshold &&
           std::fabs(lines[e].right - lines[e - 1].right) <= dx_threshold)
      ++e;
    if (e - j >= k) {
      // The fits of all windows from one set of running sums (each slide adds a line
      // and drops one): O(region) per region instead of O(region * k), within about
      // 1e-12 of the two-pass fit (fit_x_of_y). The sums are taken relative to the
      // region's first line. A side at one x over the whole window gets slope 0 and
      // that x exactly, as the two-pass fit gives it (so windows that tie stay tied):
      // the steps of each side inside the window are counted as it slides.
      const double y0 = lines[j].y, l0 = lines[j].left, r0 = lines[j].right;
      double sy = 0, syy = 0, sl = 0, syl = 0, sr = 0, syr = 0;
      int steps_l = 0, steps_r = 0;  // i in (s, s + k) with a side unlike line i - 1's
      const auto add = [&](uint32_t i, double sign) {
        const ScanLine& L = lines[i];
        const double y = L.y - y0, l = L.left - l0, r = L.right - r0;
        sy += sign * y;
        syy += sign * y * y;
        sl += sign * l;
        syl += sign * y * l;
        sr += sign * r;
        syr += sign * y * r;
      };
      // The pair (i - 1, i) enters (+1) or leaves (-1) the window's step counts.
      const auto step = [&](uint32_t i, int sign) {
        steps_l += lines[i].left != lines[i - 1].left ? sign : 0;
        steps_r += lines[i].right != lines[i - 1].right ? sign : 0;
      };
      for (uint32_t i = 0; i < k; ++i) {
        add(j + i, 1.0);
        if (i > 0) step(j + i, 1);
      }
      const double inv_k = 1.0 / static_cast<double>(k);
      for (uint32_t s = j; s + k <= e; ++s) {
        if (s > j) {
          add(s - 1, -1.0);
          add(s + k - 1, 1.0);
          step(s, -1);
          step(s + k - 1, 1);
        }
        // rank = beta + centre term, beta >= 0: once the list is full, a window whose
        // centre term alone reaches the last rank cannot enter it (the float sum of
        // non-negative terms is at least each term), so its fit is skipped.
        const float y_centre = 0.5f * (lines[s].y + lines[s + k - 1].y);
        const float centre_term = centre_weight * std::fabs(y_centre - y_ref);
        if (found >= max_out && !(centre_term < out[max_out - 1].rank)) continue;
        const double my = sy * inv_k;
        const double vyy = syy - sy * my;  // k * var(y)
        if (!(vyy > 1e-18)) continue;
        const double al = steps_l == 0 ? 0.0 : (syl - sl * my) / vyy;
        const double ar = steps_r == 0 ? 0.0 : (syr - sr * my) / vyy;
        SideFit c;
        c.first = s;
        c.count = k;
        c.a_left = static_cast<float>(al);
        c.b_left = steps_l == 0 ? lines[s].left : static_cast<float>(l0 + sl * inv_k - al * (y0 + my));
        c.a_right = static_cast<float>(ar);
        c.b_right = steps_r == 0 ? lines[s].right : static_cast<float>(r0 + sr * inv_k - ar * (y0 + my));
        if (!(std::isfinite(c.a_left) && std::isfinite(c.b_left) && std::isfinite(c.a_right) &&
              std::isfinite(c.b_right)))
          continue;
        c.beta = side_angle(c.a_left, c.a_right);
        c.y_centre = y_centre;
        c.rank = c.beta + centre_term;
        if (found >= max_out && !(c.rank < out[max_out - 1].rank)) continue;
        insert_best(out, found, max_out, c);
      }
    }
    j = e;
  }
  // Only the windows that stayed in the list need their mean centre and width.
  for (uint32_t q = 0; q < found; ++q) {
    SideFit& c = out[q];
    float xc = 0.f, w = 0.f;
    for (uint32_t i = 0; i < k; ++i) {
      xc += 0.5f * (lines[c.first + i].left + lines[c.first + i].right);
      w += lines[c.first + i].right - lines[c.first + i].left;
    }
    c.x_centre = xc / static_cast<float>(k);
    c.width = w / static_cast<float>(k);
  }
  return found;
}

}  // namespace fg
