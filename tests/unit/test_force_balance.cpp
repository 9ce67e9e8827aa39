// XOY force balance: fit_x_of_y against the closed-form least squares, side_angle on
// known slopes, build_scan_lines on polygons with known L_j / R_j (rectangle,
// triangle, L shape), mark_graspable's bounds, and best_windows on constructed line
// sets (parallel sides, a trapezoid, jumps, dropped lines, ranking) and against a
// brute-force window search written here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <vector>

#include "fg/core/force_balance.hpp"
#include "fg/core/hull.hpp"
#include "fg/core/limits.hpp"

namespace {

using fg::ScanLine;
using fg::SideFit;
using fg::Vec2;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// ------------------------------------------------------------------ fit_x_of_y

// Closed form: a = (n Sxy - Sx Sy) / (n Syy - Sy^2), b = (Sx - a Sy) / n, in long double.
void closed_form(const std::vector<float>& y, const std::vector<float>& x, double& a, double& b) {
  long double n = static_cast<long double>(y.size()), sy = 0, sx = 0, syy = 0, sxy = 0;
  for (size_t i = 0; i < y.size(); ++i) {
    sy += y[i];
    sx += x[i];
    syy += static_cast<long double>(y[i]) * y[i];
    sxy += static_cast<long double>(y[i]) * x[i];
  }
  const long double aa = (n * sxy - sx * sy) / (n * syy - sy * sy);
  a = static_cast<double>(aa);
  b = static_cast<double>((sx - aa * sy) / n);
}

TEST(FitXOfY, MatchesClosedFormOnNoisyData) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> uy(-0.05f, 0.05f);
  std::normal_distribution<float> noise(0.f, 0.001f);
  for (int trial = 0; trial < 200; ++trial) {
    const uint32_t n = 2 + static_cast<uint32_t>(rng() % 40);
    const float a0 = std::tan(static_cast<float>(trial % 17 - 8) * 0.1f), b0 = 0.01f * static_cast<float>(trial % 7);
    std::vector<float> y(n), x(n);
    for (uint32_t i = 0; i < n; ++i) {
      y[i] = uy(rng);
      x[i] = a0 * y[i] + b0 + noise(rng);
    }
    double ea, eb;
    closed_form(y, x, ea, eb);
    float a = 0, b = 0;
    ASSERT_TRUE(fg::fit_x_of_y(y.data(), x.data(), n, a, b)) << trial;
    EXPECT_NEAR(a, ea, 1e-5 * std::max(1.0, std::fabs(ea))) << trial;
    EXPECT_NEAR(b, eb, 1e-6 + 1e-5 * std::fabs(ea) * 0.05) << trial;
  }
}

TEST(FitXOfY, ExactOnExactLines) {
  const float slopes[] = {0.f, 0.25f, -0.5f, 2.f, -8.f, 1e-3f};
  for (float a0 : slopes) {
    const float b0 = 0.0125f;
    std::vector<float> y, x;
    for (int j = 0; j < 11; ++j) {
      // y on a power-of-two grid and x exactly representable: the fit is exact.
      const float yy = -0.03125f + 0.0078125f * static_cast<float>(j);
      y.push_back(yy);
      x.push_back(a0 * yy + b0);
    }
    float a = 1, b = 1;
    ASSERT_TRUE(fg::fit_x_of_y(y.data(), x.data(), 11, a, b));
    EXPECT_NEAR(a, a0, 1e-6f * std::max(1.f, std::fabs(a0))) << a0;
    EXPECT_NEAR(b, b0, 1e-7f) << a0;
  }
  // A vertical side (x constant): a = 0 exactly, b = x.
  const float y2[4] = {0.f, 0.002f, 0.004f, 0.006f}, x2[4] = {0.031f, 0.031f, 0.031f, 0.031f};
  float a = 1, b = 0;
  ASSERT_TRUE(fg::fit_x_of_y(y2, x2, 4, a, b));
  EXPECT_EQ(a, 0.f);
  EXPECT_FLOAT_EQ(b, 0.031f);
  // Two points: the line through them.
  const float y3[2] = {0.f, 0.01f}, x3[2] = {0.02f, 0.03f};
  ASSERT_TRUE(fg::fit_x_of_y(y3, x3, 2, a, b));
  EXPECT_NEAR(a, 1.0, 1e-5);
  EXPECT_NEAR(b, 0.02, 1e-7);
}

TEST(FitXOfY, DegenerateInputs) {
  const float y[3] = {0.01f, 0.01f, 0.01f}, x[3] = {0.f, 1.f, 2.f};
  float a = 0, b = 0;
  EXPECT_FALSE(fg::fit_x_of_y(y, x, 0, a, b));
  EXPECT_FALSE(fg::fit_x_of_y(y, x, 1, a, b));
  EXPECT_FALSE(fg::fit_x_of_y(y, x, 3, a, b));  // all y equal
  const float yn[3] = {0.f, kNaN, 0.02f};
  EXPECT_FALSE(fg::fit_x_of_y(yn, x, 3, a, b));
  const float y2[3] = {0.f, 0.01f, 0.02f}, xn[3] = {0.f, kNaN, 0.f};
  EXPECT_FALSE(fg::fit_x_of_y(y2, xn, 3, a, b));
}

