// Stage F: the checks of one candidate grasp (grasp_checks.hpp; algorithm.md F and G,
// docs/method.md): support plane, swept collision, the target's local hull and the
// space under it, visibility and the friction cone of the contact normals.
#include "fg/core/pipeline/grasp_checks.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "../circle_fit.hpp"
#include "fg/core/eigen_sym3.hpp"
#include "fg/core/gjk.hpp"
#include "fg/core/hull.hpp"
#include "fg/core/near_list.hpp"
#include "fg/core/segment_box.hpp"

namespace fg {

const char* to_string(CheckId id) {
  switch (id) {
    case CheckId::support_plane:
      return "support_plane";
    case CheckId::swept_collision:
      return "swept_collision";
    case CheckId::local_hull:
      return "local_hull";
    case CheckId::under_target:
      return "under_target";
    case CheckId::unknown_space:
      return "unknown_space";
    case CheckId::unseen_side:
      return "unseen_side";
    case CheckId::friction_cone:
      return "friction_cone";
    case CheckId::robot_collision:
      return "robot_collision";
    case CheckId::robot_reach:
      return "robot_reach";
    case CheckId::count:
      break;
  }
  return "unknown";
}

const char* margin_unit(CheckId id) {
  switch (id) {
    case CheckId::support_plane:
    case CheckId::swept_collision:
    case CheckId::local_hull:
    case CheckId::under_target:
      return "m";
    case CheckId::unknown_space:
      return "share";
    case CheckId::friction_cone:
      return "deg";
    default:
      return "";
  }
}

namespace {
// Normals within 30 deg of the approach belong to surfaces facing the gripper.
constexpr float kFrontFacingCos = 0.866f;
// Object points this far around the open fingers form the local hull they must avoid.
constexpr float kHullNeighbourhood = 0.01f;
// A target's footprint (its completed hull on the plane) is flat-sided when it fills at
// least this share of its smallest rectangle: a disc fills pi/4 (0.785), a rectangle 1.
constexpr float kFlatSidedFill = 0.9f;
// The unknown-space check's samples of both open fingers: 2 across a finger's thickness
// x 3 across its width x 5 along its depth, each (fingers_in_seen_space).
constexpr uint32_t kFingerSamples = 2 * 2 * 3 * 5;
// A finger may have this share of its samples hidden (edges of silhouettes blur).
constexpr float kMaxHiddenShare = 0.2f;
// A finger with at most this many hidden samples (of 30) counts as in seen space.
constexpr uint32_t kSeenFingerHidden = 2;
// The seen side's profile beside a partly hidden finger: bins along the approach.
constexpr int kProfileBins = 8;
constexpr int kSlopeBins = 3;  // the deepest seen bins that give its last slope
constexpr float kHiddenBulge = 0.005f;
// A profile bin's outermost point bounds the side when no probe between it and the open
// finger, a voxel apart (centroids lie up to half a voxel inside the surface), is hidden.
constexpr float kBeyondSide = 0.005f;
constexpr int kBeyondSteps = 40;  // at most this many probes per bin (more than 85 mm / 5 mm)
// A closing direction within 45 deg of the support plane's normal puts a finger under
// the target (fingers_clear_of_footprint).
constexpr float kSteepClosingCos = 0.7071f;
// A grasp at most this many voxels wide closes on a single layer of voxels (a sheet);
// sideways, fingers_clear_of_footprint then tests the open fingers under the target.
constexpr float kThinSheetLeaves = 2.5f;
// Such a layer is a plate only where the space on both of its sides was seen into:
// each open finger of a thin grasp needs at least this many of its 30 samples in space
// some sensor saw through (fingers_in_seen_space).
constexpr uint32_t kThinSeenFree = 10;
// A partly hidden finger's side with no contact normal at all is taken to mirror the
// seen side: a flat seen face (a box's), or a curved one within this tilt of the closing
// line (a cylinder across its axis). A curved seen side tilted more is a chord across a
// round body, whose unseen end bulges into the open finger.
constexpr float kBlindMirrorTiltCos = 0.978f;  // 12 deg
// A blind side's top goes on past its band (top_goes_on_past) when at least
// kTopBeyondMin level points at its height (within a voxel) lie from kTopGap voxels to
// kTopBeyond beyond the band's edge, along a closing direction at least kTopAlongMin
// off the plane's normal.
constexpr float kTopAlongMin = 0.3f;
constexpr float kTopGap = 2.f;
constexpr float kTopBeyond = 0.02f;
constexpr uint32_t kTopBeyondMin = 3;
// The round front beside a blind side (round_front_clears_blind_side): at most this many
// profile bins across the open gripper; a circle fitted to them is trusted within this
// rms distance, for radii in this range, and when it bends by at least kRoundSagitta
// over the profile's span (a flat face's noise fits huge circles).
constexpr int kRoundBins = 32;
constexpr int kRoundMinBins = 5;
constexpr float kRoundMinSpan = 0.015f;
constexpr double kRoundRms = 0.002;
constexpr double kRoundMinRadius = 0.005;
constexpr double kRoundMaxRadius = 0.1;
constexpr double kRoundSagitta = 0.003;
// Both pads reach the target by their tips alone and show at most this many contact
// normals between them: nothing says they hold (friction_ok).
constexpr uint32_t kTipOnlyNormals = 2;
// Both pads overlap the target by less than this many voxels along the approach: with
// at most kTipOnlyNormals contact normals, all off the cone, they fail (friction_ok).
constexpr float kShallowLeaves = 2.f;
// Off straight down, a pad whose contact normals are all off the cone fails unless the
// other pad shows at least this many (friction_ok).
constexpr uint32_t kVouchNormals = 3;
// Straight down: an approach within 5 deg (half the extension families' 10 deg step) of
// the support plane's downward normal.
constexpr float kTopDownCos = 0.9962f;
// The contact tilt fit (contact_tilt): points up to this deep inside each side, at
// least this many, spread over at least this depth.
constexpr float kTiltFitDepth = 0.012f;
constexpr uint32_t kTiltFitMin = 4;
constexpr float kTiltFitSpread = 0.003f;
// A side whose fitted 1 - cos(tilt) changes by less than this over kTiltFitDepth is
// flat (a radius above 0.06 m): its tilt is the contact's.
constexpr double kFlatChange = 0.2;
// A flat side's tilt must be this much inside the cone (its fitted tilt scatters by a
// few degrees: 5 mm voxels, sensor noise).
constexpr float kFlatMargin = 0.07f;
// The face nearest the contact (contact_tilt, near_face): fits over the points in the
// nearest kNearFaceMinBins..kNearFaceMaxBins depth bins of kNearFaceBin inside the side,
// spread over at least kNearFaceSpread.
constexpr float kNearFaceBin = 0.002f;
constexpr int kNearFaceBins = 6;  // kNearFaceBins * kNearFaceBin = kTiltFitDepth
constexpr int kNearFaceMinBins = 3;
constexpr int kNearFaceMaxBins = 5;
constexpr float kNearFaceSpread = 0.005f;
// The crease: at least this many points deeper than the face, their mean tilt at least
// this much steeper (rad).
constexpr uint32_t kCreaseMin = 3;
constexpr double kCreaseJump = 0.17;
// A face's tilt changes by less than this over the depth it spans (rad).
constexpr double kFaceTurn = 0.1;
// A patch of the 26-neighbourhood is planar when its thickness (smallest spread) is
// below this share of its width (middle spread): rounded sides of radius above a voxel
// are, the voxels on an edge whose faces turn by more than about 60 deg are not.
constexpr float kPlanarRatio = 0.1f;
// The edge at a side's extreme: points up to this deep inside the side, at least
// kEdgeMin of them, more than half not planar.
constexpr float kEdgeDepth = 0.002f;
constexpr uint32_t kEdgeMin = 2;
// The face beside that edge: the kBestFace-th smallest tilt of the planar points.
constexpr int kBestFace = 3;
// A pad must reach more than this (along the approach) past the first contact point of
// its side: a voxel (centroids lie up to half a voxel inside the surface) and a margin.
constexpr float kTipReach = 0.006f;
// The largest turn of the closing direction towards the contact normals (rad).
constexpr float kMaxClosingTurn = 0.6f;
}  // namespace

namespace {
using Box = FrameBox;
// A sample of a finger's or a pad's column at x along the closing direction: iy of 3
// across the finger's width (its edges and centre), iz of 5 along its depth (quarters).
Vec3 pad_sample(const GripperGeometry& g, const Vec3& pos, const ViewFrame& f, float x, int iy, int iz) {
  const float y = g.finger_width_m * (static_cast<float>(iy) - 1.f) * 0.5f;
  const float z = g.finger_depth_m * (static_cast<float>(iz) * 0.25f - 0.5f);
  return pos + f.X * x + f.Y * y + f.Z * z;
}
// Fingers open and palm, swept from the pre-grasp to the grasp (grasp frame).
void gripper_boxes(const PlannerConfig& cfg, Box out[3]) {
  const GripperGeometry& g = cfg.gripper;
  const float half_open = 0.5f * g.max_opening_m, t = g.finger_thickness_m;
  const float half_fd = 0.5f * g.finger_depth_m;
  const float back = g.finger_depth_m + cfg.pregrasp_clearance_m;  // approach stroke
  out[0] = {-half_open - t, -half_open, -0.5f * g.finger_width_m, 0.5f * g.finger_width_m, -half_fd - back, half_fd};
  out[1] = {half_open, half_open + t, -0.5f * g.finger_width_m, 0.5f * g.finger_width_m, -half_fd - back, half_fd};
  out[2] = {
      -half_open - t, half_open + t, -0.5f * g.palm_width_m, 0.5f * g.palm_width_m, -half_fd - g.palm_depth_m - back,
      -half_fd};
}
}  // namespace

// The voxels a gripper at any candidate could touch: candidates sit within the
// object's bounding sphere (plus a finger depth, the most the depth rule puts them
// past a surface), and no box corner lies farther than `reach` from the grasp point.
// Stored in the lent count storage, idle after clustering, and sorted by their cell of
// a coarse grid over the cube around that sphere (in the idle per-view memory): the
// collision check then reads only the cells under each box, instead of every voxel of
// the scene.
void GraspChecks::begin_target(uint32_t* storage, uint32_t* tables, Vec2* scratch) {
  for (uint32_t i = 0; i < object_.size(); ++i) normal_state_[i] = 0;
  near_ = storage;
  n_near_ = 0;
  Vec3 lo = object_[0], hi = object_[0];
  for (uint32_t i = 1; i < object_.size(); ++i) {
    lo = lo.cwiseMin(object_[i]);
    hi = hi.cwiseMax(object_[i]);
  }
  near_centre_ = 0.5f * (lo + hi);
  near_slack_ = 0.5f * (hi - lo).norm() + cfg_.gripper.finger_depth_m;
  Box boxes[3];
  gripper_boxes(cfg_, boxes);
  float reach = 0.f;
  for (const Box& b : boxes) {
    const float x = std::max(std::fabs(b.x0), std::fabs(b.x1)), y = std::max(std::fabs(b.y0), std::fabs(b.y1));
    const float z = std::max(std::fabs(b.z0), std::fabs(b.z1));
    reach = std::max(reach, std::sqrt(x * x + y * y + z * z));
  }
  const float r = near_slack_ + reach + cfg_.collision_tolerance_m;
  near_reach_ = reach;
  near_radius_ = r;
  const Vec3* centroids = grid_.centroids();
  for (uint32_t i = 0; i < grid_.size(); ++i)
    if (state_[i] != kVoxelRemoved && (centroids[i] - near_centre_).squaredNorm() <= r * r) near_[n_near_++] = i;
  // About one entry per coarse cell, within what the per-view memory holds.
  uint32_t cell_bits = 3;
  while (cell_bits < kNearCellBits && (1u << cell_bits) < n_near_) ++cell_bits;
  const NearGrid g = NearGrid::around(near_centre_, r, cell_bits);
  for (uint32_t k = 0; k < n_near_; ++k) near_[k] |= g.cell_of(centroids[near_[k]]) << kNearIndexBits;
  sort_by_cell(near_, n_near_, kNearIndexBits, cell_bits, tables, tables + (1u << kNearCellBits));
  near_grid_ = g;
  build_plausible_body(scratch);
}

void GraspChecks::build_plausible_body(Vec2* scratch) {
  n_body_edges_ = 0;
  flat_sided_ = false;
  const uint32_t m = object_.size();
  if (!support_.found || m < 3) return;
  const Vec3 n = support_.plane.n.normalized();
  const Vec3 a = std::fabs(n.x()) < 0.9f ? Vec3::UnitX() : Vec3::UnitY();
  body_u_ = (a - n * n.dot(a)).normalized();
  body_v_ = n.cross(body_u_);
  Vec2* const pts = scratch;
  Vec2* const work = scratch + kMaxObjectPoints;
  float top = -std::numeric_limits<float>::infinity();
  for (uint32_t i = 0; i < m; ++i) {
    pts[i] = Vec2{body_u_.dot(object_[i]), body_v_.dot(object_[i])};
    top = std::max(top, support_.plane.height(object_[i]));
  }
  Vec2 hull[kMaxBodyEdges];
  uint32_t h = 0;
  if (convex_hull_2d(pts, m, work, hull, kMaxBodyEdges, h) != Status::ok || h < 3) return;
  // The hull's area centroid (its points' centroid leans to the densest seen face).
  double area = 0.0, cx = 0.0, cy = 0.0;
  for (uint32_t i = 0; i < h; ++i) {
    const Vec2& p = hull[i];
    const Vec2& q = hull[i + 1 < h ? i + 1 : 0];
    const double cross = static_cast<double>(p.x) * q.y - static_cast<double>(q.x) * p.y;
    area += cross;
    cx += (static_cast<double>(p.x) + q.x) * cross;
    cy += (static_cast<double>(p.y) + q.y) * cross;
  }
  if (!(area > 1e-12)) return;
  const float mx = static_cast<float>(2.0 * cx / (3.0 * area)), my = static_cast<float>(2.0 * cy / (3.0 * area));
  for (uint32_t i = 0; i < h; ++i) {
    pts[i] = hull[i];
    pts[h + i] = Vec2{mx - hull[i].x, my - hull[i].y};
  }
  if (convex_hull_2d(pts, 2 * h, work, hull, kMaxBodyEdges, h) != Status::ok || h < 3) return;
  // Only a flat-sided body (a prism on the plane: a box, a carton) ends where its seen
  // outline ends; a round one (a sphere, an ellipsoid, a bottle's body) may bulge
  // beyond it below what was seen, and keeps every hidden sample as possibly solid
  // (plausibly_solid). A disc fills pi/4 of its smallest rectangle, a rectangle all of it.
  float major_x = 0.f, major_y = 0.f;
  const float rectangle = min_area_rectangle(hull, h, major_x, major_y);
  flat_sided_ = polygon_area(hull, h) >= kFlatSidedFill * rectangle;
  body_lo_[0] = body_hi_[0] = hull[0].x;
  body_lo_[1] = body_hi_[1] = hull[0].y;
  for (uint32_t i = 0; i < h; ++i) {
    const Vec2& p = hull[i];
    const Vec2& q = hull[i + 1 < h ? i + 1 : 0];
    const float ex = q.x - p.x, ey = q.y - p.y, len = std::sqrt(ex * ex + ey * ey);
    if (!(len > 1e-9f)) continue;
    // Counter-clockwise: the inside lies to the left of each edge.
    body_normal_[n_body_edges_] = Vec2{-ey / len, ex / len};
    body_offset_[n_body_edges_] = body_normal_[n_body_edges_].x * p.x + body_normal_[n_body_edges_].y * p.y;
    ++n_body_edges_;
    body_lo_[0] = std::min(body_lo_[0], p.x);
    body_hi_[0] = std::max(body_hi_[0], p.x);
    body_lo_[1] = std::min(body_lo_[1], p.y);
    body_hi_[1] = std::max(body_hi_[1], p.y);
  }
  flat_sided_ = flat_sided_ && n_body_edges_ >= 3;
  body_top_ = top;
}

bool GraspChecks::plausibly_solid(const Vec3& q) const {
  // Voxel centroids lie up to half a voxel inside the surface.
  return !flat_sided_ || in_body(q, 0.5f * cfg_.voxel_leaf_m);
}

bool GraspChecks::in_outline(const Vec3& q) const { return n_body_edges_ >= 3 && in_body(q, 0.5f * cfg_.voxel_leaf_m); }

bool GraspChecks::in_body(const Vec3& q, float grow) const {
  const float h = support_.plane.height(q);
  if (h < -grow || h > body_top_ + grow) return false;
  const float x = body_u_.dot(q), y = body_v_.dot(q);
  if (x < body_lo_[0] - grow || x > body_hi_[0] + grow || y < body_lo_[1] - grow || y > body_hi_[1] + grow)
    return false;
  for (uint32_t i = 0; i < n_body_edges_; ++i)
    if (body_normal_[i].x * x + body_normal_[i].y * y < body_offset_[i] - grow) return false;
  return true;
}

bool GraspChecks::plausible_wall(const Vec3& q, Vec3& outward) const {
  if (!flat_sided_) return false;
  const float x = body_u_.dot(q), y = body_v_.dot(q);
  uint32_t nearest = 0;
  float best = std::numeric_limits<float>::infinity();
  for (uint32_t i = 0; i < n_body_edges_; ++i) {
    const float d = std::fabs(body_normal_[i].x * x + body_normal_[i].y * y - body_offset_[i]);
    if (d < best) {
      best = d;
      nearest = i;
    }
  }
  // A contact farther inside than a voxel presses something within the outline (a
  // neck, a handle), not the wall under it.
  if (!(best <= cfg_.voxel_leaf_m)) return false;
  outward = -(body_u_ * body_normal_[nearest].x + body_v_ * body_normal_[nearest].y);
  return true;
}

bool GraspChecks::could_be_solid(const Vec3& q) const {
  if (plausibly_solid(q)) return true;
  // Outside the target's body: possibly solid only behind something else. The return
  // that hides q lies on the target when it falls in the target's body grown by a voxel
  // (a return is a surface point, its voxel's centroid up to half a voxel inside) and
  // by its bin's width at its depth (the bin's nearest return, placed on q's ray).
  for (uint32_t r = 0; r < kMaxSensors; ++r) {
    Vec3 hit;
    if (!sensors_.hidden_by(r, q, hit)) continue;
    const float bin = (hit - sensors_.origin[r]).norm() * (2.f / static_cast<float>(kSightBins));
    if (!in_body(hit, cfg_.voxel_leaf_m + bin)) return true;
  }
  return false;
}

// The checks in order, up to the first that fails or, in the first pass, defers the
// candidate: a finger partly in hidden space, or a pad closing through it. A pad
// whose edge meets a surface beside it (Candidate::corners_clear) is deferred by the
// selection unchecked.
CheckVerdict GraspChecks::evaluate(const Candidate& c, bool first_pass) {
  const ViewFrame f{c.X, c.Y, c.Z};
  Box boxes[3];
  gripper_boxes(cfg_, boxes);
  // Support plane: every corner above it.
  for (const Box& b : boxes)
    for (int k = 0; k < 8; ++k) {
      const Vec3 p =
          c.position + f.X * ((k & 1) ? b.x1 : b.x0) + f.Y * ((k & 2) ? b.y1 : b.y0) + f.Z * ((k & 4) ? b.z1 : b.z0);
      if (support_.plane.height(p) < cfg_.table_clearance_m - 1e-4f) return CheckVerdict::fail(CheckId::support_plane);
    }
  // Every voxel that is not table (the target and its neighbours) stays out of the
  // boxes: those of the near list when the candidate lies where that list assumes.
  const float tol = cfg_.collision_tolerance_m;
  const bool use_near = near_ != nullptr && (c.position - near_centre_).norm() <= near_slack_;
  const Vec3* centroids = grid_.centroids();
  if (use_near) {
    const Vec3 axes[3] = {f.X, f.Y, f.Z};
    // Entries of voxels since removed are skipped (state 0, kVoxelRemoved).
    for (const Box& b : boxes)
      if (near_list_hits(near_, n_near_, kNearIndexBits, near_grid_, centroids, state_, c.position, axes, b, tol))
        return CheckVerdict::fail(CheckId::swept_collision);
  } else {
    for (uint32_t i = 0; i < grid_.size(); ++i) {
      if (state_[i] == kVoxelRemoved) continue;
      const Vec3 d = centroids[i] - c.position;
      const float x = f.X.dot(d), y = f.Y.dot(d), z = f.Z.dot(d);
      for (const Box& b : boxes)
        if (b.holds(x, y, z, tol)) return CheckVerdict::fail(CheckId::swept_collision);
    }
  }
  // The fingers at the open pose stay out of the target's local convex hull: surface
  // points alone miss a finger that would sit inside the solid (a cap grasp on a big
  // sphere), and the hull of the points around the hand fills in the unseen interior.
  if (!fingers_clear_of_hull(c.position, f)) return CheckVerdict::fail(CheckId::local_hull);
  if (!fingers_clear_of_footprint(c.position, f, c.width)) return CheckVerdict::fail(CheckId::under_target);
  // The open fingers must not sit in space the sensors saw only from behind a surface;
  // in the first pass, a finger with a few hidden samples waits.
  uint32_t hidden_sides = 0;
  const int sight = fingers_in_seen_space(c.position, f, c.width, hidden_sides);
  if (sight == 2) return CheckVerdict::fail(CheckId::unknown_space);
  if (sight == 1 && first_pass) return CheckVerdict::wait(CheckId::unknown_space);
  // Such a finger may meet the object's unseen side, which bulges past what was seen
  // (rounded objects, tilted approaches): only a balanced grasp whose seen side,
  // extended along its last slope, stays clear of the open finger.
  if (sight == 1 && !c.balanced) return CheckVerdict::fail(CheckId::unknown_space);
  // A pad that closes through space no sensor saw may meet something else first: such a
  // grasp waits for those whose strokes were seen.
  if (first_pass && hidden_in_strokes(c.position, f, c.width) != 0u) return CheckVerdict::wait(CheckId::unknown_space);
  for (int side = 0; side < 2; ++side)
    if ((hidden_sides >> side & 1u) != 0u && !unseen_side_clear(c.position, f, side))
      return CheckVerdict::fail(CheckId::unseen_side);
  if (hidden_sides != 0u && !blind_side_mirrors_seen(c.position, f, c.width, hidden_sides))
    return CheckVerdict::fail(CheckId::unseen_side);
  // Each fitted side's normal within the cone in XOY (beta alone only compares the two
  // sides), and the contact normals in 3D.
  // A round body closed on its unseen tangents: the model is the friction argument.
  if (cfg_.friction_mu > 0.f && !c.tangent_contacts && (!c.sides_in_cone || !friction_ok(c.position, f, c.width)))
    return CheckVerdict::fail(CheckId::friction_cone);
  return CheckVerdict::pass();
}

// One pass over each pad's contact points (the band inside each side, within the
// pad's footprint) with a defined normal that does not face the approach: surfaces
// facing the approach are what the pads slide along, not what they squeeze (a side
// the sensors did not see leaves only its front edge in the band). Per side: how many,
// how many inside the friction cone, and the sum of the outward normals.
void GraspChecks::contact_normal_stats(const Vec3& pos, const ViewFrame& f, float width, ContactNormalStats& st) {
  const GripperGeometry& g = cfg_.gripper;
  const float cos_cone = std::cos(std::atan(cfg_.friction_mu));
  st = ContactNormalStats{};
  const uint32_t n = object_.size();
  for (uint32_t i = 0; i < n; ++i) {
    const Vec3 d = object_[i] - pos;
    const float x = f.X.dot(d), y = f.Y.dot(d), z = f.Z.dot(d);
    if (std::fabs(y) > 0.5f * g.finger_width_m || std::fabs(z) > 0.5f * g.finger_depth_m) continue;
    int side = -1;
    if (x <= -0.5f * width + cfg_.contact_band_m)
      side = 0;
    else if (x >= 0.5f * width - cfg_.contact_band_m)
      side = 1;
    if (side < 0) continue;
    st.z_first[side] = std::min(st.z_first[side], z);
    if (support_.found) st.top[side] = std::max(st.top[side], support_.plane.height(object_[i]));
    Vec3 nrm;
    if (!normal_at(i, nrm)) continue;
    if (support_.found && std::fabs(nrm.dot(support_.plane.n)) > kFrontFacingCos * support_.plane.n.norm())
      ++st.level[side];
    if (std::fabs(nrm.dot(f.Z)) > kFrontFacingCos) continue;
    const float along = nrm.dot(f.X);
    ++st.total[side];
    st.inside_cone[side] += std::fabs(along) >= cos_cone ? 1u : 0u;
    st.outward_sum[side] += (side == 0) == (along < 0.f) ? nrm : Vec3(-nrm);
  }
}

// Closing along the contact normals' mean direction, kept orthogonal to the approach,
// when that turn is small (at most kMaxClosingTurn); the width and centre are measured
// again along the turned closing direction from the points within the pads' reach.
bool GraspChecks::refine_closing(Candidate& c) {
  ContactNormalStats st;
  contact_normal_stats(c.position, ViewFrame{c.X, c.Y, c.Z}, c.width, st);
  if (st.total[0] < 3 || st.total[1] < 3) return false;
  // Along the mean outward normals: from the left contact's towards the right's.
  Vec3 x = st.outward_sum[1] / static_cast<float>(st.total[1]) - st.outward_sum[0] / static_cast<float>(st.total[0]);
  x -= c.Z * c.Z.dot(x);
  const float len = x.norm();
  if (!(len > 1e-6f)) return false;
  x /= len;
  if (x.dot(c.X) < std::cos(kMaxClosingTurn)) return false;
  const Vec3 y = c.Z.cross(x);
  const GripperGeometry& g = cfg_.gripper;
  float xmin = 1e9f, xmax = -1e9f;
  const uint32_t n = object_.size();
  for (uint32_t i = 0; i < n; ++i) {
    const Vec3 d = object_[i] - c.position;
    if (std::fabs(y.dot(d)) > 0.5f * g.finger_width_m || std::fabs(c.Z.dot(d)) > 0.5f * g.finger_depth_m) continue;
    const float px = x.dot(d);
    xmin = std::min(xmin, px);
    xmax = std::max(xmax, px);
  }
  if (!(xmax >= xmin)) return false;
  const float width = xmax - xmin;
  if (width < g.min_opening_m || width > g.max_opening_m - cfg_.width_margin_m) return false;
  c.position += x * (0.5f * (xmin + xmax));
  c.X = x;
  c.Y = y;
  c.width = width;
  return true;
}

bool GraspChecks::fingers_clear_of_hull(const Vec3& pos, const ViewFrame& f, float grow) {
  const GripperGeometry& g = cfg_.gripper;
  const float half_open = 0.5f * g.max_opening_m, t = g.finger_thickness_m;
  const float hy = 0.5f * g.finger_width_m, hz = 0.5f * g.finger_depth_m;
  const float m = kHullNeighbourhood;
  uint32_t n_local = 0;
  const uint32_t n = object_.size();
  for (uint32_t i = 0; i < n; ++i) {
    const Vec3 d = object_[i] - pos;
    const Vec3 q(f.X.dot(d), f.Y.dot(d), f.Z.dot(d));
    if (std::fabs(q.y()) <= hy + m && std::fabs(q.z()) <= hz + m && std::fabs(q.x()) <= half_open + t + m)
      local_[n_local++] = q;
  }
  if (n_local == 0) return true;
  const float tol = cfg_.collision_tolerance_m;
  const PointSetShape hull{local_, n_local};
  const ConvexSupport hs{point_set_support, &hull, Vec3::Zero()};
  for (int side = 0; side < 2; ++side) {
    const float x0 = side == 0 ? -half_open - t : half_open;
    const float in = tol - grow;
    const AabbShape box{Vec3(x0 + in, -hy + in, -hz + in), Vec3(x0 + t - in, hy - in, hz - in)};
    const ConvexSupport bs{aabb_support, &box, 0.5f * (box.lo + box.hi)};
    if (gjk_intersect(bs, hs)) return false;
  }
  return true;
}

bool GraspChecks::straight_down(const Vec3& approach) const {
  return support_.found && -approach.dot(support_.plane.n) >= kTopDownCos;
}

// A steep closing puts a finger under the target. The target rests on the support
// plane, so the space under its seen points, down to the plane, is taken as solid: a
// wall the sensors saw only at a grazing angle (its pixels dropped, so the space in
// front of it reads as free), the unseen side under a seen top. Each target point's
// vertical line, from a voxel below it down to the plane, must miss both fingers'
// sweeps from the open pose to the pads (shrunk by half a voxel: a centroid lies up to
// that far inside the surface). Only for steep closings (kSteepClosingCos): sideways,
// real overhangs (a bat's blade over its handle, a drill's body) lie over the fingers
// of good grasps.
// Sideways, a thin grasp (kThinSheetLeaves) closes on a single layer of voxels: a
// plate (a bat's blade or handle seen edge-on), or the wall of a solid seen at a
// grazing angle, with the solid's top over the open finger on the far side (a wide
// box's vertical edge). There the open fingers alone are tested: a blade's own
// points lie between the pads, and a plate has nothing over the open fingers.
bool GraspChecks::footprint_applies(const ViewFrame& f, float width) const {
  if (!support_.found) return false;
  const bool steep = std::fabs(f.X.dot(support_.plane.n)) >= kSteepClosingCos;
  return steep || width <= kThinSheetLeaves * cfg_.voxel_leaf_m;
}

bool GraspChecks::fingers_clear_of_footprint(const Vec3& pos, const ViewFrame& f, float width, float grow) {
  if (!footprint_applies(f, width)) return true;
  const bool steep = std::fabs(f.X.dot(support_.plane.n)) >= kSteepClosingCos;
  const GripperGeometry& g = cfg_.gripper;
  const float half_open = 0.5f * g.max_opening_m, t = g.finger_thickness_m;
  const float hy = 0.5f * g.finger_width_m, hz = 0.5f * g.finger_depth_m;
  const float shrink = 0.5f * cfg_.voxel_leaf_m - grow, gap = cfg_.voxel_leaf_m;
  // Each finger's sweep from open to closed, in the grasp frame; its pad's face keeps a
  // voxel clear of the contact (the side's points scatter about the fitted line).
  // A thin grasp sideways: the open fingers only.
  const float inner0 = steep ? -0.5f * width - gap : -half_open - shrink;
  const float inner1 = steep ? 0.5f * width + gap : half_open + shrink;
  const float lo[2][3] = {{-half_open - t + shrink, -hy + shrink, -hz + shrink}, {inner1, -hy + shrink, -hz + shrink}};
  const float hi[2][3] = {{inner0, hy - shrink, hz - shrink}, {half_open + t - shrink, hy - shrink, hz - shrink}};
  // Up (the plane's normal) in the grasp frame; the line below q is q - u * up.
  const float up[3] = {f.X.dot(support_.plane.n), f.Y.dot(support_.plane.n), f.Z.dot(support_.plane.n)};
  const uint32_t n = object_.size();
  for (uint32_t i = 0; i < n; ++i) {
    const float h = support_.plane.height(object_[i]);
    if (!(h > gap)) continue;
    const Vec3 d = object_[i] - pos;
    const float q[3] = {f.X.dot(d), f.Y.dot(d), f.Z.dot(d)};
    for (int side = 0; side < 2; ++side)
      if (segment_meets_box(q, up, gap, h, lo[side], hi[side])) return false;
  }
  return true;
}

// Samples of each open finger box: too many hidden ones (behind the object as every
// sensor saw it, and free to none) mean the finger would sit inside unseen matter (2);
// so do too few seen free beside a thin grasp (2).
// A few (1) are allowed, but the unseen side of a rounded object bulges past what was
// seen there, so such grasps come after those whose fingers lie in seen space (0).
int GraspChecks::fingers_in_seen_space(const Vec3& pos, const ViewFrame& f, float width, uint32_t& partly_hidden,
                                       float* hidden_share, Vec3* hidden_sum) {
  const GripperGeometry& g = cfg_.gripper;
  const float half_open = 0.5f * g.max_opening_m, t = g.finger_thickness_m;
  // A thin grasp (kThinSheetLeaves) closes on a single layer of voxels. Seen by one
  // sensor, the near surface of any solid is such a layer (a can's wall, a box's face),
  // and the space behind it may be unknown rather than hidden: no return at all there
  // (closer than the sensor's minimum range, a dropout) says nothing about it. Only a
  // layer with space seen on both sides is a plate (kThinSeenFree).
  const bool thin = width <= kThinSheetLeaves * cfg_.voxel_leaf_m;
  // Hidden samples count where something could be (could_be_solid): behind the target
  // yet outside its plausible body, a finger meets nothing of it.
  uint32_t hidden = 0, total = 0, seen_free = 0;
  partly_hidden = 0;
  for (int side = 0; side < 2; ++side) {
    const uint32_t before = hidden, free_before = seen_free;
    Vec3 not_free_sum = Vec3::Zero();  // this finger's samples no sensor saw free
    const float x0 = side == 0 ? -half_open - t : half_open;
    for (int ix = 0; ix < 2; ++ix)
      for (int iy = 0; iy < 3; ++iy)
        for (int iz = 0; iz < 5; ++iz) {
          ++total;
          const Vec3 q = pad_sample(g, pos, f, x0 + t * (0.25f + 0.5f * static_cast<float>(ix)), iy, iz);
          const int v = visibility(q);
          const bool counts = v < 0 && could_be_solid(q);
          hidden += counts ? 1u : 0u;
          if (counts && hidden_sum != nullptr) *hidden_sum += q;
          seen_free += v > 0 ? 1u : 0u;
          if (v <= 0 && hidden_sum != nullptr) not_free_sum += q;
        }
    if (hidden - before > kSeenFingerHidden) partly_hidden |= 1u << side;
    if (thin && seen_free - free_before < kThinSeenFree) {
      // Refused for the space behind the layer: this finger's samples not seen free.
      const uint32_t not_free = kFingerSamples / 2 - (seen_free - free_before);
      if (hidden_share != nullptr) *hidden_share = static_cast<float>(not_free) / static_cast<float>(kFingerSamples);
      if (hidden_sum != nullptr) *hidden_sum = not_free_sum;
      return 2;
    }
  }
  // Straight down onto a target standing on the plane, with one finger hidden beside
  // the side the sensors did not see (the far face of a tall box: the top hides it from
  // every sensor above it): not rejected, but deferred like a partly hidden finger, so
  // it is taken only balanced and with the seen side clear of the finger
  // (unseen_side_clear). Along the plane's normal the flat side that check assumes
  // where it saw no slope is a wall standing on the plane; on a tilted approach it
  // would be a wall leaning towards the finger.
  if (hidden_share != nullptr) *hidden_share = static_cast<float>(hidden) / static_cast<float>(total);
  const bool one_finger = partly_hidden == 1u || partly_hidden == 2u;
  const bool top_down = straight_down(f.Z);
  if (static_cast<float>(hidden) > kMaxHiddenShare * static_cast<float>(total) && !(one_finger && top_down)) return 2;
  return partly_hidden != 0 ? 1 : 0;
}

// Each pad's closing stroke: the space it sweeps from the open pose to its contact,
// from the sight maps' margin off the contact (closer to a surface no return frees or
// hides a point) to the open finger's inner face, sampled 3 across the stroke x 3 across
// the pad's width x 5 along its depth. A sample hidden from every sensor yet inside the
// target's outline (the prism over its completed hull, round bodies' too) may be matter
// the pad meets before its contact: a bottle's shoulder under the cap it closes on, the
// far flank of an oblong body that widens past its seen end. The grasp would close
// there, at another width and normal. A pad with more than kSeenFingerHidden such
// samples (silhouettes' edges blur, as for an open finger) counts; returns the pads
// that do (bit 0 left, bit 1 right).
uint32_t GraspChecks::hidden_in_strokes(const Vec3& pos, const ViewFrame& f, float width) const {
  const GripperGeometry& g = cfg_.gripper;
  const float half_open = 0.5f * g.max_opening_m;
  const float from = 0.5f * width + SensorViews::kSightMargin;
  if (!(half_open > from)) return 0u;
  uint32_t hidden_pads = 0;
  for (int side = 0; side < 2; ++side) {
    const float sign = side == 0 ? -1.f : 1.f;
    uint32_t hidden = 0;
    for (int ix = 0; ix < 3; ++ix)
      for (int iy = 0; iy < 3; ++iy)
        for (int iz = 0; iz < 5; ++iz) {
          const float x = from + (half_open - from) * (static_cast<float>(ix) + 0.5f) / 3.f;
          const Vec3 q = pad_sample(g, pos, f, sign * x, iy, iz);
          hidden += visibility(q) < 0 && in_outline(q) ? 1u : 0u;
        }
    if (hidden > kSeenFingerHidden) hidden_pads |= 1u << side;
  }
  return hidden_pads;
}

bool GraspChecks::hidden_centre(const Candidate& c, Vec3& centre) {
  uint32_t partly_hidden = 0;
  float share = 0.f;
  Vec3 sum = Vec3::Zero();
  (void)fingers_in_seen_space(c.position, c.frame(), c.width, partly_hidden, &share, &sum);
  if (!(share > 0.f)) return false;
  centre = sum / std::round(share * static_cast<float>(kFingerSamples));
  return true;
}

// Each side under a partly hidden finger that shows no contact normal (contact_normal_stats:
// its band holds only surfaces facing the approach, or none) must have a seen opposite
// side it can mirror (kBlindMirrorTiltCos). Straight down, the blind side is the wall
// under the top's rim (fingers_in_seen_space) and needs no mirror.
bool GraspChecks::blind_side_mirrors_seen(const Vec3& pos, const ViewFrame& f, float width, uint32_t hidden_sides) {
  if (straight_down(f.Z)) return true;
  ContactNormalStats st;
  contact_normal_stats(pos, f, width, st);
  bool blind[2] = {false, false};
  // A side is blind under a partly hidden finger when its band shows no contact normal,
  // or at most two, all off the cone: a steep glimpse of the near wall, not the side
  // the pad would squeeze (a chord across a round body seen from one side).
  for (int side = 0; side < 2; ++side) {
    const bool no_side = st.total[side] == 0u || (st.total[side] <= 2u && st.inside_cone[side] == 0u);
    blind[side] = (hidden_sides >> side & 1u) != 0u && no_side;
  }
  if (!blind[0] && !blind[1]) return true;
  if (blind[0] && blind[1]) return false;
  const int blind_side = blind[0] ? 0 : 1;
  if (st.level[blind_side] > 0u && top_goes_on_past(pos, f, width, blind_side)) return false;
  if (!round_front_clears_blind_side(pos, f, blind_side)) return false;
  float omc[2];
  bool valid[2], flat[2];
  float near_face[2], edge_face[2];
  contact_tilt(pos, f, omc, valid, flat, near_face, edge_face);
  const int seen = blind[0] ? 1 : 0;
  return valid[seen] && (flat[seen] || omc[seen] <= 1.f - kBlindMirrorTiltCos);
}

// A blind side whose band holds a top (normals along the support plane's) mirrors the
// seen side only where that top ends at the band: a top the sensors saw going on past
// it, along the closing direction laid on the plane, says the body goes on too, and the
// blind side is its unseen inside, not a wall the pad meets: a closing tilted off level
// across a wide box's corner leaves the top through the box's unseen upper side, where
// the band holds the top's last points, read as a thin slab with the body beyond it.
bool GraspChecks::top_goes_on_past(const Vec3& pos, const ViewFrame& f, float width, int side) {
  if (!support_.found) return false;
  const GripperGeometry& g = cfg_.gripper;
  const Vec3 up = support_.plane.n.normalized();
  Vec3 u = f.X - up * f.X.dot(up);
  if (!(u.norm() > kTopAlongMin)) return false;  // closing along the plane's normal
  u = u.normalized() * (side == 0 ? -1.f : 1.f);
  const Vec3 v = up.cross(u);
  const uint32_t n = object_.size();
  // The band's top: its highest level point, and how far out along u its level points go.
  float top = -1e9f, edge = -1e9f;
  for (uint32_t i = 0; i < n; ++i) {
    const Vec3 d = object_[i] - pos;
    const float x = f.X.dot(d), y = f.Y.dot(d), z = f.Z.dot(d);
    if (std::fabs(y) > 0.5f * g.finger_width_m || std::fabs(z) > 0.5f * g.finger_depth_m) continue;
    if (side == 0 ? x > -0.5f * width + cfg_.contact_band_m : x < 0.5f * width - cfg_.contact_band_m) continue;
    Vec3 nrm;
    if (!normal_at(i, nrm) || std::fabs(nrm.dot(up)) <= kFrontFacingCos) continue;
    top = std::max(top, support_.plane.height(object_[i]));
    edge = std::max(edge, u.dot(d));
  }
  if (!(top > -1e8f)) return false;
  // The same top beyond that edge, in a corridor of the pads' width.
  const float leaf = cfg_.voxel_leaf_m;
  const float from = edge + kTopGap * leaf, to = from + kTopBeyond;
  uint32_t beyond = 0;
  for (uint32_t i = 0; i < n && beyond < kTopBeyondMin; ++i) {
    const Vec3 d = object_[i] - pos;
    const float a = u.dot(d);
    if (a < from || a > to || std::fabs(v.dot(d)) > 0.5f * g.finger_width_m) continue;
    if (std::fabs(support_.plane.height(object_[i]) - top) > leaf) continue;
    Vec3 nrm;
    if (normal_at(i, nrm) && std::fabs(nrm.dot(up)) > kFrontFacingCos) ++beyond;
  }
  return beyond >= kTopBeyondMin;
}

// The mirror above reads a round body's chord as a whole body: the seen side is where
// the pad meets the body along the closing line, the blind side the edge of what the
// sensors saw of its front, and the body's unseen rest bulges past the open finger
// there (a wide can, a bottle's body seen from one side, grasped off its axis). The
// front the approach meets first, across the open gripper within the pads' width
// (per bin of a voxel or more, the nearest point), tells: when a circle fits it (Kasa's
// algebraic fit, then its rms distance), the circle's extent on the blind side over
// the fingers' depth must stay inside the open finger. A flat or irregular front says
// nothing here (the mirror stands).
bool GraspChecks::round_front_clears_blind_side(const Vec3& pos, const ViewFrame& f, int blind_side) {
  const GripperGeometry& g = cfg_.gripper;
  const float half_open = 0.5f * g.max_opening_m;
  const float bin = std::max(cfg_.voxel_leaf_m, 2.f * half_open / static_cast<float>(kRoundBins));
  const int nb = std::min(kRoundBins, static_cast<int>(2.f * half_open / bin) + 1);
  float front_z[kRoundBins], front_x[kRoundBins];
  for (int b = 0; b < nb; ++b) front_z[b] = 1e9f;
  const uint32_t n = object_.size();
  for (uint32_t i = 0; i < n; ++i) {
    const Vec3 d = object_[i] - pos;
    const float x = f.X.dot(d), y = f.Y.dot(d), z = f.Z.dot(d);
    if (std::fabs(y) > 0.5f * g.finger_width_m || !(std::fabs(x) < half_open)) continue;
    const int b = std::min(nb - 1, static_cast<int>((x + half_open) / bin));
    if (z < front_z[b]) {
      front_z[b] = z;
      front_x[b] = x;
    }
  }
  // Centred coordinates keep the normal equations well conditioned.
  double mx = 0.0, mz = 0.0;
  float xlo = 1e9f, xhi = -1e9f;
  int m = 0;
  for (int b = 0; b < nb; ++b) {
    if (front_z[b] > 1e8f) continue;
    mx += front_x[b];
    mz += front_z[b];
    xlo = std::min(xlo, front_x[b]);
    xhi = std::max(xhi, front_x[b]);
    ++m;
  }
  if (m < kRoundMinBins || xhi - xlo < kRoundMinSpan) return true;
  mx /= m;
  mz /= m;
  CircleFit fit;
  for (int b = 0; b < nb; ++b)
    if (front_z[b] <= 1e8f) fit.add(front_x[b] - mx, front_z[b] - mz);
  double xc, zc, rr;
  if (!fit.solve(xc, zc, rr)) return true;  // collinear bins: a flat front
  // The centre must lie behind the front (convex towards the gripper).
  if (!(zc > 0.0)) return true;
  const double radius = std::sqrt(rr);
  double ss = 0.0;
  for (int b = 0; b < nb; ++b) {
    if (front_z[b] > 1e8f) continue;
    const double dx = front_x[b] - mx - xc, dz = front_z[b] - mz - zc;
    const double e = std::sqrt(dx * dx + dz * dz) - radius;
    ss += e * e;
  }
  const double span = static_cast<double>(xhi - xlo);
  if (std::sqrt(ss / m) > kRoundRms || radius < kRoundMinRadius || radius > kRoundMaxRadius ||
      span * span / (8.0 * radius) < kRoundSagitta)
    return true;
  // The circle's half width over the fingers' depth: all of it when its centre lies
  // within the pads' reach, else where it crosses the fingertips' plane.
  const double cx = xc + mx, cz = zc + mz, hz = 0.5 * g.finger_depth_m;
  const double half = cz <= hz ? radius : std::sqrt(std::max(0.0, rr - (cz - hz) * (cz - hz)));
  const double extent = blind_side == 0 ? half - cx : cx + half;
  return extent <= static_cast<double>(half_open - cfg_.collision_tolerance_m);
}

// The object's side under a partly hidden finger (0 left, 1 right), as far as it was
// seen: per bin along the approach within the pad's reach, the outermost point in the
// pad's footprint. A convex side bends back, so the line along its last seen slope
// bounds what lies unseen deeper down; it must stay clear of the open finger there.
// A flat side (a box's face) has no slope; a side seen in one bin only counts as flat.
// A bin shows the side only when no space between its outermost point and the finger is
// hidden: otherwise its points are another part of the object (the far wall of a can
// seen across a chord), and the side there is unseen. Points with none such: not clear.
bool GraspChecks::unseen_side_clear(const Vec3& pos, const ViewFrame& f, int side) {
  const GripperGeometry& g = cfg_.gripper;
  const float half_fd = 0.5f * g.finger_depth_m, bin = g.finger_depth_m / kProfileBins;
  const float sign = side == 0 ? -1.f : 1.f;
  float out[kProfileBins];
  for (int b = 0; b < kProfileBins; ++b) out[b] = -1e9f;
  const uint32_t n = object_.size();
  for (uint32_t i = 0; i < n; ++i) {
    const Vec3 d = object_[i] - pos;
    const float y = f.Y.dot(d), z = f.Z.dot(d);
    if (std::fabs(y) > 0.5f * g.finger_width_m || std::fabs(z) > half_fd) continue;
    const int b = std::min(kProfileBins - 1, static_cast<int>((z + half_fd) / bin));
    out[b] = std::max(out[b], sign * f.X.dot(d));
  }
  // Least squares over the deepest seen bins: outward extent against depth.
  float sz = 0.f, sx = 0.f, szz = 0.f, szx = 0.f, x_last = 0.f, z_last = 0.f, x_max = -1e9f;
  int m = 0, unseen_bins = 0;
  const bool top_down = straight_down(f.Z);
  for (int b = 0; b < kProfileBins; ++b) x_max = std::max(x_max, out[b]);
  for (int b = kProfileBins - 1; b >= 0 && m < kSlopeBins; --b) {
    if (out[b] < -1e8f) continue;
    const float z = -half_fd + (static_cast<float>(b) + 0.5f) * bin;
    // The bin shows this side only where the sensors saw no matter in front of the space
    // between its outermost point and the open finger: a point with hidden space beyond
    // it (another part of the object, the wall under a seen top) bounds nothing.
    // Straight down the side beside the top is taken for a wall standing on the plane
    // (fingers_in_seen_space): the top's rim bounds it, with the space under the top
    // hidden from every sensor above it.
    bool bounds = true;
    const float face = 0.5f * g.max_opening_m;  // the open finger's inner face
    for (int k = 1; !top_down && k <= kBeyondSteps && bounds; ++k) {
      const float x = out[b] + static_cast<float>(k) * kBeyondSide;
      if (x > face) break;
      bounds = visibility(pos + f.X * (sign * x) + f.Z * z) >= 0;
    }
    if (!bounds) {
      ++unseen_bins;
      continue;
    }
    if (m == 0) {
      x_last = out[b];
      z_last = z;
    }
    sz += z;
    sx += out[b];
    szz += z * z;
    szx += z * out[b];
    ++m;
  }
  if (m == 0) return unseen_bins == 0;
  float slope = 0.f;
  const float den = static_cast<float>(m) * szz - sz * sz;
  if (m >= 2 && den > 1e-12f) slope = std::max(0.f, (static_cast<float>(m) * szx - sz * sx) / den);
  const float reach = std::max(x_max, x_last + slope * (half_fd - z_last));
  return reach + kHiddenBulge <= 0.5f * g.max_opening_m - cfg_.collision_tolerance_m;
}

bool GraspChecks::normal_planar(uint32_t oi) const { return normal_state_[oi] == 1; }

bool GraspChecks::normal_at(uint32_t oi, Vec3& nrm) {
  if (normal_state_[oi] != 0) {
    nrm = normals_[oi];
    return normal_state_[oi] == 1 || normal_state_[oi] == 3;
  }
  normal_state_[oi] = 2;
  const uint32_t key = grid_.voxel(object_voxel_[oi]).key;
  const int32_t x = static_cast<int32_t>(VoxelGrid::key_x(key));
  const int32_t y = static_cast<int32_t>(VoxelGrid::key_y(key));
  const int32_t z = static_cast<int32_t>(VoxelGrid::key_z(key));
  Vec3 pts[27];
  uint32_t m = 0;
  for (int32_t dz = -1; dz <= 1; ++dz)
    for (int32_t dy = -1; dy <= 1; ++dy)
      for (int32_t dx = -1; dx <= 1; ++dx) {
        const uint32_t j = grid_.find(VoxelGrid::pack(static_cast<uint32_t>(x + dx), static_cast<uint32_t>(y + dy),
                                                      static_cast<uint32_t>(z + dz)));
        if (j != VoxelGrid::kNone && state_[j] == kVoxelTarget) pts[m++] = grid_.centroid(j);
      }
  if (m < 5) return false;
  Vec3 c, ev;
  Mat3 vecs;
  if (!pca(pts, m, c, ev, vecs)) return false;
  // A surface patch: the smallest spread must be clearly below the middle one; a
  // patch thicker than kPlanarRatio of its width keeps its normal but is not planar
  // (it straddles an edge: the normal mixes the faces'; contact_tilt).
  if (!(ev[0] < 0.5f * ev[1])) return false;
  normals_[oi] = vecs.col(0);
  normal_state_[oi] = ev[0] < kPlanarRatio * ev[1] ? 1 : 3;
  nrm = normals_[oi];
  return true;
}

// The object points' least and greatest x (closing) within the pads' footprint: |y|
// within half the finger width, |z| within half the finger depth. Empty: ext[1] < ext[0].
void GraspChecks::footprint_extremes(const Vec3& pos, const ViewFrame& f, float ext[2]) const {
  const GripperGeometry& g = cfg_.gripper;
  ext[0] = 1e9f;
  ext[1] = -1e9f;
  const uint32_t n = object_.size();
  for (uint32_t i = 0; i < n; ++i) {
    const Vec3 d = object_[i] - pos;
    const float x = f.X.dot(d), y = f.Y.dot(d), z = f.Z.dot(d);
    if (std::fabs(y) > 0.5f * g.finger_width_m || std::fabs(z) > 0.5f * g.finger_depth_m) continue;
    ext[0] = std::min(ext[0], x);
    ext[1] = std::max(ext[1], x);
  }
}

namespace {
// Sums of a least-squares line over points (depth d, value v = 1 - cos(tilt)).
struct LineSums {
  double sd, sdd, sv, sdv;
  uint32_t cnt;
  float dmin, dmax;
  // One point at `depth` with 1 - cos(tilt) = v.
  void add(float depth, double v) {
    ++cnt;
    sd += depth;
    sdd += static_cast<double>(depth) * depth;
    sv += v;
    sdv += depth * v;
    dmin = std::min(dmin, depth);
    dmax = std::max(dmax, depth);
  }
};
constexpr LineSums kNoSums{0, 0, 0, 0, 0, 1e9f, -1e9f};

// What contact_tilt gathers of one side: the fit's sums over every point up to
// kTiltFitDepth inside the side, the same sums per depth bin (for the fits over the
// nearest bins, near_face), and the edge at the extreme (edge_face): the points near
// it, how many of them are not planar, and the kBestFace smallest 1 - cos(tilt) of the
// planar points (ascending).
struct SideTiltSums {
  LineSums all = kNoSums;
  LineSums bins[kNearFaceBins];
  uint32_t n_near = 0, n_near_edge = 0, n_planar = 0;
  double best[kBestFace];

