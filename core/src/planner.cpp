// Planner: the plan itself (algorithm.md A.5-F): support plane, target cluster,
// object frame, virtual viewpoints, XOY and XOZ force balance and ranking. The
// executability checks are in planner_checks.cpp.
#include <algorithm>
#include <cmath>
#include <limits>

#include "fg/core/eigen_sym3.hpp"
#include "fg/core/planner.hpp"
#include "fg/core/projection.hpp"
#include "fg/platform/platform.hpp"

namespace fg {

const char* to_string(Stage s) {
  switch (s) {
    case Stage::ingest: return "ingest";
    case Stage::plane: return "plane";
    case Stage::cluster: return "cluster";
    case Stage::frame: return "frame";
    case Stage::xoy: return "xoy";
    case Stage::xoz: return "xoz";
    case Stage::select: return "select";
    case Stage::total: return "total";
    case Stage::count: break;
  }
  return "unknown";
}

namespace {
constexpr float kPi = 3.14159265358979f;
// A surface beside a pad standing out this far past its contact is met by the pad's
// corner first (xoz).
constexpr float kCornerStandOut = 0.002f;
// The object frame: a body whose middle PCA eigenvalue is below this many times the
// smallest is round (cans, bottles: 1.4-2.6 as seen from above) rather than a plate
// (standing bats: 16.5 and more), and its axis snaps to vertical within
// vertical_snap_round.
constexpr float kRoundBodyFlatness = 6.f;
// Approaches pointing up more steeply than this come from below the object: skipped.
constexpr float kMaxApproachUp = 0.5f;
// Two family axes closer than 10 deg (the extension's step) search the same circle.
constexpr float kSameAxisCos = 0.9848078f;
// The families about the support plane's horizontal axes close within 30 deg of it.
constexpr float kSupportClosingSin = 0.5f;
// A circle passing within 60 deg of straight down gets its steepest approach as a
// viewpoint of its own, unless one of its steps lies within half a degree of it.
constexpr float kSteepestReach = 0.5f;  // sin 30 deg: the down vector's part across the axis
constexpr float kSameViewRad = 0.0087f;
// The footprint's rectangle is searched over at most this many hull vertices (h^2 work);
// a larger hull keeps the covariance axes.
constexpr uint32_t kMaxFootprintHull = 256;

class StageTimer {
 public:
  explicit StageTimer(uint32_t& slot) : slot_(slot), t0_(platform::monotonic_us()) {}
  ~StageTimer() { slot_ += static_cast<uint32_t>(platform::monotonic_us() - t0_); }
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;

