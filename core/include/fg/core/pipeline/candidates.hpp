// Stages D and E, candidates: per viewpoint, the silhouette's scan lines and the
// windows with the best XOY force balance (beta), then per window the contact regions,
// the depth along the approach and the XOZ force balance (dZ).
#pragma once
#include <cstdint>

#include "fg/core/config.hpp"
#include "fg/core/force_balance.hpp"
#include "fg/core/hull.hpp"
#include "fg/core/limits.hpp"
#include "fg/core/pipeline/stage_timer.hpp"
#include "fg/core/pipeline/support_plane.hpp"
#include "fg/core/pipeline/viewpoints.hpp"
#include "fg/core/point_buffer.hpp"
#include "fg/core/status.hpp"
#include "fg/core/types.hpp"

namespace fg {

//! A grasp frame: closing (X), across the pads (Y), approach (Z).
struct ViewFrame {
  Vec3 X, Y, Z;
};

struct Candidate {
  uint32_t view;
  float beta, dz, width;
  Vec3 position;          //!< world
  Vec3 X, Y, Z;           //!< grasp frame (closing, across, approach): the viewpoint's, or refined
  bool balanced;          //!< beta <= beta_max
  bool sides_in_cone;     //!< both fitted sides within atan(mu) of the closing normal (XOY)
  bool corners_clear;     //!< nothing beside the pads or just past their tips stands out past their contacts (xoz)
  bool tangent_contacts;  //!< the pads close on a round body's unseen tangents (grazed_round_body)
  ViewFrame frame() const { return ViewFrame{X, Y, Z}; }
};

struct CandidateList {
  Candidate items[kMaxCandidates];
  uint32_t n = 0;
};

//! The per-viewpoint work memory: the object's projection and depth, and the hull's
//! raster. Idle before the views, so the clustering and the near list borrow it.
struct ViewWork {
  Vec2 proj[kMaxObjectPoints];
  float depth[kMaxObjectPoints];
  // The hull's scratch is idle once the view's silhouette is traced: the XOZ step lists
  // there the points near a window's centre line.
  union {
    ConcaveHullScratch hull;
    uint32_t slab[kMaxObjectPoints];
  };
};
static_assert(sizeof(uint32_t) * kMaxObjectPoints <= sizeof(ConcaveHullScratch),
              "the XOZ step's list borrows the hull's scratch without growing the workspace");

//! The most windows kept per viewpoint (candidates_per_view is validated against it).
inline constexpr uint32_t kMaxWindowsPerView = 16;

//! The silhouette of one viewpoint: contour, scan lines and best windows.
struct Silhouette {
  Vec2 contour[kMaxContourVertices];
  uint32_t n_contour = 0;
  ScanLine lines[kMaxScanLines];
  uint32_t n_lines = 0;
  SideFit windows[kMaxWindowsPerView];
  uint32_t n_windows = 0;
};

//! What the candidates are computed from.
struct CandidateContext {
  const PlannerConfig& cfg;
  const PointSpan& object;
  const Vec3& centroid;
  const SupportPlane& support;
};

//! D.1-D.8 for one viewpoint: projection (into work.proj), concave hull, scan lines,
//! width filter and the best windows (at most max_windows <= kMaxWindowsPerView, best
//! first). Shared by the plan and the pictures.
[[nodiscard]] Status trace_silhouette(const CandidateContext& ctx, const ViewFrame& f, ViewWork& work,
                                      uint32_t max_windows, Silhouette& out);

//! E + F for one window: contact regions, the depth rule (with the support plane), dZ
//! and width. False when the window yields no candidate (no contact on a side within
//! the pads' reach, the width out of range, the fingers through the plane). Needs
//! work.proj (trace_silhouette) and work.depth (project_depth) of the viewpoint.
[[nodiscard]] bool xoz_candidate(const CandidateContext& ctx, const ViewFrame& f, const SideFit& w, ViewWork& work,
                                 Candidate& c);

//! work.depth[i]: the object points' depth along f.Z from the centroid.
void project_depth(const CandidateContext& ctx, const ViewFrame& f, ViewWork& work);

//! Stages D and E over the viewpoints [first, last) of `views`: each one's best windows
//! become candidates (appended while there is room), and its record gets its best
//! candidate's beta and dZ. Times go to the xoy and xoz slots.
void find_candidates(const CandidateContext& ctx, ViewList& views, uint32_t first, uint32_t last, ViewWork& work,
                     Silhouette& scratch, CandidateList& out, StageTimes& times);

}  // namespace fg