  SideTiltSums() {
    for (LineSums& b : bins) b = kNoSums;
    for (double& b : best) b = 2.0;
  }

  // One point at `depth` inside the side with 1 - cos(tilt) = v.
  void add(float depth, double v, bool planar) {
    if (depth <= kEdgeDepth) {
      ++n_near;
      n_near_edge += planar ? 0u : 1u;
    }
    if (planar) {
      ++n_planar;
      double ins = v;  // insertion into the ascending kBestFace smallest
      for (double& b : best)
        if (ins < b) std::swap(ins, b);
    }
    all.add(depth, v);
    bins[std::min(kNearFaceBins - 1, std::max(0, static_cast<int>(depth / kNearFaceBin)))].add(depth, v);
  }

  // An edge at the extreme: the pad touches it, and holds by the better of the faces
  // beside it (the planar points' smallest tilt, kBestFace of them). The normals of
  // the voxels on the edge mix both faces' and read as their bisector, in the cone
  // when neither face is (a standing bat's handle closed 30 deg off its faces).
  // -1 when there is none.
  float edge_face() const {
    if (n_near >= kEdgeMin && 2 * n_near_edge > n_near && n_planar >= static_cast<uint32_t>(kBestFace) &&
        2 * n_planar >= all.cnt)
      return static_cast<float>(best[kBestFace - 1]);
    return -1.f;
  }

