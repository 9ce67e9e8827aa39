// Stages D and E: candidates (candidates.hpp).
#include "fg/core/pipeline/candidates.hpp"

#include <algorithm>
#include <cmath>

#include "fg/core/projection.hpp"

namespace fg {
namespace {
// A surface beside a pad standing out this far past its contact is met by the pad's
// corner first (xoz_candidate).
constexpr float kCornerStandOut = 0.002f;

//! A window's place in the view and the gripper's half sizes, as the XOZ steps use them.
struct XozPads {
  float xc, yc;      // the window's centre (projection)
  float half_pad;    // half the finger width
  float half_palm;   // half the palm's (or finger's, if wider) width
  float half_outer;  // half the open gripper's outer width
  float half_fd;     // half the finger depth
  float band;        // half the pad's footprint grown by half a voxel
};

XozPads xoz_pads(const PlannerConfig& cfg, const SideFit& w) {
  const GripperGeometry& g = cfg.gripper;
  XozPads p{};
  p.yc = w.y_centre;
  p.half_pad = 0.5f * g.finger_width_m;
  p.half_palm = 0.5f * std::max(g.palm_width_m, g.finger_width_m);
  p.half_outer = 0.5f * g.max_opening_m + g.finger_thickness_m;
  p.half_fd = 0.5f * g.finger_depth_m;
  p.xc = w.x_centre;
  p.band = p.half_pad + 0.5f * cfg.voxel_leaf_m;
  return p;
}

//! The grasp's depth from the contact regions of the fitted sides (paper eq. 7) and
//! the first surface ahead of the palm; false when a side has no contact. The later
//! passes look only at points within `slab` of the window's centre line: they are
//! listed in work.slab (n_near of them) in index order, so those passes sum the same
//! terms in the same order as passes over every point.
[[nodiscard]] bool contact_depth(const PlannerConfig& cfg, uint32_t n, const SideFit& w, const XozPads& p,
                                 ViewWork& work, uint32_t& n_near, float& pos_z) {
  double zl = 0, zr = 0;
  uint32_t nl = 0, nr = 0;
  float z_first_palm = 1e9f;
  const float slab = std::max(p.half_pad, p.band);
  uint32_t* const near = work.slab;
  n_near = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const float x = work.proj[i].x, y = work.proj[i].y - p.yc, z = work.depth[i];
    near[n_near] = i;
    n_near += std::fabs(y) <= slab ? 1u : 0u;
    if (std::fabs(y) <= p.half_palm && std::fabs(x - p.xc) <= p.half_outer) z_first_palm = std::min(z_first_palm, z);
    if (std::fabs(y) > p.half_pad) continue;
    const float yy = work.proj[i].y;
    if (x <= w.a_left * yy + w.b_left + cfg.contact_band_m) {
      zl += z;
      ++nl;
    }
    if (x >= w.a_right * yy + w.b_right - cfg.contact_band_m) {
      zr += z;
      ++nr;
    }
  }
  if (nl == 0 || nr == 0) return false;
  pos_z = static_cast<float>(0.5 * (zl / nl + zr / nr));
  if (!cfg.paper_depth) pos_z = std::min(pos_z, z_first_palm + p.half_fd - cfg.palm_clearance_m);
  return true;
}

//! The support plane bounds the depth: every corner of the open fingers and the palm
//! must stay table_clearance above it. Height is linear in pos_z. pos_z is lowered to
//! the bound; false when no depth clears the plane.
[[nodiscard]] bool plane_bounds_depth(const CandidateContext& ctx, const ViewFrame& f, const XozPads& p, float& pos_z) {
  const PlannerConfig& cfg = ctx.cfg;
  const Plane& plane = ctx.support.plane;
  const Vec3 o = ctx.centroid + f.X * p.xc + f.Y * p.yc;
  const float h_o = plane.height(o);
  const float nx = plane.n.dot(f.X), ny = plane.n.dot(f.Y), nz = plane.n.dot(f.Z);
  float lo = -1e9f, hi = 1e9f;
  const float xs[2] = {-p.half_outer, p.half_outer};
  const float ys[2] = {-p.half_palm, p.half_palm};
  const float zs[2] = {-p.half_fd - cfg.gripper.palm_depth_m, p.half_fd};  // relative to pos_z
  for (float xx : xs)
    for (float yy : ys)
      for (float zz : zs) {
        const float h0 = h_o + nx * xx + ny * yy + nz * zz - cfg.table_clearance_m;
        // need h0 + nz * pos_z >= 0
        if (nz < -1e-6f)
          hi = std::min(hi, h0 / -nz);
        else if (nz > 1e-6f)
          lo = std::max(lo, -h0 / nz);
        else if (h0 < 0.f)
          return false;
      }
  pos_z = std::min(pos_z, hi);
  return !(pos_z < lo);
}

//! The contacts within the pads' reach at depth pos_z: their least and greatest x
//! (xmax < xmin when there is none).
void reach_extent(const ViewWork& work, uint32_t n_near, const XozPads& p, float pos_z, float& xmin, float& xmax) {
  const uint32_t* const near = work.slab;
  xmin = 1e9f;
  xmax = -1e9f;
  for (uint32_t q = 0; q < n_near; ++q) {
    const uint32_t i = near[q];
    if (std::fabs(work.proj[i].y - p.yc) > p.half_pad || std::fabs(work.depth[i] - pos_z) > p.half_fd) continue;
    xmin = std::min(xmin, work.proj[i].x);
    xmax = std::max(xmax, work.proj[i].x);
  }
}

//! The contact regions at depth pos_z, and the pads' edges: c.corners_clear and c.dz.
//! A surface just beyond a pad's footprint that stands out past the contact meets the
//! pad's corner first (a lying bat's blade beside its handle; past the fingertips, a
//! bottle's shoulder under its cap). Its voxels' centroids lie up to half a voxel beyond
//! the footprint. Such a grasp waits for the second pass (rank_and_check): on real
//! captures a mixed pixel at the silhouette's edge stands out as far (2-7 mm), and may
//! be all a can shows.
//!
//! dZ (paper eq. 8) weighs each contact by how far inside the pads' reach it lies:
//! 1 from one voxel leaf inside either end of the reach, falling linearly to 0 at the
//! end. Voxel centroids come in rows one leaf apart, so a hard cut at the reach's ends
//! takes a row in on one side and out on the other under a sub-millimetre shift and
//! dZ jumps by up to a leaf; with the ramp a row fades in and dZ moves continuously.
//! The plain means stand in when a side has all its contacts at the ends.
void contact_dz(const PlannerConfig& cfg, const ViewWork& work, uint32_t n_near, const XozPads& p, float pos_z,
                float xmin, float xmax, Candidate& c) {
  const uint32_t* const near = work.slab;
  const float half_fd = p.half_fd;
  double zl = 0, zr = 0;
  uint32_t nl = 0, nr = 0;
  double wl = 0, wr = 0, wzl = 0, wzr = 0;
  const float inv_ramp = 1.f / cfg.voxel_leaf_m;
  c.corners_clear = true;
  const float tip_band = half_fd + 0.5f * cfg.voxel_leaf_m;
  for (uint32_t q = 0; q < n_near; ++q) {
    const uint32_t i = near[q];
    const float dy = std::fabs(work.proj[i].y - p.yc);
    const float dd = work.depth[i] - pos_z;
    if (dy > p.band || dd < -half_fd || dd > tip_band) continue;
    if (dy > p.half_pad || dd > half_fd) {
      const float x = work.proj[i].x;
      if (x < xmin - kCornerStandOut || x > xmax + kCornerStandOut) c.corners_clear = false;
      continue;
    }
    const float z = work.depth[i];
    const float wgt = std::min(1.f, (half_fd - std::fabs(dd)) * inv_ramp);
    if (work.proj[i].x <= xmin + cfg.contact_band_m) {
      zl += z;
      ++nl;
      wl += wgt;
      wzl += static_cast<double>(wgt) * z;
    }
    if (work.proj[i].x >= xmax - cfg.contact_band_m) {
      zr += z;
      ++nr;
      wr += wgt;
      wzr += static_cast<double>(wgt) * z;
    }
  }
  constexpr double kMinWeight = 1e-3;
  const double ml = wl > kMinWeight ? wzl / wl : zl / nl, mr = wr > kMinWeight ? wzr / wr : zr / nr;
  c.dz = static_cast<float>(std::fabs(ml - mr));
}
}  // namespace

