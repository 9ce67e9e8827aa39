// Stage F, a candidate repaired: a round body whose flanks the sensor saw only up to a grazing angle
// (docs/method.md, check 5's round flanks). A depth sensor drops the pixels where its
// rays graze a surface, so across its own line of sight a can or a bottle shows its
// flanks only up to about 45-55 deg from the view: the last points seen on each side
// face the sensor, the true tangents lie some millimetres beyond them, unseen, and the
// contact normals of the seen band say "outside the friction cone" for a grasp whose
// pads would close on those tangents, square to the closing line. The search then
// settled on a viewpoint where one side was a real edge and the other was where the
// view ended, and reported a width 1-2 cm short (README, one camera).
//
// The model: in the candidate's closing-approach plane (X, Z) a circle whose centre
// lies behind both seen edges along their inward normals, c = p_s - r n_s. Both
// equations give r by least squares; the two centres they give must agree. The circle
// itself is then fitted to the seen arc's points (Kasa's least squares), whose rms
// distance from it must stay small (a rounded box's flat front fails). Then the
// pads close on the tangents c.x -/+ r, along -/+X: a grasp of width 2r centred on
// c.x, moved along the approach as far as the tangents need and the depth rule allows
// (the palm stops palm_clearance before the first surface). Tangents still past the
// fingertips are met before them, at the tips, where the flank's tilt must stay well
// inside the friction cone and the width is the chord there. Only when the space just
// beyond each seen edge, out to its tangent, was not seen empty by any sensor.
#include <cmath>

#include "../circle_fit.hpp"
#include "fg/core/pipeline/grasp_checks.hpp"

