// 2D hulls over caller memory: Andrew's monotone chain (convex) and a raster concave
// hull (closing, hole filling, component choice, crack-following boundary trace),
// plus small polygon queries. No allocation, no exceptions; every loop is bounded by
// n, the raster size or a small constant.
#include "fg/core/hull.hpp"

#include "fg/core/byte_flags.hpp"
#include "fg/core/byte_order.hpp"
#include "fg/core/vec4.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace fg {
namespace {

//! Both coordinates finite: neither exponent field is all ones (one test per point,
//! no branch; the hull's passes over the points make this hot).
bool is_finite(const Vec2& p) {
  uint32_t bx, by;
  std::memcpy(&bx, &p.x, sizeof bx);
  std::memcpy(&by, &p.y, sizeof by);
  constexpr uint32_t kExp = 0x7F800000u;
  return ((bx & kExp) != kExp) & ((by & kExp) != kExp);
}

bool same(const Vec2& a, const Vec2& b) { return a.x == b.x && a.y == b.y; }

bool lex_less(const Vec2& a, const Vec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); }

//! (a - o) x (b - o) in double: > 0 when o -> a -> b turns left (counter-clockwise).
double cross(const Vec2& o, const Vec2& a, const Vec2& b) {
  const double ax = static_cast<double>(a.x) - o.x;
  const double ay = static_cast<double>(a.y) - o.y;
  const double bx = static_cast<double>(b.x) - o.x;
  const double by = static_cast<double>(b.y) - o.y;
  return ax * by - ay * bx;
}

// ----------------------------------------------------------------------------------
// Raster concave hull helpers. Cell flag bits (the first half of ConcaveHullScratch::raster):
//   binning       : bits1-7 a full cell's slot + 1 (0: none); occupied cells are
//                   those with a count (the closed image ORs them in)
//   after closing : bit0 foreground (F), bit1 visited, bits2-4 DFS parent direction,
//                   bit5 "current component" mark used by the exact recount
// The second half holds the number of points per cell, saturated at 255, and
// ConcaveHullScratch::full the exact counts of the saturated ("full") cells;
// ConcaveHullScratch::rows holds the closing's images, one bit per cell.
constexpr uint8_t kSlotShift = 1;

constexpr uint8_t kFg = 0x01;
constexpr uint8_t kVisited = 0x02;
constexpr uint8_t kParentShift = 2;
constexpr uint8_t kParentMask = 0x1C;
constexpr uint8_t kCurrent = 0x20;
constexpr uint64_t kBytes01 = 0x0101010101010101u;  // bit 0 of each of 8 cells read as one word

// 8 directions, counter-clockwise from east. 4-connectivity uses the even ones.
constexpr int kDx8[8] = {1, 1, 0, -1, -1, -1, 0, 1};
constexpr int kDy8[8] = {0, 1, 1, 1, 0, -1, -1, -1};

//! Geometry of the raster: cell (i, j) spans [xs[i], xs[i+1]] x [ys[j], ys[j+1]],
//! row-major with index j * w + i, row 0 at the smallest y. The corners are the exact
//! grid (origin + i * cell, in double) rounded to the nearest float; a point's cell is
//! its truncated offset from the origin in cells, computed in double.
struct Raster {
  double origin_x;  // the exact lower-left corner of cell (0, 0)
  double origin_y;
  double cell;
  double inv_cell;
  uint32_t w;
  uint32_t h;
  float* xs;  // xs[i] = vx(i) for i = 0..w, ys[j] = vy(j) for j = 0..h (set by corners())
  float* ys;

  float vx(int64_t i) const { return static_cast<float>(origin_x + static_cast<double>(i) * cell); }
  float vy(int64_t j) const { return static_cast<float>(origin_y + static_cast<double>(j) * cell); }

  //! Tabulates the float corner coordinates (the polygon's vertices).
  void corners(float* x_table, float* y_table) {
    xs = x_table;
    ys = y_table;
    for (uint32_t i = 0; i <= w; ++i) xs[i] = vx(i);
    for (uint32_t j = 0; j <= h; ++j) ys[j] = vy(j);
  }

  //! The cell (column, row) of a finite point of the raster's span: no point lies
  //! outside its own cell's float corners. The column is the truncated double
  //! (x - origin) / cell, whose threshold T_i for column i is the exact corner to
  //! within ~1e-15 relative; the float corner is T_i rounded to nearest. A float x
  //! below xs[i] is at least one float step below it, so below T_i: it is never put
  //! in column i; likewise a float above xs[i+1] is in column i + 1 or more. So the
  //! points of cell i lie in [xs[i], xs[i+1]] (one exactly on a corner may go to
  //! either cell, and lies on both). The points lie at least a cell inside the raster
  //! (its margin); the clamps only keep a broken caller's point from indexing outside.
  //! x and y go in the two lanes of one double vector (the same IEEE operations), are
  //! clamped to [0, w - 1] x [0, h - 1] before the truncation (the same cell as
  //! truncating then clamping), and so convert to 32-bit integers.
  void cell_of(const Vec2& p, uint32_t& col, uint32_t& row) const {
    typedef double V2d __attribute__((vector_size(16)));
    typedef int32_t V2i __attribute__((vector_size(8)));
    V2d t = (V2d{static_cast<double>(p.x), static_cast<double>(p.y)} - V2d{origin_x, origin_y}) * inv_cell;
    const V2d top{static_cast<double>(w - 1), static_cast<double>(h - 1)};
    t = t > 0.0 ? t : V2d{};  // a finite point's t is finite
    t = t < top ? t : top;
    const V2i ij = __builtin_convertvector(t, V2i);
    col = static_cast<uint32_t>(ij[0]);
    row = static_cast<uint32_t>(ij[1]);
  }
  uint32_t index_of(const Vec2& p) const {
    uint32_t col, row;
    cell_of(p, col, row);
    return row * w + col;
  }
};

#if defined(__SSE2__)
//! The same for p[0..15].
inline uint32_t nonzero_bytes16(const uint8_t* p) {
  const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
  return ~static_cast<uint32_t>(_mm_movemask_epi8(_mm_cmpeq_epi8(v, _mm_setzero_si128()))) & 0xFFFFu;
}
#endif

//! Rows of a raster as bit sets: cell i of a row is bit i % 64 of word i / 64; bits
//! at and past the row's width stay 0.
struct BitRows {
  uint64_t* bits;
  uint32_t words;  // per row
  uint32_t h;
  uint64_t last_mask;  // the valid bits of a row's last word

  uint64_t* row(uint32_t j) const { return bits + static_cast<size_t>(j) * words; }

