// Convex hull against a brute-force O(n^3) edge oracle; raster concave hull against
// shapes of known area (L, U, ring), containment of every point, orientation,
// component choice and degenerate inputs; the polygon queries against brute force.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "fg/core/hull.hpp"

namespace {

using fg::Status;
using fg::Vec2;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

double cross(const Vec2& o, const Vec2& a, const Vec2& b) {
  return (static_cast<double>(a.x) - o.x) * (static_cast<double>(b.y) - o.y) -
         (static_cast<double>(a.y) - o.y) * (static_cast<double>(b.x) - o.x);
}
bool same(const Vec2& a, const Vec2& b) { return a.x == b.x && a.y == b.y; }

// ---------------------------------------------------------------------------------
// Convex hull oracle: (i, j) is a hull edge iff every other point is strictly left
// of i -> j or on the open segment (i, j). Vertices are the edges' starts.

struct Oracle {
  std::vector<Vec2> pts;  // distinct finite points
  std::vector<std::vector<bool>> edge;
  std::vector<bool> vertex;
  int index_of(const Vec2& p) const {
    for (size_t i = 0; i < pts.size(); ++i) {
      if (same(pts[i], p)) return static_cast<int>(i);
    }
    return -1;
  }
};

Oracle brute_hull(const std::vector<Vec2>& in) {
  Oracle o;
  for (const Vec2& p : in) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) continue;
    if (o.index_of(p) < 0) o.pts.push_back(p);
  }
  const size_t m = o.pts.size();
  o.edge.assign(m, std::vector<bool>(m, false));
  o.vertex.assign(m, m == 1);
  for (size_t i = 0; i < m; ++i) {
    for (size_t j = 0; j < m; ++j) {
      if (i == j) continue;
      const Vec2 &a = o.pts[i], &b = o.pts[j];
      bool ok = true;
      for (size_t k = 0; k < m && ok; ++k) {
        if (k == i || k == j) continue;
        const Vec2& c = o.pts[k];
        const double cr = cross(a, b, c);
        if (cr < 0.0) ok = false;
        if (cr == 0.0) {
          const double d1 = (static_cast<double>(c.x) - a.x) * (static_cast<double>(b.x) - a.x) +
                            (static_cast<double>(c.y) - a.y) * (static_cast<double>(b.y) - a.y);
          const double d2 = (static_cast<double>(c.x) - b.x) * (static_cast<double>(a.x) - b.x) +
                            (static_cast<double>(c.y) - b.y) * (static_cast<double>(a.y) - b.y);
          if (!(d1 > 0.0 && d2 > 0.0)) ok = false;
        }
      }
      if (ok) {
        o.edge[i][j] = true;
        o.vertex[i] = true;
      }
    }
  }
  return o;
}

void check_convex_hull(const std::vector<Vec2>& pts, const char* what) {
  SCOPED_TRACE(what);
  const Oracle o = brute_hull(pts);
  std::vector<Vec2> scratch(pts.size() + 1), out(pts.size() + 1);
  uint32_t out_n = 12345;
  ASSERT_EQ(fg::convex_hull_2d(pts.data(), static_cast<uint32_t>(pts.size()), scratch.data(), out.data(),
                               static_cast<uint32_t>(out.size()), out_n),
            Status::ok);
  const size_t expected = static_cast<size_t>(std::count(o.vertex.begin(), o.vertex.end(), true));
  ASSERT_EQ(out_n, expected);
  std::vector<bool> seen(o.pts.size(), false);
  for (uint32_t t = 0; t < out_n; ++t) {
    const int i = o.index_of(out[t]);
    ASSERT_GE(i, 0) << "not an input point";
    ASSERT_TRUE(o.vertex[i]) << "not a hull vertex: " << out[t].x << ", " << out[t].y;
    ASSERT_FALSE(seen[i]) << "repeated vertex";
    seen[i] = true;
    if (out_n >= 2) {
      const int j = o.index_of(out[(t + 1) % out_n]);
      ASSERT_TRUE(o.edge[i][j]) << "consecutive vertices are not a counter-clockwise hull edge";
    }
  }
  if (out_n >= 1) {  // starts at the lexicographically smallest point
    for (const Vec2& p : o.pts) {
      EXPECT_TRUE(out[0].x < p.x || (out[0].x == p.x && out[0].y <= p.y));
    }
  }
  if (out_n >= 3) {
    EXPECT_GT(fg::polygon_area(out.data(), out_n), 0.0f);
  }
}

float quantize(float v) { return std::round(v * 4096.0f) / 4096.0f; }  // exact cross products

TEST(ConvexHull, MatchesBruteForceOnRandomSets) {
  std::mt19937 rng(12345u);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::uniform_real_distribution<float> ang(0.0f, 6.2831853f);
  for (int trial = 0; trial < 400; ++trial) {
    const int n = 1 + static_cast<int>(rng() % (trial < 380 ? 60u : 250u));
    std::vector<Vec2> pts;
    const int kind = trial % 5;
    for (int i = 0; i < n; ++i) {
      Vec2 p{};
      switch (kind) {
        case 0:  // uniform square, raw floats
          p = {u(rng), u(rng)};
          break;
        case 1:  // uniform square on a grid
          p = {quantize(u(rng)), quantize(u(rng))};
          break;
        case 2: {  // on a circle (rounded to the grid: near-collinear triples)
          const float a = ang(rng);
          p = {quantize(std::cos(a)), quantize(std::sin(a))};
          break;
        }
        case 3:  // a coarse grid: many duplicates and collinear points
          p = {static_cast<float>(static_cast<int>(rng() % 5u)) * 0.25f,
               static_cast<float>(static_cast<int>(rng() % 4u)) * 0.5f};
          break;
        default: {  // points on the sides of a triangle plus a few inside
          const float t = quantize(0.5f * (u(rng) + 1.0f));
          const int side = static_cast<int>(rng() % 4u);
          if (side == 0) p = {t, 0.0f};
          if (side == 1) p = {1.0f - t, t};
          if (side == 2) p = {0.0f, 1.0f - t};
          if (side == 3) p = {0.25f * t, 0.25f * t};
          break;
        }
      }
      pts.push_back(p);
      if (rng() % 10u == 0) pts.push_back(p);  // duplicates
    }
    check_convex_hull(pts, ("trial " + std::to_string(trial)).c_str());
    if (HasFatalFailure()) return;
  }
}