namespace fg {
namespace {
// The seen edge of a side: the points with a normal within this depth of its extreme.
constexpr float kEdgeBand = 0.003f;
constexpr uint32_t kEdgeMinPoints = 2;
// The edges' normals must face the approach by this much at least (a side square to
// the closing line needs no model) and at most (past 65 deg the edge is a top's rim).
constexpr float kMinFacing = 0.26f;  // sin 15 deg
constexpr float kMaxFacing = 0.91f;  // sin 65 deg
// The two centres the edges give agree within this distance, and the seen points in
// the pads' footprint lie on the circle within this rms distance (voxel centroids,
// sensor noise; a flat front between rounded edges bends off it by its sagitta).
constexpr float kCentreAgree = 0.004f;
constexpr double kArcRms = 0.002;
// Moved deeper, the palm keeps this much more than palm_clearance from the first
// surface seen: the model's centre is the seen arc's, the unseen body is wider there.
constexpr float kShiftPalmMargin = 0.003f;
// The tangents lie at most this far beyond the seen edges: a grazing dropout hides a
// few millimetres of flank, not a body's half.
constexpr float kMaxBeyond = 0.012f;
// The pads' contact stays this far inside their reach along the approach.
constexpr float kReachMargin = 0.003f;
// Where the tangents lie past the fingertips, the tips meet the flank before them, its
// normal tilted off the closing line: at most this far inside the friction cone's edge.
constexpr float kTipTiltMargin = 0.17f;  // 10 deg
}  // namespace

namespace {
// The candidate's frame (unit axes) and the gripper's half sizes, as the model's steps
// use them.
struct RoundFrame {
  Vec3 pos, X, Y, Z;
  const GripperGeometry& g;
  float half_fd, half_palm, half_outer;
};

// Each side's seen edge in (x, z): its mean point and its unit outward normal.
struct SeenEdges {
  float px[2], pz[2];
  float ux[2], uz[2];
};

// Each side's seen edge (the points with a normal within kEdgeBand of the footprint's
// extremes ext): mean point and mean normal in (x, z), outward, facing the approach
// within the model's range. normal_at(i, n) is the checks' normal of object point i.
// False when a side has too few such points or its normal is out of range.
template <class NormalAt>
bool seen_edges(const PointSpan& object, const RoundFrame& fr, const float ext[2], NormalAt&& normal_at, SeenEdges& e) {
  float px[2] = {0, 0}, pz[2] = {0, 0}, nx[2] = {0, 0}, nz[2] = {0, 0};
  uint32_t cnt[2] = {0, 0};
  for (uint32_t i = 0; i < object.size(); ++i) {
    const Vec3 d = object[i] - fr.pos;
    const float y = fr.Y.dot(d), z = fr.Z.dot(d);
    if (std::fabs(y) > 0.5f * fr.g.finger_width_m || std::fabs(z) > 0.5f * fr.g.finger_depth_m) continue;
    const float x = fr.X.dot(d);
    const int side = x - ext[0] <= kEdgeBand ? 0 : ext[1] - x <= kEdgeBand ? 1 : -1;
    Vec3 nrm;
    if (side < 0 || !normal_at(i, nrm)) continue;
    // Outward: away from the other side.
    float ax = nrm.dot(fr.X), az = nrm.dot(fr.Z);
    if ((side == 0) != (ax < 0.f)) ax = -ax, az = -az;
    px[side] += x;
    pz[side] += z;
    nx[side] += ax;
    nz[side] += az;
    ++cnt[side];
  }
  for (int s = 0; s < 2; ++s) {
    if (cnt[s] < kEdgeMinPoints) return false;
    const float inv = 1.f / static_cast<float>(cnt[s]);
    e.px[s] = px[s] * inv;
    e.pz[s] = pz[s] * inv;
    const float len = std::sqrt(nx[s] * nx[s] + nz[s] * nz[s]);
    if (!(len > 1e-6f)) return false;
    e.ux[s] = nx[s] / len;
    e.uz[s] = nz[s] / len;
    // Facing the approach (its origin lies at -Z): the flank turns towards the sensor
    // beyond this edge, and only within the range the model is for.
    if (-e.uz[s] < kMinFacing || -e.uz[s] > kMaxFacing) return false;
    if ((s == 0) != (e.ux[s] < 0.f)) return false;
  }
  return true;
}

// The centre (cx, cz) behind both seen edges along their inward normals; false when
// the two centres the edges give do not agree.
bool centre_behind_edges(const SeenEdges& e, float& cx, float& cz) {
  // p_0 - r u_0 = p_1 - r u_1  =>  r (u_1 - u_0) = p_1 - p_0, by least squares.
  const float dux = e.ux[1] - e.ux[0], duz = e.uz[1] - e.uz[0];
  const float dpx = e.px[1] - e.px[0], dpz = e.pz[1] - e.pz[0];
  const float den = dux * dux + duz * duz;
  if (!(den > 1e-6f)) return false;
  const float r = (dpx * dux + dpz * duz) / den;
  if (!(r > 0.f)) return false;
  const float c0x = e.px[0] - r * e.ux[0], c0z = e.pz[0] - r * e.uz[0];
  const float c1x = e.px[1] - r * e.ux[1], c1z = e.pz[1] - r * e.uz[1];
  if (std::hypot(c0x - c1x, c0z - c1z) > kCentreAgree) return false;
  cx = 0.5f * (c0x + c1x);
  cz = 0.5f * (c0z + c1z);
  return true;
}

// The circle through the seen arc itself (circle_fit.hpp), over the points in the
// pads' footprint, about the centre the normals gave (cx, cz, moved to the circle's
// centre; r its radius). The normals only say that one centre lies behind both edges:
// at an edge the neighbourhood is one-sided, which turns them towards the sensor and
// read the radius 6-8% long (constructed cans of test_grazed_round: 60, 70, 78 mm read
// 65, 73, 85).
bool fit_seen_arc(const PointSpan& object, const RoundFrame& fr, float& cx, float& cz, float& r) {
  CircleFit fit;
  for (uint32_t i = 0; i < object.size(); ++i) {
    const Vec3 d = object[i] - fr.pos;
    const float z = fr.Z.dot(d);
    if (std::fabs(fr.Y.dot(d)) > 0.5f * fr.g.finger_width_m || std::fabs(z) > fr.half_fd) continue;
    fit.add(fr.X.dot(d) - cx, z - cz);
  }
  double dx, dz, rr;
  if (!fit.solve(dx, dz, rr)) return false;
  cx += static_cast<float>(dx);
  cz += static_cast<float>(dz);
  r = static_cast<float>(std::sqrt(rr));
  return true;
}

// The whole seen arc between the edges lies on that circle (a rounded box's flat
// front does not); and the first surface ahead of the palm centred on the circle
// (z_first_palm).
bool arc_on_circle(const PointSpan& object, const RoundFrame& fr, float cx, float cz, float r, float& z_first_palm) {
  double sq = 0.0;
  uint32_t n_arc = 0;
  z_first_palm = 1e9f;
  for (uint32_t i = 0; i < object.size(); ++i) {
    const Vec3 d = object[i] - fr.pos;
    const float x = fr.X.dot(d), y = fr.Y.dot(d), z = fr.Z.dot(d);
    if (std::fabs(y) <= fr.half_palm && std::fabs(x - cx) <= fr.half_outer) z_first_palm = std::min(z_first_palm, z);
    if (std::fabs(y) > 0.5f * fr.g.finger_width_m || std::fabs(z) > fr.half_fd) continue;
    const double e = std::hypot(x - cx, z - cz) - r;
    sq += e * e;
    ++n_arc;
  }
  return !(n_arc < 2 * kEdgeMinPoints || std::sqrt(sq / n_arc) > kArcRms);
}

// No sensor saw through the flank the model adds: between each seen edge (ext) and its
// tangent (left, right), at the tangent's depth cz, nothing is seen empty.
// visibility(q) is the checks' (+1 seen free).
template <class Visibility>
bool flanks_unseen(const RoundFrame& fr, const float ext[2], float left, float right, float cz,
                   Visibility&& visibility) {
  for (int s = 0; s < 2; ++s) {
    const float from = s == 0 ? ext[0] : ext[1], to = s == 0 ? left : right;
    for (int k = 1; k <= 4; ++k) {
      const float x = from + (to - from) * (0.25f * static_cast<float>(k));
      for (int iy = -1; iy <= 1; ++iy) {
        const Vec3 q = fr.pos + fr.X * x + fr.Y * (0.25f * fr.g.finger_width_m * static_cast<float>(iy)) + fr.Z * cz;
        if (visibility(q) > 0) return false;
      }
    }
  }
  return true;
}
}  // namespace

bool GraspChecks::grazed_round_body(const Candidate& c, Candidate& round) {
  if (!cfg_.round_flanks) return false;
  const GripperGeometry& g = cfg_.gripper;
  const RoundFrame fr{c.position,
                      c.X.normalized(),
                      c.Y.normalized(),
                      c.Z.normalized(),
                      g,
                      0.5f * g.finger_depth_m,
                      0.5f * std::max(g.palm_width_m, g.finger_width_m),
                      0.5f * g.max_opening_m + g.finger_thickness_m};
  const float half_fd = fr.half_fd;
  float ext[2];
  footprint_extremes(c.position, ViewFrame{fr.X, fr.Y, fr.Z}, ext);
  if (!(ext[1] > ext[0])) return false;
  SeenEdges edges;
  const auto normal = [this](uint32_t i, Vec3& nrm) { return normal_at(i, nrm); };
  if (!seen_edges(object_, fr, ext, normal, edges)) return false;
  float cx = 0.f, cz = 0.f, r = 0.f;
  if (!centre_behind_edges(edges, cx, cz) || !fit_seen_arc(object_, fr, cx, cz, r)) return false;
  float z_first_palm = 1e9f;
  if (!arc_on_circle(object_, fr, cx, cz, r, z_first_palm)) return false;
  // The tangents, beyond the seen edges by at most kMaxBeyond, within the opening and
  // within the pads' reach along the approach.
  const float left = cx - r, right = cx + r;
  if (left > ext[0] || right < ext[1]) return false;
  if (ext[0] - left > kMaxBeyond || right - ext[1] > kMaxBeyond) return false;
  // The opening clears the circle by width_margin, as every other grasp's width.
  if (2.f * r > g.max_opening_m - cfg_.width_margin_m || 2.f * r < g.min_opening_m) return false;
  // Deeper along the approach when the tangents lie past the fingertips' reach, as far
  // as the depth rule lets the palm go; the support plane's bound is the checks'
  // (first_failed_check tests every corner).
  const float reach = half_fd - kReachMargin;
  const float shift =
      std::max(0.f, std::min(cz - reach, z_first_palm + half_fd - cfg_.palm_clearance_m - kShiftPalmMargin));
  if (cz - shift < -reach) return false;
  const float past_tips = std::max(0.f, cz - shift - reach);
  const float max_tilt = std::atan(cfg_.friction_mu) - kTipTiltMargin;
  if (!(max_tilt > 0.f) || past_tips > r * std::sin(max_tilt)) return false;
  const float width = 2.f * std::sqrt(r * r - past_tips * past_tips);
  if (width < ext[1] - ext[0]) return false;
  const auto seen = [this](const Vec3& q) { return visibility(q); };
  if (!flanks_unseen(fr, ext, left, right, cz, seen)) return false;
  round = c;
  round.position = c.position + fr.X * cx + fr.Z * shift;
  round.width = width;
  round.tangent_contacts = true;
  return true;
}

}  // namespace fg
