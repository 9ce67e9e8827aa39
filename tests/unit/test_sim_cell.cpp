// hal/sim's cell distribution (scene_gen.hpp Distribution::cell): over a few hundred seeds,
// the scenes honour the stated ranges, measured on the geometry of each scene (sensor
// poses, object boxes, surface points found by ray casting and exact distances), not on
// what the generator reports; the same seed gives the same scene; classic stays the default.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <vector>

#include "fg/core/constants.hpp"
#include "sim/grasp_judge.hpp"
#include "sim/scene_export.hpp"
#include "sim/scene_gen.hpp"
#include "sim/sim_rng.hpp"

using namespace fg::sim;

namespace {

using fg::kPi;
constexpr double kDeg = kPi / 180.0;

// Points on an object's outer surface: the first hits of rays from a sphere around it
// towards random points of its bounding box.
std::vector<V3> ray_surface_points(const Object& o, int rays, uint64_t seed) {
  const Aabb box = o.aabb();
  const V3 c = box.centre();
  const double reach = 0.5 * box.size().norm() + 0.05;
  Rng rng(seed);
  std::vector<V3> pts;
  for (int i = 0; i < rays; ++i) {
    const double z = rng.uniform(-1.0, 1.0);
    const double phi = rng.uniform(0.0, 2.0 * kPi);
    const double rxy = std::sqrt(1.0 - z * z);
    const V3 from = c + reach * V3(rxy * std::cos(phi), rxy * std::sin(phi), z);
    const double ax = rng.uniform(-0.5, 0.5);
    const double ay = rng.uniform(-0.5, 0.5);
    const double az = rng.uniform(-0.5, 0.5);
    const V3 to = c + box.size().cwiseProduct(V3(ax, ay, az));
    double t = 0.0;
    V3 normal;
    if (o.intersect(from, to - from, 0.0, 1.0, t, normal)) pts.push_back(from + t * (to - from));
  }
  return pts;
}

// Smallest exact distance from the points to the object (a point whose distance to the
// object's box is already larger cannot be nearer).
double min_distance(const std::vector<V3>& pts, const Object& o) {
  const Aabb box = o.aabb();
  double d = 1e9;
  for (const V3& p : pts)
    if ((box.lo - p).cwiseMax(p - box.hi).cwiseMax(0.0).norm() < d) d = std::min(d, o.distance(p));
  return d;
}

struct Gap {
  double distance = 0.0;  //!< from both sides' surface points: at most a few mm above the truth
  bool overlap = false;   //!< a surface point of one inside the other (exact sign)
};

Gap measure_gap(const Object& a, const Object& b) {
  const std::vector<V3> pa = ray_surface_points(a, 4000, 11), pb = ray_surface_points(b, 4000, 12);
  Gap g;
  g.distance = std::min(min_distance(pb, a), min_distance(pa, b));
  for (const V3& p : pb) g.overlap = g.overlap || a.sdf(p) < 0.0;
  for (const V3& p : pa) g.overlap = g.overlap || b.sdf(p) < 0.0;
  return g;
}

double angle_deg(const V3& a, const V3& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) / kDeg;
}

// 296 scenes: every analytic kind on 24 seeds, every mesh kind on 4 (a mesh scene takes
// ten times as long to draw).
std::vector<std::pair<ObjectKind, uint64_t>> sample_scenes() {
  std::vector<std::pair<ObjectKind, uint64_t>> out;
  for (ObjectKind k : all_kinds())
    for (uint64_t seed = 100; seed < 124; ++seed) out.emplace_back(k, seed);
  for (ObjectKind k : mesh_kinds())
    for (uint64_t seed = 100; seed < 104; ++seed) out.emplace_back(k, seed);
  return out;
}

std::string temp_dir(const std::string& name) {
  const auto d =
      std::filesystem::temp_directory_path() / ("fg_test_sim_cell_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  return d.string();
}

}  // namespace