TEST(ConvexHull, DegenerateInputs) {
  Vec2 scratch[16], out[8];  // scratch holds n points
  uint32_t out_n = 99;
  EXPECT_EQ(fg::convex_hull_2d(nullptr, 0, nullptr, out, 8, out_n), Status::ok);
  EXPECT_EQ(out_n, 0u);

  const Vec2 nan_only[3] = {{kNaN, 0.0f}, {0.0f, kInf}, {-kInf, kNaN}};
  EXPECT_EQ(fg::convex_hull_2d(nan_only, 3, scratch, out, 8, out_n), Status::ok);
  EXPECT_EQ(out_n, 0u);

  const Vec2 one[1] = {{0.5f, -0.25f}};
  EXPECT_EQ(fg::convex_hull_2d(one, 1, scratch, out, 8, out_n), Status::ok);
  ASSERT_EQ(out_n, 1u);
  EXPECT_TRUE(same(out[0], one[0]));

  const Vec2 ident[4] = {{1.0f, 2.0f}, {1.0f, 2.0f}, {kNaN, 1.0f}, {1.0f, 2.0f}};
  EXPECT_EQ(fg::convex_hull_2d(ident, 4, scratch, out, 8, out_n), Status::ok);
  ASSERT_EQ(out_n, 1u);
  EXPECT_TRUE(same(out[0], ident[0]));

  const Vec2 line[6] = {{0.0f, 3.0f}, {0.0f, -1.0f}, {0.0f, 0.5f}, {0.0f, 2.0f}, {0.0f, -1.0f}, {0.0f, 3.0f}};
  EXPECT_EQ(fg::convex_hull_2d(line, 6, scratch, out, 8, out_n), Status::ok);
  ASSERT_EQ(out_n, 2u);
  EXPECT_TRUE(same(out[0], Vec2{0.0f, -1.0f}));
  EXPECT_TRUE(same(out[1], Vec2{0.0f, 3.0f}));

  const Vec2 diag[5] = {{2.0f, 2.0f}, {0.0f, 0.0f}, {1.0f, 1.0f}, {3.0f, 3.0f}, {-1.0f, -1.0f}};
  EXPECT_EQ(fg::convex_hull_2d(diag, 5, scratch, out, 8, out_n), Status::ok);
  ASSERT_EQ(out_n, 2u);
  EXPECT_TRUE(same(out[0], Vec2{-1.0f, -1.0f}));
  EXPECT_TRUE(same(out[1], Vec2{3.0f, 3.0f}));

  // A square with mid-edge points, a centre point and a NaN: 4 corners, CCW.
  const Vec2 sq[10] = {{1, 1}, {0, 0},    {0.5f, 0},    {1, 0},    {kNaN, kNaN},
                       {0, 1}, {1, 0.5f}, {0.5f, 0.5f}, {0, 0.5f}, {0.5f, 1}};
  EXPECT_EQ(fg::convex_hull_2d(sq, 10, scratch, out, 8, out_n), Status::ok);
  ASSERT_EQ(out_n, 4u);
  const Vec2 expect[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(same(out[i], expect[i])) << i;

  // Capacity: the square needs 4 vertices.
  EXPECT_EQ(fg::convex_hull_2d(sq, 10, scratch, out, 3, out_n), Status::capacity_exceeded);
  EXPECT_EQ(out_n, 0u);
  EXPECT_EQ(fg::convex_hull_2d(sq, 10, scratch, out, 4, out_n), Status::ok);
  EXPECT_EQ(out_n, 4u);
  EXPECT_EQ(fg::convex_hull_2d(one, 1, scratch, nullptr, 0, out_n), Status::capacity_exceeded);

  // Null pointers with n > 0.
  EXPECT_EQ(fg::convex_hull_2d(nullptr, 3, scratch, out, 8, out_n), Status::invalid_argument);
  EXPECT_EQ(fg::convex_hull_2d(sq, 3, nullptr, out, 8, out_n), Status::invalid_argument);
  EXPECT_EQ(fg::convex_hull_2d(sq, 3, scratch, nullptr, 8, out_n), Status::invalid_argument);
}

TEST(ConvexHull, ExtremeMagnitudes) {
  const float big = 1e30f;
  const std::vector<Vec2> pts = {{-big, -big}, {big, -big},      {big, big},    {-big, big},
                                 {0.0f, 0.0f}, {1e-30f, 1e-30f}, {3e38f, 0.0f}, {-3e38f, 1.0f}};
  check_convex_hull(pts, "extreme");
}

// ---------------------------------------------------------------------------------
// Concave hull

fg::ConcaveHullScratch g_scratch;  // 2 x kHullGridDim^2 bytes: keep it off the stack

struct Concave {
  Status status;
  std::vector<Vec2> poly;
  float cell;
  bool all_inside;
};

Concave concave(const std::vector<Vec2>& pts, float cell_m = 0.0025f, uint32_t closing = 2,
                uint32_t capacity = fg::kMaxContourVertices, const fg::ConcaveHullParams* bounds = nullptr) {
  fg::ConcaveHullParams params;
  if (bounds != nullptr) params = *bounds;
  params.cell_m = cell_m;
  params.closing_cells = closing;
  Concave r{};
  r.poly.resize(std::max<uint32_t>(capacity, 1u));
  uint32_t out_n = 777;
  r.status = fg::concave_hull_2d(pts.data(), static_cast<uint32_t>(pts.size()), params, g_scratch, r.poly.data(),
                                 capacity, out_n, r.cell, r.all_inside);
  r.poly.resize(out_n);
  return r;
}

// Independent point-in-polygon: winding number, with points within tol of an edge inside.
bool inside_or_on(const std::vector<Vec2>& poly, Vec2 p, double tol = 1e-7) {
  int winding = 0;
  const size_t n = poly.size();
  for (size_t i = 0; i < n; ++i) {
    const Vec2& a = poly[i];
    const Vec2& b = poly[(i + 1) % n];
    const double ex = static_cast<double>(b.x) - a.x, ey = static_cast<double>(b.y) - a.y;
    const double len2 = ex * ex + ey * ey;
    double t = len2 > 0 ? ((static_cast<double>(p.x) - a.x) * ex + (static_cast<double>(p.y) - a.y) * ey) / len2 : 0;
    t = std::min(1.0, std::max(0.0, t));
    const double dx = a.x + t * ex - p.x, dy = a.y + t * ey - p.y;
    if (std::sqrt(dx * dx + dy * dy) <= tol) return true;
    if (a.y <= p.y) {
      if (b.y > p.y && cross(a, b, p) > 0) ++winding;
    } else {
      if (b.y <= p.y && cross(a, b, p) < 0) --winding;
    }
  }
  return winding != 0;
}

// Structure of a raster contour: axis-aligned edges alternating between horizontal
// and vertical (so no collinear consecutive vertices and no repeated first vertex),
// vertices on the cell lattice, counter-clockwise.
void check_contour_structure(const std::vector<Vec2>& poly, float cell) {
  ASSERT_GE(poly.size(), 4u);
  ASSERT_EQ(poly.size() % 2, 0u);
  for (size_t i = 0; i < poly.size(); ++i) {
    const Vec2& a = poly[i];
    const Vec2& b = poly[(i + 1) % poly.size()];
    const Vec2& c = poly[(i + 2) % poly.size()];
    const bool ab_h = a.y == b.y && a.x != b.x;
    const bool ab_v = a.x == b.x && a.y != b.y;
    const bool bc_h = b.y == c.y && b.x != c.x;
    const bool bc_v = b.x == c.x && b.y != c.y;
    ASSERT_TRUE((ab_h && bc_v) || (ab_v && bc_h)) << "vertex " << i + 1;
    const double kx = (static_cast<double>(a.x) - poly[0].x) / cell;
    const double ky = (static_cast<double>(a.y) - poly[0].y) / cell;
    // On the lattice up to the float rounding of the corner coordinates.
    const double tol =
        1e-3 + 1.2e-7 * (std::fabs(a.x) + std::fabs(a.y) + std::fabs(poly[0].x) + std::fabs(poly[0].y)) / cell;
    EXPECT_NEAR(kx, std::round(kx), tol);
    EXPECT_NEAR(ky, std::round(ky), tol);
  }
  EXPECT_GT(fg::polygon_area(poly.data(), static_cast<uint32_t>(poly.size())), 0.0f);
}

void expect_all_inside(const std::vector<Vec2>& poly, const std::vector<Vec2>& pts) {
  size_t outside = 0;
  for (const Vec2& p : pts) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) continue;
    if (!inside_or_on(poly, p)) ++outside;
    EXPECT_TRUE(fg::polygon_contains(poly.data(), static_cast<uint32_t>(poly.size()), p));
  }
  EXPECT_EQ(outside, 0u);
}