  //! One word of `src` shifted by s cells (s > 0: towards larger i), zeros shifted in.
  static uint64_t shifted_word(const uint64_t* src, uint32_t words, uint32_t k, int32_t s) {
    const int32_t ws = s >= 0 ? s / 64 : -((-s + 63) / 64);  // floor(s / 64)
    const uint32_t b = static_cast<uint32_t>(s - ws * 64);   // 0..63
    const int64_t lo = static_cast<int64_t>(k) - ws;         // source word of the low part
    auto at = [&](int64_t q) { return q >= 0 && q < static_cast<int64_t>(words) ? src[q] : uint64_t{0}; };
    if (b == 0) return at(lo);
    return (at(lo) << b) | (at(lo - 1) >> (64 - b));
  }

  //! out = the union (dilate) or the intersection (erode) of `in` shifted by -r..r
  //! cells along each row; cells beyond the row count as unset.
  void along_rows(const BitRows& in, uint32_t r, bool erode) const {
    for (uint32_t j = 0; j < h; ++j) {
      const uint64_t* src = in.row(j);
      uint64_t* dst = row(j);
      if (r < 64) {
        // Shifts within a word and its two neighbours: shifted_word's values.
        for (uint32_t k = 0; k < words; ++k) {
          const uint64_t prev = k > 0 ? src[k - 1] : 0, cur = src[k], next = k + 1 < words ? src[k + 1] : 0;
          uint64_t acc = cur;
          for (uint32_t s = 1; s <= r; ++s) {
            const uint64_t a = (cur << s) | (prev >> (64 - s));
            const uint64_t b = (cur >> s) | (next << (64 - s));
            acc = erode ? (acc & a & b) : (acc | a | b);
          }
          dst[k] = k + 1 == words ? (acc & last_mask) : acc;
        }
        continue;
      }
      for (uint32_t k = 0; k < words; ++k) {
        uint64_t acc = src[k];
        for (uint32_t s = 1; s <= r; ++s) {
          const uint64_t a = shifted_word(src, words, k, static_cast<int32_t>(s));
          const uint64_t b = shifted_word(src, words, k, -static_cast<int32_t>(s));
          acc = erode ? (acc & a & b) : (acc | a | b);
        }
        dst[k] = k + 1 == words ? (acc & last_mask) : acc;
      }
    }
  }

  //! The same across rows (rows beyond the raster count as unset).
  void across_rows(const BitRows& in, uint32_t r, bool erode) const {
    for (uint32_t j = 0; j < h; ++j) {
      const bool clipped = j < r || j + r >= h;
      for (uint32_t k = 0; k < words; ++k) {
        if (erode && clipped) {
          row(j)[k] = 0;
          continue;
        }
        uint64_t acc = in.row(j)[k];
        for (uint32_t t = 1; t <= r; ++t) {
          if (erode) {
            acc &= in.row(j - t)[k] & in.row(j + t)[k];
          } else {
            if (j >= t) acc |= in.row(j - t)[k];
            if (j + t < h) acc |= in.row(j + t)[k];
          }
        }
        row(j)[k] = acc;
      }
    }
  }
};

//! Points per cell: the saturated counts (the raster's second half), exact through the
//! full cells' table (sorted by cell) where a count saturated.
struct CellCounts {
  const uint8_t* counts;
  const ConcaveHullScratch::FullCell* full;
  uint32_t n_full;

  //! The points in cell k; `uncounted` is set when its count saturated and the table
  //! did not have room for it (the result, 255, is then a lower bound).
  uint32_t at(uint32_t k, bool& uncounted) const {
    const uint32_t c = counts[k];
    if (c != 255) return c;
    uint32_t lo = 0, hi = n_full;  // bisection: the first entry with cell >= k
    while (lo < hi) {
      const uint32_t mid = (lo + hi) / 2;
      if (full[mid].cell < k) {
        lo = mid + 1;
      } else {
        hi = mid;
      }
    }
    if (lo < n_full && full[lo].cell == k) return full[lo].points;
    uncounted = true;
    return c;
  }
};

struct DfsResult {
  uint64_t points;  //!< sum of the per-cell point counts
  bool saturated;   //!< some cell's count was not kept: `points` is a lower bound
  bool ok;          //!< false only if the step bound was hit (a bug)
};

//! Iterative depth-first flood from `start` over the cells whose F bit equals
//! `want_fg`, 4- (dir_step 2) or 8-connected (dir_step 1). Marks them with `mark`; the
//! path back to `start` is kept as parent directions in the cell bits, so no stack is
//! needed. Each cell is entered once and left once. Every cell the flood may enter is
//! interior (off the raster's outer ring): the callers make the ring fail its test
//! (background for a foreground flood, marked before a background flood), so a
//! neighbour is one index offset away, with no bounds test.
[[nodiscard]] DfsResult flood(uint8_t* g, const CellCounts* counts, uint32_t w, uint32_t h, uint32_t start,
                              bool want_fg, int dir_step, uint8_t mark) {
  DfsResult res{0, false, true};
  const uint64_t cells = static_cast<uint64_t>(w) * h;
  const uint64_t max_steps = 2 * cells + 2;
  int64_t off[8];  // index offsets of the 8 directions
  for (int d = 0; d < 8; ++d) off[d] = static_cast<int64_t>(kDy8[d]) * static_cast<int64_t>(w) + kDx8[d];
  const uint8_t want = want_fg ? kFg : 0;
  int64_t cur = start;
  g[cur] = static_cast<uint8_t>((g[cur] & ~kParentMask) | mark);
  if (counts != nullptr) res.points += counts->at(static_cast<uint32_t>(cur), res.saturated);
  int dir_from = 0;
  for (uint64_t step = 0; step < max_steps; ++step) {
    bool moved = false;
    for (int d = dir_from; d < 8; d += dir_step) {
      const int64_t nb = cur + off[d];
      const uint8_t v = g[nb];
      if ((v & kFg) != want || (v & mark) != 0) continue;
      const int back = (d + 4) & 7;  // direction from this cell back to its parent
      g[nb] = static_cast<uint8_t>((v & ~kParentMask) | mark | (back << kParentShift));
      if (counts != nullptr) res.points += counts->at(static_cast<uint32_t>(nb), res.saturated);
      cur = nb;
      dir_from = 0;
      moved = true;
      break;
    }
    if (moved) continue;
    if (cur == static_cast<int64_t>(start)) return res;
    const int back = (g[cur] & kParentMask) >> kParentShift;
    cur += off[back];
    dir_from = ((back + 4) & 7) + dir_step;  // resume after the child just finished
  }
  res.ok = false;
  return res;
}

//! Union-find over runs: the root of a run's component (path halving; a root is its
//! component's first run in raster order, since unions keep the smaller index).
uint32_t run_root(HullRun* runs, uint32_t x) {
  for (uint32_t guard = 0; runs[x].parent != x && guard < ConcaveHullScratch::kMaxRuns; ++guard) {
    runs[x].parent = runs[runs[x].parent].parent;
    x = runs[x].parent;
  }
  return x;
}

