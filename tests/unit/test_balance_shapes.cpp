// The two force-balance figures of the planner on constructed shapes whose answers are
// known in closed form, through the public fg::Planner API only:
//   beta (XOY, design/algorithm.md D): the angle between the least-squares sides of a
//        window of the viewpoint's silhouette;
//   dZ   (XOZ, E): |mean depth of the left contact region - mean depth of the right|,
//        with the regions of docs/method.md E/F (contact band inside each side in the
//        pad's y window, then the pads' reach +-finger_depth/2 about their mean depth).
// Shapes: a trapezoidal prism (a wedge, sides at +-a to the axis: beta = 2a), boxes seen
// face-on, a two-slab "step" (contact faces of different depth: dZ known from the
// construction) and a cylinder.
//
// Scenes: every shape stands on a 0.6 x 0.6 m table at z = 0 (2 mm grid, the part under
// the object left out) and is sampled noise-free on a 2 mm grid over ALL its surfaces
// except the bottom face (side walls and top cap), so the figures are those of the
// constructed solid and not of one sensor's view. The points are given in world
// coordinates to the head role with an identity pose (its origin is the world
// origin); the hand role is added with no points and a pose whose translation is the
// viewpoint wanted, so the arc's theta = 0 viewpoint looks from there. The planner runs
// with the paper's literal settings (no checks, paper depth, no friction test, no
// extended search, centre only breaking ties, no viewing-angle limit, PCA axis as is).
// One test documents a core bug and is skipped (GTEST_SKIP "BUG: ..."); run it with
// FG_RUN_KNOWN_BUGS=1 in the environment. Each case prints its measured values.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

#include "fg/core/constants.hpp"
#include "fg/core/planner.hpp"

namespace {

using fg::PlannerConfig;
using fg::PlanResult;
using fg::Pose;
using fg::SensorRole;
using fg::Status;
using fg::Vec3;
using fg::ViewDetail;
using fg::ViewRecord;

using fg::kPi;
constexpr double kStep = 0.002;  // surface sampling (m)

struct P2 {
  double x, y;
};

PlannerConfig paper_config() {
  PlannerConfig c;
  c.executability_checks = false;
  c.paper_depth = true;
  c.friction_mu = 0.f;
  c.extend_search = false;
  c.centre_weight = 1e-6f;
  c.approach_view_max_rad = 3.14159f;
  c.axis_ratio_min = 1.f;
  c.vertical_snap_rad = 0.f;
  c.vertical_snap_round_rad = 0.f;
  c.range_min_m = 0.f;  // identity pose: the sensor-frame depth is world z
  return c;
}

// Even-odd point-in-polygon.
bool inside(const std::vector<P2>& poly, double x, double y) {
  bool in = false;
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const P2 &a = poly[i], &b = poly[j];
    if ((a.y > y) != (b.y > y) && x < (b.x - a.x) * (y - a.y) / (b.y - a.y) + a.x) in = !in;
  }
  return in;
}