std::vector<Vec2> sample_grid(float x0, float x1, float y0, float y1, float step, bool (*keep)(float, float)) {
  std::vector<Vec2> pts;
  const int nx = static_cast<int>(std::lround((x1 - x0) / step));
  const int ny = static_cast<int>(std::lround((y1 - y0) / step));
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      const float x = x0 + step * static_cast<float>(i);
      const float y = y0 + step * static_cast<float>(j);
      if (keep(x, y)) pts.push_back({x, y});
    }
  }
  return pts;
}

// The shape tests below assume the host raster resolution (2.5 mm cells over the
// shapes' extent); a small-raster preset coarsens the cell and skips them.
#define FG_NEED_RASTER(dim) \
  if (fg::kHullGridDim < (dim)) GTEST_SKIP() << "needs kHullGridDim >= " << (dim)

constexpr float kEps = 1e-6f;
bool keep_l(float x, float y) { return x <= 0.05f + kEps || y <= 0.05f + kEps; }
bool keep_u(float x, float y) { return !(x > 0.04f + kEps && x < 0.08f - kEps && y > 0.04f + kEps); }
bool keep_ring(float x, float y) {
  const float r = std::sqrt(x * x + y * y);
  return r >= 0.03f && r <= 0.06f;
}

TEST(ConcaveHull, LShape) {
  FG_NEED_RASTER(64u);
  const auto pts = sample_grid(0.0f, 0.1f, 0.0f, 0.1f, 0.002f, keep_l);
  const Concave r = concave(pts);
  ASSERT_EQ(r.status, Status::ok);
  EXPECT_TRUE(r.all_inside);
  EXPECT_FLOAT_EQ(r.cell, 0.0025f);
  check_contour_structure(r.poly, r.cell);
  EXPECT_EQ(r.poly.size(), 6u);
  expect_all_inside(r.poly, pts);
  const double area = fg::polygon_area(r.poly.data(), static_cast<uint32_t>(r.poly.size()));
  const double true_area = 0.0075, perimeter = 0.4;
  EXPECT_GT(area, true_area);
  EXPECT_LT(area, true_area + perimeter * r.cell);
  EXPECT_FALSE(fg::polygon_contains(r.poly.data(), static_cast<uint32_t>(r.poly.size()), Vec2{0.08f, 0.08f}));
}

TEST(ConcaveHull, UShapeKeepsItsNotch) {
  FG_NEED_RASTER(64u);
  const auto pts = sample_grid(0.0f, 0.12f, 0.0f, 0.1f, 0.002f, keep_u);
  const Concave r = concave(pts);
  ASSERT_EQ(r.status, Status::ok);
  EXPECT_TRUE(r.all_inside);
  check_contour_structure(r.poly, r.cell);
  EXPECT_EQ(r.poly.size(), 8u);
  expect_all_inside(r.poly, pts);
  const double area = fg::polygon_area(r.poly.data(), static_cast<uint32_t>(r.poly.size()));
  const double true_area = 0.12 * 0.1 - 0.04 * 0.06, perimeter = 2 * 0.12 + 2 * 0.1 + 2 * 0.06;
  EXPECT_GT(area, true_area);
  EXPECT_LT(area, true_area + perimeter * r.cell);
  const Vec2 notch{0.06f, 0.08f};
  EXPECT_FALSE(fg::polygon_contains(r.poly.data(), static_cast<uint32_t>(r.poly.size()), notch));
  EXPECT_FALSE(inside_or_on(r.poly, notch));
  // The span across the arms still reports the outermost crossings.
  float xl = 0, xr = 0;
  ASSERT_TRUE(fg::polygon_span_at_y(r.poly.data(), static_cast<uint32_t>(r.poly.size()), 0.08f, xl, xr));
  EXPECT_NEAR(xl, 0.0f, r.cell);
  EXPECT_NEAR(xr, 0.12f, r.cell);

  // Capacity: 8 vertices needed.
  const Concave small = concave(pts, 0.0025f, 2, 7);
  EXPECT_EQ(small.status, Status::capacity_exceeded);
  EXPECT_EQ(small.poly.size(), 0u);
  const Concave exact = concave(pts, 0.0025f, 2, 8);
  EXPECT_EQ(exact.status, Status::ok);
  EXPECT_EQ(exact.poly.size(), 8u);
}

TEST(ConcaveHull, RingHoleIsFilled) {
  const auto pts = sample_grid(-0.06f, 0.06f, -0.06f, 0.06f, 0.002f, keep_ring);
  const Concave r = concave(pts);
  ASSERT_EQ(r.status, Status::ok);
  EXPECT_TRUE(r.all_inside);
  check_contour_structure(r.poly, r.cell);
  expect_all_inside(r.poly, pts);
  const double area = fg::polygon_area(r.poly.data(), static_cast<uint32_t>(r.poly.size()));
  const double disc = M_PI * 0.06 * 0.06, perimeter = 2 * M_PI * 0.06;
  EXPECT_GT(area, disc * 0.97);
  EXPECT_LT(area, disc + perimeter * r.cell);
  EXPECT_TRUE(fg::polygon_contains(r.poly.data(), static_cast<uint32_t>(r.poly.size()), Vec2{0.0f, 0.0f}));
}

// A square ring of 9 x 9 cells at 1 cm with one point alone at its middle, one point
// per cell centre, traced without closing (so the polygon's area counts cells
// exactly). A hole is background that no 4-connected path joins to the raster's
// border (the dual of the 8-connected foreground); filling it joins the middle point
// to the ring, so every point is inside. Opened edge-on, the inside is no hole and the
// middle point is a component of its own.
TEST(ConcaveHull, HolesAreBackgroundNotFourConnectedToTheBorder) {
  auto ring = [](int skip_i, int skip_j) {
    std::vector<Vec2> pts;
    for (int j = 0; j < 9; ++j)
      for (int i = 0; i < 9; ++i) {
        const bool edge = i == 0 || j == 0 || i == 8 || j == 8;
        if ((edge && !(i == skip_i && j == skip_j)) || (i == 4 && j == 4))
          pts.push_back({0.01f * static_cast<float>(i), 0.01f * static_cast<float>(j)});
      }
    return pts;
  };
  auto cells_inside = [](const Concave& r) {
    return fg::polygon_area(r.poly.data(), static_cast<uint32_t>(r.poly.size())) / (0.01 * 0.01);
  };
  const Concave closed = concave(ring(-1, -1), 0.01f, 0);
  ASSERT_EQ(closed.status, Status::ok);
  ASSERT_FLOAT_EQ(closed.cell, 0.01f);
  EXPECT_TRUE(closed.all_inside);
  EXPECT_NEAR(cells_inside(closed), 81.0, 1e-3);
  // A corner cell missing: the inside meets the outside only diagonally, still a hole.
  const Concave corner = concave(ring(0, 0), 0.01f, 0);
  ASSERT_EQ(corner.status, Status::ok);
  EXPECT_TRUE(corner.all_inside);
  EXPECT_NEAR(cells_inside(corner), 80.0, 1e-3);
  // An edge cell missing, on each side in turn: no hole; the ring, 31 cells, is traced.
  for (const auto& gap : {std::pair<int, int>{4, 0}, {8, 4}, {4, 8}, {0, 4}}) {
    const Concave r = concave(ring(gap.first, gap.second), 0.01f, 0);
    ASSERT_EQ(r.status, Status::ok);
    EXPECT_FALSE(r.all_inside) << gap.first << "," << gap.second;
    EXPECT_NEAR(cells_inside(r), 31.0, 1e-3) << gap.first << "," << gap.second;
  }
}