void run_union(HullRun* runs, uint32_t a, uint32_t b) {
  uint32_t ra = run_root(runs, a), rb = run_root(runs, b);
  if (ra == rb) return;
  if (rb < ra) std::swap(ra, rb);
  runs[rb].parent = ra;
  runs[ra].points = ((runs[ra].points | runs[rb].points) & 0x80000000u) +
                    ((runs[ra].points & 0x7FFFFFFFu) + (runs[rb].points & 0x7FFFFFFFu));
}

//! Labels the 8-connected foreground components (kFg cells of g) by runs: each row's
//! runs, with their points summed from `counts`, joined to the runs of the row below
//! that touch them (overlap, or meet diagonally). n_runs receives the count; false
//! when the raster has more runs than `runs` holds (nothing else is then valid).
//! The sums must stay below 2^31 (bit 31 marks an uncounted cell).
[[nodiscard]] bool label_runs(const uint8_t* g, const CellCounts& counts, uint32_t w, uint32_t h, HullRun* runs,
                              uint32_t* row_first, uint32_t& n_runs) {
  n_runs = 0;
  for (uint32_t j = 0; j < h; ++j) {
    row_first[j] = n_runs;
    const uint8_t* line = g + static_cast<size_t>(j) * w;
    const uint8_t* cnt = counts.counts + static_cast<size_t>(j) * w;
    for (uint32_t i = 0; i < w;) {
#if defined(__SSE2__)
      // Background skipped 16 cells at a time, to the first foreground one.
      if (i + 16 <= w) {
        const __m128i fg16 =
            _mm_and_si128(_mm_loadu_si128(reinterpret_cast<const __m128i*>(line + i)), _mm_set1_epi8(kFg));
        const uint32_t set = static_cast<uint32_t>(_mm_movemask_epi8(_mm_cmpeq_epi8(fg16, _mm_set1_epi8(kFg))));
        if (set == 0) {
          i += 16;
          continue;
        }
        i += static_cast<uint32_t>(__builtin_ctz(set));
      }
#endif
      if ((line[i] & kFg) == 0) {
        ++i;
        continue;
      }
      const uint32_t x0 = i;
      uint32_t pts = 0;
      bool sat = false;
      for (;;) {
#if defined(__SSE2__)
        // Sixteen foreground cells at a time while none of them is full: their counts
        // summed by psadbw (two sums of eight, at most 8 * 254 each).
        for (; i + 16 <= w; i += 16) {
          const __m128i fg16 =
              _mm_and_si128(_mm_loadu_si128(reinterpret_cast<const __m128i*>(line + i)), _mm_set1_epi8(kFg));
          const __m128i cnt16 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(cnt + i));
          const __m128i bad = _mm_or_si128(_mm_cmpeq_epi8(fg16, _mm_setzero_si128()),
                                           _mm_cmpeq_epi8(cnt16, _mm_set1_epi8(static_cast<char>(0xFF))));
          if (_mm_movemask_epi8(bad) != 0) break;
          const __m128i sums = _mm_sad_epu8(cnt16, _mm_setzero_si128());
          pts += static_cast<uint32_t>(_mm_cvtsi128_si32(sums)) +
                 static_cast<uint32_t>(_mm_cvtsi128_si32(_mm_unpackhi_epi64(sums, sums)));
        }
#endif
        // Eight foreground cells at a time while none of them is full: their counts
        // summed as one word (bytes -> 16-bit lanes -> one sum, at most 8 * 254).
        for (; i + 8 <= w; i += 8) {
          uint64_t fg8, cnt8;
          std::memcpy(&fg8, line + i, sizeof fg8);
          std::memcpy(&cnt8, cnt + i, sizeof cnt8);
          const uint64_t inv = ~cnt8;  // a count of 255 is a zero byte here
          const bool full = ((inv - kBytes01) & ~inv & (kBytes01 << 7)) != 0;
          if ((fg8 & kBytes01) != kBytes01 || full) break;
          const uint64_t lanes = (cnt8 & 0x00FF00FF00FF00FFu) + ((cnt8 >> 8) & 0x00FF00FF00FF00FFu);
          pts += static_cast<uint32_t>((lanes * 0x0001000100010001u) >> 48);
        }
        if (i >= w || (line[i] & kFg) == 0) break;
        pts += cnt[i] != 255 ? cnt[i] : counts.at(j * w + i, sat);
        ++i;
      }
      if (n_runs == ConcaveHullScratch::kMaxRuns) return false;
      runs[n_runs] =
          HullRun{n_runs, pts | (sat ? 0x80000000u : 0u), static_cast<uint16_t>(x0), static_cast<uint16_t>(i - 1)};
      ++n_runs;
    }
    if (j == 0) continue;
    // Join with the row below: runs a and b touch when a.x0 <= b.x1 + 1 and
    // b.x0 <= a.x1 + 1 (8-connected).
    uint32_t a = row_first[j - 1], b = row_first[j];
    const uint32_t a_end = row_first[j], b_end = n_runs;
    while (a < a_end && b < b_end) {
      if (runs[a].x1 + 1u < runs[b].x0) {
        ++a;
      } else if (runs[b].x1 + 1u < runs[a].x0) {
        ++b;
      } else {
        run_union(runs, a, b);
        if (runs[a].x1 < runs[b].x1) {
          ++a;
        } else {
          ++b;
        }
      }
    }
  }
  row_first[h] = n_runs;
  return true;
}

}  // namespace