Vec3 v3(double x, double y, double z) {
  return Vec3(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
}

// A vertical prism over the polygon (horizontal cross-section), z in [0, h]: its side
// walls (each edge cut into round(length / kStep) equal steps, z in round(h / kStep)
// equal steps from 0 to h) and its top cap (the kStep lattice points strictly inside
// the polygon, at z = h). No bottom face.
std::vector<Vec3> prism(const std::vector<P2>& poly, double h) {
  std::vector<Vec3> pts;
  const int nz = static_cast<int>(std::lround(h / kStep));
  for (size_t i = 0; i < poly.size(); ++i) {
    const P2 a = poly[i], b = poly[(i + 1) % poly.size()];
    const int n = std::max(1, static_cast<int>(std::lround(std::hypot(b.x - a.x, b.y - a.y) / kStep)));
    for (int k = 0; k < n; ++k) {
      const double s = static_cast<double>(k) / n;
      for (int j = 0; j <= nz; ++j) pts.push_back(v3(a.x + s * (b.x - a.x), a.y + s * (b.y - a.y), h * j / nz));
    }
  }
  double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
  for (const P2& p : poly) {
    x0 = std::min(x0, p.x);
    x1 = std::max(x1, p.x);
    y0 = std::min(y0, p.y);
    y1 = std::max(y1, p.y);
  }
  for (int i = static_cast<int>(std::floor(x0 / kStep)); i * kStep <= x1; ++i)
    for (int j = static_cast<int>(std::floor(y0 / kStep)); j * kStep <= y1; ++j)
      if (inside(poly, i * kStep, j * kStep)) pts.push_back(v3(i * kStep, j * kStep, h));
  return pts;
}

struct Scene {
  std::vector<Vec3> object;  // the constructed surface points
  std::vector<Vec3> all;     // table + object, what the planner gets
};

// The object on a 0.6 x 0.6 m table centred at (0.5, 0), z = 0, 2 mm grid, without the
// object's footprint.
Scene make_scene(const std::vector<P2>& poly, double h) {
  Scene s;
  s.object = prism(poly, h);
  for (int i = 0; i <= 300; ++i)
    for (int j = 0; j <= 300; ++j) {
      const double x = 0.2 + i * kStep, y = -0.3 + j * kStep;
      if (!inside(poly, x, y)) s.all.push_back(v3(x, y, 0.0));
    }
  s.all.insert(s.all.end(), s.object.begin(), s.object.end());
  return s;
}

// Plans the scene: points to the head role (identity pose, origin = world origin), the
// hand role empty at `viewpoint`.
std::unique_ptr<fg::Planner> plan_scene(const Scene& s, const Vec3& viewpoint, PlanResult& r,
                                        const PlannerConfig& cfg = paper_config()) {
  auto pl = std::make_unique<fg::Planner>();
  const char* field = nullptr;
  EXPECT_EQ(pl->configure(cfg, &field), Status::ok) << (field ? field : "");
  EXPECT_EQ(
      pl->add_points(SensorRole::head, s.all.front().data(), static_cast<uint32_t>(s.all.size()), sizeof(Vec3), Pose{}),
      Status::ok);
  Pose hand;
  hand.t = viewpoint;
  EXPECT_EQ(pl->add_points(SensorRole::hand, nullptr, 0, 12, hand), Status::ok);
  EXPECT_EQ(pl->plan(r), Status::ok) << r.message;
  return pl;
}

// The viewpoint whose approach Z is closest to `approach`; -1 when none is within
// acos(min_cos).
int32_t view_towards(const fg::Planner& pl, const Vec3& approach, float min_cos) {
  int32_t best = -1;
  float best_cos = min_cos;
  for (uint32_t i = 0; i < pl.view_count(); ++i) {
    const float c = pl.view(i).Z.normalized().dot(approach.normalized());
    if (c >= best_cos) {
      best_cos = c;
      best = static_cast<int32_t>(i);
    }
  }
  return best;
}

// A straight horizontal edge of the construction (world p0 -> p1 at height z) in the
// silhouette plane of view v about origin c, as x = a y + b.
struct Line {
  double a, b;
};
Line project_edge(const ViewRecord& v, const Vec3& c, P2 p0, P2 p1, double z) {
  const Eigen::Vector3d X = v.X.cast<double>(), Y = v.Y.cast<double>();
  const Eigen::Vector3d q0 = Eigen::Vector3d(p0.x, p0.y, z) - c.cast<double>();
  const Eigen::Vector3d d(p1.x - p0.x, p1.y - p0.y, 0.0);
  const double a = X.dot(d) / Y.dot(d);
  return Line{a, X.dot(q0) - a * Y.dot(q0)};
}

// The wedge: a trapezoid centred at (cx, cy), symmetric about x = cx, its two long sides
// at +-a to the y axis, half-width h0 at y = cy - len/2 growing to h0 + tan(a) len.
struct Wedge {
  double a, cx, cy, len, h0;
  std::vector<P2> poly() const {
    const double t = std::tan(a), h1 = h0 + t * len;
    return {{cx - h0, cy - len / 2}, {cx + h0, cy - len / 2}, {cx + h1, cy + len / 2}, {cx - h1, cy + len / 2}};
  }
  // The long sides as (start, end) along +y: world -x side, then +x side.
  void sides(P2 s[2][2]) const {
    const std::vector<P2> p = poly();
    s[0][0] = p[0];
    s[0][1] = p[3];
    s[1][0] = p[1];
    s[1][1] = p[2];
  }
};
constexpr double kWedgeHeight = 0.12;

// Expected sides of the wedge in view v: left (smaller x) and right.
void wedge_sides(const Wedge& w, const ViewRecord& v, const Vec3& c, Line& left, Line& right) {
  P2 s[2][2];
  w.sides(s);
  const Line l0 = project_edge(v, c, s[0][0], s[0][1], kWedgeHeight);
  const Line l1 = project_edge(v, c, s[1][0], s[1][1], kWedgeHeight);
  // Which is left: compare x at the centroid's y (0).
  const bool first_left = l0.b < l1.b;
  left = first_left ? l0 : l1;
  right = first_left ? l1 : l0;
}

double beta_of(const Line& l, const Line& r) { return std::fabs(std::atan(l.a) - std::atan(r.a)); }

// Paper eq. 7/8 with the regions of docs/method.md E/F, written here: in view v about
// origin c, the contact band inside the sides xl / xr within the pad's y window about
// yc, its mean depth; the pads' reach +-finger_depth/2 about it; the contacts again at
// the extremes of the points in reach; dZ.
struct Xoz {
  double pos = 0, ml = 0, mr = 0, d = 0, width = 0;
  int nl = 0, nr = 0;
};
Xoz xoz_expect(const Vec3* pts, size_t n, const ViewRecord& v, const Vec3& c, double yc, double xl, double xr,
               const PlannerConfig& cfg) {
  const double half_pad = 0.5 * cfg.gripper.finger_width_m, band = cfg.contact_band_m;
  const double half_fd = 0.5 * cfg.gripper.finger_depth_m;
  const Eigen::Vector3d X = v.X.cast<double>(), Y = v.Y.cast<double>(), Z = v.Z.cast<double>();
  std::vector<double> px(n), py(n), pz(n);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d d = (pts[i] - c).cast<double>();
    px[i] = X.dot(d);
    py[i] = Y.dot(d);
    pz[i] = Z.dot(d);
  }
  Xoz e;
  double zl = 0, zr = 0;
  int nl = 0, nr = 0;
  for (size_t i = 0; i < n; ++i) {
    if (std::fabs(py[i] - yc) > half_pad) continue;
    if (px[i] <= xl + band) zl += pz[i], ++nl;
    if (px[i] >= xr - band) zr += pz[i], ++nr;
  }
  if (nl == 0 || nr == 0) return e;
  e.pos = 0.5 * (zl / nl + zr / nr);
  double xmin = 1e9, xmax = -1e9;
  for (size_t i = 0; i < n; ++i) {
    if (std::fabs(py[i] - yc) > half_pad || std::fabs(pz[i] - e.pos) > half_fd) continue;
    xmin = std::min(xmin, px[i]);
    xmax = std::max(xmax, px[i]);
  }
  // Each contact weighs 1 from one voxel leaf inside the reach's ends, falling linearly
  // to 0 at the ends (method.md E.2).
  zl = zr = 0;
  nl = nr = 0;
  double wl = 0, wr = 0;
  for (size_t i = 0; i < n; ++i) {
    const double dd = std::fabs(pz[i] - e.pos);
    if (std::fabs(py[i] - yc) > half_pad || dd > half_fd) continue;
    const double w = std::min(1.0, (half_fd - dd) / cfg.voxel_leaf_m);
    if (px[i] <= xmin + band) zl += w * pz[i], wl += w, ++nl;
    if (px[i] >= xmax - band) zr += w * pz[i], wr += w, ++nr;
  }
  e.nl = nl;
  e.nr = nr;
  if (nl == 0 || nr == 0 || wl <= 0 || wr <= 0) return e;
  e.ml = zl / wl;
  e.mr = zr / wr;
  e.d = std::fabs(e.ml - e.mr);
  e.width = xmax - xmin;
  return e;
}