 private:
  uint32_t& slot_;
  uint64_t t0_;
};

uint32_t& stage(PlanResult& r, Stage s) { return r.stage_us[static_cast<uint32_t>(s)]; }

Vec3 rotate_about(const Vec3& v, const Vec3& axis_unit, float theta) {
  // Rodrigues for a vector orthogonal or not to the axis.
  const float c = std::cos(theta), s = std::sin(theta);
  return v * c + axis_unit.cross(v) * s + axis_unit * axis_unit.dot(v) * (1.f - c);
}

// The angle, on the circle of viewpoints about `axis` that add_family turns from X0,
// of the circle's steepest approach (straight down the support plane's normal `n` when
// the axis lies along the plane); false when the circle passes farther than 60 deg from
// straight down, or one of its steps of `step` lies within kSameViewRad of it.
bool steepest_theta(const Vec3& axis, const Vec3& X0, const Vec3& n, float step, float& theta) {
  const Vec3 down = -n;
  const Vec3 across = down - axis * axis.dot(down);
  if (across.norm() <= kSteepestReach) return false;
  const Vec3 Z0 = X0.cross(axis);
  float th = std::atan2(across.dot(axis.cross(Z0)), across.dot(Z0));
  if (th < 0.f) th += 2.f * kPi;
  if (std::fabs(std::remainder(th, step)) <= kSameViewRad || th >= 2.f * kPi - kSameViewRad) return false;
  theta = th;
  return true;
}

// A unit vector orthogonal to `axis`, derived from `hint` (projected), with fallbacks.
Vec3 orthogonal_from(const Vec3& axis, const Vec3& hint) {
  const Vec3 cands[3] = {hint, Vec3::UnitZ(), Vec3::UnitX()};
  for (const Vec3& h : cands) {
    const Vec3 v = h.cross(axis);  // orthogonal to the axis
    const float n = v.norm();
    if (n > 1e-3f * (h.norm() + 1e-12f)) return v / n;
  }
  return Vec3::UnitY();
}
}  // namespace

// A.6's labelling, its frame off plan()'s (the deepest stack path runs through plan()).
// The walks test their neighbours in a bitmap of the objects' cells in the idle
// per-view memory; when the cells span more than it holds, they ask the hash, through
// the larger filter that memory then holds (fewer false positives, each a cache miss in
// the table). Either goes back to the views after the clustering.
ClusterResult Planner::label_clusters(const ClusterParams& cp, uint32_t* queue) {
  CellBitmap free_cells;
  const bool dense = build_cell_bitmap(grid_, state_, kVoxelFree, queue, view_words_,
                                       sizeof(view_words_) / sizeof(view_words_[0]), free_cells);
  if (!dense) grid_.prepare_lookups(state_, view_words_, kViewWorkWordBits);
  return cluster_and_pick(grid_, state_, queue, cp, object_voxel_, kMaxObjectPoints, dense ? &free_cells : nullptr);
}

Status Planner::plan(PlanResult& out) {
  out = PlanResult{};
  const uint64_t t_start = platform::monotonic_us();
  stage(out, Stage::ingest) = ingest_us_;
  // The viewpoints and candidates of a first search whose target gave way to the
  // fall-back (the counts cover both searches).
  uint32_t views_before = 0, candidates_before = 0;
  auto finish = [&](Status s, NoGraspReason r, const char* msg) {
    out.status = s;
    out.reason = r;
    out.message = msg;
    message_ = msg;
    out.points = counts_;
    out.points.after_filter -= crop_used_.points_dropped;
    out.crop = crop_used_;
    out.viewpoints = views_before + n_views_;
    out.candidates = candidates_before + n_candidates_;
    stage(out, Stage::total) =
        static_cast<uint32_t>(platform::monotonic_us() - t_start) + ingest_us_;
    return s;
  };
  n_views_ = 0;
  n_candidates_ = 0;
  checks_left_ = kMaxCheckedCandidates;
  if (grasp_check_ != nullptr) grasp_check_->begin_plan();
  n_deferred_ = 0;
  n_near_ = 0;
  chosen_view_ = -1;
  object_.clear();

  if (!role_added_[0] && !role_added_[1])
    return finish(Status::no_input, NoGraspReason::none, "no sensor data was added before plan()");
  if (overflow_)
    return finish(Status::capacity_exceeded, NoGraspReason::none,
                  "more occupied voxels than the build's FG_MAX_VOXELS");
  const uint32_t nv = grid_.size();
  counts_.voxels = nv;
  if (nv == 0)
    return finish(Status::no_grasp, NoGraspReason::no_points,
                  "no point is left after the range filter and the workspace crop box");

  // A.5 support plane
  {
    StageTimer t(stage(out, Stage::plane));
    grid_.finalize();  // sums become centroids; no more points until reset()
    const Vec3* centroids = grid_.centroids();
    PlaneParams pp;
    pp.distance_m = cfg_.plane_distance_m;
    pp.iterations = cfg_.ransac_iterations;
    pp.seed = cfg_.ransac_seed;
    pp.max_tilt_rad = cfg_.plane_max_tilt_rad;
    uint32_t inl = 0;
    plane_found_ = ransac_plane(centroids, nv, pp, plane_, inl);
    if (!plane_found_) {
      // No support plane in view: nothing is removed, and the lowest point stands in
      // for the floor in the clearance checks.
      float zmin = centroids[0].z();
      for (uint32_t i = 1; i < nv; ++i) zmin = std::min(zmin, centroids[i].z());
      plane_.n = Vec3::UnitZ();
      plane_.d = -zmin;
    }
    uint32_t removed = 0;
    for (uint32_t i = 0; i < nv; ++i) {
      const bool table = plane_found_ && plane_.height(centroids[i]) < cfg_.object_min_height_m;
      state_[i] = table ? kVoxelRemoved : kVoxelFree;
      removed += table ? 1u : 0u;
    }
    counts_.plane = removed;
    // Neighbour searches from here on (clustering, normals) look for object voxels
    // only: take the support plane out of the hash.
    static_assert(kVoxelRemoved == 0, "state_ doubles as the keep flags");
    if (removed > 0) grid_.keep_in_index_only(state_);
  }

  // A.6 target cluster
  ClusterParams cp;
  cp.cells = cfg_.cluster_cells;
  cp.min_points = cfg_.min_object_points;
  cp.centre_x = cfg_.workspace_centre_x_m;
  cp.centre_y = cfg_.workspace_centre_y_m;
  cp.rule = cfg_.target_rule;
  // The breadth-first queue borrows the voxel count storage, idle after finalize().
  uint32_t* const queue = grid_.lend_count_storage();
  uint32_t clusters = 0;
  ClusterResult cr;  // kept for the fall-back: its list of the largest clusters
  {
    StageTimer t(stage(out, Stage::cluster));
    cr = label_clusters(cp, queue);
    grid_.prepare_lookups(state_);  // the per-view memory back to the views (same kept set)
    if (cr.target_size == 0)
      return finish(Status::no_grasp, NoGraspReason::no_object,
                    plane_found_ ? "no cluster large enough stands on the support plane"
                                 : "no support plane and no cluster large enough");
    if (cr.target_size > kMaxObjectPoints)
      return finish(Status::capacity_exceeded, NoGraspReason::none,
                    "the target object has more voxels than the build's FG_MAX_OBJECT_POINTS");
    clusters = cr.clusters;
    load_target(cr.target_size, queue);
  }

  // B-F on the target.
  NoGraspReason reason = NoGraspReason::none;
  const char* why = "";
  uint32_t found = search_grasp(out, reason, why);

  // The target-fragment fall-back (A.6): a target that yields no grasp and lies over
  // a larger cluster's footprint (the stand under a standing bat, a veil of mixed
  // pixels beside a bottle) gives way to that cluster, once. The checks' budget is the
  // plan's: the fall-back gets what the first search left.
  if (found == kMaxCandidates && cfg_.extend_search && cp.rule == TargetRule::nearest_to_centre &&
      clusters > 1) {
    const uint32_t first_size = object_.size();
    uint32_t size = 0;
    {
      StageTimer t(stage(out, Stage::cluster));
      double sx = 0.0, sy = 0.0;
      for (uint32_t i = 0; i < first_size; ++i) {
        sx += object_[i].x();
        sy += object_[i].y();
      }
      const float cx = static_cast<float>(sx / first_size), cy = static_cast<float>(sy / first_size);
      // The walks use the near list's storage as their queue: without a fall-back
      // nothing checks collisions after this, and with one load_target rebuilds it.
      size = retarget_to_cover(grid_, state_, queue, cp, object_voxel_, first_size, cx, cy, object_voxel_,
                               kMaxObjectPoints, &cr);
      if (size > 0) load_target(size, queue);
    }
    if (size > 0) {
      views_before = n_views_;
      candidates_before = n_candidates_;
      NoGraspReason r2 = NoGraspReason::none;
      const char* why2 = "";
      found = search_grasp(out, r2, why2);
      // Both failed: the target's own reason and size are reported (the fall-back
      // was a second chance, not the target); the inspection shows the last search.
      if (found == kMaxCandidates) counts_.object = first_size;
    }
  }
  if (found == kMaxCandidates) return finish(Status::no_grasp, reason, why);
  fill_grasp(candidates_[found], out);
  return finish(Status::ok, NoGraspReason::none, "ok");
}

// The target's voxels (object_voxel_[0, size)) become the object points; the near
// list of the collision check is built around them in `storage`.
void Planner::load_target(uint32_t size, uint32_t* storage) {
  object_.clear();
  for (uint32_t i = 0; i < size; ++i) {
    (void)object_.push(grid_.centroid(object_voxel_[i]));
    normal_state_[i] = 0;
  }
  counts_.object = size;
  build_near_list(storage);
}

// B-F for the current target: the object frame, the view families one at a time
// until one yields an executable grasp, then the deferred grasps. Returns the grasp's
// candidate index, or kMaxCandidates with the no_grasp reason and message.
uint32_t Planner::search_grasp(PlanResult& out, NoGraspReason& reason, const char*& why) {
  n_views_ = 0;
  n_candidates_ = 0;
  n_deferred_ = 0;
  chosen_view_ = -1;
  // B/C. object frame and the sensor arc
  Vec3 axes[3];
  Vec3 X0;
  uint32_t arc_views = 0;
  float arc_from = 0.f, arc_to = 0.f;
  {
    StageTimer t(stage(out, Stage::frame));
    if (!build_object_frame(axes, X0)) {
      reason = NoGraspReason::degenerate;
      why = "the object points have no defined principal axis (all identical)";
      return kMaxCandidates;
    }
    const Vec3& Y = axes[0];
    const Vec3 Z0 = X0.cross(Y);
    if (role_added_[0] && role_added_[1]) {
      // theta_1: the head sensor's direction about Y, measured from the hand's.
      const Vec3 zh = orthogonal_from(Y, sensor_origin_[0] - centroid_).cross(Y);
      arc_to = std::atan2(zh.dot(X0), zh.dot(Z0));
      arc_from = 0.f;
    } else {
      arc_from = -cfg_.single_sensor_arc_rad;
      arc_to = cfg_.single_sensor_arc_rad;
    }
    if (arc_to < arc_from) std::swap(arc_from, arc_to);
    arc_views = add_family(ViewFamily::sensor_arc, Y, X0, arc_from, arc_to, false, 0.f, 0.f);
  }
  analyse_views(0, arc_views, out);
  uint32_t found = rank_and_check(0, out);
  // The extension (algorithm.md G), one family at a time, stopping at the first that
  // yields an executable grasp: the rest of the circle about Y, then circles about the
  // middle and the minor PCA axes.
  for (int fam = 1; fam <= 3 && found == kMaxCandidates && cfg_.extend_search; ++fam) {
    const uint32_t first_view = n_views_, first_cand = n_candidates_;
    {
      StageTimer t(stage(out, Stage::frame));
      if (fam == 1) {
        add_family(ViewFamily::full_circle, axes[0], X0, 0.f, 2.f * kPi, true, arc_from, arc_to);
      } else {
        const Vec3 hint = sensor_origin_[role_added_[1] ? 1 : 0] - centroid_;
        const Vec3 Xa = orthogonal_from(axes[fam - 1], hint);
        const ViewFamily vf = fam == 2 ? ViewFamily::middle_axis : ViewFamily::minor_axis;
        add_family(vf, axes[fam - 1], Xa, 0.f, 2.f * kPi, false, 0.f, 0.f);
        // The steps start from the sensor's direction, so they pass straight down only
        // by chance (5 deg off at worst), yet an object standing on the plane is grasped
        // best from straight above, its closing level: tilted 10 deg, the lower
        // fingertip of a grasp on a bottle's cap meets the unseen shoulder under it.
        float th = 0.f;
        if (plane_found_ && steepest_theta(axes[fam - 1], Xa, plane_.n, cfg_.extension_dtheta_rad, th))
          add_family(vf, axes[fam - 1], Xa, th, th, false, 0.f, 0.f);
      }
    }
    analyse_views(first_view, n_views_, out);
    found = rank_and_check(first_cand, out);
  }
  // Then (G, a tilted principal axis): circles about the support plane's axes. A
  // partial cloud (the top and one side of a box) tilts the PCA axes across it, and
  // then no family above approaches square to the faces of an object standing on the
  // plane: horizontal approaches all round, and approaches in the vertical planes
  // through the object's major and minor directions along the plane (top-down grasps
  // closing across the narrow side, or along the long one).
  Vec3 sup[3], foot[3];
  bool have_sup = false, foot_measured = false, have_foot = false;
  if (found == kMaxCandidates && cfg_.extend_search) {
    StageTimer t(stage(out, Stage::frame));
    have_sup = support_frame(sup);
  }
  for (int fam = 4; fam <= 6 && found == kMaxCandidates && have_sup; ++fam) {
    const uint32_t first_view = n_views_, first_cand = n_candidates_;
    {
      StageTimer t(stage(out, Stage::frame));
      // The footprint's sides, once, when the first circle that turns about them comes.
      if (fam >= 5 && !foot_measured) {
        foot_measured = true;
        have_foot = footprint_axes(sup, foot);
      }
      // Axis and start: the normal from the minor direction; the major direction
      // from the minor (theta 0: top-down, closing across the narrow side); the minor
      // from the major (theta pi: top-down, closing along the long side). The last two
      // take the footprint's sides when known (footprint_axes).
      const Vec3* in_plane = have_foot ? foot : sup;
      const Vec3& axis = fam == 4 ? sup[0] : in_plane[fam - 4];
      const Vec3& x0 = fam == 4 ? sup[2] : fam == 6 ? in_plane[1] : in_plane[2];
      // A circle about (nearly) the same axis as one searched above is skipped: it
      // would search the same approaches again (an upright object's principal axis
      // snaps to the vertical, and its other axes are then horizontal too).
      bool searched = false;
      for (int a = 0; a < 3; ++a) searched = searched || std::fabs(axis.dot(axes[a])) > kSameAxisCos;
      if (!searched) add_family(static_cast<ViewFamily>(fam), axis, x0, 0.f, 2.f * kPi, false, 0.f, 0.f);
    }
    analyse_views(first_view, n_views_, out);
    found = rank_and_check(first_cand, out);
  }
  if (found == kMaxCandidates && cfg_.executability_checks) found = check_deferred(out);

  if (found != kMaxCandidates) return found;
  bool any_kept = false;
  for (uint32_t v = 0; v < n_views_; ++v) any_kept = any_kept || views_[v].has_candidate;
  reason = NoGraspReason::collision;
  if (n_candidates_ == 0) {
    // Nothing survived the width filter and the window search.
    if (any_kept) {
      reason = NoGraspReason::no_candidate;
      why = "graspable windows exist, but none has contacts on both sides within the pads' reach";
    } else {
      reason = NoGraspReason::too_wide;
      why = "the object is wider than the gripper opening from every viewpoint searched";
    }
    return kMaxCandidates;
  }
  // A candidate that passed every check of the gripper but the arm's: a grasp exists
  // where the arm cannot go, which says more than the other candidates' rejections.
  const RejectCounts& rj = out.rejected;
  if (rj.unreachable > 0) {
    reason = NoGraspReason::unreachable;
    why = "the arm reaches none of the candidates that pass the gripper's checks";
  } else if (rj.friction >= rj.collision + rj.table && rj.friction >= rj.occluded) {
    reason = NoGraspReason::friction;
    why = "every candidate's contact normals lie outside the friction cone";
  } else if (rj.occluded > rj.collision + rj.table) {
    // Not a collision: nothing was seen where the finger goes. The robot can look
    // from elsewhere (the wrist camera) and plan again.
    reason = NoGraspReason::occluded;
    why = "every candidate puts a finger in space the sensors saw only behind the object";
  } else {
    why = "every candidate hits the support plane or another object";
  }
  return kMaxCandidates;
}

bool Planner::build_object_frame(Vec3 axes[3], Vec3& X0) {
  Vec3 evals;
  Mat3 evecs;
  if (!pca(object_.data(), object_.size(), centroid_, evals, evecs)) return false;
  if (!(evals[2] > 1e-12f)) return false;
  Vec3 Y = evecs.col(2);
  const float up = std::fabs(Y.z());
  const bool ill_defined = evals[2] < cfg_.axis_ratio_min * evals[1];
  // Seen from above, a round body's top and the wall one sensor faced form an L whose
  // axis leans 20-25 deg; a plate's lean (kRoundBodyFlatness) is real.
  const bool round_body = evals[1] < kRoundBodyFlatness * evals[0];
  const float snap = round_body ? cfg_.vertical_snap_round_rad : cfg_.vertical_snap_rad;
  if (ill_defined || up > std::cos(snap)) {
    Y = Vec3::UnitZ();  // gravity is the better axis for upright or round objects
  } else if (up > 0.05f) {
    if (Y.z() < 0) Y = -Y;
  } else if (Y.x() < 0) {
    Y = -Y;
  }
  axes[0] = Y;
  // The other two axes: PCA's, made orthogonal to Y.
  Vec3 m = evecs.col(1) - Y * Y.dot(evecs.col(1));
  if (m.norm() < 1e-3f) m = orthogonal_from(Y, evecs.col(0));
  axes[1] = m.normalized();
  axes[2] = Y.cross(axes[1]).normalized();
  // Paper eq. (2): X = normalize(Sp x Y) with Sp the hand sensor relative to c;
  // then the head sensor, then world z.
  const uint32_t first = role_added_[1] ? 1u : 0u;
  Vec3 hint = sensor_origin_[first] - centroid_;
  if (hint.cross(Y).norm() < 1e-3f * (hint.norm() + 1e-12f) && role_added_[1 - first])
    hint = sensor_origin_[1 - first] - centroid_;
  X0 = orthogonal_from(Y, hint);  // normalize(Sp x Y), with fallbacks
  return X0.allFinite() && Y.allFinite();
}

const char* to_string(ViewFamily f) {
  switch (f) {
    case ViewFamily::sensor_arc: return "sensor_arc";
    case ViewFamily::full_circle: return "full_circle";
    case ViewFamily::middle_axis: return "middle_axis";
    case ViewFamily::minor_axis: return "minor_axis";
    case ViewFamily::support_normal: return "support_normal";
    case ViewFamily::support_major: return "support_major";
    case ViewFamily::support_minor: return "support_minor";
  }
  return "unknown";
}

// The support plane's frame: its upward normal, then the object's major and minor
// directions along it (PCA of the points projected onto the plane), right-handed
// (major x minor = normal). False without a plane or when the projection is round
// to float precision (no major direction: the normal's circle alone would do, but
// the families are searched as a set).
bool Planner::support_frame(Vec3 axes[3]) const {
  if (!plane_found_ || object_.size() < 3) return false;
  Vec3 n = plane_.n;
  if (!(n.norm() > 0.5f)) return false;
  n.normalize();
  if (n.z() < 0.f) n = -n;
  const Vec3 a = std::fabs(n.x()) < 0.9f ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 u = (a - n * n.dot(a)).normalized(), v = n.cross(u);
  double suu = 0.0, suv = 0.0, svv = 0.0, su = 0.0, sv = 0.0;
  const uint32_t m = object_.size();
  for (uint32_t i = 0; i < m; ++i) {
    const Vec3 d = object_[i] - centroid_;
    const double x = u.dot(d), y = v.dot(d);
    su += x;
    sv += y;
    suu += x * x;
    suv += x * y;
    svv += y * y;
  }
  const double k = static_cast<double>(m);
  const double cxx = suu / k - (su / k) * (su / k), cxy = suv / k - (su / k) * (sv / k),
               cyy = svv / k - (sv / k) * (sv / k);
  // Major direction of the 2x2 covariance: angle 0.5 atan2(2 cxy, cxx - cyy).
  if (!(std::fabs(cxy) + std::fabs(cxx - cyy) > 1e-12)) return false;
  const double phi = 0.5 * std::atan2(2.0 * cxy, cxx - cyy);
  const Vec3 major = (u * static_cast<float>(std::cos(phi)) + v * static_cast<float>(std::sin(phi))).normalized();
  axes[0] = n;
  axes[1] = major;
  axes[2] = n.cross(major).normalized();
  return axes[1].allFinite() && axes[2].allFinite();
}

bool Planner::footprint_axes(const Vec3 sup[3], Vec3 foot[3]) {
  // The target's points on the plane's (major, minor) axes, then their convex hull;
  // the hull overwrites the projection (its scratch), both idle between the families.
  const uint32_t m = object_.size();
  Vec2* const p = view_.proj;
  for (uint32_t i = 0; i < m; ++i) {
    const Vec3 d = object_[i] - centroid_;
    p[i] = Vec2{sup[1].dot(d), sup[2].dot(d)};
  }
  uint32_t h = 0;
  if (convex_hull_2d(p, m, p, contour_, kMaxContourVertices, h) != Status::ok || h < 3 || h > kMaxFootprintHull)
    return false;
  // The smallest-area rectangle has a side along a hull edge (Freeman and Shapira).
  const float inf = std::numeric_limits<float>::infinity();
  float best = inf, major_x = 0.f, major_y = 0.f;
  for (uint32_t i = 0; i < h; ++i) {
    const Vec2& q = contour_[i + 1 < h ? i + 1 : 0];
    float ex = q.x - contour_[i].x, ey = q.y - contour_[i].y;
    const float len = std::sqrt(ex * ex + ey * ey);
    if (!(len > 1e-6f)) continue;
    ex /= len;
    ey /= len;
    float a0 = inf, a1 = -inf, b0 = inf, b1 = -inf;  // along the edge, across it
    for (uint32_t j = 0; j < h; ++j) {
      const float a = ex * contour_[j].x + ey * contour_[j].y, b = ex * contour_[j].y - ey * contour_[j].x;
      a0 = std::min(a0, a);
      a1 = std::max(a1, a);
      b0 = std::min(b0, b);
      b1 = std::max(b1, b);
    }
    const float area = (a1 - a0) * (b1 - b0);
    if (area < best) {
      best = area;
      const bool along = a1 - a0 >= b1 - b0;  // the major side: the longer one
      major_x = along ? ex : -ey;
      major_y = along ? ey : ex;
    }
  }
  if (!(best < inf)) return false;
  foot[0] = sup[0];
  foot[1] = (sup[1] * major_x + sup[2] * major_y).normalized();
  foot[2] = sup[0].cross(foot[1]).normalized();
  return foot[1].allFinite() && foot[2].allFinite();
}

uint32_t Planner::add_family(ViewFamily fam, const Vec3& axis, const Vec3& X0, float from,
                             float to, bool skip_arc, float arc_from, float arc_to) {
  const Vec3 Z0 = X0.cross(axis);
  // The paper's arc at dtheta; the wider families of the extension at their own step.
  const float step = fam == ViewFamily::sensor_arc ? cfg_.dtheta_rad : cfg_.extension_dtheta_rad;
  const uint32_t steps = static_cast<uint32_t>((to - from) / step + 1e-4f);
  const bool circle = fam != ViewFamily::sensor_arc;
  // The arc runs from `from` to exactly `to` (theta_1); circles stop short of 2 pi.
  const bool add_end = !circle && (to - from) - static_cast<float>(steps) * step > 1e-4f;
  uint32_t added = 0;
  for (uint32_t s = 0; s <= steps + (add_end ? 1u : 0u) && n_views_ < kMaxViewpoints; ++s) {
    const float th = s > steps ? to : from + static_cast<float>(s) * step;
    if (circle && th >= 2.f * kPi - 1e-4f) break;
    if (skip_arc) {
      const float wrapped = th > kPi ? th - 2.f * kPi : th;
      if (wrapped >= arc_from - 1e-4f && wrapped <= arc_to + 1e-4f) continue;
    }
    ViewRecord& v = views_[n_views_];
    v.family = fam;
    v.theta = th;
    v.Y = axis;
    v.X = rotate_about(X0, axis, th);
    v.Z = rotate_about(Z0, axis, th);
    if (v.Z.z() > kMaxApproachUp) continue;  // from below the object
    // About the support plane's horizontal axes: closing within 30 deg of the plane
    // (approaches within 30 deg of top-down). A steeper closing needs a finger under
    // the object, which stands on the plane.
    if ((fam == ViewFamily::support_major || fam == ViewFamily::support_minor) &&
        std::fabs(v.X.dot(plane_.n)) > kSupportClosingSin * plane_.n.norm())
      continue;
    if (!seen_from_a_sensor(v.Z)) continue;
    v.has_candidate = false;
    v.beta = v.dz = 0.f;
    ++n_views_;
    ++added;
  }
  return added;
}

// The partial cloud only shows the sides the sensors faced: an approach is allowed
// when it comes from within approach_view_max of some sensor's line of sight, so the
// surfaces the palm and fingers move through were observed.
bool Planner::seen_from_a_sensor(const Vec3& approach) const {
  const float min_cos = std::cos(cfg_.approach_view_max_rad);
  for (uint32_t r = 0; r < kMaxSensors; ++r) {
    if (!role_added_[r]) continue;
    const Vec3 sight = centroid_ - sensor_origin_[r];
    const float len = sight.norm();
    if (!(len > 1e-6f) || approach.dot(sight) >= min_cos * len) return true;
  }
  return false;
}

void Planner::project_depth(const ViewFrame& f) {
  const uint32_t n = object_.size();
  for (uint32_t i = 0; i < n; ++i) view_.depth[i] = f.Z.dot(object_[i] - centroid_);
}

// D.1-D.8 for one viewpoint: projection, concave hull, scan lines, width filter and the
// best windows (at most max_windows, best first). Shared by the plan and the pictures.
Status Planner::silhouette_windows(const ViewFrame& f, Vec2* contour, uint32_t& n_contour,
                                   ScanLine* lines, uint32_t& n_lines, SideFit* windows,
                                   uint32_t max_windows, uint32_t& n_windows) {
  n_contour = n_lines = n_windows = 0;
  ConcaveHullParams hp;
  project_to_view(object_.data(), object_.size(), centroid_, f.X, f.Y, view_.proj, hp);
  hp.cell_m = cfg_.hull_cell_m;
  hp.closing_cells = cfg_.hull_closing_cells;
  float cell = 0.f;
  bool inside = false;
  const Status s = concave_hull_2d(view_.proj, object_.size(), hp, view_.hull, contour,
                                   kMaxContourVertices, n_contour, cell, inside);
  if (s != Status::ok || n_contour < 3) return s;
  float ymin = contour[0].y, ymax = contour[0].y;
  for (uint32_t i = 1; i < n_contour; ++i) {
    ymin = std::min(ymin, contour[i].y);
    ymax = std::max(ymax, contour[i].y);
  }
  float delta = cfg_.scan_delta_m;
  n_lines = build_scan_lines(contour, n_contour, ymin, ymax, cfg_.scan_delta_m, lines,
                             kMaxScanLines, delta);
  mark_graspable(lines, n_lines, cfg_.gripper.min_opening_m,
                 cfg_.gripper.max_opening_m - cfg_.width_margin_m);
  // k = ceil(finger_width / delta) lines per window (delta may have grown to fit).
  uint32_t k = static_cast<uint32_t>(std::ceil(cfg_.gripper.finger_width_m / delta - 1e-4f));
  if (k < 2) k = 2;
  n_windows = best_windows(lines, n_lines, cfg_.dx_threshold_m, k, 0.f, cfg_.centre_weight,
                           windows, max_windows);
  return Status::ok;
}

Status Planner::analyze_view(uint32_t view_index, ViewDetail& out) {
  if (view_index >= n_views_) return Status::invalid_argument;
  const ViewRecord& v = views_[view_index];
  uint32_t n_windows = 0;
  const Status s = silhouette_windows(ViewFrame{v.X, v.Y, v.Z}, out.contour, out.n_contour,
                                      out.lines, out.n_lines, &out.best, 1, n_windows);
  const uint32_t n = object_.size();
  for (uint32_t i = 0; i < n; ++i) out.points[i] = view_.proj[i];
  out.n_points = n;
  out.has_best = n_windows > 0;
  return s;
}

void Planner::analyse_views(uint32_t first, uint32_t last, PlanResult& out) {
  for (uint32_t vi = first; vi < last; ++vi) {
    ViewRecord& v = views_[vi];
    const ViewFrame f{v.X, v.Y, v.Z};
    uint32_t n_windows = 0;
    {
      StageTimer t(stage(out, Stage::xoy));
      uint32_t nc = 0, nl = 0;
      if (silhouette_windows(f, contour_, nc, lines_, nl, windows_, cfg_.candidates_per_view,
                             n_windows) != Status::ok)
        continue;
    }
    StageTimer t(stage(out, Stage::xoz));
    if (n_windows > 0) project_depth(f);  // only views with windows look along Z
    for (uint32_t w = 0; w < n_windows && n_candidates_ < kMaxCandidates; ++w) {
      Candidate c;
      c.view = vi;
      if (!xoz(f, windows_[w], c)) continue;
      if (!v.has_candidate) {
        v.has_candidate = true;
        v.beta = c.beta;
        v.dz = c.dz;
      }
      candidates_[n_candidates_++] = c;
    }
    if (n_windows > 0 && !v.has_candidate) {
      v.has_candidate = true;  // windows exist, but no contact within reach
      v.beta = windows_[0].beta;
      v.dz = -1.f;
    }
  }
}

// E + F: contact regions, the depth rule (with the support plane), dZ and width.
bool Planner::xoz(const ViewFrame& f, const SideFit& w, Candidate& c) {
  const GripperGeometry& g = cfg_.gripper;
  const uint32_t n = object_.size();
  const float yc = w.y_centre;
  const float half_pad = 0.5f * g.finger_width_m;
  const float half_palm = 0.5f * std::max(g.palm_width_m, g.finger_width_m);
  const float half_outer = 0.5f * g.max_opening_m + g.finger_thickness_m;
  const float half_fd = 0.5f * g.finger_depth_m;
  const float xc = w.x_centre;

  // Contact regions of the fitted sides (paper eq. 7) and the first surface ahead of
  // the palm.
  double zl = 0, zr = 0;
  uint32_t nl = 0, nr = 0;
  float z_first_palm = 1e9f;
  // The later passes look only at points within `slab` of the window's centre line:
  // they are listed here in index order, so those passes sum the same terms in the
  // same order as passes over every point.
  const float band = half_pad + 0.5f * cfg_.voxel_leaf_m;
  const float slab = std::max(half_pad, band);
  uint32_t* const near = view_.slab;
  uint32_t n_near = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const float x = view_.proj[i].x, y = view_.proj[i].y - yc, z = view_.depth[i];
    near[n_near] = i;
    n_near += std::fabs(y) <= slab ? 1u : 0u;
    if (std::fabs(y) <= half_palm && std::fabs(x - xc) <= half_outer) z_first_palm = std::min(z_first_palm, z);
    if (std::fabs(y) > half_pad) continue;
    const float yy = view_.proj[i].y;
    if (x <= w.a_left * yy + w.b_left + cfg_.contact_band_m) {
      zl += z;
      ++nl;
    }
    if (x >= w.a_right * yy + w.b_right - cfg_.contact_band_m) {
      zr += z;
      ++nr;
    }
  }
  if (nl == 0 || nr == 0) return false;
  float pos_z = static_cast<float>(0.5 * (zl / nl + zr / nr));
  if (!cfg_.paper_depth) pos_z = std::min(pos_z, z_first_palm + half_fd - cfg_.palm_clearance_m);