// ------------------------------------------------------------------------------------
Status convex_hull_2d(const Vec2* points, uint32_t n, Vec2* scratch, Vec2* out, uint32_t out_capacity,
                      uint32_t& out_n) {
  out_n = 0;
  if (n > 0 && (points == nullptr || scratch == nullptr)) return Status::invalid_argument;
  if (out == nullptr && out_capacity > 0) return Status::invalid_argument;

  uint32_t m = 0;  // finite points copied to scratch
  for (uint32_t i = 0; i < n; ++i) {
    if (is_finite(points[i])) scratch[m++] = points[i];
  }
  if (m == 0) return Status::ok;

  Vec2 lo = scratch[0];
  Vec2 hi = scratch[0];
  for (uint32_t i = 1; i < m; ++i) {
    if (lex_less(scratch[i], lo)) lo = scratch[i];
    if (lex_less(hi, scratch[i])) hi = scratch[i];
  }
  if (same(lo, hi)) {  // all points identical
    if (out_capacity < 1) return Status::capacity_exceeded;
    out[0] = lo;
    out_n = 1;
    return Status::ok;
  }

  // Split by the chord lo -> hi: the lower chain uses lo, hi and the points strictly
  // right of the chord; the upper chain the points strictly left of it. Points on the
  // chord (other than lo, hi) are never vertices. Each group is sorted the way
  // Andrew's passes visit it (lower: ascending; upper: descending).
  Vec2* const g0_end = std::partition(
      scratch, scratch + m, [&](const Vec2& p) { return same(p, lo) || same(p, hi) || cross(lo, hi, p) < 0.0; });
  Vec2* const g1_end = std::partition(g0_end, scratch + m, [&](const Vec2& p) { return cross(lo, hi, p) > 0.0; });
  std::sort(scratch, g0_end, [](const Vec2& a, const Vec2& b) { return lex_less(a, b); });
  std::sort(g0_end, g1_end, [](const Vec2& a, const Vec2& b) { return lex_less(b, a); });

  // Monotone chain, in place: the stack H = scratch[0..k) never overtakes the read index.
  Vec2* const H = scratch;
  uint32_t k = 0;
  const uint32_t n0 = static_cast<uint32_t>(g0_end - scratch);
  for (uint32_t i = 0; i < n0; ++i) {
    const Vec2 q = scratch[i];
    if (k > 0 && same(H[k - 1], q)) continue;
    while (k >= 2 && cross(H[k - 2], H[k - 1], q) <= 0.0) --k;
    H[k++] = q;
  }
  const uint32_t k_lower = k;  // lo ... hi
  const uint32_t n1 = static_cast<uint32_t>(g1_end - g0_end);
  for (uint32_t i = 0; i <= n1; ++i) {
    const Vec2 q = (i < n1) ? g0_end[i] : lo;  // finally close back at lo
    if (same(H[k - 1], q)) continue;
    while (k >= k_lower + 1 && cross(H[k - 2], H[k - 1], q) <= 0.0) --k;
    if (i < n1) H[k++] = q;
  }

  if (k > out_capacity) return Status::capacity_exceeded;
  for (uint32_t i = 0; i < k; ++i) out[i] = H[i];
  out_n = k;
  return Status::ok;
}

// ------------------------------------------------------------------------------------
// The concave hull's steps, in the order concave_hull_2d takes them.
namespace {

constexpr uint32_t kDim = kHullGridDim;

//! Every argument the concave hull refuses: invalid_argument, else ok.
[[nodiscard]] Status check_concave_args(const Vec2* points, uint32_t n, const ConcaveHullParams& params,
                                        const Vec2* out, uint32_t out_capacity) {
  constexpr uint32_t kMaxClosing = (kDim - 5) / 2;
  if (n > 0 && points == nullptr) return Status::invalid_argument;
  if (out == nullptr && out_capacity > 0) return Status::invalid_argument;
  if (!std::isfinite(params.cell_m) || !(params.cell_m > 0.0f)) return Status::invalid_argument;
  if (params.closing_cells > kMaxClosing) return Status::invalid_argument;

  if (params.bounds_given &&
      !(std::isfinite(params.xmin) && std::isfinite(params.ymin) && std::isfinite(params.xmax) &&
        std::isfinite(params.ymax) && params.xmin <= params.xmax && params.ymin <= params.ymax)) {
    return Status::invalid_argument;
  }
  return Status::ok;
}

//! The finite points' bounding box (or the caller's), and how many points are finite.
struct PointBounds {
  uint32_t finite;
  float xmin, ymin, xmax, ymax;
};

//! The bounding box of the finite points from points[first], the first finite one (or
//! the caller's box, every point then counted finite).
PointBounds bounding_box(const Vec2* points, uint32_t n, uint32_t first, const ConcaveHullParams& params) {
  uint32_t finite = params.bounds_given ? n : 1;
  float xmin = points[first].x, xmax = xmin, ymin = points[first].y, ymax = ymin;
  if (params.bounds_given) {
    xmin = params.xmin;
    ymin = params.ymin;
    xmax = params.xmax;
    ymax = params.ymax;
  } else {
    // Four points, two (x, y, x, y) vectors, per step, the non-finite coordinates only
    // noted (an exponent of all ones); where there was one, every point again one by
    // one (the steps' bounds may hold NaN).
    const V4f start{xmin, ymin, xmin, ymin};
    V4f lo = start, hi = start;
    uint32_t i = first + 1;
    auto one = [&](const Vec2& p) {
      if (!is_finite(p)) return;
      lo = V4f{p.x < lo[0] ? p.x : lo[0], p.y < lo[1] ? p.y : lo[1], lo[2], lo[3]};
      hi = V4f{p.x > hi[0] ? p.x : hi[0], p.y > hi[1] ? p.y : hi[1], hi[2], hi[3]};
      ++finite;
    };
    V4i inf_or_nan{};
    for (; i + 4 <= n; i += 4) {
      V4f a, b;
      std::memcpy(&a, points + i, sizeof a);
      std::memcpy(&b, points + i + 2, sizeof b);
      V4i bits_a, bits_b;
      std::memcpy(&bits_a, &a, sizeof bits_a);
      std::memcpy(&bits_b, &b, sizeof bits_b);
      inf_or_nan |= ((bits_a & 0x7F800000) == 0x7F800000) | ((bits_b & 0x7F800000) == 0x7F800000);
      const V4f lo_ab = a < b ? a : b, hi_ab = a > b ? a : b;
      lo = lo_ab < lo ? lo_ab : lo;
      hi = hi_ab > hi ? hi_ab : hi;
    }
    if (lane_mask(inf_or_nan) != 0) {
      lo = hi = start;
      i = first + 1;
    } else {
      finite += i - (first + 1);
    }
    for (; i < n; ++i) one(points[i]);
    xmin = lo[2] < lo[0] ? lo[2] : lo[0];
    ymin = lo[3] < lo[1] ? lo[3] : lo[1];
    xmax = hi[2] > hi[0] ? hi[2] : hi[0];
    ymax = hi[3] > hi[1] ? hi[3] : hi[1];
  }
  return PointBounds{finite, xmin, ymin, xmax, ymax};
}

//! The raster's cell size and placement over the bounding box b (corners not yet
//! tabulated), and the float cell size in cell_f. numeric_failure when the cell or the
//! raster's corners overflow float; internal_error when the raster would not fit.
[[nodiscard]] Status place_raster(const PointBounds& b, uint32_t r, float cell_m, Raster& ras, float& cell_f) {
  const float xmin = b.xmin, ymin = b.ymin, xmax = b.xmax, ymax = b.ymax;
  // Cell size: large enough that the occupied span plus a margin of r + 1 empty
  // cells on every side fits the kDim x kDim raster, and at least two float ulps of
  // the coordinates (so the float cell corners are strictly increasing even for
  // points far from the origin).
  const uint32_t avail = kDim - 2 * r - 4;
  const double ext_x = static_cast<double>(xmax) - xmin;
  const double ext_y = static_cast<double>(ymax) - ymin;
  const double max_abs = std::max(std::max(std::fabs(static_cast<double>(xmin)), std::fabs(static_cast<double>(xmax))),
                                  std::max(std::fabs(static_cast<double>(ymin)), std::fabs(static_cast<double>(ymax))));
  const double ulp = max_abs > 0.0 ? std::ldexp(1.0, std::ilogb(2.0 * max_abs) - 23) : 0.0;
  const double need = std::max(std::max(ext_x, ext_y) / static_cast<double>(avail), 2.0 * ulp);
  cell_f = cell_m;
  if (need > static_cast<double>(cell_f)) {
    cell_f = static_cast<float>(need);
    if (static_cast<double>(cell_f) < need) {
      cell_f = std::nextafter(cell_f, std::numeric_limits<float>::infinity());  // round up
    }
  }
  if (!std::isfinite(cell_f)) return Status::numeric_failure;
  const double cell = cell_f;
  // Cells spanned per axis; the slack (between 1/2 and 3/2 cell) is split evenly so
  // the extreme points sit well inside their cells.
  const uint32_t mx = static_cast<uint32_t>(std::floor(ext_x / cell + 0.5)) + 1;
  const uint32_t my = static_cast<uint32_t>(std::floor(ext_y / cell + 0.5)) + 1;
  const uint32_t margin = r + 1;
  ras = Raster{};
  ras.cell = cell;
  ras.inv_cell = 1.0 / cell;
  ras.w = mx + 2 * margin;
  ras.h = my + 2 * margin;
  if (ras.w > kDim || ras.h > kDim) return Status::internal_error;
  ras.origin_x = xmin - 0.5 * (mx * cell - ext_x) - margin * cell;
  ras.origin_y = ymin - 0.5 * (my * cell - ext_y) - margin * cell;
  if (!std::isfinite(ras.vx(0)) || !std::isfinite(ras.vx(ras.w)) || !std::isfinite(ras.vy(0)) ||
      !std::isfinite(ras.vy(ras.h))) {
    return Status::numeric_failure;  // the raster's corners are beyond the float range
  }
  return Status::ok;
}

//! The raster and the scratch memory the steps below share: the cell flags g, the
//! per-cell counts, the closing's two bit images and the full cells' table.
struct HullGrid {
  Raster ras;
  uint32_t w, h, cells;
  uint8_t* g;
  uint8_t* counts;
  BitRows occ, tmp;
  ConcaveHullScratch::FullCell* full;
  uint32_t n_full;