// Two 8 x 10-cell rectangles side by side, `gap` empty columns apart, one point per
// cell centre at 1 cm. A closing with a (2r+1)^2 square bridges the gap exactly when
// it is at most 2r columns wide, and then gives the bounding rectangle. The larger
// radii shift rows across the 64-cell words of the raster.
TEST(ConcaveHull, ClosingBridgesGapsUpToTwiceItsRadius) {
  FG_NEED_RASTER(256u);
  auto pair_of_boxes = [](int gap) {
    std::vector<Vec2> pts;
    for (int j = 0; j < 10; ++j)
      for (int i = 0; i < 16 + gap; ++i)
        if (i < 8 || i >= 8 + gap) pts.push_back({0.01f * static_cast<float>(i), 0.01f * static_cast<float>(j)});
    return pts;
  };
  struct Case {
    uint32_t r;
    int gap;
    bool joined;
  } cases[] = {{3, 6, true}, {3, 7, false}, {30, 60, true}, {30, 61, false}, {100, 30, true}};
  for (const Case& c : cases) {
    const Concave h = concave(pair_of_boxes(c.gap), 0.01f, c.r);
    ASSERT_EQ(h.status, Status::ok) << c.r << " " << c.gap;
    ASSERT_FLOAT_EQ(h.cell, 0.01f) << c.r << " " << c.gap;
    const double cells = fg::polygon_area(h.poly.data(), static_cast<uint32_t>(h.poly.size())) / (0.01 * 0.01);
    EXPECT_EQ(h.all_inside, c.joined) << c.r << " " << c.gap;
    // Joined: the bounding rectangle. Apart: equal point counts, so the first box in
    // raster order (the left one), closed onto itself.
    EXPECT_NEAR(cells, c.joined ? 10.0 * (16 + c.gap) : 80.0, 1e-3) << c.r << " " << c.gap;
  }
}

// A comb: `cols` vertical bars of `rows` cells, one empty column between bars, one
// point per cell (1 cm) and 300 more in the bottom cell of the second bar, which so
// holds the most points (its cell's count saturates and is recounted exactly). With
// few rows the components are labelled by runs; with more runs than the scratch
// holds, by flooding: both trace the second bar alone.
TEST(ConcaveHull, CombOfBarsTracesTheBarWithTheMostPoints) {
  FG_NEED_RASTER(128u);
  for (const int rows : {4, 20, 30}) {
    const int cols = 60;
    std::vector<Vec2> pts;
    for (int j = 0; j < rows; ++j)
      for (int c = 0; c < cols; ++c) pts.push_back({0.02f * static_cast<float>(c), 0.01f * static_cast<float>(j)});
    for (int k = 0; k < 300; ++k) pts.push_back({0.02f, 0.0f});
    const bool many_runs = static_cast<uint32_t>(rows * cols) > fg::ConcaveHullScratch::kMaxRuns;
    const Concave r = concave(pts, 0.01f, 0);
    ASSERT_EQ(r.status, Status::ok) << rows;
    ASSERT_FLOAT_EQ(r.cell, 0.01f);
    EXPECT_FALSE(r.all_inside);
    ASSERT_EQ(r.poly.size(), 4u) << rows << (many_runs ? " (flooded)" : " (runs)");
    float x0 = 1e9f, x1 = -1e9f;
    for (const Vec2& v : r.poly) {
      x0 = std::min(x0, v.x);
      x1 = std::max(x1, v.x);
    }
    EXPECT_NEAR(x0, 0.015f, 1e-4f) << rows;  // the bar of x = 0.02 m, one cell wide
    EXPECT_NEAR(x1, 0.025f, 1e-4f) << rows;
    EXPECT_NEAR(fg::polygon_area(r.poly.data(), 4) / (0.01 * 0.01), rows, 1e-3) << rows;
  }
  EXPECT_LT(4u * 60u, fg::ConcaveHullScratch::kMaxRuns);
  EXPECT_GT(30u * 60u, fg::ConcaveHullScratch::kMaxRuns);  // the last comb floods
}

// Full cells (more than 254 points) counted exactly, whether the scratch's table of
// full cells has room for them or overflows (then the component is recounted over the
// points). The comb of the test above, one point per cell; bar R (x = 0.10 m) gets 10
// cells of 254 points and one of 11, bar H (x = 0.30 m) 10 cells of 500: counting a
// full cell as 255 would tie them and hand the win to R, the first in raster order; H
// holds 2,450 points more. "Filler" full cells (2 per bar in the bars right of x = 0.40 m, 255 + 1
// points each, far below H's total) come before or after H's points, so the table is
// full before H's cells reach it, or not. The oracle: the per-bar totals by
// construction.
TEST(ConcaveHull, FullCellsCountExactlyWithAndWithoutRoomInTheTable) {
  FG_NEED_RASTER(128u);
  const int cols = 60;
  const uint32_t table = fg::ConcaveHullScratch::kMaxFullCells;
  for (const int rows : {20, 30}) {
    for (const bool fillers_first : {true, false}) {
      const int n_fillers = static_cast<int>(table) + 4;  // more than the table holds
      ASSERT_LE(n_fillers, 2 * (cols - 21)) << "too few bars for the fillers";
      auto cell = [](int c, int j) { return Vec2{0.02f * static_cast<float>(c), 0.01f * static_cast<float>(j)}; };
      std::vector<Vec2> base, heavy, fillers;
      for (int j = 0; j < rows; ++j)
        for (int c = 0; c < cols; ++c) base.push_back(cell(c, j));
      for (int k = 0; k < 10; ++k) base.push_back(cell(5, 10));  // R: 1 + 10 in its 11th cell
      for (int j = 0; j < 10; ++j) {
        for (int k = 0; k < 253; ++k) base.push_back(cell(5, j));    // R: 1 + 253 = 254 per cell
        for (int k = 0; k < 499; ++k) heavy.push_back(cell(15, j));  // H: 1 + 499 = 500 per cell
      }
      for (int f = 0; f < n_fillers; ++f)
        for (int k = 0; k < 255; ++k) fillers.push_back(cell(21 + f / 2, f % 2));
      std::vector<Vec2> pts = base;
      const std::vector<Vec2>& first = fillers_first ? fillers : heavy;
      const std::vector<Vec2>& second = fillers_first ? heavy : fillers;
      pts.insert(pts.end(), first.begin(), first.end());
      pts.insert(pts.end(), second.begin(), second.end());
      // Oracle: each bar's points; the most wins (ties: the leftmost).
      std::vector<long> per_bar(cols, rows);
      per_bar[5] += 10 * 253 + 10;
      per_bar[15] += 10 * 499;
      for (int f = 0; f < n_fillers; ++f) per_bar[21 + f / 2] += 255;
      const int winner = static_cast<int>(std::max_element(per_bar.begin(), per_bar.end()) - per_bar.begin());
      ASSERT_EQ(winner, 15);
      const Concave r = concave(pts, 0.01f, 0);
      const std::string what = std::to_string(rows) + (fillers_first ? " fillers first" : " fillers last");
      ASSERT_EQ(r.status, Status::ok) << what;
      ASSERT_EQ(r.poly.size(), 4u) << what;
      EXPECT_TRUE(inside_or_on(r.poly, cell(winner, 0))) << what;
      EXPECT_FALSE(inside_or_on(r.poly, cell(5, 0))) << what;
      EXPECT_NEAR(fg::polygon_area(r.poly.data(), 4) / (0.01 * 0.01), rows, 1e-3) << what;
    }
  }
}