uint32_t bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

// ------------------------------------------------------------------------------------
// 1. The wedge seen from above: the viewpoint straight down (hand sensor above the
// object) has the trapezoid as its silhouette, Y along the wedge (its principal axis),
// X across. The sides' slopes in that frame follow from the construction and the
// view's own X, Y (PCA tilts Y a little towards z, as the wide end carries more top
// cap): x = a y + b with a = (X.d) / (Y.d) for each side direction d.

struct WedgeRun {
  std::unique_ptr<fg::Planner> pl;
  PlanResult r;
  int32_t top = -1;  // the top-down viewpoint
  std::unique_ptr<ViewDetail> detail = std::make_unique<ViewDetail>();
  Line left{}, right{};
};

void run_wedge(const Wedge& w, WedgeRun& out) {
  const Scene s = make_scene(w.poly(), kWedgeHeight);
  out.pl = plan_scene(s, Vec3(static_cast<float>(w.cx), static_cast<float>(w.cy), 0.7f), out.r);
  out.top = view_towards(*out.pl, Vec3(0, 0, -1), std::cos(0.05f));
  ASSERT_GE(out.top, 0) << "no top-down viewpoint";
  const ViewRecord& v = out.pl->view(static_cast<uint32_t>(out.top));
  // The frame is the wedge's: Y along the wedge (world +-y), X across it.
  ASSERT_GT(std::fabs(v.Y.y()), 0.99f);
  ASSERT_GT(std::fabs(v.X.x()), 0.99f);
  ASSERT_EQ(out.pl->analyze_view(static_cast<uint32_t>(out.top), *out.detail), Status::ok);
  wedge_sides(w, v, out.pl->object_centroid(), out.left, out.right);
}