  // The support plane bounds the depth: every corner of the open fingers and the palm
  // must stay table_clearance above it. Height is linear in pos_z.
  if (cfg_.executability_checks) {
    const Vec3 o = centroid_ + f.X * xc + f.Y * yc;
    const float h_o = plane_.height(o);
    const float nx = plane_.n.dot(f.X), ny = plane_.n.dot(f.Y), nz = plane_.n.dot(f.Z);
    float lo = -1e9f, hi = 1e9f;
    const float xs[2] = {-half_outer, half_outer};
    const float ys[2] = {-half_palm, half_palm};
    const float zs[2] = {-half_fd - g.palm_depth_m, half_fd};  // relative to pos_z
    for (float xx : xs)
      for (float yy : ys)
        for (float zz : zs) {
          const float h0 = h_o + nx * xx + ny * yy + nz * zz - cfg_.table_clearance_m;
          // need h0 + nz * pos_z >= 0
          if (nz < -1e-6f) hi = std::min(hi, h0 / -nz);
          else if (nz > 1e-6f) lo = std::max(lo, -h0 / nz);
          else if (h0 < 0.f) return false;
        }
    pos_z = std::min(pos_z, hi);
    if (pos_z < lo) return false;
  }

  // Contacts within the pads' reach at that depth.
  float xmin = 1e9f, xmax = -1e9f;
  for (uint32_t q = 0; q < n_near; ++q) {
    const uint32_t i = near[q];
    if (std::fabs(view_.proj[i].y - yc) > half_pad || std::fabs(view_.depth[i] - pos_z) > half_fd) continue;
    xmin = std::min(xmin, view_.proj[i].x);
    xmax = std::max(xmax, view_.proj[i].x);
  }
  if (!(xmax >= xmin)) return false;
  const float width = xmax - xmin;
  if (width < g.min_opening_m || width > g.max_opening_m - cfg_.width_margin_m) return false;
  // The silhouette's width must be within the pads' reach: when the points in reach
  // span much less, the object's widest part lies beyond the fingertips (or only a
  // sliver of it is seen there), and the width the pads would meet is unknown.
  if (width < cfg_.reach_width_ratio * w.width) return false;
  // The contact regions at that depth, and the pads' edges: a surface just beyond a
  // pad's footprint that stands out past the contact meets the pad's corner first (a
  // lying bat's blade beside its handle; past the fingertips, a bottle's shoulder under
  // its cap). Its voxels' centroids lie up to half a voxel beyond the footprint. Such a
  // grasp waits for the second pass (rank_and_check): on real captures a mixed pixel at
  // the silhouette's edge stands out as far (2-7 mm), and may be all a can shows.
  //
  // dZ (paper eq. 8) weighs each contact by how far inside the pads' reach it lies:
  // 1 from one voxel leaf inside either end of the reach, falling linearly to 0 at the
  // end. Voxel centroids come in rows one leaf apart, so a hard cut at the reach's ends
  // takes a row in on one side and out on the other under a sub-millimetre shift and
  // dZ jumps by up to a leaf; with the ramp a row fades in and dZ moves continuously.
  // The plain means stand in when a side has all its contacts at the ends.
  zl = zr = 0;
  nl = nr = 0;
  double wl = 0, wr = 0, wzl = 0, wzr = 0;
  const float inv_ramp = 1.f / cfg_.voxel_leaf_m;
  c.corners_clear = true;
  c.tangent_contacts = false;
  const float tip_band = half_fd + 0.5f * cfg_.voxel_leaf_m;
  for (uint32_t q = 0; q < n_near; ++q) {
    const uint32_t i = near[q];
    const float dy = std::fabs(view_.proj[i].y - yc);
    const float dd = view_.depth[i] - pos_z;
    if (dy > band || dd < -half_fd || dd > tip_band) continue;
    if (dy > half_pad || dd > half_fd) {
      const float x = view_.proj[i].x;
      if (x < xmin - kCornerStandOut || x > xmax + kCornerStandOut) c.corners_clear = false;
      continue;
    }
    const float z = view_.depth[i];
    const float wgt = std::min(1.f, (half_fd - std::fabs(dd)) * inv_ramp);
    if (view_.proj[i].x <= xmin + cfg_.contact_band_m) {
      zl += z;
      ++nl;
      wl += wgt;
      wzl += static_cast<double>(wgt) * z;
    }
    if (view_.proj[i].x >= xmax - cfg_.contact_band_m) {
      zr += z;
      ++nr;
      wr += wgt;
      wzr += static_cast<double>(wgt) * z;
    }
  }
  constexpr double kMinWeight = 1e-3;
  const double ml = wl > kMinWeight ? wzl / wl : zl / nl, mr = wr > kMinWeight ? wzr / wr : zr / nr;
  c.dz = static_cast<float>(std::fabs(ml - mr));
  c.sides_in_cone = cfg_.friction_mu <= 0.f ||
                    (std::fabs(w.a_left) <= cfg_.friction_mu && std::fabs(w.a_right) <= cfg_.friction_mu);
  c.width = width;
  c.beta = w.beta;
  c.balanced = w.beta <= cfg_.beta_max_rad;
  c.position = centroid_ + f.X * (0.5f * (xmin + xmax)) + f.Y * yc + f.Z * pos_z;
  c.X = f.X;
  c.Y = f.Y;
  c.Z = f.Z;
  return c.position.allFinite() && std::isfinite(c.dz);
}