void project_depth(const CandidateContext& ctx, const ViewFrame& f, ViewWork& work) {
  const uint32_t n = ctx.object.size();
  for (uint32_t i = 0; i < n; ++i) work.depth[i] = f.Z.dot(ctx.object[i] - ctx.centroid);
}

Status trace_silhouette(const CandidateContext& ctx, const ViewFrame& f, ViewWork& work, uint32_t max_windows,
                        Silhouette& out) {
  const PlannerConfig& cfg = ctx.cfg;
  out.n_contour = out.n_lines = out.n_windows = 0;
  ConcaveHullParams hp;
  project_to_view(ctx.object.data(), ctx.object.size(), ctx.centroid, f.X, f.Y, work.proj, hp);
  hp.cell_m = cfg.hull_cell_m;
  hp.closing_cells = cfg.hull_closing_cells;
  float cell = 0.f;
  bool inside = false;
  const Status s = concave_hull_2d(work.proj, ctx.object.size(), hp, work.hull, out.contour, kMaxContourVertices,
                                   out.n_contour, cell, inside);
  if (s != Status::ok || out.n_contour < 3) return s;
  float ymin = out.contour[0].y, ymax = out.contour[0].y;
  for (uint32_t i = 1; i < out.n_contour; ++i) {
    ymin = std::min(ymin, out.contour[i].y);
    ymax = std::max(ymax, out.contour[i].y);
  }
  float delta = cfg.scan_delta_m;
  out.n_lines =
      build_scan_lines(out.contour, out.n_contour, ymin, ymax, cfg.scan_delta_m, out.lines, kMaxScanLines, delta);
  mark_graspable(out.lines, out.n_lines, cfg.gripper.min_opening_m, cfg.gripper.max_opening_m - cfg.width_margin_m);
  // k = ceil(finger_width / delta) lines per window (delta may have grown to fit).
  uint32_t k = static_cast<uint32_t>(std::ceil(cfg.gripper.finger_width_m / delta - 1e-4f));
  if (k < 2) k = 2;
  const uint32_t cap = max_windows < kMaxWindowsPerView ? max_windows : kMaxWindowsPerView;
  out.n_windows = best_windows(out.lines, out.n_lines, cfg.dx_threshold_m, k, 0.f, cfg.centre_weight, out.windows, cap);
  return Status::ok;
}