TEST(SimCell, ScenesHonourTheStatedRanges) {
  const SceneOptions opt = SceneOptions::of(Distribution::cell);
  const double opening = opt.gripper.max_opening_m;
  std::map<size_t, int> others_count;
  int scenes = 0, lying = 0, dark = 0, others_total = 0, smallest_gap_seen = 0, largest_gap_seen = 0;
  double head_az_max = 0.0, wrist_el_min = 90.0, wrist_el_max = 0.0;
  for (const auto& [kind, seed] : sample_scenes()) {
    const GeneratedScene s = make_scene(kind, seed, opt);
    SCOPED_TRACE(std::string(kind_name(kind)) + " seed " + std::to_string(seed));
    ++scenes;
    ASSERT_EQ(s.distribution, Distribution::cell);
    ASSERT_EQ(s.target, 0);
    const Object& target = s.world.objects[0];
    const Aabb tb = target.aabb();
    const V3 tc = tb.centre();

    // The target: anywhere in the contract's area, on the table.
    EXPECT_NEAR(tb.lo.z(), 0.0, 1e-9);
    EXPECT_GE(tc.x(), 0.3 - 1e-9);
    EXPECT_LE(tc.x(), 0.7 + 1e-9);
    EXPECT_LE(std::abs(tc.y()), 0.35 + 1e-9);
    // Its class: a kind that fits leaves 3 mm or more per finger, one too wide is wider
    // than the opening, and the truth's rule says the same.
    const double min_width = target_fit(target, s.gripper, 0.0).min_width;
    if (kind_fits(kind)) {
      EXPECT_LE(min_width, opening - 2 * 0.003 + 1e-9);
    } else {
      EXPECT_GT(min_width, opening);
    }
    EXPECT_EQ(s.truth.target_fits, min_width <= opening - 2 * 0.003 + 1e-12);
    // Lying: a can's axis, or a box's height axis, turned horizontal.
    if (kind == ObjectKind::can || kind == ObjectKind::box)
      lying += std::abs(target.parts[0].world_T_shape.R(2, 2)) < 1e-9 ? 1 : 0;
    dark += target.albedo < 0.3 ? 1 : 0;

    // The head: 0.5-1.5 m from the target's centre, looking at it 25-75 deg down, on the
    // robot's side: within 90 deg of the direction from the target to the robot base.
    const V3 head = s.head.world_T_sensor.t;
    const V3 head_axis = s.head.world_T_sensor.R.col(2);
    EXPECT_GE((head - tc).norm(), 0.5 - 1e-9);
    EXPECT_LE((head - tc).norm(), 1.5 + 1e-9);
    EXPECT_LT(angle_deg(head_axis, tc - head), 1e-4);
    const double down = std::asin(-head_axis.z()) / kDeg;
    EXPECT_GE(down, 25.0 - 1e-6);
    EXPECT_LE(down, 75.0 + 1e-6);
    const V3 to_head(head.x() - tc.x(), head.y() - tc.y(), 0.0), to_base(-tc.x(), -tc.y(), 0.0);
    const double head_az = angle_deg(to_head, to_base);
    EXPECT_LE(head_az, 90.0 + 1e-6);
    head_az_max = std::max(head_az_max, head_az);

    // The wrist: on the hemisphere 0.25-0.6 m about the target's centre, 10-90 deg up.
    const V3 wrist = s.hand.world_T_sensor.t;
    const V3 wv = wrist - tc;
    EXPECT_GE(wv.norm(), 0.25 - 1e-9);
    EXPECT_LE(wv.norm(), 0.6 + 1e-9);
    const double el = std::asin(wv.z() / wv.norm()) / kDeg;
    EXPECT_GE(el, 10.0 - 1e-6);
    EXPECT_LE(el, 90.0 + 1e-6);
    wrist_el_min = std::min(wrist_el_min, el);
    wrist_el_max = std::max(wrist_el_max, el);
    EXPECT_LT(angle_deg(s.hand.world_T_sensor.R.col(2), -wv), 1e-4);
    // Neither sensor inside or against an object.
    for (const Object& o : s.world.objects) {
      EXPECT_GE(o.distance(head), 0.05 - 1e-9) << o.name;
      EXPECT_GE(o.distance(wrist), 0.05 - 1e-9) << o.name;
    }

    // Other objects: 0-3, each 3-30 cm from the target surface to surface, no overlap with
    // the target or each other, on the table, farther from the workspace centre.
    const size_t others = s.world.objects.size() - 1;
    EXPECT_LE(others, 3u);
    ++others_count[others];
    others_total += static_cast<int>(others);
    const double target_to_ws = std::hypot(tc.x() - 0.5, tc.y());
    for (size_t i = 1; i < s.world.objects.size(); ++i) {
      const Object& o = s.world.objects[i];
      SCOPED_TRACE(o.name + " (" + o.kind + ")");
      const Aabb ob = o.aabb();
      EXPECT_NEAR(ob.lo.z(), 0.0, 1e-9);
      EXPECT_GE(ob.lo.x(), s.world.table.x_min);
      EXPECT_LE(ob.hi.x(), s.world.table.x_max);
      EXPECT_GE(ob.lo.y(), s.world.table.y_min);
      EXPECT_LE(ob.hi.y(), s.world.table.y_max);
      EXPECT_GT(std::hypot(ob.centre().x() - 0.5, ob.centre().y()), target_to_ws);
      const Gap g = measure_gap(target, o);
      EXPECT_FALSE(g.overlap);
      // The ray points lie a few mm apart: their distance is at most that much above the truth.
      EXPECT_GE(g.distance, 0.03 - 1e-3);
      EXPECT_LE(g.distance, 0.30 + 1e-3);
      smallest_gap_seen += g.distance < 0.06 ? 1 : 0;
      largest_gap_seen += g.distance > 0.25 ? 1 : 0;
      for (size_t j = 1; j < i; ++j) EXPECT_FALSE(measure_gap(s.world.objects[j], o).overlap) << j;
    }
  }
  // The ranges are spanned, not just respected.
  EXPECT_EQ(scenes, 296);
  for (size_t n = 0; n <= 3; ++n) EXPECT_GT(others_count[n], scenes / 8) << n << " other objects";
  EXPECT_GT(smallest_gap_seen, others_total / 20);
  EXPECT_GT(largest_gap_seen, others_total / 20);
  EXPECT_GT(head_az_max, 80.0);
  EXPECT_LT(wrist_el_min, 20.0);
  EXPECT_GT(wrist_el_max, 80.0);
  EXPECT_GT(lying, 10);  // of 48 cans and boxes
  EXPECT_LT(lying, 38);
  EXPECT_GT(dark, scenes / 10);
}