uint32_t Planner::rank_and_check(uint32_t first, PlanResult& out) {
  StageTimer t(stage(out, Stage::select));
  const uint32_t m = n_candidates_ - first;
  for (uint32_t i = 0; i < m; ++i) order_[i] = static_cast<uint16_t>(first + i);
  // Paper E.3: balanced candidates (beta <= beta_max) by dZ, then the rest by beta.
  // The index breaks ties, so the order is total and the result deterministic. A heap
  // sort: O(m log m) at worst and no recursion.
  const Candidate* cs = candidates_;
  const auto before = [cs](uint16_t a, uint16_t b) {
    const Candidate &ca = cs[a], &cb = cs[b];
    if (ca.balanced != cb.balanced) return ca.balanced;
    const float ka = ca.balanced ? ca.dz : ca.beta, kb = cb.balanced ? cb.dz : cb.beta;
    if (ka != kb) return ka < kb;
    return a < b;
  };
  std::make_heap(order_, order_ + m, before);
  std::sort_heap(order_, order_ + m, before);
  if (!cfg_.executability_checks) return m > 0 ? order_[0] : kMaxCandidates;
  // At most kMaxCheckedCandidates checked per plan(): the checks dominate the worst case.
  // Grasps with a finger partly in hidden space, or a pad whose corner meets a surface
  // beside it, wait in rank order for check_deferred(): every family is searched for
  // one without either.
  first_pass_ = true;
  for (uint32_t i = 0; i < m && checks_left_ > 0; ++i) {
    Candidate& c = candidates_[order_[i]];
    // A pad's corner meets a surface beside it (xoz): the grasp waits unchecked, so the
    // budget goes to the others first.
    if (!c.corners_clear) {
      deferred_list_[n_deferred_++] = order_[i];
      continue;
    }
    --checks_left_;
    if (executable(c, out)) return order_[i];
    if (deferred_) deferred_list_[n_deferred_++] = order_[i];
  }
  return kMaxCandidates;
}