// ------------------------------------------------------------------ side_angle

TEST(SideAngle, KnownSlopes) {
  const double pi = 3.14159265358979323846;
  EXPECT_FLOAT_EQ(fg::side_angle(0.f, 0.f), 0.f);
  EXPECT_NEAR(fg::side_angle(1.f, 0.f), pi / 4, 1e-7);
  EXPECT_NEAR(fg::side_angle(0.f, 1.f), pi / 4, 1e-7);
  EXPECT_NEAR(fg::side_angle(1.f, -1.f), pi / 2, 1e-6);
  EXPECT_NEAR(fg::side_angle(-1.f, 1.f), pi / 2, 1e-6);
  EXPECT_NEAR(fg::side_angle(0.3f, 0.3f), 0.0, 1e-9);
  EXPECT_NEAR(fg::side_angle(std::tan(0.1f), std::tan(-0.05f)), 0.15, 1e-6);
  EXPECT_NEAR(fg::side_angle(std::sqrt(3.f), 1.f / std::sqrt(3.f)), pi / 6, 1e-6);
  // Near-vertical in opposite senses: close to pi, never more.
  EXPECT_NEAR(fg::side_angle(1e6f, -1e6f), pi, 1e-5);
  EXPECT_LE(fg::side_angle(1e30f, -1e30f), static_cast<float>(pi) + 1e-6f);
  for (float a = -3.f; a <= 3.f; a += 0.37f)
    for (float b = -3.f; b <= 3.f; b += 0.41f)
      EXPECT_NEAR(fg::side_angle(a, b),
                  std::fabs(std::atan(static_cast<double>(a)) - std::atan(static_cast<double>(b))),
                  5e-7);  // float atan: a few ulps at ~2.5 rad
}

// ------------------------------------------------------------------ build_scan_lines

struct Shape {
  std::vector<Vec2> poly;
  // Analytic leftmost / rightmost x at y (double); false outside.
  std::function<bool(double, double&, double&)> span;
};

void check_lines(const Shape& s, float y_min, float y_max, float delta, uint32_t expect_n, double tol = 1e-6) {
  std::vector<ScanLine> lines(1024);
  float used = 0;
  const uint32_t n = fg::build_scan_lines(s.poly.data(), static_cast<uint32_t>(s.poly.size()), y_min, y_max, delta,
                                          lines.data(), 1024, used);
  ASSERT_EQ(n, expect_n);
  EXPECT_EQ(used, delta);
  for (uint32_t j = 0; j < n; ++j) {
    const ScanLine& l = lines[j];
    EXPECT_NEAR(l.y, y_min + static_cast<double>(j) * delta, 1e-6) << j;
    EXPECT_FALSE(l.kept);
    double L, R;
    const bool in = s.span(l.y, L, R);
    ASSERT_EQ(l.hit, in) << "line " << j << " y " << l.y;
    if (in) {
      EXPECT_NEAR(l.left, L, tol) << "line " << j << " y " << l.y;
      EXPECT_NEAR(l.right, R, tol) << "line " << j << " y " << l.y;
    } else {
      EXPECT_EQ(l.left, 0.f);
      EXPECT_EQ(l.right, 0.f);
    }
  }
}

TEST(ScanLines, Rectangle) {
  Shape s;
  s.poly = {{-0.02f, -0.03f}, {0.025f, -0.03f}, {0.025f, 0.05f}, {-0.02f, 0.05f}};
  s.span = [](double y, double& L, double& R) {
    if (y < -0.03 || y > 0.05) return false;
    L = -0.02;
    R = 0.025;
    return true;
  };
  // A 0.079 m span at 2 mm: 40 lines from -0.03 to 0.048 (span / delta = 39.5: no
  // float rounding question about a line exactly at y_max).
  check_lines(s, -0.03f, 0.049f, 0.002f, 40);
  // Clockwise order gives the same lines.
  std::reverse(s.poly.begin(), s.poly.end());
  check_lines(s, -0.03f, 0.049f, 0.002f, 40);
  // Lines inside only (start 1 mm in): 0.0775 / 0.002 = 38.75 -> 39 lines.
  check_lines(s, -0.029f, 0.0485f, 0.002f, 39);
}

TEST(ScanLines, Triangle) {
  Shape s;
  s.poly = {{0.f, 0.f}, {0.04f, 0.f}, {0.02f, 0.03f}};
  s.span = [](double y, double& L, double& R) {
    if (y < 0 || y > 0.03) return false;
    L = 0.02 * y / 0.03;
    R = 0.04 - 0.02 * y / 0.03;
    return true;
  };
  check_lines(s, 0.0005f, 0.0295f, 0.001f, 30);
}

TEST(ScanLines, LShape) {
  Shape s;
  // Foot 0.06 wide and 0.02 high, upright 0.02 wide up to 0.05.
  s.poly = {{0.f, 0.f}, {0.06f, 0.f}, {0.06f, 0.02f}, {0.02f, 0.02f}, {0.02f, 0.05f}, {0.f, 0.05f}};
  s.span = [](double y, double& L, double& R) {
    if (y < 0 || y > 0.05) return false;
    L = 0.0;
    R = y <= 0.02 ? 0.06 : 0.02;
    return true;
  };
  // Lines at 0.001, 0.003, ..., 0.049 (never on the inner corner's height).
  check_lines(s, 0.001f, 0.049f, 0.002f, 25);
}