TEST(SimCell, SizesReachBeyondTheClassicRanges) {
  // A can's radius and height are drawn from 0.025-0.04 m and 0.08-0.15 m in classic,
  // widened by 30% either way in cell (a fitting target stays within the opening less 6 mm).
  double r_min = 1.0, r_max = 0.0, h_min = 1.0, h_max = 0.0;
  for (uint64_t seed = 0; seed < 60; ++seed) {
    const GeneratedScene s = make_scene(ObjectKind::can, seed, SceneOptions::of(Distribution::cell));
    const Part& body = s.world.objects[0].parts[0];
    r_min = std::min(r_min, body.radius());
    r_max = std::max(r_max, body.radius());
    h_min = std::min(h_min, 2 * body.half_height());
    h_max = std::max(h_max, 2 * body.half_height());
  }
  EXPECT_LT(r_min, 0.025);
  EXPECT_GE(r_min, 0.025 / 1.3);
  EXPECT_GT(r_max, 0.037);
  EXPECT_LE(r_max, 0.04 * 1.3);
  EXPECT_LT(h_min, 0.08);
  EXPECT_GE(h_min, 0.08 / 1.3);
  EXPECT_GT(h_max, 0.15);
  EXPECT_LE(h_max, 0.15 * 1.3);
}

TEST(SimCell, SameSeedSameScene) {
  const SceneOptions opt = SceneOptions::of(Distribution::cell);
  for (ObjectKind k : {ObjectKind::box, ObjectKind::bottle, ObjectKind::ycb_power_drill}) {
    const GeneratedScene a = make_scene(k, 4242, opt), b = make_scene(k, 4242, opt);
    EXPECT_EQ(truth_to_json(a), truth_to_json(b)) << kind_name(k);
    EXPECT_NE(truth_to_json(a), truth_to_json(make_scene(k, 4243, opt))) << kind_name(k);
  }
  // The images too, structured-light noise included.
  const GeneratedScene a = make_scene(ObjectKind::can, 7, opt), b = make_scene(ObjectKind::can, 7, opt);
  const SceneImages ia = render_scene(a), ib = render_scene(b);
  EXPECT_EQ(ia.head.mm, ib.head.mm);
  EXPECT_EQ(ia.hand.mm, ib.hand.mm);
  // The two distributions draw unrelated scenes from a seed.
  EXPECT_NE(truth_to_json(a), truth_to_json(make_scene(ObjectKind::can, 7)));
}