// The grasps rank_and_check deferred, with the hidden samples the visibility check
// allows and the pads' corners let be: those straight down first, then the others,
// each in the order they were met. Straight down, the pads close level and meet the
// sides they were fitted to; tilted, the lower pad reaches past them, and a grasp
// deferred for a partly hidden finger may meet what the sensors did not see there.
uint32_t Planner::check_deferred(PlanResult& out) {
  StageTimer t(stage(out, Stage::select));
  first_pass_ = false;
  for (int down = 1; down >= 0; --down)
    for (uint32_t i = 0; i < n_deferred_ && checks_left_ > 0; ++i) {
      Candidate& c = candidates_[deferred_list_[i]];
      if (straight_down(c.Z) != (down == 1)) continue;
      --checks_left_;
      if (executable(c, out)) return deferred_list_[i];
    }
  return kMaxCandidates;
}

void Planner::fill_grasp(const Candidate& c, PlanResult& out) {
  const ViewRecord& v = views_[c.view];
  chosen_view_ = static_cast<int32_t>(c.view);
  Grasp& g = out.grasp;
  g.position = c.position;
  g.approach = c.Z.normalized();
  g.closing = c.X.normalized();
  g.width = c.width;
  g.beta = c.beta;
  g.dz = c.dz;
  g.viewpoint = v.theta;
  g.family = v.family;
  g.pregrasp = c.position - g.approach * (cfg_.gripper.finger_depth_m + cfg_.pregrasp_clearance_m);
}

}  // namespace fg