  //! The raster `placed` with its corners tabulated in the scratch, every cell's flags
  //! and count cleared, and the occupancy image empty.
  HullGrid(const Raster& placed, ConcaveHullScratch& scratch)
      : ras(placed),
        w(placed.w),
        h(placed.h),
        cells(placed.w * placed.h),
        g(scratch.raster),
        counts(scratch.raster + ConcaveHullScratch::kRasterCells),
        occ{},
        tmp{},
        full(scratch.full),
        n_full(0) {
    ras.corners(scratch.corner_x, scratch.corner_y);
    for (uint32_t k = 0; k < cells; ++k) {
      g[k] = 0;
      counts[k] = 0;
    }
    const uint32_t words = (w + 63) / 64;
    const uint32_t tail_bits = w - (words - 1) * 64;
    occ = BitRows{scratch.rows[0], words, h, tail_bits == 64 ? ~uint64_t{0} : (uint64_t{1} << tail_bits) - 1};
    tmp = BitRows{scratch.rows[1], words, h, occ.last_mask};
    for (uint32_t k = 0; k < words * h; ++k) occ.bits[k] = 0;
  }
};

//! Bins the points: per point only its cell's count, saturated at 255 (almost always
//! the first branch); a cell reaching 255 points takes a slot of the full cells'
//! table (its slot + 1 in the cell's high bits) while there is one, and the table's
//! counts are exact. Component sums stay below 2^31 (label_runs) when n does.
void bin_points(HullGrid& grid, const Vec2* points, uint32_t n, bool all_finite) {
  const Raster& ras = grid.ras;
  uint8_t* const g = grid.g;
  uint8_t* const counts = grid.counts;
  ConcaveHullScratch::FullCell* const full = grid.full;
  const uint32_t full_capacity = n < 0x80000000u ? ConcaveHullScratch::kMaxFullCells : 0;
  uint32_t n_full = 0;
  auto bin = [&](uint32_t k) {
    const uint8_t c = counts[k];
    if (c < 254) {
      counts[k] = static_cast<uint8_t>(c + 1);
    } else if (c == 254) {
      counts[k] = 255;
      if (n_full < full_capacity) {
        full[n_full] = ConcaveHullScratch::FullCell{k, 255};
        g[k] = static_cast<uint8_t>((n_full + 1) << kSlotShift);
        ++n_full;
      }
    } else if (const uint32_t slot = g[k] >> kSlotShift; slot != 0) {
      ++full[slot - 1].points;
    }
  };
  if (all_finite) {
    uint32_t i = 0;
#if defined(__SSE2__)
    const uint32_t w = grid.w, h = grid.h;
    // Two points per step: cell_of()'s operations in the lanes of two double vectors,
    // then each cell's index row * w + col in one multiply-add of 16-bit lanes (rows
    // and columns are below kHullGridDim <= 4096).
    const __m128d org = _mm_set_pd(ras.origin_y, ras.origin_x), inv = _mm_set1_pd(ras.inv_cell);
    const __m128d top = _mm_set_pd(static_cast<double>(h - 1), static_cast<double>(w - 1));
    const __m128i row_len = _mm_set_epi16(static_cast<int16_t>(w), 1, static_cast<int16_t>(w), 1,
                                          static_cast<int16_t>(w), 1, static_cast<int16_t>(w), 1);
    for (; i + 2 <= n; i += 2) {
      const __m128 xy = _mm_loadu_ps(&points[i].x);  // x0 y0 x1 y1
      const __m128d t0 = _mm_mul_pd(_mm_sub_pd(_mm_cvtps_pd(xy), org), inv);
      const __m128d t1 = _mm_mul_pd(_mm_sub_pd(_mm_cvtps_pd(_mm_movehl_ps(xy, xy)), org), inv);
      const __m128i ij = _mm_unpacklo_epi64(_mm_cvttpd_epi32(_mm_min_pd(_mm_max_pd(t0, _mm_setzero_pd()), top)),
                                            _mm_cvttpd_epi32(_mm_min_pd(_mm_max_pd(t1, _mm_setzero_pd()), top)));
      const __m128i k = _mm_madd_epi16(_mm_packs_epi32(ij, ij), row_len);
      bin(static_cast<uint32_t>(_mm_cvtsi128_si32(k)));
      bin(static_cast<uint32_t>(_mm_cvtsi128_si32(_mm_shuffle_epi32(k, 1))));
    }
#endif
    for (; i < n; ++i) bin(ras.index_of(points[i]));
  } else {
    for (uint32_t i = 0; i < n; ++i)
      if (is_finite(points[i])) bin(ras.index_of(points[i]));
  }
  grid.n_full = n_full;
}

//! The occupied cells (a count above 0) as the occupancy image's bits.
void mark_occupied(const HullGrid& grid) {
  for (uint32_t j = 0; j < grid.h; ++j) {
    const uint8_t* count_line = grid.counts + static_cast<size_t>(j) * grid.w;
    uint64_t* bits = grid.occ.row(j);
    uint32_t c = 0;
#if defined(__SSE2__)
    for (; c + 16 <= grid.w; c += 16)
      bits[c / 64] |= static_cast<uint64_t>(nonzero_bytes16(count_line + c)) << (c % 64);
#endif
    for (; c + 8 <= grid.w; c += 8) bits[c / 64] |= static_cast<uint64_t>(nonzero_bytes8(count_line + c)) << (c % 64);
    for (; c < grid.w; ++c)
      if (count_line[c] != 0) bits[c / 64] |= uint64_t{1} << (c % 64);
  }
}

//! The full cells' table sorted by cell (insertion sort: at most a few dozen), for the
//! look-ups of the component counts.
void sort_full_cells(ConcaveHullScratch::FullCell* full, uint32_t n_full) {
  for (uint32_t a = 1; a < n_full; ++a) {
    const ConcaveHullScratch::FullCell e = full[a];
    uint32_t b = a;
    for (; b > 0 && full[b - 1].cell > e.cell; --b) full[b] = full[b - 1];
    full[b] = e;
  }
}

//! Closing (dilate then erode) with a (2r+1)^2 square, separably, on bit rows (the
//! occupancy image is overwritten by the steps, ending as the closed image); then the
//! closed image, with the occupied cells ORed back in (a no-op with the margin, kept so
//! the guarantee never rests on it), becomes the foreground bit of every cell.
void close_image(const HullGrid& grid, uint32_t r) {
  const uint32_t w = grid.w;
  grid.tmp.along_rows(grid.occ, r, false);
  grid.occ.across_rows(grid.tmp, r, false);
  grid.tmp.along_rows(grid.occ, r, true);
  grid.occ.across_rows(grid.tmp, r, true);
  for (uint32_t j = 0; j < grid.h; ++j) {
    const uint64_t* closed = grid.occ.row(j);
    const uint8_t* count_line = grid.counts + static_cast<size_t>(j) * w;
    uint8_t* line = grid.g + static_cast<size_t>(j) * w;
    static_assert(kFg == 1, "the foreground bit is bit 0");
    uint32_t c = 0;
#if defined(__SSE2__)
    for (; c + 16 <= w; c += 16) {  // 16 cells: bit b of the closed row or a point -> byte b = 1
      const uint32_t bits16 = static_cast<uint32_t>(closed[c / 64] >> (c % 64)) & 0xFFFFu;
      const __m128i one = _mm_set1_epi8(1), pick = _mm_set1_epi64x(static_cast<int64_t>(0x8040201008040201u));
      const __m128i spread = _mm_set_epi64x(static_cast<int64_t>((bits16 >> 8) * kBytes01),
                                            static_cast<int64_t>((bits16 & 0xFFu) * kBytes01));
      const __m128i set = _mm_cmpeq_epi8(_mm_and_si128(spread, pick), pick);
      const __m128i empty =
          _mm_cmpeq_epi8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(count_line + c)), _mm_setzero_si128());
      _mm_storeu_si128(reinterpret_cast<__m128i*>(line + c), _mm_and_si128(_mm_or_si128(set, ~empty), one));
    }
#endif
    for (; c + 8 <= w; c += 8) {  // 8 cells at a time: bit b of the byte -> byte b (0 or 1)
      const uint64_t byte = (closed[c / 64] >> (c % 64)) & 0xFFu;
      const uint64_t picked = (byte * kBytes01) & 0x8040201008040201u;
      const uint64_t spread = ((picked + 0x7F7F7F7F7F7F7F7Fu) >> 7) & kBytes01;
      uint64_t c8;
      std::memcpy(&c8, count_line + c, sizeof c8);                     // nonzero_ones8 keeps each byte in its place
      const uint64_t cells8 = le_order64(spread) | nonzero_ones8(c8);  // spread's byte b is cell c + b
      std::memcpy(line + c, &cells8, sizeof cells8);
    }
    for (; c < w; ++c) line[c] = static_cast<uint8_t>(((closed[c / 64] >> (c % 64)) & kFg) | (count_line[c] != 0));
  }
}