  // The face nearest the contact: over the nearest 3, 4, 5 bins (6-10 mm), the
  // steepest mean 1 - cos(tilt) of a prefix whose tilt is flat (changes by less than
  // kFaceTurn) with a crease behind it; -1 when there is none.
  // A side with an edge inside the fit's depth (a handle's corner) mixes the face the
  // pad meets with the next one, deeper and steeper: the fit over all of it bends,
  // reads as round and extrapolates below the tilt of the face beside the edge.
  float near_face() const {
    float near = -1.f;
    LineSums acc = kNoSums;
    for (int k = 0; k < kNearFaceMaxBins; ++k) {
      const LineSums& b = bins[k];
      acc.sd += b.sd;
      acc.sdd += b.sdd;
      acc.sv += b.sv;
      acc.sdv += b.sdv;
      acc.cnt += b.cnt;
      acc.dmin = std::min(acc.dmin, b.dmin);
      acc.dmax = std::max(acc.dmax, b.dmax);
      if (k + 1 < kNearFaceMinBins || acc.cnt < kTiltFitMin || acc.dmax - acc.dmin < kNearFaceSpread) continue;
      const double m = static_cast<double>(acc.cnt);
      const double var = acc.sdd / m - (acc.sd / m) * (acc.sd / m);
      if (!(var > 1e-12)) continue;
      const double slope = (acc.sdv / m - (acc.sd / m) * (acc.sv / m)) / var;
      // Flat: its tilt changes by less than kFaceTurn over the prefix's depth.
      const double face = acc.sv / m;
      const double sin_face = std::sqrt(std::max(0.0, face * (2.0 - face)));
      if (std::fabs(slope) * static_cast<double>(acc.dmax - acc.dmin) >= kFaceTurn * sin_face) continue;
      // A crease behind it: the points deeper in (up to kTiltFitDepth) clearly steeper.
      const uint32_t rest = all.cnt - acc.cnt;
      if (rest < kCreaseMin) continue;
      const double deeper = (all.sv - acc.sv) / static_cast<double>(rest);
      if (std::acos(1.0 - std::min(1.0, deeper)) < std::acos(1.0 - std::min(1.0, face)) + kCreaseJump) continue;
      near = std::max(near, static_cast<float>(face));
    }
    return near;
  }