void find_candidates(const CandidateContext& ctx, ViewList& views, uint32_t first, uint32_t last, ViewWork& work,
                     Silhouette& sil, CandidateList& out, StageTimes& times) {
  for (uint32_t vi = first; vi < last; ++vi) {
    ViewRecord& v = views.views[vi];
    const ViewFrame f{v.X, v.Y, v.Z};
    {
      StageTimer t(times, Stage::xoy);
      if (trace_silhouette(ctx, f, work, ctx.cfg.candidates_per_view, sil) != Status::ok) continue;
    }
    StageTimer t(times, Stage::xoz);
    const uint32_t n_windows = sil.n_windows;
    if (n_windows > 0) project_depth(ctx, f, work);  // only views with windows look along Z
    for (uint32_t w = 0; w < n_windows && out.n < kMaxCandidates; ++w) {
      Candidate c;
      c.view = vi;
      if (!xoz_candidate(ctx, f, sil.windows[w], work, c)) continue;
      if (!v.has_candidate) {
        v.has_candidate = true;
        v.beta = c.beta;
        v.dz = c.dz;
      }
      out.items[out.n++] = c;
    }
    if (n_windows > 0 && !v.has_candidate) {
      v.has_candidate = true;  // windows exist, but no contact within reach
      v.beta = sil.windows[0].beta;
      v.dz = -1.f;
    }
  }
}

// E + F: contact regions, the depth rule (with the support plane), dZ and width.
bool xoz_candidate(const CandidateContext& ctx, const ViewFrame& f, const SideFit& w, ViewWork& work, Candidate& c) {
  const PlannerConfig& cfg = ctx.cfg;
  const GripperGeometry& g = cfg.gripper;
  const XozPads p = xoz_pads(cfg, w);
  uint32_t n_near = 0;
  float pos_z = 0.f;
  if (!contact_depth(cfg, ctx.object.size(), w, p, work, n_near, pos_z)) return false;
  if (cfg.executability_checks && !plane_bounds_depth(ctx, f, p, pos_z)) return false;

  // Contacts within the pads' reach at that depth.
  float xmin = 0.f, xmax = 0.f;
  reach_extent(work, n_near, p, pos_z, xmin, xmax);
  if (!(xmax >= xmin)) return false;
  const float width = xmax - xmin;
  if (width < g.min_opening_m || width > g.max_opening_m - cfg.width_margin_m) return false;
  // The silhouette's width must be within the pads' reach: when the points in reach
  // span much less, the object's widest part lies beyond the fingertips (or only a
  // sliver of it is seen there), and the width the pads would meet is unknown.
  if (width < cfg.reach_width_ratio * w.width) return false;
  c.tangent_contacts = false;
  contact_dz(cfg, work, n_near, p, pos_z, xmin, xmax, c);
  c.sides_in_cone =
      cfg.friction_mu <= 0.f || (std::fabs(w.a_left) <= cfg.friction_mu && std::fabs(w.a_right) <= cfg.friction_mu);
  c.width = width;
  c.beta = w.beta;
  c.balanced = w.beta <= cfg.beta_max_rad;
  c.position = ctx.centroid + f.X * (0.5f * (xmin + xmax)) + f.Y * p.yc + f.Z * pos_z;
  c.X = f.X;
  c.Y = f.Y;
  c.Z = f.Z;
  return c.position.allFinite() && std::isfinite(c.dz);
}

}  // namespace fg