// The silhouette, its scan lines and a fit over the whole wedge follow the constructed
// sides: what the planner measures before it cuts the sides into finger-wide windows.
TEST(BalanceShapes, WedgeSilhouetteFollowsTheConstructedSides) {
  const PlannerConfig cfg = paper_config();
  for (double a : {0.1, 0.2})
    for (double off : {0.0, 0.0013}) {
      SCOPED_TRACE(testing::Message() << "a " << a << " offset " << off);
      const Wedge w{a, 0.5 + off, off, 0.2, 0.01};
      WedgeRun run;
      run_wedge(w, run);
      if (HasFatalFailure()) return;
      const ViewDetail& d = *run.detail;
      // Closed form: the sides are at -+a to the wedge's axis. The viewpoint's Y (PCA
      // of the voxelised cloud) may turn a few mrad off that axis, which shifts both
      // sides' angles alike and leaves their difference, beta, at 2a.
      EXPECT_NEAR(std::atan(run.left.a), -std::atan(run.right.a), 0.03);
      EXPECT_NEAR(beta_of(run.left, run.right), 2 * a, 2e-3);
      // Every scan line's L_j, R_j lies on the outer edge of the raster cells holding
      // the side: outside the side by less than a hull cell (plus a voxel centroid's
      // sub-millimetre offset at the edges), never inside it.
      const double tol = cfg.hull_cell_m + 0.001;
      const float ymin = d.lines[0].y, ymax = d.lines[d.n_lines - 1].y;
      std::vector<float> ys, ls, rs;
      for (uint32_t j = 0; j < d.n_lines; ++j) {
        const fg::ScanLine& l = d.lines[j];
        if (!l.kept || l.y < ymin + 0.006f || l.y > ymax - 0.006f) continue;  // ends: corners
        const double xl = run.left.a * l.y + run.left.b, xr = run.right.a * l.y + run.right.b;
        EXPECT_LE(l.left, xl + 0.0005) << "line " << j;
        EXPECT_GE(l.left, xl - tol) << "line " << j;
        EXPECT_GE(l.right, xr - 0.0005) << "line " << j;
        EXPECT_LE(l.right, xr + tol) << "line " << j;
        ys.push_back(l.y);
        ls.push_back(l.left);
        rs.push_back(l.right);
      }
      ASSERT_GE(ys.size(), 40u);
      // A least-squares fit over all those lines recovers the sides' angles.
      float al, bl, ar, br;
      ASSERT_TRUE(fg::fit_x_of_y(ys.data(), ls.data(), static_cast<uint32_t>(ys.size()), al, bl));
      ASSERT_TRUE(fg::fit_x_of_y(ys.data(), rs.data(), static_cast<uint32_t>(ys.size()), ar, br));
      EXPECT_NEAR(std::atan(al), std::atan(run.left.a), 0.01);
      EXPECT_NEAR(std::atan(ar), std::atan(run.right.a), 0.01);
      EXPECT_NEAR(fg::side_angle(al, ar), 2 * a, 0.01);
      // The viewpoint's best window exists and is what the view record reports.
      ASSERT_TRUE(d.has_best);
      EXPECT_EQ(d.best.count, static_cast<uint32_t>(std::ceil(cfg.gripper.finger_width_m / cfg.scan_delta_m - 1e-4)));
      const ViewRecord& v = run.pl->view(static_cast<uint32_t>(run.top));
      ASSERT_TRUE(v.has_candidate);
      EXPECT_EQ(bits(v.beta), bits(d.best.beta));
      std::printf(
          "[ wedge    ] a=%.2f off=%.4f: 2a=%.4f, whole-side fit %.4f, best window beta %.4f "
          "(a_L %.4f a_R %.4f, expected %.4f %.4f)\n",
          a, off, 2 * a, fg::side_angle(al, ar), d.best.beta, d.best.a_left, d.best.a_right, run.left.a, run.right.a);
    }
}