TEST(ScanLines, LinesOutsideThePolygonMiss) {
  Shape s;
  s.poly = {{0.f, 0.f}, {0.01f, 0.f}, {0.01f, 0.01f}, {0.f, 0.01f}};
  s.span = [](double y, double& L, double& R) {
    if (y < 0 || y > 0.01) return false;
    L = 0;
    R = 0.01;
    return true;
  };
  // -0.0101 .. 0.0190: 14.55 spacings -> 15 lines, the first five and the last below / above.
  check_lines(s, -0.0101f, 0.0190f, 0.002f, 15);
}

TEST(ScanLines, CapacityGrowsDelta) {
  const std::vector<Vec2> rect = {{0.f, 0.f}, {0.03f, 0.f}, {0.03f, 0.2f}, {0.f, 0.2f}};
  std::vector<ScanLine> lines(64);
  float used = 0;
  // 0.2 m at 1 mm needs 201 lines; only 50 fit: delta becomes 0.2 / 49.
  const uint32_t n = fg::build_scan_lines(rect.data(), 4, 0.f, 0.2f, 0.001f, lines.data(), 50, used);
  ASSERT_EQ(n, 50u);
  EXPECT_NEAR(used, 0.2 / 49, 1e-7);
  EXPECT_NEAR(lines[0].y, 0.0, 1e-9);
  EXPECT_NEAR(lines[49].y, 0.2, 1e-6);
  // Every line but the last (which may round to just above y_max) crosses the rectangle.
  for (uint32_t j = 0; j + 1 < n; ++j) {
    EXPECT_TRUE(lines[j].hit) << j;
    EXPECT_NEAR(lines[j].y, j * (0.2 / 49), 1e-6) << j;
  }
  // Capacity 1: one line at y_min.
  const uint32_t n1 = fg::build_scan_lines(rect.data(), 4, 0.f, 0.2f, 0.001f, lines.data(), 1, used);
  EXPECT_EQ(n1, 1u);
  EXPECT_EQ(lines[0].y, 0.f);
  // A single-height span (y_max == y_min): one line.
  const uint32_t n2 = fg::build_scan_lines(rect.data(), 4, 0.1f, 0.1f, 0.001f, lines.data(), 50, used);
  EXPECT_EQ(n2, 1u);
}

TEST(ScanLines, HugeSpanOverDeltaStillFillsTheCapacity) {
  // span / delta = 1e10 lines and more wanted (beyond 2^32): the documented behaviour is
  // n = capacity with delta grown to fit.
  const std::vector<Vec2> rect = {{0.f, 0.f}, {0.03f, 0.f}, {0.03f, 100.f}, {0.f, 100.f}};
  std::vector<ScanLine> lines(64);
  for (float delta : {1e-8f, 2.3283064e-8f /* 100 / 2^32 */, 1e-12f}) {
    float used = 0;
    const uint32_t n = fg::build_scan_lines(rect.data(), 4, 0.f, 100.f, delta, lines.data(), 64, used);
    EXPECT_EQ(n, 64u) << "delta " << delta;
    EXPECT_NEAR(used, 100.0 / 63, 1e-4) << "delta " << delta;
  }
}

// The lines are built in one sweep over the contour's edges; each must equal the line
// asked of the polygon on its own (polygon_span_at_y, tested against brute force in
// test_hull). Random star polygons with vertices on the lines' own y values, so lines
// pass through vertices and along horizontal edges, and lines beyond the polygon.
TEST(ScanLines, SweepEqualsEachLineOnItsOwn) {
  std::mt19937 rng(77);
  std::uniform_int_distribution<int> verts(3, 40);
  std::uniform_real_distribution<float> radius(0.2f, 1.f), jitter(-0.5f, 0.5f);
  std::vector<ScanLine> lines(fg::kMaxScanLines);
  int through_vertex = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const float delta = trial % 3 == 0 ? 0.01f : 0.0037f;
    const float y0 = -0.2f + 0.001f * static_cast<float>(trial % 7);
    const int nv = verts(rng);
    std::vector<Vec2> poly;
    for (int k = 0; k < nv; ++k) {  // a star polygon about the origin
      const float ang = 6.2831853f * (static_cast<float>(k) + 0.4f * jitter(rng)) / static_cast<float>(nv);
      const float r = 0.1f * radius(rng);
      float y = r * std::sin(ang);
      if (trial % 2 == 0) {  // snapped onto a line's y, computed as the lines' are
        const float j = std::round((y - y0) / delta);
        y = y0 + j * delta;
      }
      poly.push_back({r * std::cos(ang), y});
    }
    if (trial % 5 == 0) poly.push_back({poly.back().x + 0.01f, poly.back().y});  // a horizontal edge
    if (trial % 7 == 3) poly.insert(poly.begin() + 1, Vec2{std::numeric_limits<float>::quiet_NaN(), 0.f});
    if (trial % 11 == 4) poly.insert(poly.begin() + 2, Vec2{0.01f, std::numeric_limits<float>::infinity()});
    float used = 0;
    const uint32_t n = fg::build_scan_lines(poly.data(), static_cast<uint32_t>(poly.size()), y0, y0 + 0.5f, delta,
                                            lines.data(), fg::kMaxScanLines, used);
    ASSERT_GT(n, 0u);
    for (uint32_t j = 0; j < n; ++j) {
      float xl = 0, xr = 0;
      const bool hit = fg::polygon_span_at_y(poly.data(), static_cast<uint32_t>(poly.size()), lines[j].y, xl, xr);
      ASSERT_EQ(lines[j].hit, hit) << "trial " << trial << " line " << j;
      EXPECT_EQ(lines[j].left, xl) << "trial " << trial << " line " << j;
      EXPECT_EQ(lines[j].right, xr) << "trial " << trial << " line " << j;
      for (const Vec2& v : poly) through_vertex += v.y == lines[j].y ? 1 : 0;
    }
  }
  EXPECT_GT(through_vertex, 100);  // the vertex cases were exercised
}