//! Fills the holes of the closed image; false when a flood hit its step bound (a bug).
[[nodiscard]] bool fill_holes(const HullGrid& grid) {
  const uint32_t w = grid.w, h = grid.h;
  uint8_t* const g = grid.g;
  // The dilation cannot reach the outer ring of cells; make that an invariant: the ring
  // is background, and marked visited for the hole filling below.
  for (uint32_t i = 0; i < w; ++i) {
    g[i] = kVisited;
    g[(h - 1) * w + i] = kVisited;
  }
  for (uint32_t j = 0; j < h; ++j) {
    g[static_cast<size_t>(j) * w] = kVisited;
    g[j * w + w - 1] = kVisited;
  }

  // Fill holes: flood the background (4-connected, the dual of 8-connected
  // foreground) from the outer ring; every background cell not reached is a hole. The
  // ring is marked (above) and the flood starts from each unmarked background cell next
  // to it (the flood never steps onto the ring).
  auto flood_background = [&](uint32_t i, uint32_t j) {
    const uint32_t k = j * w + i;
    return (g[k] & (kFg | kVisited)) != 0 || flood(g, nullptr, w, h, k, false, 2, kVisited).ok;
  };
  for (uint32_t i = 1; i + 1 < w; ++i)
    if (!flood_background(i, 1) || !flood_background(i, h - 2)) return false;
  for (uint32_t j = 1; j + 1 < h; ++j)
    if (!flood_background(1, j) || !flood_background(w - 2, j)) return false;
  for (uint32_t k = 0; k < grid.cells; ++k) g[k] = ((g[k] & kFg) || !(g[k] & kVisited)) ? kFg : 0;
  return true;
}

//! The component the hull traces: its first cell (start; grid.cells while none is
//! found) and the points it holds.
struct Component {
  uint32_t start;
  uint64_t points;
};