// An arch: two legs joined only by a top row, so its left and right halves are labelled
// apart until that row. The polygon starts at the lower-left corner of the component's
// lowest, then leftmost cell: the left leg's foot.
TEST(ConcaveHull, ArchStartsAtItsFirstCellInRasterOrder) {
  std::vector<Vec2> pts;
  for (int j = 0; j < 7; ++j)
    for (int i = 0; i < 5; ++i)
      if (j == 6 || i == 0 || i == 4) pts.push_back({0.01f * static_cast<float>(i), 0.01f * static_cast<float>(j)});
  const Concave r = concave(pts, 0.01f, 0);
  ASSERT_EQ(r.status, Status::ok);
  ASSERT_FLOAT_EQ(r.cell, 0.01f);
  EXPECT_TRUE(r.all_inside);
  ASSERT_FALSE(r.poly.empty());
  EXPECT_NEAR(r.poly[0].x, -0.005f, 1e-5f);
  EXPECT_NEAR(r.poly[0].y, -0.005f, 1e-5f);
  EXPECT_NEAR(fg::polygon_area(r.poly.data(), static_cast<uint32_t>(r.poly.size())) / (0.01 * 0.01), 17.0, 1e-3);
}

std::vector<Vec2> random_blob(std::mt19937& rng, int n, Vec2 centre, float radius) {
  // Union of three overlapping discs, uniform by rejection.
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  const Vec2 c[3] = {{0.0f, 0.0f}, {0.5f * u(rng), 0.5f * u(rng)}, {0.5f * u(rng), 0.5f * u(rng)}};
  const float rr[3] = {0.6f, 0.3f + 0.2f * std::fabs(u(rng)), 0.3f + 0.2f * std::fabs(u(rng))};
  std::vector<Vec2> pts;
  while (static_cast<int>(pts.size()) < n) {
    const float x = u(rng), y = u(rng);
    bool in = false;
    for (int k = 0; k < 3; ++k) in = in || (x - c[k].x) * (x - c[k].x) + (y - c[k].y) * (y - c[k].y) <= rr[k] * rr[k];
    if (in) pts.push_back({centre.x + radius * x, centre.y + radius * y});
  }
  return pts;
}

TEST(ConcaveHull, RandomBlobsContainEveryPoint) {
  std::mt19937 rng(4242u);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  const uint32_t closings[4] = {0, 1, 2, 3};
  int dense_closed = 0;
  for (int trial = 0; trial < 60; ++trial) {
    // Even trials: small dense blobs; odd trials: up to 0.33 m, where the cell grows.
    const float radius = (trial % 2 == 0) ? 0.02f + 0.06f * std::fabs(u(rng)) : 0.03f + 0.3f * std::fabs(u(rng));
    const int n = 200 + static_cast<int>(rng() % 3000u);
    const auto pts = random_blob(rng, n, Vec2{u(rng), u(rng)}, radius);
    const uint32_t closing = closings[(trial / 2) % 4];
    const Concave r = concave(pts, 0.0025f, closing);
    SCOPED_TRACE("trial " + std::to_string(trial));
    ASSERT_EQ(r.status, Status::ok);
    ASSERT_GE(r.cell, 0.0025f);
    float xmin = pts[0].x, xmax = pts[0].x, ymin = pts[0].y, ymax = pts[0].y;
    for (const Vec2& p : pts) {
      xmin = std::min(xmin, p.x);
      xmax = std::max(xmax, p.x);
      ymin = std::min(ymin, p.y);
      ymax = std::max(ymax, p.y);
    }
    const double extent = std::max(xmax - xmin, ymax - ymin);
    ASSERT_LE(extent / r.cell, fg::kHullGridDim - 2 * closing - 4 + 1e-3);
    if (extent / (fg::kHullGridDim - 2 * closing - 4) > 0.0025) {
      EXPECT_NEAR(extent / r.cell, fg::kHullGridDim - 2 * closing - 4, 1e-3);
    }
    check_contour_structure(r.poly, r.cell);
    if (r.all_inside) {
      expect_all_inside(r.poly, pts);
    } else {
      // Without closing a sparse blob falls apart; the traced piece holds points.
      size_t in = 0;
      for (const Vec2& p : pts) in += inside_or_on(r.poly, p) ? 1 : 0;
      EXPECT_GT(in, 0u);
      EXPECT_LT(in, pts.size());
    }
    // A closing of 2 cells bridges the sampling gaps of a blob with at least one
    // point per two cells on average.
    const double points_per_cell = static_cast<double>(pts.size()) * r.cell * r.cell /
                                   ((static_cast<double>(xmax) - xmin) * (static_cast<double>(ymax) - ymin));
    if (closing >= 2 && points_per_cell >= 0.5) {
      EXPECT_TRUE(r.all_inside) << points_per_cell;
    }
    dense_closed += (closing >= 2 && points_per_cell >= 0.5 && r.all_inside) ? 1 : 0;
  }
  EXPECT_GE(dense_closed, 10);  // the property above was exercised
}

// Points on the cell corners and one float step either side of them are binned with
// the corners the polygon is written with: every point lies inside or exactly on the
// polygon, with no tolerance. The corners come from a first hull of the blob; the
// second hull adds the 9 points at and around each of its vertices (the blob's
// component grows into the neighbouring cells, so all of them are traced).
TEST(ConcaveHull, PointsAtAndBesideCellCornersLieInTheirCells) {
  std::mt19937 rng(515u);
  for (const float centre : {0.05f, -3.0f, 700.0f}) {
    for (const uint32_t closing : {0u, 2u}) {
      std::vector<Vec2> pts = random_blob(rng, 1500, Vec2{centre, -centre}, 0.04f);
      const Concave first = concave(pts, 0.0025f, 2);
      ASSERT_EQ(first.status, Status::ok);
      for (const Vec2& v : first.poly)
        for (const float x : {std::nextafter(v.x, -1e30f), v.x, std::nextafter(v.x, 1e30f)})
          for (const float y : {std::nextafter(v.y, -1e30f), v.y, std::nextafter(v.y, 1e30f)}) pts.push_back({x, y});
      const Concave r = concave(pts, 0.0025f, closing);
      SCOPED_TRACE("centre " + std::to_string(centre) + " closing " + std::to_string(closing));
      ASSERT_EQ(r.status, Status::ok);
      check_contour_structure(r.poly, r.cell);
      size_t outside = 0, traced = 0;
      for (const Vec2& p : pts) {
        const bool in = inside_or_on(r.poly, p, 0.0);
        traced += in ? 1 : 0;
        outside += (!in && r.all_inside) ? 1 : 0;
      }
      EXPECT_EQ(outside, 0u);
      if (closing == 2) {
        EXPECT_TRUE(r.all_inside);
      }
      EXPECT_GT(traced, pts.size() / 2);
    }
  }
}

TEST(ConcaveHull, TwoFarApartBlobsTraceTheBiggerOne) {
  FG_NEED_RASTER(160u);
  std::mt19937 rng(77u);
  const auto small = random_blob(rng, 300, Vec2{0.25f, 0.02f}, 0.02f);
  const auto big = random_blob(rng, 900, Vec2{0.0f, 0.0f}, 0.04f);
  for (int order = 0; order < 2; ++order) {
    std::vector<Vec2> pts = order == 0 ? small : big;
    pts.insert(pts.end(), (order == 0 ? big : small).begin(), (order == 0 ? big : small).end());
    const Concave r = concave(pts);
    ASSERT_EQ(r.status, Status::ok);
    EXPECT_FALSE(r.all_inside);
    check_contour_structure(r.poly, r.cell);
    expect_all_inside(r.poly, big);
    for (const Vec2& p : small) EXPECT_FALSE(inside_or_on(r.poly, p));
  }
}