// The planner's beta of the wedge: the best window of the top-down viewpoint must
// measure the wedge angle 2a.
TEST(BalanceShapes, WedgeWindowBetaIsTwiceTheHalfAngle) {
  if (std::getenv("FG_RUN_KNOWN_BUGS") == nullptr)
    GTEST_SKIP() << "BUG: a window's beta is fitted to the raster contour, a staircase of 2.5 mm "
                    "(hull_cell) steps, over only k = 11 scan lines (22 mm), and the smallest beta wins: "
                    "top-down wedge 2a = 0.2 rad -> best window beta 0.000 (window betas 0..0.34), "
                    "2a = 0.4 -> 0.271 (0.27..0.53), while a fit over the whole side gives 0.201 / 0.404. "
                    "The grasp inherits it: a = 0.2 is planned as balanced with beta 0.192 from a viewpoint "
                    "whose true beta is 0.380. Fitting the slopes to the voxel centroids instead "
                    "(docs/method.md D) follows the sides within 1 mm but leaves the best window at "
                    "0.13 / 0.37: the centroids wander ~1 mm, so a 22 mm window's beta scatters by ~0.03 "
                    "and the smallest of ~90 windows lies low; in simulation it lost more than it gained. "
                    "Set FG_RUN_KNOWN_BUGS=1 to run.";
  for (double a : {0.1, 0.2})
    for (double off : {0.0, 0.0013}) {
      SCOPED_TRACE(testing::Message() << "a " << a << " offset " << off);
      const Wedge w{a, 0.5 + off, off, 0.2, 0.01};
      WedgeRun run;
      run_wedge(w, run);
      if (HasFatalFailure()) return;
      const ViewDetail& d = *run.detail;
      ASSERT_TRUE(d.has_best);
      std::printf("[ wedge    ] a=%.2f off=%.4f: best window beta %.4f vs 2a %.4f\n", a, off, d.best.beta, 2 * a);
      EXPECT_NEAR(std::atan(d.best.a_left), std::atan(run.left.a), 0.03);
      EXPECT_NEAR(std::atan(d.best.a_right), std::atan(run.right.a), 0.03);
      EXPECT_NEAR(d.best.beta, 2 * a, 0.03);
      EXPECT_NEAR(run.pl->view(static_cast<uint32_t>(run.top)).beta, 2 * a, 0.03);
      // The grasp's beta is that of its viewpoint's wedge, whichever viewpoint won.
      ASSERT_GE(run.pl->chosen_view(), 0);
      const ViewRecord& vc = run.pl->view(static_cast<uint32_t>(run.pl->chosen_view()));
      Line l, r;
      wedge_sides(w, vc, run.pl->object_centroid(), l, r);
      EXPECT_NEAR(run.r.grasp.beta, beta_of(l, r), 0.03);
    }
}

// ------------------------------------------------------------------------------------
// 2. Boxes seen face-on: parallel sides (beta = 0) and contact faces of equal depth
// (dZ = 0). A low box from above (approach -z, closing across its 0.04 m side) and a
// tall box from the side (approach +x, closing across its 0.05 m side), each placed at
// sub-voxel offsets 0..5 mm (x and y) from the voxel grid.

struct BoxCase {
  const char* what;
  double sx, sy, h;  // box extents
  Vec3 viewpoint;    // hand sensor position
  Vec3 approach;     // the face-on approach
  double width;      // the box's extent across the closing direction
};
const BoxCase kBoxes[] = {
    {"low box from above", 0.04, 0.16, 0.12, Vec3(0.5f, 0.f, 0.7f), Vec3(0, 0, -1), 0.04},
    {"tall box from the side", 0.04, 0.05, 0.16, Vec3(-0.1f, 0.f, 0.08f), Vec3(1, 0, 0), 0.05},
};

struct BoxRun {
  std::unique_ptr<fg::Planner> pl;
  PlanResult r;
  int32_t face_on = -1;
};

void run_box(const BoxCase& c, double off, BoxRun& out) {
  const double cx = 0.5 + off, cy = off;
  const std::vector<P2> poly = {{cx - c.sx / 2, cy - c.sy / 2},
                                {cx + c.sx / 2, cy - c.sy / 2},
                                {cx + c.sx / 2, cy + c.sy / 2},
                                {cx - c.sx / 2, cy + c.sy / 2}};
  out.pl = plan_scene(make_scene(poly, c.h), c.viewpoint, out.r);
  out.face_on = view_towards(*out.pl, c.approach, std::cos(0.02f));
  ASSERT_GE(out.face_on, 0) << "no face-on viewpoint";
  ASSERT_TRUE(out.pl->view(static_cast<uint32_t>(out.face_on)).has_candidate);
}