TEST(ScanLines, InvalidArguments) {
  const std::vector<Vec2> rect = {{0.f, 0.f}, {0.03f, 0.f}, {0.03f, 0.2f}, {0.f, 0.2f}};
  std::vector<ScanLine> lines(8);
  float used = 0;
  EXPECT_EQ(fg::build_scan_lines(nullptr, 4, 0.f, 0.1f, 0.01f, lines.data(), 8, used), 0u);
  EXPECT_EQ(fg::build_scan_lines(rect.data(), 2, 0.f, 0.1f, 0.01f, lines.data(), 8, used), 0u);
  EXPECT_EQ(fg::build_scan_lines(rect.data(), 4, 0.f, 0.1f, 0.01f, lines.data(), 0, used), 0u);
  EXPECT_EQ(fg::build_scan_lines(rect.data(), 4, 0.1f, 0.f, 0.01f, lines.data(), 8, used), 0u);
  EXPECT_EQ(fg::build_scan_lines(rect.data(), 4, 0.f, 0.1f, 0.f, lines.data(), 8, used), 0u);
  EXPECT_EQ(fg::build_scan_lines(rect.data(), 4, 0.f, 0.1f, -0.01f, lines.data(), 8, used), 0u);
  EXPECT_EQ(fg::build_scan_lines(rect.data(), 4, kNaN, 0.1f, 0.01f, lines.data(), 8, used), 0u);
  EXPECT_EQ(fg::build_scan_lines(rect.data(), 4, 0.f, kNaN, 0.01f, lines.data(), 8, used), 0u);
  EXPECT_EQ(fg::build_scan_lines(rect.data(), 4, 0.f, 0.1f, kNaN, lines.data(), 8, used), 0u);
}

// ------------------------------------------------------------------ mark_graspable

TEST(MarkGraspable, WidthBoundsAndMisses) {
  // widths: 0.01, 0.02 (= min), 0.05, 0.0805, 0.081 (= max), 0.09, and a miss.
  std::vector<ScanLine> l(7);
  const float widths[6] = {0.01f, 0.02f, 0.05f, 0.0805f, 0.081f, 0.09f};
  for (int i = 0; i < 6; ++i) l[i] = ScanLine{0.002f * i, -0.5f * widths[i], 0.5f * widths[i], true, false};
  l[6] = ScanLine{0.012f, 0.f, 0.f, false, true};
  // Apply the same float arithmetic the bounds are compared with.
  const float min_w = l[1].right - l[1].left, max_w = l[4].right - l[4].left;
  fg::mark_graspable(l.data(), 7, min_w, max_w);
  const bool expect[7] = {false, true, true, true, false, false, false};
  for (int i = 0; i < 7; ++i) EXPECT_EQ(l[i].kept, expect[i]) << i;
  // Re-marking overwrites earlier marks.
  fg::mark_graspable(l.data(), 7, 0.f, 1.f);
  for (int i = 0; i < 6; ++i) EXPECT_TRUE(l[i].kept) << i;
  EXPECT_FALSE(l[6].kept);
}

// ------------------------------------------------------------------ best_windows

// Lines y_j = y0 + j * dy, L = aL y + bL, R = aR y + bR, all kept.
std::vector<ScanLine> sides(uint32_t n, float y0, float dy, float aL, float bL, float aR, float bR) {
  std::vector<ScanLine> l(n);
  for (uint32_t j = 0; j < n; ++j) {
    const float y = y0 + dy * static_cast<float>(j);
    l[j] = ScanLine{y, aL * y + bL, aR * y + bR, true, true};
  }
  return l;
}

bool spans(const SideFit& w, uint32_t a, uint32_t b) { return w.first <= a && w.first + w.count - 1 >= b; }