TEST(ConcaveHull, ComponentChoiceCountsPointsExactly) {
  // A: 1000 points in one cell (more than a saturated per-cell count holds);
  // B: 400 points spread over a 20 mm square. A holds more points.
  std::vector<Vec2> a(1000, Vec2{0.0f, 0.0f});
  std::vector<Vec2> b = sample_grid(0.1f, 0.138f, 0.0f, 0.038f, 0.002f, [](float, float) { return true; });
  ASSERT_EQ(b.size(), 400u);
  std::vector<Vec2> pts = b;
  pts.insert(pts.end(), a.begin(), a.end());
  Concave r = concave(pts);
  ASSERT_EQ(r.status, Status::ok);
  EXPECT_FALSE(r.all_inside);
  ASSERT_EQ(r.poly.size(), 4u);  // the single cell of A
  EXPECT_TRUE(inside_or_on(r.poly, a[0]));
  EXPECT_NEAR(fg::polygon_area(r.poly.data(), 4), r.cell * r.cell, 1e-9);

  a.resize(300);  // now B holds more
  pts = b;
  pts.insert(pts.end(), a.begin(), a.end());
  r = concave(pts);
  ASSERT_EQ(r.status, Status::ok);
  expect_all_inside(r.poly, b);
  EXPECT_FALSE(inside_or_on(r.poly, a[0]));
}

TEST(ConcaveHull, TiesGoToTheFirstComponentInRasterOrder) {
  FG_NEED_RASTER(128u);
  // Two equal blobs; raster order is row by row from the smallest y.
  const auto blob = sample_grid(0.0f, 0.02f, 0.0f, 0.02f, 0.002f, [](float, float) { return true; });
  for (float dy : {0.01f, -0.01f}) {
    std::vector<Vec2> pts = blob;
    for (const Vec2& p : blob) pts.push_back({p.x + 0.2f, p.y + dy});
    const Concave r = concave(pts);
    ASSERT_EQ(r.status, Status::ok);
    EXPECT_FALSE(r.all_inside);
    const Vec2 probe_a{0.01f, 0.01f}, probe_b{0.21f, 0.01f + dy};
    EXPECT_EQ(inside_or_on(r.poly, probe_a), dy > 0.0f);
    EXPECT_EQ(inside_or_on(r.poly, probe_b), dy < 0.0f);
  }
}

TEST(ConcaveHull, NonFinitePointsAreSkipped) {
  std::mt19937 rng(9u);
  const auto clean = random_blob(rng, 800, Vec2{0.1f, -0.2f}, 0.05f);
  std::vector<Vec2> dirty;
  for (size_t i = 0; i < clean.size(); ++i) {
    dirty.push_back(clean[i]);
    if (i % 7 == 0) dirty.push_back({kNaN, 0.1f});
    if (i % 11 == 0) dirty.push_back({0.1f, kInf});
    if (i % 13 == 0) dirty.push_back({-kInf, -kInf});
  }
  const Concave a = concave(clean), b = concave(dirty);
  ASSERT_EQ(a.status, Status::ok);
  ASSERT_EQ(b.status, Status::ok);
  EXPECT_EQ(a.all_inside, b.all_inside);
  EXPECT_EQ(a.cell, b.cell);
  ASSERT_EQ(a.poly.size(), b.poly.size());
  for (size_t i = 0; i < a.poly.size(); ++i) EXPECT_TRUE(same(a.poly[i], b.poly[i]));

  const std::vector<Vec2> only_bad = {{kNaN, kNaN}, {kInf, 0.0f}};
  const Concave c = concave(only_bad);
  EXPECT_EQ(c.status, Status::ok);
  EXPECT_EQ(c.poly.size(), 0u);
}

TEST(ConcaveHull, EmptySinglePointAndIdenticalPoints) {
  const Concave e = concave({});
  EXPECT_EQ(e.status, Status::ok);
  EXPECT_EQ(e.poly.size(), 0u);
  EXPECT_TRUE(e.all_inside);

  for (size_t count : {size_t{1}, size_t{50}}) {
    const std::vector<Vec2> pts(count, Vec2{0.3f, -0.7f});
    const Concave r = concave(pts);
    ASSERT_EQ(r.status, Status::ok);
    EXPECT_TRUE(r.all_inside);
    EXPECT_EQ(r.cell, 0.0025f);
    ASSERT_EQ(r.poly.size(), 4u);
    check_contour_structure(r.poly, r.cell);
    EXPECT_NEAR(fg::polygon_area(r.poly.data(), 4), r.cell * r.cell, 1e-9);
    float cx = 0, cy = 0;
    for (const Vec2& v : r.poly) {
      cx += 0.25f * v.x;
      cy += 0.25f * v.y;
    }
    EXPECT_NEAR(cx, 0.3f, 1e-6f);  // the point sits in the middle of its cell
    EXPECT_NEAR(cy, -0.7f, 1e-6f);
    expect_all_inside(r.poly, pts);
  }

  const std::vector<Vec2> one = {{0.0f, 0.0f}};
  EXPECT_EQ(concave(one, 0.0025f, 2, 3).status, Status::capacity_exceeded);
}

TEST(ConcaveHull, DiagonalNeighboursAreOneComponent) {
  // Without closing, two diagonal cells are 8-connected: one polygon touching
  // itself at the shared corner, holding both points.
  const std::vector<Vec2> pts = {{0.0f, 0.0f}, {0.0025f, 0.0025f}, {0.005f, 0.005f}};
  const Concave r = concave(pts, 0.0025f, 0);
  ASSERT_EQ(r.status, Status::ok);
  EXPECT_TRUE(r.all_inside);
  check_contour_structure(r.poly, r.cell);
  EXPECT_EQ(r.poly.size(), 12u);
  EXPECT_NEAR(fg::polygon_area(r.poly.data(), static_cast<uint32_t>(r.poly.size())), 3 * r.cell * r.cell, 1e-9);
  expect_all_inside(r.poly, pts);
}

TEST(ConcaveHull, LargeExtentGrowsTheCell) {
  FG_NEED_RASTER(64u);
  std::vector<Vec2> pts;
  for (int i = 0; i <= 400; ++i) {  // the outline of a 4 m x 1 m rectangle
    const float t = static_cast<float>(i) / 400.0f;
    pts.push_back({4.0f * t, 0.0f});
    pts.push_back({4.0f * t, 1.0f});
    pts.push_back({0.0f, t});
    pts.push_back({4.0f, t});
  }
  const Concave r = concave(pts);
  ASSERT_EQ(r.status, Status::ok);
  EXPECT_NEAR(r.cell, 4.0f / static_cast<float>(fg::kHullGridDim - 2 * 2 - 4), 1e-6f);
  EXPECT_TRUE(r.all_inside);
  check_contour_structure(r.poly, r.cell);
  expect_all_inside(r.poly, pts);
  // The outline's interior is a hole: filled.
  const double area = fg::polygon_area(r.poly.data(), static_cast<uint32_t>(r.poly.size()));
  EXPECT_GT(area, 4.0);
  EXPECT_LT(area, 4.0 + 10.0 * r.cell);  // at most about one cell beyond the perimeter
}

TEST(ConcaveHull, ThinLineOfPoints) {
  std::vector<Vec2> pts;
  for (int i = 0; i < 200; ++i) pts.push_back({0.001f * static_cast<float>(i), 0.0007f * static_cast<float>(i)});
  for (uint32_t closing : {0u, 2u}) {
    const Concave r = concave(pts, 0.0025f, closing);
    ASSERT_EQ(r.status, Status::ok);
    EXPECT_TRUE(r.all_inside);
    check_contour_structure(r.poly, r.cell);
    expect_all_inside(r.poly, pts);
  }
}