//! The exact count of the points in the cells marked kCurrent; clears the marks.
uint64_t count_marked(const HullGrid& grid, const Vec2* points, uint32_t n) {
  uint8_t* const g = grid.g;
  uint64_t marked = 0;
  for (uint32_t i = 0; i < n; ++i) {
    if (is_finite(points[i]) && (g[grid.ras.index_of(points[i])] & kCurrent)) ++marked;
  }
  for (uint32_t c = 0; c < grid.cells; ++c) g[c] = static_cast<uint8_t>(g[c] & ~kCurrent);
  return marked;
}

//! The component with the most points among those labelled by runs (label_runs filled
//! runs and row_first), ties to the earlier one; a component with an uncounted cell is
//! recounted over the points.
Component best_labelled_component(const HullGrid& grid, HullRun* runs, const uint32_t* row_first, const Vec2* points,
                                  uint32_t n) {
  const uint32_t w = grid.w, h = grid.h;
  Component best{grid.cells, 0};
  for (uint32_t j = 0; j < h; ++j) {
    for (uint32_t q = row_first[j]; q < row_first[j + 1]; ++q) {
      if (runs[q].parent != q) continue;  // not a component's first run
      uint64_t pts = runs[q].points & 0x7FFFFFFFu;
      if ((runs[q].points & 0x80000000u) != 0) {
        // Exact recount: mark the component's cells, count the points in them.
        for (uint32_t jj = j; jj < h; ++jj)
          for (uint32_t p = row_first[jj]; p < row_first[jj + 1]; ++p)
            if (run_root(runs, p) == q)
              for (uint32_t c = runs[p].x0; c <= runs[p].x1; ++c) grid.g[jj * w + c] |= kCurrent;
        pts = count_marked(grid, points, n);
      }
      if (best.start == grid.cells || pts > best.points) {
        best.points = pts;
        best.start = j * w + runs[q].x0;
      }
    }
  }
  return best;
}

//! The same choice by flooding the components one by one (a raster with more runs than
//! the scratch holds); false when a flood hit its step bound (a bug).
[[nodiscard]] bool best_flooded_component(const HullGrid& grid, const CellCounts& cell_counts, const Vec2* points,
                                          uint32_t n, uint32_t finite, Component& best) {
  uint8_t* const g = grid.g;
  best = Component{grid.cells, 0};
  for (uint32_t k = 0; k < grid.cells; ++k) {
    if (!(g[k] & kFg) || (g[k] & kVisited)) continue;
    const DfsResult comp = flood(g, &cell_counts, grid.w, grid.h, k, true, 1, kVisited);
    if (!comp.ok) return false;
    uint64_t pts = comp.points;
    if (comp.saturated) {
      if (!flood(g, nullptr, grid.w, grid.h, k, true, 1, kCurrent).ok) return false;
      pts = count_marked(grid, points, n);
    }
    if (best.start == grid.cells || pts > best.points) {
      best.points = pts;
      best.start = k;
    }
    // Holding every point, it wins: any later component has none, and ties go to it.
    if (best.points == finite) break;
  }
  return true;
}

//! Components (8-connected) in raster order; keep the one with the most points
//! (ties: the earlier one). Counts come from the per-cell counts and the full cells'
//! table; a component with a full cell the table had no room for is recounted over
//! the points (only inputs beyond kMaxObjectPoints). Labelled by runs of the rows; a raster
//! with more runs than the scratch holds is flooded component by component instead.
//! internal_error when no component is found (a point's cell is always set) or a flood
//! hit its bound.
[[nodiscard]] Status choose_component(const HullGrid& grid, HullRun* runs, const Vec2* points, uint32_t n,
                                      uint32_t finite, Component& best) {
  const CellCounts cell_counts{grid.counts, grid.full, grid.n_full};
  uint32_t row_first[kDim + 1];
  uint32_t n_runs = 0;
  if (label_runs(grid.g, cell_counts, grid.w, grid.h, runs, row_first, n_runs)) {
    best = best_labelled_component(grid, runs, row_first, points, n);
  } else if (!best_flooded_component(grid, cell_counts, points, n, finite, best)) {
    return Status::internal_error;
  }
  if (best.start == grid.cells) return Status::internal_error;  // a point's cell is always set
  return Status::ok;
}

// The boundary trace's directions 0 E, 1 N, 2 W, 3 S; offsets of the AL and AR cells
// from the corner.
constexpr int kStepX[4] = {1, 0, -1, 0};
constexpr int kStepY[4] = {0, 1, 0, -1};
constexpr int kAlX[4] = {0, -1, -1, 0};
constexpr int kAlY[4] = {0, 0, -1, -1};
constexpr int kArX[4] = {0, 0, -1, -1};
constexpr int kArY[4] = {-1, 0, 0, -1};

//! Trace the outer boundary along cell edges, foreground on the left (so the loop
//! is counter-clockwise), starting at the bottom-left corner of the component's
//! first cell heading east. At a corner, with AL / AR the cells ahead-left /
//! ahead-right: AR set -> turn right (this also joins diagonal neighbours: the
//! 8-connected reading), else AL set -> straight, else turn left. Vertices are
//! written only where the direction changes, so collinear runs are merged.
[[nodiscard]] Status trace_boundary(const HullGrid& grid, uint32_t best_start, Vec2* out, uint32_t out_capacity,
                                    uint32_t& out_n) {
  const uint32_t w = grid.w, h = grid.h;
  const uint8_t* const g = grid.g;
  const Raster& ras = grid.ras;
  auto fg_at = [&](int64_t i, int64_t j) {
    if (i < 0 || j < 0 || i >= static_cast<int64_t>(w) || j >= static_cast<int64_t>(h)) return false;
    return (g[static_cast<uint32_t>(j) * w + static_cast<uint32_t>(i)] & kFg) != 0;
  };
  const int64_t sx = best_start % w;
  const int64_t sy = best_start / w;
  uint32_t nv = 0;
  auto emit = [&](int64_t x, int64_t y) {
    if (nv >= out_capacity) return false;
    out[nv++] = Vec2{ras.xs[x], ras.ys[y]};
    return true;
  };
  if (!emit(sx, sy)) return Status::capacity_exceeded;
  int dir = 0;
  int64_t x = sx + 1;
  int64_t y = sy;
  const uint64_t max_steps = 4 * static_cast<uint64_t>(grid.cells) + 4;
  bool closed = false;
  for (uint64_t step = 0; step < max_steps; ++step) {
    if (x == sx && y == sy) {
      closed = true;
      break;
    }
    const bool ar = fg_at(x + kArX[dir], y + kArY[dir]);
    const bool al = fg_at(x + kAlX[dir], y + kAlY[dir]);
    const int next = ar ? (dir + 3) & 3 : (al ? dir : (dir + 1) & 3);
    if (next != dir) {
      if (!emit(x, y)) {
        out_n = 0;
        return Status::capacity_exceeded;
      }
    }
    dir = next;
    x += kStepX[dir];
    y += kStepY[dir];
  }
  if (!closed) return Status::internal_error;
  out_n = nv;
  return Status::ok;
}

}  // namespace