TEST(BestWindows, ParallelSidesGiveBetaZeroAndPreferTheCentre) {
  const auto l = sides(30, -0.029f, 0.002f, 0.f, -0.025f, 0.f, 0.025f);
  std::vector<SideFit> out(64);
  const uint32_t k = 11;
  const uint32_t n = fg::best_windows(l.data(), 30, 0.004f, k, 0.f, 0.5f, out.data(), 64);
  ASSERT_EQ(n, 20u);
  for (uint32_t i = 0; i < n; ++i) {
    EXPECT_NEAR(out[i].beta, 0.0, 1e-9);
    EXPECT_EQ(out[i].count, k);
    EXPECT_NEAR(out[i].width, 0.05, 1e-6);
    EXPECT_NEAR(out[i].x_centre, 0.0, 1e-6);
    EXPECT_NEAR(out[i].y_centre, 0.5 * (l[out[i].first].y + l[out[i].first + k - 1].y), 1e-7);
    EXPECT_NEAR(out[i].rank, 0.5 * std::fabs(out[i].y_centre), 1e-7);
    if (i > 0) {
      EXPECT_LE(out[i - 1].rank, out[i].rank);
    }
  }
  // The best windows are centred 1 mm either side of y_ref = 0: lines 9..19 and 10..20.
  EXPECT_EQ(std::min(out[0].first, out[1].first), 9u);
  EXPECT_EQ(std::max(out[0].first, out[1].first), 10u);
  // Another y_ref moves the best window.
  const uint32_t n2 = fg::best_windows(l.data(), 30, 0.004f, k, 0.02f, 0.5f, out.data(), 1);
  ASSERT_EQ(n2, 1u);
  EXPECT_NEAR(out[0].y_centre, 0.019, 1e-6);
}

TEST(BestWindows, TrapezoidBetaIsTheAngleBetweenTheSides) {
  struct Case {
    float aL, aR;
  };
  const Case cases[] = {{0.1f, -0.1f}, {0.f, 0.3f}, {-0.2f, -0.05f}, {0.5f, 0.5f}, {0.02f, -0.3f}};
  for (const Case& c : cases) {
    const auto l = sides(20, 0.f, 0.002f, c.aL, -0.02f, c.aR, 0.02f);
    std::vector<SideFit> out(32);
    const uint32_t n = fg::best_windows(l.data(), 20, 0.004f, 6, 0.f, 0.f, out.data(), 32);
    ASSERT_EQ(n, 15u);
    const double beta = std::fabs(std::atan(static_cast<double>(c.aL)) - std::atan(static_cast<double>(c.aR)));
    for (uint32_t i = 0; i < n; ++i) {
      EXPECT_NEAR(out[i].beta, beta, 2e-6) << c.aL << " " << c.aR;
      EXPECT_NEAR(out[i].a_left, c.aL, 1e-4);
      EXPECT_NEAR(out[i].a_right, c.aR, 1e-4);
      EXPECT_NEAR(out[i].b_left, -0.02, 1e-6);
      EXPECT_NEAR(out[i].b_right, 0.02, 1e-6);
    }
  }
}

TEST(BestWindows, AJumpAboveTheThresholdSplitsRegions) {
  // Lines 0..19: L = 0; lines 20..39: L = 0.01 (a 10 mm step), R = 0.05 throughout.
  auto l = sides(40, 0.f, 0.002f, 0.f, 0.f, 0.f, 0.05f);
  for (uint32_t j = 20; j < 40; ++j) l[j].left = 0.01f;
  std::vector<SideFit> out(128);
  const uint32_t k = 5;
  const uint32_t n = fg::best_windows(l.data(), 40, 0.004f, k, 0.f, 0.f, out.data(), 128);
  EXPECT_EQ(n, 2u * (20 - k + 1));
  for (uint32_t i = 0; i < n; ++i) {
    EXPECT_FALSE(spans(out[i], 19, 20)) << "window at " << out[i].first;
    EXPECT_NEAR(out[i].beta, 0.0, 1e-9);
  }
  // The same step on the right side.
  auto r = sides(40, 0.f, 0.002f, 0.f, 0.f, 0.f, 0.05f);
  for (uint32_t j = 25; j < 40; ++j) r[j].right = 0.045f;
  const uint32_t nr = fg::best_windows(r.data(), 40, 0.004f, k, 0.f, 0.f, out.data(), 128);
  EXPECT_EQ(nr, (25 - k + 1) + (15 - k + 1));
  for (uint32_t i = 0; i < nr; ++i) EXPECT_FALSE(spans(out[i], 24, 25)) << "window at " << out[i].first;
}

TEST(BestWindows, AStepAtTheThresholdDoesNotSplit) {
  // Power-of-two values: the step equals the threshold exactly (only above splits).
  const float th = 0.00390625f;  // 2^-8
  auto l = sides(12, 0.f, 0.0078125f, 0.f, 0.f, 0.f, 0.0625f);
  for (uint32_t j = 6; j < 12; ++j) l[j].left = th;
  std::vector<SideFit> out(16);
  EXPECT_EQ(fg::best_windows(l.data(), 12, th, 4, 0.f, 0.f, out.data(), 16), 9u);
  // Slightly below the step: split.
  EXPECT_EQ(fg::best_windows(l.data(), 12, th * 0.99f, 4, 0.f, 0.f, out.data(), 16), 3u + 3u);
}

TEST(BestWindows, GradualDriftBelowTheThresholdIsOneRegion) {
  // The left side moves 1 mm per line (a slope of 0.5), far less than the 4 mm threshold.
  const auto l = sides(30, 0.f, 0.002f, 0.5f, 0.f, 0.f, 0.08f);
  std::vector<SideFit> out(64);
  const uint32_t n = fg::best_windows(l.data(), 30, 0.004f, 8, 0.f, 0.f, out.data(), 64);
  EXPECT_EQ(n, 23u);
  for (uint32_t i = 0; i < n; ++i) EXPECT_NEAR(out[i].beta, std::atan(0.5), 2e-6);
}