TEST(BalanceShapes, BoxSeenFaceOnIsBalanced) {
  for (const BoxCase& c : kBoxes)
    for (int k = 0; k <= 10; ++k) {
      const double off = 0.0005 * k;
      SCOPED_TRACE(testing::Message() << c.what << " offset " << off);
      BoxRun run;
      run_box(c, off, run);
      if (HasFatalFailure()) return;
      const ViewRecord& v = run.pl->view(static_cast<uint32_t>(run.face_on));
      EXPECT_LT(v.beta, 0.02f);
      auto d = std::make_unique<ViewDetail>();
      ASSERT_EQ(run.pl->analyze_view(static_cast<uint32_t>(run.face_on), *d), Status::ok);
      ASSERT_TRUE(d->has_best);
      EXPECT_LT(std::fabs(std::atan(d->best.a_left)), 0.01);
      EXPECT_LT(std::fabs(std::atan(d->best.a_right)), 0.01);
      EXPECT_LT(run.r.grasp.beta, 0.02f);
      EXPECT_GE(v.dz, 0.f);
      if (k == 0) {
        // On the grid's symmetry the voxels keep the box's: dZ vanishes.
        EXPECT_LT(v.dz, 0.002f);
        EXPECT_LT(run.r.grasp.dz, 0.002f);
        EXPECT_NEAR(run.r.grasp.width, c.width, 0.001);
      }
      // Elsewhere too (BoxDzAtAnyGridOffset).
      EXPECT_LT(v.dz, 0.002f);
      std::printf("[ box      ] %s off=%.4f: face-on beta %.4f dz %.5f; grasp beta %.4f dz %.5f width %.4f\n", c.what,
                  off, v.beta, v.dz, run.r.grasp.beta, run.r.grasp.dz, run.r.grasp.width);
    }
}

// dZ of a box seen face-on is 0 wherever the box stands relative to the voxel grid.
// Before the reach's ends faded over a leaf (method.md E.2), dZ jumped by up to a leaf
// here: face-on from above 4.94 mm at 1.5 mm offset, from the side 2.49 mm at 0.5 mm.
TEST(BalanceShapes, BoxDzAtAnyGridOffset) {
  for (const BoxCase& c : kBoxes)
    for (int k = 0; k <= 10; ++k) {
      const double off = 0.0005 * k;
      SCOPED_TRACE(testing::Message() << c.what << " offset " << off);
      BoxRun run;
      run_box(c, off, run);
      if (HasFatalFailure()) return;
      EXPECT_LT(run.pl->view(static_cast<uint32_t>(run.face_on)).dz, 0.002f);
      EXPECT_LT(run.r.grasp.dz, 0.002f);
    }
}

// ------------------------------------------------------------------------------------
// 3. The step: two vertical slabs side by side (0.2 m tall, 0.025 m wide each, common
// front face at x = xf facing -x), the left one 0.04 m deep along the approach, the
// right one 0.02 m. Seen from -x (approach +x, Y = z, X = +y), the silhouette is a
// rectangle (beta = 0) and the contact faces span depths 0..0.04 and 0..0.02 behind
// the front. dZ follows from the construction with method.md's regions: the bands' mean
// depth puts the pads at ~0.015 m, their reach (+-0.02 m) cuts the deep face at
// ~0.035 m, its last voxel leaf (0.030-0.035 m) fading out (method.md E.2), and the
// front face's strip inside each band pulls both means forward. On the 2 mm samples:
// left 0..30 mm at weight 1, 32 and 34 mm at 0.6 and 0.2, two front points at 0 ->
// 14.1 mm; right 0..20 mm and three front points, all at weight 1 -> 10 mm (+ a few
// back-face points): d ~ 4.2 mm, not the naive 10 mm (a hard cut gave ~5.3 mm).