Status concave_hull_2d(const Vec2* points, uint32_t n, const ConcaveHullParams& params, ConcaveHullScratch& scratch,
                       Vec2* out, uint32_t out_capacity, uint32_t& out_n, float& out_cell_m, bool& all_inside) {
  out_n = 0;
  out_cell_m = 0.0f;
  all_inside = false;
  const Status args = check_concave_args(points, n, params, out, out_capacity);
  if (args != Status::ok) return args;
  // Bounding box of the finite points (or the caller's).
  uint32_t first = 0;
  if (!params.bounds_given)
    while (first < n && !is_finite(points[first])) ++first;
  if (first == n) {
    all_inside = true;
    return Status::ok;
  }
  const PointBounds bounds = bounding_box(points, n, first, params);
  const uint32_t r = params.closing_cells;
  Raster placed{};
  float cell_f = 0.0f;
  const Status placing = place_raster(bounds, r, params.cell_m, placed, cell_f);
  if (placing != Status::ok) return placing;
  out_cell_m = cell_f;

  HullGrid grid(placed, scratch);
  bin_points(grid, points, n, bounds.finite == n);
  mark_occupied(grid);
  sort_full_cells(grid.full, grid.n_full);
  close_image(grid, r);
  if (!fill_holes(grid)) return Status::internal_error;
  Component best{};
  const Status choosing = choose_component(grid, scratch.runs, points, n, bounds.finite, best);
  if (choosing != Status::ok) return choosing;
  all_inside = (best.points == bounds.finite);
  return trace_boundary(grid, best.start, out, out_capacity, out_n);
}

// ------------------------------------------------------------------------------------
float min_area_rectangle(const Vec2* hull, uint32_t h, float& major_x, float& major_y) {
  const float inf = std::numeric_limits<float>::infinity();
  float best = inf;
  for (uint32_t i = 0; i < h; ++i) {
    const Vec2& q = hull[i + 1 < h ? i + 1 : 0];
    float ex = q.x - hull[i].x, ey = q.y - hull[i].y;
    const float len = std::sqrt(ex * ex + ey * ey);
    if (!(len > 1e-6f)) continue;
    ex /= len;
    ey /= len;
    float a0 = inf, a1 = -inf, b0 = inf, b1 = -inf;  // along the edge, across it
    for (uint32_t j = 0; j < h; ++j) {
      const float a = ex * hull[j].x + ey * hull[j].y, b = ex * hull[j].y - ey * hull[j].x;
      a0 = std::min(a0, a);
      a1 = std::max(a1, a);
      b0 = std::min(b0, b);
      b1 = std::max(b1, b);
    }
    const float area = (a1 - a0) * (b1 - b0);
    if (area < best) {
      best = area;
      const bool along = a1 - a0 >= b1 - b0;  // the major side: the longer one
      major_x = along ? ex : -ey;
      major_y = along ? ey : ex;
    }
  }
  return best;
}

float polygon_area(const Vec2* poly, uint32_t n) {
  if (poly == nullptr || n < 3) return 0.0f;
  double twice = 0.0;
  for (uint32_t i = 0; i < n; ++i) {
    const Vec2& a = poly[i];
    const Vec2& b = poly[(i + 1 == n) ? 0 : i + 1];
    twice += static_cast<double>(a.x) * b.y - static_cast<double>(b.x) * a.y;
  }
  return static_cast<float>(0.5 * twice);
}

bool polygon_contains(const Vec2* poly, uint32_t n, Vec2 p, float edge_tol_m) {
  if (poly == nullptr || n == 0 || !is_finite(p)) return false;
  const double tol = (std::isfinite(edge_tol_m) && edge_tol_m > 0.0f) ? edge_tol_m : 0.0;
  const double tol2 = tol * tol;
  const double px = p.x;
  const double py = p.y;
  bool inside = false;
  for (uint32_t i = 0; i < n; ++i) {
    const Vec2& a = poly[i];
    const Vec2& b = poly[(i + 1 == n) ? 0 : i + 1];
    const double ax = a.x, ay = a.y, bx = b.x, by = b.y;
    // On the edge (within tol)?
    const double ex = bx - ax, ey = by - ay;
    const double len2 = ex * ex + ey * ey;
    double t = 0.0;
    if (len2 > 0.0) t = std::min(1.0, std::max(0.0, ((px - ax) * ex + (py - ay) * ey) / len2));
    const double dx = ax + t * ex - px;
    const double dy = ay + t * ey - py;
    if (dx * dx + dy * dy <= tol2) return true;
    // Even-odd crossing of the ray towards +x (half-open in y).
    if ((ay > py) != (by > py)) {
      const double x_cross = ax + (py - ay) * ex / ey;
      if (px < x_cross) inside = !inside;
    }
  }
  return inside;
}

uint32_t edge_meets_line(const Vec2& a, const Vec2& b, double yl, double x[2]) {
  if (!is_finite(a) || !is_finite(b)) return 0;  // a broken edge crosses nothing
  const double ay = a.y, by = b.y;
  if (ay == yl && by == yl) {  // along a horizontal edge (or a degenerate one)
    x[0] = a.x;
    x[1] = b.x;
    return 2;
  }
  if ((ay < yl && by < yl) || (ay > yl && by > yl)) return 0;  // both on one side
  if (ay == yl) {                                              // through a vertex: the vertex itself
    x[0] = a.x;
    return 1;
  }
  if (by == yl) {
    x[0] = b.x;
    return 1;
  }
  const double t = (yl - ay) / (by - ay);
  const double xi = a.x + t * (static_cast<double>(b.x) - a.x);
  x[0] = std::min(std::max(xi, std::min<double>(a.x, b.x)), std::max<double>(a.x, b.x));
  return 1;
}

bool polygon_span_at_y(const Vec2* poly, uint32_t n, float y_line, float& x_left, float& x_right) {
  x_left = 0.0f;
  x_right = 0.0f;
  if (poly == nullptr || n == 0 || !std::isfinite(y_line)) return false;
  const double yl = y_line;
  bool any = false;
  double lo = 0.0, hi = 0.0;
  for (uint32_t i = 0; i < n; ++i) {
    double x[2];
    const uint32_t m = edge_meets_line(poly[i], poly[(i + 1 == n) ? 0 : i + 1], yl, x);
    for (uint32_t k = 0; k < m; ++k) {
      if (!std::isfinite(x[k])) continue;
      if (!any) {
        lo = hi = x[k];
        any = true;
      } else {
        lo = std::min(lo, x[k]);
        hi = std::max(hi, x[k]);
      }
    }
  }
  if (!any) return false;
  x_left = static_cast<float>(lo);
  x_right = static_cast<float>(hi);
  return true;
}

}  // namespace fg