TEST(BestWindows, DroppedLinesSplit) {
  auto l = sides(30, 0.f, 0.002f, 0.f, 0.f, 0.f, 0.05f);
  l[15].kept = false;
  std::vector<SideFit> out(64);
  const uint32_t k = 5;
  const uint32_t n = fg::best_windows(l.data(), 30, 0.004f, k, 0.f, 0.f, out.data(), 64);
  EXPECT_EQ(n, (15 - k + 1) + (14 - k + 1));
  for (uint32_t i = 0; i < n; ++i) {
    EXPECT_FALSE(spans(out[i], 15, 15)) << "window at " << out[i].first;
  }
  // A miss (hit = false) counts as dropped too when not kept.
  l[15].kept = true;
  l[3].kept = false;
  l[3].hit = false;
  const uint32_t n2 = fg::best_windows(l.data(), 30, 0.004f, k, 0.f, 0.f, out.data(), 64);
  EXPECT_EQ(n2, 0u + (26 - k + 1));
  // A region shorter than k gives no window; nothing kept gives none.
  for (auto& s : l) s.kept = false;
  EXPECT_EQ(fg::best_windows(l.data(), 30, 0.004f, k, 0.f, 0.f, out.data(), 64), 0u);
}

TEST(BestWindows, RankingPrefersSmallBetaThenTheCentre) {
  // Region A (lines 0..9): parallel, far from y_ref. Region B (lines 20..29): sides at
  // beta ~0.2 rad, centred on y_ref. With centre_weight 0.5 rad/m and A 0.1 m away,
  // A ranks 0.05 < 0.2: small beta wins.
  std::vector<ScanLine> l(30);
  for (uint32_t j = 0; j < 30; ++j) {
    const float y = -0.12f + 0.002f * static_cast<float>(j) + (j >= 20 ? 0.1f : 0.f);
    const bool b = j >= 20;
    l[j] = ScanLine{y, b ? 0.1f * y : 0.f, b ? -0.1f * y + 0.04f : 0.04f, true, j < 10 || j >= 20};
  }
  // Region A: y from -0.12 to -0.102; region B: y from 0.02 to 0.038, y_ref at its centre.
  const float y_ref = 0.5f * (l[20].y + l[29].y);
  std::vector<SideFit> out(16);
  const uint32_t k = 10;
  const uint32_t n = fg::best_windows(l.data(), 30, 0.004f, k, y_ref, 0.5f, out.data(), 16);
  ASSERT_EQ(n, 2u);
  EXPECT_EQ(out[0].first, 0u);
  EXPECT_NEAR(out[0].beta, 0.0, 1e-9);
  EXPECT_EQ(out[1].first, 20u);
  EXPECT_NEAR(out[1].beta, 2 * std::atan(0.1), 2e-6);
  // With a large centre weight the window at the centre wins despite its beta.
  const uint32_t n2 = fg::best_windows(l.data(), 30, 0.004f, k, y_ref, 50.f, out.data(), 16);
  ASSERT_EQ(n2, 2u);
  EXPECT_EQ(out[0].first, 20u);
}

TEST(BestWindows, InvalidArguments) {
  const auto l = sides(300, 0.f, 0.001f, 0.f, 0.f, 0.f, 0.05f);
  std::vector<SideFit> out(4);
  EXPECT_EQ(fg::best_windows(nullptr, 300, 0.004f, 5, 0.f, 0.f, out.data(), 4), 0u);
  EXPECT_EQ(fg::best_windows(l.data(), 300, 0.004f, 5, 0.f, 0.f, nullptr, 4), 0u);
  EXPECT_EQ(fg::best_windows(l.data(), 300, 0.004f, 5, 0.f, 0.f, out.data(), 0), 0u);
  EXPECT_EQ(fg::best_windows(l.data(), 300, 0.004f, 1, 0.f, 0.f, out.data(), 4), 0u);
  EXPECT_EQ(fg::best_windows(l.data(), 300, 0.004f, 0, 0.f, 0.f, out.data(), 4), 0u);
  EXPECT_EQ(fg::best_windows(l.data(), 4, 0.004f, 5, 0.f, 0.f, out.data(), 4), 0u);
  // Any k up to the line count: the windows are fitted from running sums, with no
  // per-window buffer to bound k.
  EXPECT_EQ(fg::best_windows(l.data(), 300, 0.004f, 300, 0.f, 0.f, out.data(), 4), 1u);
  EXPECT_EQ(fg::best_windows(l.data(), 300, 0.004f, 301, 0.f, 0.f, out.data(), 4), 0u);
  EXPECT_EQ(fg::best_windows(l.data(), 300, 0.004f, 257, 0.f, 0.f, out.data(), 4), 4u);
  EXPECT_EQ(fg::best_windows(l.data(), 300, 0.004f, 2, 0.f, 0.f, out.data(), 4), 4u);
}

// Brute force: regions, windows, fits (closed form), rank; sorted stably by rank.
struct RefWindow {
  uint32_t first;
  double beta, rank, width, xc, yc;
};