TEST(BalanceShapes, StepObjectDzMatchesTheConstruction) {
  const PlannerConfig cfg = paper_config();
  for (bool deep_left : {true, false})
    for (int k = 0; k <= 5; ++k) {
      const double xf = 0.480 + 0.001 * k;
      SCOPED_TRACE(testing::Message() << (deep_left ? "deep slab left" : "deep slab right") << " xf " << xf);
      const double w = 0.05, dl = deep_left ? 0.04 : 0.02, dr = deep_left ? 0.02 : 0.04;
      // y < 0 is the view's left (X = +y); counter-clockwise.
      const std::vector<P2> poly = {{xf, -w / 2}, {xf + dl, -w / 2}, {xf + dl, 0},
                                    {xf + dr, 0}, {xf + dr, w / 2},  {xf, w / 2}};
      const Scene s = make_scene(poly, 0.2);
      PlanResult r;
      auto pl = plan_scene(s, Vec3(-0.1f, 0.f, 0.1f), r);
      const int32_t vi = view_towards(*pl, Vec3(1, 0, 0), std::cos(0.035f));
      ASSERT_GE(vi, 0) << "no viewpoint approaching along +x";
      const ViewRecord& v = pl->view(static_cast<uint32_t>(vi));
      ASSERT_GT(v.Y.z(), 0.999f);
      ASSERT_GT(v.X.y(), 0.99f);
      ASSERT_TRUE(v.has_candidate);
      ASSERT_GE(v.dz, 0.f) << "no contact within reach";
      EXPECT_LT(v.beta, 0.02f);
      auto d = std::make_unique<ViewDetail>();
      ASSERT_EQ(pl->analyze_view(static_cast<uint32_t>(vi), *d), Status::ok);
      ASSERT_TRUE(d->has_best);
      // The window lies on the extruded part (away from the top and the table).
      const Vec3 c = pl->object_centroid();
      const double z_win = c.z() + d->best.y_centre;
      ASSERT_GT(z_win, 0.006 + 0.011 + 0.005);
      ASSERT_LT(z_win, 0.2 - 0.011 - 0.005);

      // Expected, from the constructed surface points and the constructed sides.
      double xl = 1e9, xr = -1e9;
      for (const Vec3& p : s.object) {
        const double x = v.X.cast<double>().dot((p - c).cast<double>());
        xl = std::min(xl, x);
        xr = std::max(xr, x);
      }
      const Xoz e = xoz_expect(s.object.data(), s.object.size(), v, c, d->best.y_centre, xl, xr, cfg);
      ASSERT_GT(e.nl, 0);
      ASSERT_GT(e.nr, 0);
      EXPECT_NEAR(e.d, 0.0042, 0.0004);  // the closed form above, as a check of this test's code
      EXPECT_NEAR(e.width, w, 0.001);
      EXPECT_NEAR(v.dz, e.d, 0.003);
      // The same rules on the planner's own object points (voxel centroids) and its
      // fitted sides give its dZ to rounding: the difference above is all voxelisation.
      const Xoz ev = xoz_expect(pl->object_points().data(), pl->object_points().size(), v, c, d->best.y_centre,
                                d->best.b_left, d->best.b_right, cfg);
      EXPECT_NEAR(v.dz, ev.d, 2e-5);
      std::printf(
          "[ step     ] %s xf=%.3f: expected d %.5f (left %.5f right %.5f), planner dz %.5f "
          "(same rules on its voxels %.5f), beta %.4f\n",
          deep_left ? "deep left " : "deep right", xf, e.d, e.ml, e.mr, v.dz, ev.d, v.beta);
    }
}

// ------------------------------------------------------------------------------------
// 4. A standing cylinder (r = 0.03 m, 0.15 m tall; Y = z): every side view sees a
// rectangle (beta = 0) and, by symmetry, contact regions of equal mean depth. The arc
// runs from the hand's side (approach +y) to the head's (approach ~+x).