  // The line 1 - cos(tilt) = a + b d over every point: a (clamped to [0, 1]) in
  // one_minus_cos, flat when b changes it by less than kFlatChange over kTiltFitDepth;
  // valid false (one_minus_cos 1) with too few points or too little spread.
  void fit(float& one_minus_cos, bool& valid, bool& flat) const {
    valid = flat = false;
    one_minus_cos = 1.f;
    if (all.cnt < kTiltFitMin || all.dmax - all.dmin < kTiltFitSpread) return;
    const double m = static_cast<double>(all.cnt);
    const double var = all.sdd / m - (all.sd / m) * (all.sd / m);
    if (!(var > 1e-12)) return;
    const double b = (all.sdv / m - (all.sd / m) * (all.sv / m)) / var;
    const double a = all.sv / m - b * all.sd / m;
    one_minus_cos = static_cast<float>(std::min(1.0, std::max(0.0, a)));
    flat = b * static_cast<double>(kTiltFitDepth) < kFlatChange;
    valid = true;
  }
};
}  // namespace

// The tilt of each pad's contact normal from the closing line, extrapolated to the
// side's extreme (where the pad touches first): over the points within the pad's
// footprint up to kTiltFitDepth inside the side, with a defined normal not facing the
// approach, a least-squares line 1 - cos(tilt) = a + b d in their depth d inside the
// side. A round side (radius r) has 1 - cos(tilt) = d / r: a ~ 0, the pad meets it
// along the closing line; a flat face beside an edge keeps its tilt at every depth:
// a = 1 - cos(its tilt). The sensors seldom see the part of a round side nearest the
// extreme (the view grazes it there), which a count of the normals inside the cone
// read as a steep contact. valid[s] is false with fewer than kTiltFitMin points or
// less than kTiltFitSpread of depth between them. near_face[s] and edge_face[s] are the
// 1 - cos(tilt) of the face beside an edge found near the extreme (-1: none found).
void GraspChecks::contact_tilt(const Vec3& pos, const ViewFrame& f, float one_minus_cos[2], bool valid[2], bool flat[2],
                               float near_face[2], float edge_face[2]) {
  const GripperGeometry& g = cfg_.gripper;
  const uint32_t n = object_.size();
  float ext[2];  // the sides' extremes in the footprint (x)
  footprint_extremes(pos, f, ext);
  SideTiltSums sums[2];
  for (uint32_t i = 0; i < n && ext[1] >= ext[0]; ++i) {
    const Vec3 d = object_[i] - pos;
    const float x = f.X.dot(d), y = f.Y.dot(d), z = f.Z.dot(d);
    if (std::fabs(y) > 0.5f * g.finger_width_m || std::fabs(z) > 0.5f * g.finger_depth_m) continue;
    const float dl = x - ext[0], dr = ext[1] - x;
    int side = -1;
    float depth = 0.f;
    if (dl <= kTiltFitDepth && dl <= dr) {
      side = 0;
      depth = dl;
    } else if (dr <= kTiltFitDepth) {
      side = 1;
      depth = dr;
    }
    Vec3 nrm;
    if (side < 0 || !normal_at(i, nrm) || std::fabs(nrm.dot(f.Z)) > kFrontFacingCos) continue;
    const double v = 1.0 - std::fabs(static_cast<double>(nrm.dot(f.X)));
    sums[side].add(depth, v, normal_planar(i));
  }
  for (int s = 0; s < 2; ++s) {
    edge_face[s] = sums[s].edge_face();
    near_face[s] = sums[s].near_face();
    sums[s].fit(one_minus_cos[s], valid[s], flat[s]);
  }
}

// Contact normals inside the friction cone, per pad: the tilt extrapolated to the
// side's extreme (contact_tilt) within atan(mu) passes; a flat side whose tilt is
// outside fails (a face beside an edge the pad would touch); otherwise (no fit, or a
// curved side whose extrapolation is steep: on real captures the normals next to a
// silhouette's edge are bent by mixed pixels) at least a third of the pad's contact
// normals must have |n . closing| >= cos(atan(mu)). Corner and edge contacts fail;
// faces and rounded sides pass, noisy normals on small faces too.
bool GraspChecks::friction_ok(const Vec3& pos, const ViewFrame& f, float width) {
  ContactNormalStats st;
  contact_normal_stats(pos, f, width, st);
  // A pad on a part that stands less than two voxel rows above the band taken for the
  // table: a contact normal needs a 26-neighbourhood of side voxels, which such a side
  // does not have, so no normal there is evidence either way (the scissors' blades and
  // pivot, 10-20 mm high, held 27-31 deg outside the cone by their bevels). One such
  // pad is enough: the grasp holds only if both pads do. Tested before the tilt fit.
  const float verifiable = cfg_.object_min_height_m + 2.f * cfg_.voxel_leaf_m;
  if (support_.found && (st.top[0] < verifiable || st.top[1] < verifiable)) return false;
  // A pad whose band shows no contact normal, or at most two all off the cone, presses
  // a side no sensor saw. On a flat-sided body that side is the wall under its seen
  // outline's edge (plausible_wall), whose normal must lie within the cone: a closing
  // square to the unseen face of a box holds, one across its corner does not.
  const float cos_wall_cone = std::cos(std::atan(cfg_.friction_mu));
  for (int s = 0; s < 2; ++s) {
    if (!(st.total[s] == 0u || (st.total[s] <= 2u && st.inside_cone[s] == 0u))) continue;
    Vec3 wall;
    const Vec3 contact = pos + f.X * ((s == 0 ? -0.5f : 0.5f) * width);
    if (plausible_wall(contact, wall) && std::fabs(wall.dot(f.X)) < cos_wall_cone) return false;
  }
  const float tip = 0.5f * cfg_.gripper.finger_depth_m - kTipReach;
  // Both pads reach the target by their tips alone and show at most kTipOnlyNormals
  // contact normals between them: the pads overlap it by less than kTipReach and nothing
  // says they hold (a chord across the near side of a round body under a tilted
  // approach; a wide can's front, one stray normal on one pad).
  if (st.total[0] + st.total[1] <= kTipOnlyNormals && st.z_first[0] > tip && st.z_first[1] > tip) return false;
  const bool down = straight_down(f.Z);
  // Off straight down, a pad whose band shows no contact normal while the other pad's
  // show fewer than a third inside the cone: that pad's normals are the only evidence
  // there is, and they judge the grasp, not the tilt extrapolated to its extreme
  // (a closing across a wide box's top edge 25 deg off the top's normal, the lower pad
  // in the box's unseen side; standing bats held 29-64 deg outside the cone). Straight
  // down such a band is the wall under a top's rim, judged below.
  const auto third_inside = [&st](int s) { return 3 * st.inside_cone[s] >= st.total[s]; };
  for (int s = 0; s < 2 && !down; ++s)
    if (st.total[1 - s] == 0 && st.total[s] >= 2 && !third_inside(s)) return false;
  float omc[2];
  bool valid[2], flat[2];
  float near_face[2], edge_face[2];
  contact_tilt(pos, f, omc, valid, flat, near_face, edge_face);
  const float cos_cone = std::cos(std::atan(cfg_.friction_mu));
  const float cos_flat = std::cos(std::atan(cfg_.friction_mu) - kFlatMargin);
  // Straight down, a pad whose band holds the rim of a top (normals facing up) and at
  // most 2 contact normals, none in the cone, while the other pad shows at least 3, a
  // third of them inside: the sensors saw the top and the near wall, and this band
  // holds the rim's curve, not the unseen wall under it that the pad squeezes (a
  // bottle's cap). The other pad judges the grasp, as for a blind side straight down.
  const auto rim_only = [&st](int s) { return st.level[s] > 0 && st.total[s] <= 2 && st.inside_cone[s] == 0; };
  const auto holds = [&st, &third_inside](int s) { return st.total[s] >= 3 && third_inside(s); };
  for (int s = 0; s < 2; ++s) {
    if (down && rim_only(s) && holds(1 - s)) continue;
    // Every contact point within kTipReach of the fingertip, some of them on a face
    // parallel to the support plane (a top): the pad overlaps the side by less than
    // that, and its tip may land on the top beyond the edge it was to squeeze (a low
    // object under a tilted approach, the hand raised off the table; a thin one).
    if (st.z_first[s] > tip && st.level[s] > 0) return false;
    // The face nearest the contact, flat and off the cone: an edge contact, whatever
    // the fit over the deeper points says.
    if (near_face[s] > 1.f - cos_flat) return false;
    // An edge at the extreme whose better face is off the cone.
    if (edge_face[s] > 1.f - cos_flat) return false;
    if (valid[s] && flat[s]) {
      if (omc[s] > 1.f - cos_flat) return false;  // a flat face off the cone: an edge contact
      continue;
    }
    if (valid[s] && omc[s] <= 1.f - cos_cone) continue;  // in the cone at the extreme
    // A curved side fitted steep at the extreme that the pad's tip alone reaches: too
    // few contact normals to overrule the fit leave its verdict standing.
    if (valid[s] && st.total[s] < 3 && st.z_first[s] > tip) return false;
    if (st.total[s] >= 3 && !third_inside(s)) return false;
    // At least two contact normals on this pad, all off the cone, and nothing that
    // says otherwise: the other pad shows none (a tilted closing across a wide box's
    // top edge) or, off straight down, fewer than kVouchNormals, too few to vouch for
    // this one (a thin part's bevel). Straight down the other pad must show none: there
    // a small top's rim bends both pads' normals (a cap's).
    if (st.total[s] >= 2 && st.inside_cone[s] == 0 && st.total[1 - s] < (down ? 1u : kVouchNormals)) return false;
  }
  // Both pads on the target by less than kShallowLeaves voxels (deeper than their tips
  // alone, above) and the grasp's only contact normals, 1 or 2, off the cone with no
  // tilt fit inside it: what little evidence there is says the pads slip (a low part
  // closed across its bevelled edges).
  const float shallow = 0.5f * cfg_.gripper.finger_depth_m - kShallowLeaves * cfg_.voxel_leaf_m;
  const uint32_t normals = st.total[0] + st.total[1];
  const bool fit_inside = (valid[0] && omc[0] <= 1.f - cos_cone) || (valid[1] && omc[1] <= 1.f - cos_cone);
  if (st.z_first[0] > shallow && st.z_first[1] > shallow && normals > 0 && normals <= kTipOnlyNormals &&
      st.inside_cone[0] + st.inside_cone[1] == 0 && !fit_inside)
    return false;
  return true;
}

// ---- Margins of the returned grasp -------------------------------------------------

namespace {
// The largest growth g in [-deepest, cap] of a test's boxes for which clear(g) holds
// (the test is monotone in g), to within (cap + deepest) / 2^14: the clearance when
// positive, the penetration when negative; the bound when it lies beyond. `deepest`
// keeps the shrunk boxes from turning inside out.
template <class Clear>
float largest_clear_growth(const Clear& clear, float deepest, float cap) {
  if (clear(cap)) return cap;
  if (!clear(-deepest)) return -deepest;
  float lo = -deepest, hi = cap;
  for (int i = 0; i < 14; ++i) {
    const float mid = 0.5f * (lo + hi);
    if (clear(mid))
      lo = mid;
    else
      hi = mid;
  }
  return lo;
}

// Signed distance from (x, y, z) to box b shrunk by tol on every side: positive
// outside, minus the depth inside.
float box_distance(const FrameBox& b, float tol, float x, float y, float z) {
  const float dx = std::max(b.x0 + tol - x, x - (b.x1 - tol));
  const float dy = std::max(b.y0 + tol - y, y - (b.y1 - tol));
  const float dz = std::max(b.z0 + tol - z, z - (b.z1 - tol));
  if (dx <= 0.f && dy <= 0.f && dz <= 0.f) return std::max(dx, std::max(dy, dz));
  const float ox = std::max(dx, 0.f), oy = std::max(dy, 0.f), oz = std::max(dz, 0.f);
  return std::sqrt(ox * ox + oy * oy + oz * oz);
}

constexpr double kRadToDegD = 57.29577951308232;
// Without a fit, a pad's contact tilt is this quantile of its contact normals' tilts
// (friction_margin_deg).
constexpr float kContactTiltQuantile = 0.25f;
}  // namespace

// The nearest voxel of the scene (the plane's aside) to the swept fingers and palm. The
// near list holds every voxel within its radius r of its centre; one outside it lies
// more than r - |position - centre| - reach from any box, which bounds the answer.
float GraspChecks::swept_clearance(const Candidate& c) const {
  Box boxes[3];
  gripper_boxes(cfg_, boxes);
  const float tol = cfg_.collision_tolerance_m;
  const Vec3* centroids = grid_.centroids();
  float best = std::numeric_limits<float>::infinity();
  const auto visit = [&](uint32_t i) {
    if (state_[i] == kVoxelRemoved) return;
    const Vec3 d = centroids[i] - c.position;
    const float x = c.X.dot(d), y = c.Y.dot(d), z = c.Z.dot(d);
    for (const Box& b : boxes) best = std::min(best, box_distance(b, tol, x, y, z));
  };
  const float off_centre = (c.position - near_centre_).norm();
  if (near_ != nullptr && off_centre <= near_slack_) {
    const uint32_t index_mask = (1u << kNearIndexBits) - 1u;
    for (uint32_t k = 0; k < n_near_; ++k) visit(near_[k] & index_mask);
    best = std::min(best, near_radius_ - off_centre - near_reach_);
  } else {
    for (uint32_t i = 0; i < grid_.size(); ++i) visit(i);
  }
  return best;
}

// Degrees between atan(mu) and the steeper pad's contact tilt. A pad's contact tilt is
// the evidence friction_ok judges by (contact_tilt): the tilt fitted at the side's
// extreme, raised to that of a flat face found next to the contact or beside an edge
// there (a pad on an edge holds by the faces beside it). Without any of them, the
// kContactTiltQuantile-th smallest tilt of the planar contact normals in the pad's
// band (those of surfaces facing the approach aside, which the pad slides along). A
// grasp on a round body's unseen tangents closes square to them by its model. NaN when
// no pad shows a normal.
float GraspChecks::friction_margin_deg(const Candidate& c) {
  // In double, rounded once to float: the same report on every target's libm.
  const double cone = std::atan(static_cast<double>(cfg_.friction_mu));
  if (c.tangent_contacts) return static_cast<float>(cone * kRadToDegD);
  const GripperGeometry& g = cfg_.gripper;
  const ViewFrame f = c.frame();
  float omc[2], near_face[2], edge_face[2];
  bool valid[2], flat[2];
  contact_tilt(c.position, f, omc, valid, flat, near_face, edge_face);
  ContactNormalStats st;
  contact_normal_stats(c.position, f, c.width, st);
  const float half = 0.5f * c.width;
  double steepest = -1.0;
  for (int side = 0; side < 2; ++side) {
    // A pad on a side no sensor saw: the plausible body's wall there (friction_ok).
    Vec3 wall;
    if (st.total[side] == 0u && plausible_wall(c.position + f.X * ((side == 0 ? -1.f : 1.f) * half), wall)) {
      steepest = std::max(steepest, std::acos(std::min(1.0, static_cast<double>(std::fabs(wall.dot(f.X))))));
      continue;
    }
    const float evidence = std::max(valid[side] ? omc[side] : -1.f, std::max(near_face[side], edge_face[side]));
    if (evidence >= 0.f) {
      steepest = std::max(steepest, std::acos(1.0 - std::min(1.0, static_cast<double>(evidence))));
      continue;
    }
    // The tilts go to the x of the scratch points (idle between the checks' calls).
    uint32_t m = 0;
    for (uint32_t i = 0; i < object_.size(); ++i) {
      const Vec3 d = object_[i] - c.position;
      const float x = f.X.dot(d), y = f.Y.dot(d), z = f.Z.dot(d);
      if (std::fabs(y) > 0.5f * g.finger_width_m || std::fabs(z) > 0.5f * g.finger_depth_m) continue;
      if (side == 0 ? x > -half + cfg_.contact_band_m : x < half - cfg_.contact_band_m) continue;
      Vec3 nrm;
      if (!normal_at(i, nrm) || !normal_planar(i) || std::fabs(nrm.dot(f.Z)) > kFrontFacingCos) continue;
      local_[m++].x() = std::fabs(nrm.dot(f.X));  // the cosine: the steeper, the smaller
    }
    if (m == 0) continue;
    // The quantile-th smallest tilt: the quantile-th largest cosine.
    const uint32_t q = static_cast<uint32_t>(kContactTiltQuantile * static_cast<float>(m - 1));
    std::nth_element(local_, local_ + q, local_ + m, [](const Vec3& a, const Vec3& b) { return a.x() > b.x(); });
    steepest = std::max(steepest, std::acos(std::min(1.0, static_cast<double>(local_[q].x()))));
  }
  if (!(steepest >= 0.0)) return std::numeric_limits<float>::quiet_NaN();
  return static_cast<float>((cone - steepest) * kRadToDegD);
}

void GraspChecks::margins(const Candidate& c, CheckMargins& out) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (float& v : out.value) v = nan;
  const ViewFrame f = c.frame();
  Box boxes[3];
  gripper_boxes(cfg_, boxes);
  float lowest = std::numeric_limits<float>::infinity();
  for (const Box& b : boxes)
    for (int k = 0; k < 8; ++k) {
      const Vec3 p =
          c.position + f.X * ((k & 1) ? b.x1 : b.x0) + f.Y * ((k & 2) ? b.y1 : b.y0) + f.Z * ((k & 4) ? b.z1 : b.z0);
      lowest = std::min(lowest, support_.plane.height(p));
    }
  out.value[static_cast<uint32_t>(CheckId::support_plane)] = lowest - cfg_.table_clearance_m;
  out.value[static_cast<uint32_t>(CheckId::swept_collision)] = swept_clearance(c);
  // The fingers' boxes shrink by at most 90% of their half thinnest side.
  const GripperGeometry& g = cfg_.gripper;
  const float half_thinnest = 0.5f * std::min(g.finger_thickness_m, std::min(g.finger_width_m, g.finger_depth_m));
  const float tol = cfg_.collision_tolerance_m, half_leaf = 0.5f * cfg_.voxel_leaf_m;
  out.value[static_cast<uint32_t>(CheckId::local_hull)] =
      largest_clear_growth([&](float grow) { return fingers_clear_of_hull(c.position, f, grow); },
                           std::max(0.f, 0.9f * half_thinnest - tol), kHullNeighbourhood);
  if (footprint_applies(f, c.width))
    out.value[static_cast<uint32_t>(CheckId::under_target)] =
        largest_clear_growth([&](float grow) { return fingers_clear_of_footprint(c.position, f, c.width, grow); },
                             std::max(0.f, 0.9f * half_thinnest - half_leaf), cfg_.voxel_leaf_m);
  uint32_t hidden_sides = 0;
  float hidden_share = 0.f;
  (void)fingers_in_seen_space(c.position, f, c.width, hidden_sides, &hidden_share);
  out.value[static_cast<uint32_t>(CheckId::unknown_space)] = kMaxHiddenShare - hidden_share;
  if (cfg_.friction_mu > 0.f) out.value[static_cast<uint32_t>(CheckId::friction_cone)] = friction_margin_deg(c);
}

}  // namespace fg