std::vector<RefWindow> brute_windows(const std::vector<ScanLine>& l, float th, uint32_t k, float y_ref, float cw) {
  std::vector<RefWindow> all;
  const uint32_t n = static_cast<uint32_t>(l.size());
  for (uint32_t s = 0; s + k <= n; ++s) {
    bool ok = true;
    for (uint32_t i = s; i < s + k && ok; ++i) {
      if (!l[i].kept) ok = false;
      if (i > s && (std::fabs(l[i].left - l[i - 1].left) > th || std::fabs(l[i].right - l[i - 1].right) > th))
        ok = false;
    }
    if (!ok) continue;
    std::vector<float> y, L, R;
    double w = 0, xc = 0;
    for (uint32_t i = s; i < s + k; ++i) {
      y.push_back(l[i].y);
      L.push_back(l[i].left);
      R.push_back(l[i].right);
      w += static_cast<double>(l[i].right) - l[i].left;
      xc += 0.5 * (static_cast<double>(l[i].left) + l[i].right);
    }
    double aL, bL, aR, bR;
    closed_form(y, L, aL, bL);
    closed_form(y, R, aR, bR);
    RefWindow r;
    r.first = s;
    r.beta = std::fabs(std::atan(aL) - std::atan(aR));
    r.yc = 0.5 * (static_cast<double>(l[s].y) + l[s + k - 1].y);
    r.rank = r.beta + cw * std::fabs(r.yc - y_ref);
    r.width = w / k;
    r.xc = xc / k;
    all.push_back(r);
  }
  std::stable_sort(all.begin(), all.end(), [](const RefWindow& a, const RefWindow& b) { return a.rank < b.rank; });
  return all;
}

TEST(BestWindows, MatchesBruteForceOnRandomLineSets) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  for (int trial = 0; trial < 150; ++trial) {
    const uint32_t n = 10 + static_cast<uint32_t>(rng() % 80);
    std::vector<ScanLine> l(n);
    float L = 0.f, R = 0.05f;
    for (uint32_t j = 0; j < n; ++j) {
      // Mostly small random walks, sometimes a jump, sometimes a dropped line.
      L += (u(rng) - 0.5f) * 0.004f + (u(rng) < 0.05f ? 0.01f : 0.f);
      R += (u(rng) - 0.5f) * 0.004f - (u(rng) < 0.05f ? 0.01f : 0.f);
      l[j] = ScanLine{-0.05f + 0.002f * static_cast<float>(j), L, R, true, u(rng) > 0.05f};
    }
    const uint32_t k = 2 + static_cast<uint32_t>(rng() % 10);
    const float y_ref = (u(rng) - 0.5f) * 0.1f, cw = u(rng) < 0.3f ? 0.f : u(rng) * 2.f;
    const float th = 0.004f;
    const std::vector<RefWindow> ref = brute_windows(l, th, k, y_ref, cw);
    const uint32_t max_out = 1 + static_cast<uint32_t>(rng() % 12);
    std::vector<SideFit> out(max_out);
    const uint32_t got = fg::best_windows(l.data(), n, th, k, y_ref, cw, out.data(), max_out);
    ASSERT_EQ(got, std::min<size_t>(max_out, ref.size())) << "trial " << trial;
    for (uint32_t i = 0; i < got; ++i) {
      // Same ranks in order (float vs double: compare values, not identities of near-ties).
      EXPECT_NEAR(out[i].rank, ref[i].rank, 2e-5) << "trial " << trial << " #" << i;
      if (i > 0) {
        EXPECT_LE(out[i - 1].rank, out[i].rank);
      }
      // The window reported is a real window with its own values.
      const auto it = std::find_if(ref.begin(), ref.end(), [&](const RefWindow& r) { return r.first == out[i].first; });
      ASSERT_NE(it, ref.end()) << "trial " << trial << ": window at " << out[i].first << " is not valid";
      EXPECT_NEAR(out[i].beta, it->beta, 2e-5) << "trial " << trial;
      EXPECT_NEAR(out[i].width, it->width, 1e-6) << "trial " << trial;
      EXPECT_NEAR(out[i].x_centre, it->xc, 1e-6) << "trial " << trial;
      EXPECT_NEAR(out[i].y_centre, it->yc, 1e-6) << "trial " << trial;
      EXPECT_EQ(out[i].count, k);
    }
  }
}