TEST(ConcaveHull, InvalidArguments) {
  const std::vector<Vec2> pts = {{0.0f, 0.0f}};
  EXPECT_EQ(concave(pts, 0.0f).status, Status::invalid_argument);
  EXPECT_EQ(concave(pts, -1.0f).status, Status::invalid_argument);
  EXPECT_EQ(concave(pts, kNaN).status, Status::invalid_argument);
  EXPECT_EQ(concave(pts, kInf).status, Status::invalid_argument);
  EXPECT_EQ(concave(pts, 0.0025f, (fg::kHullGridDim - 5) / 2 + 1).status, Status::invalid_argument);
  EXPECT_EQ(concave(pts, 0.0025f, (fg::kHullGridDim - 5) / 2).status, Status::ok);

  fg::ConcaveHullParams params;
  Vec2 out[8];
  uint32_t out_n = 0;
  float cell = 0;
  bool all = false;
  EXPECT_EQ(fg::concave_hull_2d(nullptr, 3, params, g_scratch, out, 8, out_n, cell, all), Status::invalid_argument);
  EXPECT_EQ(fg::concave_hull_2d(pts.data(), 1, params, g_scratch, nullptr, 8, out_n, cell, all),
            Status::invalid_argument);
  EXPECT_EQ(fg::concave_hull_2d(nullptr, 0, params, g_scratch, nullptr, 0, out_n, cell, all), Status::ok);
}

TEST(ConcaveHull, HugeCoordinatesGiveADefinedStatus) {
  const std::vector<Vec2> pts = {{-3.4e38f, 0.0f}, {3.4e38f, 1.0f}};
  const Concave r = concave(pts);
  EXPECT_EQ(r.status, Status::numeric_failure);
  EXPECT_EQ(r.poly.size(), 0u);
  // Points a few float ulps apart at 1e30 (ulp 7.6e22): the cell is raised to two
  // ulps so that the cell corners stay distinct; every point is still covered.
  std::vector<Vec2> far;
  for (int i = 0; i <= 100; ++i) {
    far.push_back({1e30f + 2e23f * static_cast<float>(i), 1e30f + 1e23f * static_cast<float>(i % 2)});
  }
  const Concave f = concave(far);
  ASSERT_EQ(f.status, Status::ok);
  EXPECT_GE(f.cell, 2 * 7.5e22f);
  EXPECT_TRUE(f.all_inside);
  check_contour_structure(f.poly, f.cell);
  expect_all_inside(f.poly, far);
}

TEST(ConcaveHull, Deterministic) {
  std::mt19937 rng(31u);
  const auto pts = random_blob(rng, 2000, Vec2{0.0f, 0.0f}, 0.1f);
  const Concave a = concave(pts), b = concave(pts);
  ASSERT_EQ(a.poly.size(), b.poly.size());
  for (size_t i = 0; i < a.poly.size(); ++i) EXPECT_TRUE(same(a.poly[i], b.poly[i]));
}

// The caller's bounding box (the planner's projection computes it in passing) gives
// the hull computed without it, bit for bit, whatever the order of the points (the
// box here in reverse order, with -0.0 and +0.0 both present where a box is at 0).
TEST(ConcaveHull, GivenBoundsGiveTheHullWithout) {
  std::mt19937 rng(9001u);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int trial = 0; trial < 80; ++trial) {
    const float radius = trial % 3 == 0 ? 0.3f * std::fabs(u(rng)) + 1e-4f : 0.06f * std::fabs(u(rng)) + 1e-4f;
    std::vector<Vec2> pts = random_blob(rng, 1 + static_cast<int>(rng() % 4000u), Vec2{u(rng), u(rng)}, radius);
    if (trial % 4 == 1) pts.push_back(Vec2{0.0f, -0.0f});
    if (trial % 4 == 1) pts.push_back(Vec2{-0.0f, 0.0f});
    if (trial % 5 == 2) pts.resize(1 + rng() % 3);  // a few points, some steps' tails only
    fg::ConcaveHullParams b;
    b.bounds_given = true;
    b.xmin = b.xmax = pts.back().x;
    b.ymin = b.ymax = pts.back().y;
    for (size_t i = pts.size(); i-- > 0;) {
      b.xmin = std::min(b.xmin, pts[i].x);
      b.xmax = std::max(b.xmax, pts[i].x);
      b.ymin = std::min(b.ymin, pts[i].y);
      b.ymax = std::max(b.ymax, pts[i].y);
    }
    const uint32_t closing = static_cast<uint32_t>(trial % 4);
    const Concave own = concave(pts, 0.0025f, closing),
                  given = concave(pts, 0.0025f, closing, fg::kMaxContourVertices, &b);
    SCOPED_TRACE("trial " + std::to_string(trial));
    ASSERT_EQ(own.status, given.status);
    EXPECT_EQ(std::memcmp(&own.cell, &given.cell, sizeof own.cell), 0);
    EXPECT_EQ(own.all_inside, given.all_inside);
    ASSERT_EQ(own.poly.size(), given.poly.size());
    EXPECT_EQ(std::memcmp(own.poly.data(), given.poly.data(), own.poly.size() * sizeof(Vec2)), 0);
  }
}

// Bounds that are not finite or not ordered are refused; bounds that are wrong (the
// points beyond them, NaN points the caller said were finite) stay in the raster.
TEST(ConcaveHull, WrongBoundsAreRefusedOrStayInTheRaster) {
  std::mt19937 rng(77u);
  std::vector<Vec2> pts = random_blob(rng, 500, Vec2{0.2f, -0.1f}, 0.05f);
  fg::ConcaveHullParams b;
  b.bounds_given = true;
  b.xmin = 0.1f, b.xmax = 0.3f, b.ymin = -0.2f, b.ymax = 0.0f;
  for (const float bad : {kNaN, kInf, -kInf}) {
    fg::ConcaveHullParams c = b;
    c.xmax = bad;
    EXPECT_EQ(concave(pts, 0.0025f, 2, fg::kMaxContourVertices, &c).status, Status::invalid_argument);
  }
  fg::ConcaveHullParams swapped = b;
  std::swap(swapped.ymin, swapped.ymax);
  EXPECT_EQ(concave(pts, 0.0025f, 2, fg::kMaxContourVertices, &swapped).status, Status::invalid_argument);
  // Too small a box, and NaN points: defined statuses, no read or write outside the
  // scratch (the sanitizer builds run this too).
  fg::ConcaveHullParams small = b;
  small.xmin = 0.19f, small.xmax = 0.21f, small.ymin = -0.11f, small.ymax = -0.09f;
  pts[7] = Vec2{kNaN, 0.2f};
  pts[8] = Vec2{0.2f, kNaN};
  for (const fg::ConcaveHullParams* p : {&b, &small}) {
    const Concave r = concave(pts, 0.0025f, 2, fg::kMaxContourVertices, p);
    EXPECT_TRUE(r.status == Status::ok || r.status == Status::capacity_exceeded) << static_cast<int>(r.status);
  }
}

// ---------------------------------------------------------------------------------
// Polygon queries

TEST(Polygon, AreaSignFollowsOrientation) {
  const Vec2 ccw[4] = {{0, 0}, {2, 0}, {2, 1}, {0, 1}};
  const Vec2 cw[4] = {{0, 0}, {0, 1}, {2, 1}, {2, 0}};
  EXPECT_FLOAT_EQ(fg::polygon_area(ccw, 4), 2.0f);
  EXPECT_FLOAT_EQ(fg::polygon_area(cw, 4), -2.0f);
  EXPECT_EQ(fg::polygon_area(ccw, 2), 0.0f);
  EXPECT_EQ(fg::polygon_area(nullptr, 4), 0.0f);
}