TEST(BalanceShapes, CylinderSideViewsAreBalanced) {
  const PlannerConfig cfg = paper_config();
  for (int k = 0; k <= 5; ++k) {
    const double off = 0.001 * k;
    SCOPED_TRACE(testing::Message() << "offset " << off);
    const double r0 = 0.03, cx = 0.5 + off, cy = 0.0017;
    const int n = static_cast<int>(std::lround(2 * kPi * r0 / kStep));
    std::vector<P2> poly;
    for (int i = 0; i < n; ++i)
      poly.push_back({cx + r0 * std::cos(2 * kPi * i / n), cy + r0 * std::sin(2 * kPi * i / n)});
    PlanResult r;
    auto pl = plan_scene(make_scene(poly, 0.15), Vec3(0.5f, -0.6f, 0.075f), r);
    ASSERT_GE(pl->view_count(), 10u);
    const int32_t side = view_towards(*pl, Vec3(0, 1, 0), std::cos(0.02f));
    ASSERT_GE(side, 0);
    const ViewRecord& v = pl->view(static_cast<uint32_t>(side));
    ASSERT_TRUE(v.has_candidate);
    EXPECT_LT(v.beta, 0.02f);
    EXPECT_GE(v.dz, 0.f);
    EXPECT_LT(v.dz, 0.003f);
    EXPECT_LT(r.grasp.beta, 0.02f);
    EXPECT_LT(r.grasp.dz, 0.003f);
    EXPECT_NEAR(r.grasp.width, 2 * r0, 0.003);
    // Every viewpoint of the arc: parallel sides; dZ within a voxel leaf (measured up
    // to 5.4 mm at 2.5 mm offset: the quantisation of BoxDzAtAnyGridOffset).
    float worst_beta = 0.f, worst_dz = 0.f;
    for (uint32_t i = 0; i < pl->view_count(); ++i) {
      const ViewRecord& vi = pl->view(i);
      ASSERT_TRUE(vi.has_candidate) << i;
      EXPECT_LT(vi.beta, 0.02f) << i;
      EXPECT_GE(vi.dz, 0.f) << i;
      EXPECT_LT(vi.dz, cfg.voxel_leaf_m + 0.001f) << i;
      worst_beta = std::max(worst_beta, vi.beta);
      worst_dz = std::max(worst_dz, vi.dz);
    }
    std::printf(
        "[ cylinder ] off=%.4f: side view beta %.4f dz %.5f; grasp beta %.4f dz %.5f; over %u views "
        "beta <= %.4f dz <= %.5f\n",
        off, v.beta, v.dz, r.grasp.beta, r.grasp.dz, pl->view_count(), worst_beta, worst_dz);
  }
}

// ------------------------------------------------------------------------------------
// Determinism: the same input planned by two planners, and again by the first after
// reset(), gives the same bits for beta and dZ, of the grasp and of every viewpoint.

TEST(BalanceShapes, SameInputSameBits) {
  const std::vector<P2> step = {{0.48, -0.025}, {0.52, -0.025}, {0.52, 0.0}, {0.50, 0.0}, {0.50, 0.025}, {0.48, 0.025}};
  const Wedge wedge{0.2, 0.5, 0.0, 0.2, 0.01};
  struct Case {
    std::vector<P2> poly;
    double h;
    Vec3 viewpoint;
  };
  const Case cases[] = {{step, 0.2, Vec3(-0.1f, 0.f, 0.1f)}, {wedge.poly(), kWedgeHeight, Vec3(0.5f, 0.f, 0.7f)}};
  for (const Case& c : cases) {
    const Scene s = make_scene(c.poly, c.h);
    PlanResult r1, r2, r3;
    auto a = plan_scene(s, c.viewpoint, r1);
    auto b = plan_scene(s, c.viewpoint, r2);
    ASSERT_EQ(r1.status, Status::ok);
    EXPECT_EQ(bits(r1.grasp.beta), bits(r2.grasp.beta));
    EXPECT_EQ(bits(r1.grasp.dz), bits(r2.grasp.dz));
    EXPECT_EQ(bits(r1.grasp.width), bits(r2.grasp.width));
    EXPECT_EQ(std::memcmp(r1.grasp.position.data(), r2.grasp.position.data(), 12), 0);
    ASSERT_EQ(a->view_count(), b->view_count());
    for (uint32_t i = 0; i < a->view_count(); ++i) {
      EXPECT_EQ(bits(a->view(i).beta), bits(b->view(i).beta)) << i;
      EXPECT_EQ(bits(a->view(i).dz), bits(b->view(i).dz)) << i;
    }
    // The first planner again, after reset().
    std::vector<float> beta1, dz1;
    for (uint32_t i = 0; i < a->view_count(); ++i) {
      beta1.push_back(a->view(i).beta);
      dz1.push_back(a->view(i).dz);
    }
    a->reset();
    ASSERT_EQ(a->add_points(SensorRole::head, s.all.front().data(), static_cast<uint32_t>(s.all.size()), sizeof(Vec3),
                            Pose{}),
              Status::ok);
    Pose hand;
    hand.t = c.viewpoint;
    ASSERT_EQ(a->add_points(SensorRole::hand, nullptr, 0, 12, hand), Status::ok);
    ASSERT_EQ(a->plan(r3), Status::ok);
    EXPECT_EQ(bits(r1.grasp.beta), bits(r3.grasp.beta));
    EXPECT_EQ(bits(r1.grasp.dz), bits(r3.grasp.dz));
    ASSERT_EQ(a->view_count(), beta1.size());
    for (uint32_t i = 0; i < a->view_count(); ++i) {
      EXPECT_EQ(bits(a->view(i).beta), bits(beta1[i])) << i;
      EXPECT_EQ(bits(a->view(i).dz), bits(dz1[i])) << i;
    }
  }
}

}  // namespace
