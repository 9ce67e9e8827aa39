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

bool GraspChecks::grazed_round_body(const Candidate& c, Candidate& round) {
  if (!cfg_.round_flanks) return false;
  const GripperGeometry& g = cfg_.gripper;
  const Vec3 X = c.X.normalized(), Y = c.Y.normalized(), Z = c.Z.normalized();
  const uint32_t n = object_.size();
  const float half_fd = 0.5f * g.finger_depth_m;
  const float half_palm = 0.5f * std::max(g.palm_width_m, g.finger_width_m);
  const float half_outer = 0.5f * g.max_opening_m + g.finger_thickness_m;
  float ext[2];
  footprint_extremes(c.position, ViewFrame{X, Y, Z}, ext);
  if (!(ext[1] > ext[0])) return false;
  // Each side's seen edge: mean point and mean normal in (x, z).
  float px[2] = {0, 0}, pz[2] = {0, 0}, nx[2] = {0, 0}, nz[2] = {0, 0};
  uint32_t cnt[2] = {0, 0};
  for (uint32_t i = 0; i < n; ++i) {
    const Vec3 d = object_[i] - c.position;
    const float y = Y.dot(d), z = Z.dot(d);
    if (std::fabs(y) > 0.5f * g.finger_width_m || std::fabs(z) > 0.5f * g.finger_depth_m) continue;
    const float x = X.dot(d);
    const int side = x - ext[0] <= kEdgeBand ? 0 : ext[1] - x <= kEdgeBand ? 1 : -1;
    Vec3 nrm;
    if (side < 0 || !normal_at(i, nrm)) continue;
    // Outward: away from the other side.
    float ax = nrm.dot(X), az = nrm.dot(Z);
    if ((side == 0) != (ax < 0.f)) ax = -ax, az = -az;
    px[side] += x;
    pz[side] += z;
    nx[side] += ax;
    nz[side] += az;
    ++cnt[side];
  }
  float ux[2], uz[2];
  for (int s = 0; s < 2; ++s) {
    if (cnt[s] < kEdgeMinPoints) return false;
    const float inv = 1.f / static_cast<float>(cnt[s]);
    px[s] *= inv;
    pz[s] *= inv;
    const float len = std::sqrt(nx[s] * nx[s] + nz[s] * nz[s]);
    if (!(len > 1e-6f)) return false;
    ux[s] = nx[s] / len;
    uz[s] = nz[s] / len;
    // Facing the approach (its origin lies at -Z): the flank turns towards the sensor
    // beyond this edge, and only within the range the model is for.
    if (-uz[s] < kMinFacing || -uz[s] > kMaxFacing) return false;
    if ((s == 0) != (ux[s] < 0.f)) return false;
  }
  // p_0 - r u_0 = p_1 - r u_1  =>  r (u_1 - u_0) = p_1 - p_0, by least squares.
  const float dux = ux[1] - ux[0], duz = uz[1] - uz[0];
  const float dpx = px[1] - px[0], dpz = pz[1] - pz[0];
  const float den = dux * dux + duz * duz;
  if (!(den > 1e-6f)) return false;
  float r = (dpx * dux + dpz * duz) / den;
  if (!(r > 0.f)) return false;
  const float c0x = px[0] - r * ux[0], c0z = pz[0] - r * uz[0];
  const float c1x = px[1] - r * ux[1], c1z = pz[1] - r * uz[1];
  if (std::hypot(c0x - c1x, c0z - c1z) > kCentreAgree) return false;
  float cx = 0.5f * (c0x + c1x), cz = 0.5f * (c0z + c1z);
  // The circle through the seen arc itself (circle_fit.hpp), over the points in the
  // pads' footprint, about the centre the normals gave. The normals only say that one
  // centre lies behind both edges: at an edge the neighbourhood is one-sided, which
  // turns them towards the sensor and read the radius 6-8% long (constructed cans of
  // test_grazed_round: 60, 70, 78 mm read 65, 73, 85).
  {
    CircleFit fit;
    for (uint32_t i = 0; i < n; ++i) {
      const Vec3 d = object_[i] - c.position;
      const float z = Z.dot(d);
      if (std::fabs(Y.dot(d)) > 0.5f * g.finger_width_m || std::fabs(z) > half_fd) continue;
      fit.add(X.dot(d) - cx, z - cz);
    }
    double dx, dz, rr;
    if (!fit.solve(dx, dz, rr)) return false;
    cx += static_cast<float>(dx);
    cz += static_cast<float>(dz);
    r = static_cast<float>(std::sqrt(rr));
  }
  // The whole seen arc between the edges lies on that circle (a rounded box's flat
  // front does not); and the first surface ahead of the palm centred on the circle.
  double sq = 0.0;
  uint32_t n_arc = 0;
  float z_first_palm = 1e9f;
  for (uint32_t i = 0; i < n; ++i) {
    const Vec3 d = object_[i] - c.position;
    const float x = X.dot(d), y = Y.dot(d), z = Z.dot(d);
    if (std::fabs(y) <= half_palm && std::fabs(x - cx) <= half_outer) z_first_palm = std::min(z_first_palm, z);
    if (std::fabs(y) > 0.5f * g.finger_width_m || std::fabs(z) > half_fd) continue;
    const double e = std::hypot(x - cx, z - cz) - r;
    sq += e * e;
    ++n_arc;
  }
  if (n_arc < 2 * kEdgeMinPoints || std::sqrt(sq / n_arc) > kArcRms) return false;
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
  // No sensor saw through the flank the model adds: between each seen edge and its
  // tangent, at the tangent's depth, nothing is seen empty.
  for (int s = 0; s < 2; ++s) {
    const float from = s == 0 ? ext[0] : ext[1], to = s == 0 ? left : right;
    for (int k = 1; k <= 4; ++k) {
      const float x = from + (to - from) * (0.25f * static_cast<float>(k));
      for (int iy = -1; iy <= 1; ++iy) {
        const Vec3 q = c.position + X * x + Y * (0.25f * g.finger_width_m * static_cast<float>(iy)) + Z * cz;
        if (visibility(q) > 0) return false;
      }
    }
  }
  round = c;
  round.position = c.position + X * cx + Z * shift;
  round.width = width;
  round.tangent_contacts = true;
  return true;
}

}  // namespace fg