TEST(Polygon, ContainsTable) {
  // An L, in both orientations (ArduPilot test_polygon style).
  const std::vector<Vec2> l = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  const std::vector<Vec2> l_cw(l.rbegin(), l.rend());
  struct Case {
    Vec2 p;
    bool in;
  };
  const Case cases[] = {
      {{0.5f, 0.5f}, true},  {{1.5f, 0.5f}, true}, {{0.5f, 1.5f}, true},     {{1.5f, 1.5f}, false},
      {{0, 0}, true},        {{2, 0}, true},       {{1, 1}, true},           {{1, 1.5f}, true},
      {{1.5f, 1}, true},     {{0, 1}, true},       {{-0.01f, 1}, false},     {{2.01f, 0.5f}, false},
      {{1, 2.0001f}, false}, {{0.5f, 2}, true},    {{1.0001f, 1.5f}, false}, {{3, 1}, false},
  };
  for (const auto* poly : {&l, &l_cw}) {
    for (const Case& c : cases) {
      EXPECT_EQ(fg::polygon_contains(poly->data(), static_cast<uint32_t>(poly->size()), c.p), c.in)
          << c.p.x << ", " << c.p.y;
    }
  }
  EXPECT_FALSE(fg::polygon_contains(l.data(), 6, Vec2{kNaN, 0.5f}));
  EXPECT_FALSE(fg::polygon_contains(nullptr, 6, Vec2{0.5f, 0.5f}));
  EXPECT_FALSE(fg::polygon_contains(l.data(), 0, Vec2{0.5f, 0.5f}));
  // Tolerance: 1 mm off the edge counts with a 2 mm tolerance only.
  EXPECT_FALSE(fg::polygon_contains(l.data(), 6, Vec2{-0.001f, 0.5f}));
  EXPECT_TRUE(fg::polygon_contains(l.data(), 6, Vec2{-0.001f, 0.5f}, 0.002f));
}

TEST(Polygon, ContainsAgreesWithWindingOnRandomProbes) {
  std::mt19937 rng(8u);
  std::uniform_real_distribution<float> u(-0.1f, 0.2f);
  const auto pts = sample_grid(0.0f, 0.12f, 0.0f, 0.1f, 0.002f, keep_u);
  const Concave r = concave(pts);
  ASSERT_EQ(r.status, Status::ok);
  for (int i = 0; i < 20000; ++i) {
    const Vec2 p{u(rng), u(rng)};
    EXPECT_EQ(fg::polygon_contains(r.poly.data(), static_cast<uint32_t>(r.poly.size()), p, 0.0f),
              inside_or_on(r.poly, p, 0.0));
  }
}

// Brute-force span: sample the line densely with an independent inside test.
bool brute_span(const std::vector<Vec2>& poly, float y, double step, double x0, double x1, double& lo, double& hi) {
  bool any = false;
  const int n = static_cast<int>((x1 - x0) / step);
  for (int i = 0; i <= n; ++i) {
    const double x = x0 + step * i;
    if (inside_or_on(poly, Vec2{static_cast<float>(x), y}, 0.0)) {
      if (!any) lo = x;
      hi = x;
      any = true;
    }
  }
  return any;
}

TEST(Polygon, SpanMatchesBruteForceOnConvexPolygons) {
  std::mt19937 rng(2025u);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int trial = 0; trial < 40; ++trial) {
    // A convex polygon: sorted angles on an ellipse.
    const int n = 3 + static_cast<int>(rng() % 12u);
    std::vector<float> ang(n);
    for (float& a : ang) a = 6.2831853f * u(rng);
    std::sort(ang.begin(), ang.end());
    const float rx = 0.2f + u(rng), ry = 0.2f + u(rng), cx = u(rng) - 0.5f, cy = u(rng) - 0.5f;
    std::vector<Vec2> poly;
    for (float a : ang) poly.push_back({cx + rx * std::cos(a), cy + ry * std::sin(a)});
    if (fg::polygon_area(poly.data(), static_cast<uint32_t>(poly.size())) <= 1e-4f) continue;
    float ymin = poly[0].y, ymax = poly[0].y;
    for (const Vec2& v : poly) {
      ymin = std::min(ymin, v.y);
      ymax = std::max(ymax, v.y);
    }
    for (int k = 0; k < 12; ++k) {
      const float y = ymin - 0.05f + (ymax - ymin + 0.1f) * u(rng);
      float xl = 0, xr = 0;
      const bool got = fg::polygon_span_at_y(poly.data(), static_cast<uint32_t>(poly.size()), y, xl, xr);
      double lo = 0, hi = 0;
      const double step = 5e-4;
      const bool want = brute_span(poly, y, step, cx - rx - 0.01, cx + rx + 0.01, lo, hi);
      if (want) {
        ASSERT_TRUE(got) << y;
        EXPECT_LE(xl, lo + 1e-6);
        EXPECT_GT(xl, lo - step - 1e-6);
        EXPECT_GE(xr, hi - 1e-6);
        EXPECT_LT(xr, hi + step + 1e-6);
      } else if (got) {  // a sliver thinner than the sampling step
        EXPECT_LT(xr - xl, step + 1e-6);
      }
    }
  }
}

TEST(Polygon, SpanOnTheLShapeVerticesAndHorizontalEdges) {
  const std::vector<Vec2> l = {{0, 0}, {0.1f, 0}, {0.1f, 0.05f}, {0.05f, 0.05f}, {0.05f, 0.1f}, {0, 0.1f}};
  const std::vector<Vec2> l_cw(l.rbegin(), l.rend());
  struct Case {
    float y;
    bool hit;
    float xl, xr;
  };
  const Case cases[] = {
      {0.02f, true, 0.0f, 0.1f}, {0.07f, true, 0.0f, 0.05f},  {0.05f, true, 0.0f, 0.1f},  // along the step
      {0.0f, true, 0.0f, 0.1f},  {0.1f, true, 0.0f, 0.05f},   {0.1001f, false, 0, 0},
      {-0.0001f, false, 0, 0},   {0.0499f, true, 0.0f, 0.1f}, {0.0501f, true, 0.0f, 0.05f},
  };
  for (const auto* poly : {&l, &l_cw}) {
    for (const Case& c : cases) {
      float xl = -1, xr = -1;
      const bool got = fg::polygon_span_at_y(poly->data(), 6, c.y, xl, xr);
      ASSERT_EQ(got, c.hit) << c.y;
      if (got) {
        EXPECT_FLOAT_EQ(xl, c.xl) << c.y;
        EXPECT_FLOAT_EQ(xr, c.xr) << c.y;
      }
    }
    // And against brute force on a sweep of lines.
    for (int k = 1; k < 100; ++k) {
      const float y = 0.001f * static_cast<float>(k) + 0.0003f;
      float xl = 0, xr = 0;
      ASSERT_TRUE(fg::polygon_span_at_y(poly->data(), 6, y, xl, xr));
      double lo = 0, hi = 0;
      ASSERT_TRUE(brute_span(*poly, y, 1e-4, -0.05, 0.15, lo, hi));
      EXPECT_NEAR(xl, lo, 1.01e-4);
      EXPECT_NEAR(xr, hi, 1.01e-4);
    }
  }
  // Through a single vertex: a diamond's apex.
  const Vec2 diamond[4] = {{0, -1}, {1, 0}, {0, 1}, {-1, 0}};
  float xl = -5, xr = -5;
  ASSERT_TRUE(fg::polygon_span_at_y(diamond, 4, 1.0f, xl, xr));
  EXPECT_EQ(xl, 0.0f);
  EXPECT_EQ(xr, 0.0f);
  ASSERT_TRUE(fg::polygon_span_at_y(diamond, 4, 0.0f, xl, xr));
  EXPECT_EQ(xl, -1.0f);
  EXPECT_EQ(xr, 1.0f);
  EXPECT_FALSE(fg::polygon_span_at_y(diamond, 4, kNaN, xl, xr));
  EXPECT_FALSE(fg::polygon_span_at_y(nullptr, 4, 0.0f, xl, xr));
  EXPECT_FALSE(fg::polygon_span_at_y(diamond, 0, 0.0f, xl, xr));
}

}  // namespace