// The running sums over a long region (kMaxScanLines lines, the finest line spacing,
// wide windows: views_max and candidates_max) against the two-pass closed form of
// every window: slopes, intercepts and beta stay within float precision of it.
TEST(BestWindows, SlidingFitsMatchTheClosedFormOverLongRegions) {
  std::mt19937 rng(77);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  const uint32_t n = fg::kMaxScanLines;
  for (int trial = 0; trial < 6; ++trial) {
    std::vector<ScanLine> l(n);
    // Curved sides (a sphere-like bulge) plus noise, all within the jump threshold.
    for (uint32_t j = 0; j < n; ++j) {
      const float y = -0.128f + 0.0005f * static_cast<float>(j);
      const float bulge = 0.03f * std::sqrt(std::max(0.f, 1.f - (y / 0.13f) * (y / 0.13f)));
      l[j] = ScanLine{y, 0.2f - bulge + 0.0003f * u(rng), 0.2f + bulge + 0.0003f * u(rng), true, true};
    }
    const uint32_t k = 44 + static_cast<uint32_t>(trial) * 20;
    std::vector<SideFit> out(n);
    const uint32_t got = fg::best_windows(l.data(), n, 0.004f, k, 0.f, 0.f, out.data(), n);
    ASSERT_EQ(got, n - k + 1);
    for (uint32_t i = 0; i < got; ++i) {
      const uint32_t s = out[i].first;
      std::vector<float> y, L, R;
      for (uint32_t m = s; m < s + k; ++m) {
        y.push_back(l[m].y);
        L.push_back(l[m].left);
        R.push_back(l[m].right);
      }
      double aL, bL, aR, bR;
      closed_form(y, L, aL, bL);
      closed_form(y, R, aR, bR);
      EXPECT_NEAR(out[i].a_left, aL, 1e-6 * (1.0 + std::fabs(aL))) << "window " << s;
      EXPECT_NEAR(out[i].a_right, aR, 1e-6 * (1.0 + std::fabs(aR))) << "window " << s;
      EXPECT_NEAR(out[i].b_left, bL, 1e-6) << "window " << s;
      EXPECT_NEAR(out[i].b_right, bR, 1e-6) << "window " << s;
      EXPECT_NEAR(out[i].beta, std::fabs(std::atan(aL) - std::atan(aR)), 2e-6) << "window " << s;
    }
  }
}

// A side at one x over a window has slope 0 and that x exactly, wherever the window
// lies in its region (after steps below the threshold), as the two-pass fit gives it:
// windows mirrored about y_ref keep equal ranks, and the earlier one stays first.
TEST(BestWindows, ConstantSidesFitExactlyAfterSteps) {
  auto l = sides(40, -0.039f, 0.002f, 0.f, -0.021f, 0.f, 0.019f);
  for (uint32_t j = 10; j < 30; ++j) {
    l[j].left = -0.0237f;  // steps of 2.7 mm in, then out
    l[j].right = 0.0213f;
  }
  std::vector<SideFit> out(64);
  const uint32_t k = 6;
  const uint32_t n = fg::best_windows(l.data(), 40, 0.004f, k, 0.f, 0.f, out.data(), 64);
  ASSERT_EQ(n, 40u - k + 1);
  uint32_t flat = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const SideFit& w = out[i];
    const bool inside = w.first >= 10 && w.first + k <= 30;
    const bool before = w.first + k <= 10, after = w.first >= 30;
    if (!(inside || before || after)) continue;
    ++flat;
    EXPECT_EQ(w.a_left, 0.f) << "window " << w.first;
    EXPECT_EQ(w.a_right, 0.f) << "window " << w.first;
    EXPECT_EQ(w.beta, 0.f) << "window " << w.first;
    EXPECT_EQ(w.b_left, l[w.first].left) << "window " << w.first;
    EXPECT_EQ(w.b_right, l[w.first].right) << "window " << w.first;
  }
  EXPECT_EQ(flat, 5u + 15u + 5u);
  // With a centre weight, the flat windows rank by distance alone: ties keep line order.
  const uint32_t n2 = fg::best_windows(l.data(), 40, 0.004f, k, -0.001f, 1.f, out.data(), 64);
  ASSERT_EQ(n2, n);
  for (uint32_t i = 1; i < n2; ++i)
    if (out[i].rank == out[i - 1].rank) {
      EXPECT_LT(out[i - 1].first, out[i].first);
    }
}

// A kept line with a NaN or infinite y or side (a caller's bad input; build_scan_lines
// never keeps one) splits its region like a dropped line: the windows on either side
// of it are fitted as without it.
TEST(BestWindows, NonFiniteLinesSplitTheirRegion) {
  const uint32_t k = 5;
  const auto clean = sides(30, 0.f, 0.002f, 0.1f, -0.02f, -0.1f, 0.02f);
  auto dropped = clean;
  dropped[12].kept = false;
  std::vector<SideFit> want(64);
  const uint32_t n_want = fg::best_windows(dropped.data(), 30, 0.004f, k, 0.f, 0.f, want.data(), 64);
  ASSERT_EQ(n_want, (12 - k + 1) + (17 - k + 1));
  const float bad[] = {kNaN, std::numeric_limits<float>::infinity()};
  for (int field = 0; field < 3; ++field)
    for (float v : bad) {
      auto l = clean;
      (field == 0 ? l[12].y : field == 1 ? l[12].left : l[12].right) = v;
      std::vector<SideFit> out(64);
      const uint32_t n = fg::best_windows(l.data(), 30, 0.004f, k, 0.f, 0.f, out.data(), 64);
      ASSERT_EQ(n, n_want) << "field " << field << " value " << v;
      for (uint32_t i = 0; i < n; ++i) {
        EXPECT_EQ(out[i].first, want[i].first) << "field " << field;
        EXPECT_EQ(out[i].beta, want[i].beta) << "field " << field;
        EXPECT_EQ(out[i].a_left, want[i].a_left) << "field " << field;
        EXPECT_EQ(out[i].b_right, want[i].b_right) << "field " << field;
      }
    }
}

}  // namespace