TEST(SimCell, ClassicIsTheLibraryDefault) {
  EXPECT_EQ(SceneOptions{}.distribution, Distribution::classic);
  for (ObjectKind k : {ObjectKind::box, ObjectKind::ycb_banana}) {
    const GeneratedScene a = make_scene(k, 5), b = make_scene(k, 5, SceneOptions::of(Distribution::classic));
    EXPECT_EQ(truth_to_json(a), truth_to_json(b));
    EXPECT_EQ(truth_to_json(a).find("distribution"), std::string::npos);  // classic files as they were
  }
  Distribution d;
  EXPECT_TRUE(distribution_from_name("cell", d));
  EXPECT_EQ(d, Distribution::cell);
  EXPECT_TRUE(distribution_from_name("classic", d));
  EXPECT_EQ(d, Distribution::classic);
  EXPECT_FALSE(distribution_from_name("Cell", d));
  EXPECT_STREQ(distribution_name(Distribution::cell), "cell");
}

TEST(SimCell, AWristPoseTheArmRefusesIsDrawnAgain) {
  const SceneOptions opt = SceneOptions::of(Distribution::cell);
  const WristPoseTest negative_y_only = [](const Rigid& world_T_sensor) { return world_T_sensor.t.y() < 0.0; };
  for (uint64_t seed = 0; seed < 20; ++seed)
    EXPECT_LT(make_scene(ObjectKind::sphere, seed, opt, negative_y_only).hand.world_T_sensor.t.y(), 0.0) << seed;
}

TEST(SimCell, SurfaceGapOfKnownShapes) {
  Object a, b;
  a.parts.push_back(Part::sphere("s", 0.03, V3(0.5, 0.0, 0.03)));
  b.parts.push_back(Part::box("b", V3(0.02, 0.04, 0.05), Rigid::translation(V3(0.5, 0.15, 0.05))));
  EXPECT_NEAR(surface_gap(a, b), 0.15 - 0.04 - 0.03, 1e-3);
  // An ellipsoid, whose sdf is only a bound: its long axis towards the box.
  Object e;
  e.parts.push_back(Part::ellipsoid("e", V3(0.02, 0.07, 0.04), Rigid::translation(V3(0.5, 0.0, 0.04))));
  EXPECT_NEAR(surface_gap(e, b), 0.15 - 0.04 - 0.07, 1e-3);
  // Touching or overlapping: 0.
  Object c;
  c.parts.push_back(Part::sphere("s", 0.05, V3(0.5, 0.1, 0.05)));
  EXPECT_NEAR(surface_gap(c, b), 0.0, 1e-9);
}

TEST(SimCell, ExportedSceneReadsBackAndRendersTheSame) {
  const GeneratedScene s = make_scene(ObjectKind::bottle, 31, SceneOptions::of(Distribution::cell));
  const std::string dir = temp_dir("export");
  const SceneImages images = render_scene(s);
  ASSERT_TRUE(export_scene(s, images, dir).ok);
  GeneratedScene back;
  const fg::host::ReadResult r = read_truth(dir + "/truth.json", back);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(back.distribution, Distribution::cell);
  EXPECT_EQ(back.world.table.albedo, s.world.table.albedo);
  ASSERT_EQ(back.world.objects.size(), s.world.objects.size());
  for (size_t i = 0; i < s.world.objects.size(); ++i)
    EXPECT_EQ(back.world.objects[i].albedo, s.world.objects[i].albedo);
  EXPECT_TRUE(back.noise.projector_shadow);
  EXPECT_TRUE(back.noise.dark_dropout);
  EXPECT_TRUE(back.noise.steep_dropout);
  EXPECT_EQ(back.noise.edge_band_px, 2);
  EXPECT_EQ(back.truth.fit_margin, 0.006);
  EXPECT_EQ(render_scene(back).head.mm, images.head.mm);
  EXPECT_EQ(truth_to_json(back), truth_to_json(s));
  std::filesystem::remove_all(dir);
}
