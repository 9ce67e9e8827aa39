// Planner: the composition of the pipeline's stages (docs/method.md, "The pipeline"):
// A.5 support plane, A.6 target, B object frame, then per family of viewpoints C
// viewpoints, D/E candidates, F checks and G selection, then G's second pass. Each
// stage is a function or a small class of core/src/pipeline/ over the memory the
// planner lends it; the planner runs them in order and fills the report. Ingest
// (A.1-A.4) is in planner_ingest.cpp.
#include "fg/core/planner.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "fg/core/constants.hpp"
#include "fg/platform/platform.hpp"

namespace fg {

namespace {
// Two family axes closer than 10 deg (the extension's step) search the same circle.
constexpr float kSameAxisCos = 0.9848078f;
}  // namespace

RejectCounts RejectCounts::of(const CheckRejections& r) {
  RejectCounts c;
  c.table = r[CheckId::support_plane];
  c.collision =
      r[CheckId::swept_collision] + r[CheckId::local_hull] + r[CheckId::under_target] + r[CheckId::robot_collision];
  c.occluded = r[CheckId::unknown_space] + r[CheckId::unseen_side];
  c.friction = r[CheckId::friction_cone];
  c.unreachable = r[CheckId::robot_reach];
  return c;
}

void Planner::begin_report(PlanResult& out) {
  out = PlanResult{};
  for (float& m : out.margins.value) m = std::numeric_limits<float>::quiet_NaN();
  views_.n = 0;
  candidates_.n = 0;
  selection_.begin_plan();
  if (grasp_check_ != nullptr) grasp_check_->begin_plan();
  checks_.forget_target();
  chosen_view_ = -1;
  chosen_candidate_ = kMaxCandidates;
  n_alternates_ = 0;
  object_.clear();
}

Status Planner::finish(PlanResult& out, const PlanTally& tally, Status s, NoGraspReason r, const char* msg) {
  out.status = s;
  out.reason = r;
  out.message = msg;
  message_ = msg;
  out.points = counts_;
  out.points.after_filter -= crop_used_.points_dropped;
  out.crop = crop_used_;
  out.viewpoints = tally.views_before + views_.n;
  out.candidates = tally.candidates_before + candidates_.n;
  out.rejected = RejectCounts::of(out.rejected_by_check);
  look_ = out.look;
  out.stage_us[static_cast<uint32_t>(Stage::total)] =
      static_cast<uint32_t>(platform::monotonic_us() - tally.t_start) + tally.earlier_us;
  return s;
}

Status Planner::report_search(PlanResult& out, const PlanTally& tally, uint32_t found, NoGraspReason reason,
                              const char* why) {
  if (found == kMaxCandidates) return finish(out, tally, Status::no_grasp, reason, why);
  fill_grasp(candidates_.items[found], out);
  {
    StageTimer t(out.stage_us, Stage::select);
    checks_.margins(candidates_.items[found], out.margins);
  }
  chosen_candidate_ = found;
  return finish(out, tally, Status::ok, NoGraspReason::none, "ok");
}

const char* Planner::target_outside_workspace() const {
  Vec3 lo, hi;
  configured_crop(lo, hi);
  if (target_.kind == TargetKind::nearest_point &&
      !((target_.point.array() >= lo.array()).all() && (target_.point.array() <= hi.array()).all()))
    return "the target point lies outside the workspace crop box";
  if (target_.kind == TargetKind::inside_box &&
      !((target_.box_max.array() >= lo.array()).all() && (target_.box_min.array() <= hi.array()).all()))
    return "the target box does not overlap the workspace crop box";
  return nullptr;
}

Status Planner::set_target(const TargetSpec& target) {
  const char* why = "";
  const Status s = validate(target, &why);
  if (s != Status::ok) {
    message_ = why;
    return s;
  }
  target_ = target;
  return Status::ok;
}

int32_t Planner::target_object() const {
  for (uint32_t k = 0; k < object_count(); ++k)
    if (state_[clusters_.objects[k].seed] == kVoxelTarget) return static_cast<int32_t>(k);
  return -1;
}

Status Planner::plan(PlanResult& out) {
  PlanTally tally;
  tally.t_start = platform::monotonic_us();
  tally.earlier_us = ingest_us_;
  begin_report(out);
  out.stage_us[static_cast<uint32_t>(Stage::ingest)] = ingest_us_;
  out.registration = registration_;  // A.4b ran in the ingest
  objects_ready_ = false;

  if (!sensors_.any())
    return finish(out, tally, Status::no_input, NoGraspReason::none, "no sensor data was added before plan()");
  if (registration_.outcome == RegistrationOutcome::sensor_disagreement &&
      registration_mode_ == RegistrationMode::strict)
    return finish(out, tally, Status::sensor_disagreement, NoGraspReason::none,
                  "the hand sensor's cloud disagrees with the head's after the registration: the hand saw through "
                  "surfaces the head saw (registration.see_through); check the hand's pose, its hand-eye calibration "
                  "and the clouds' frames, and the head's pose when its table is off level "
                  "(registration.head_tilt_deg)");
  if (overflow_)
    return finish(out, tally, Status::capacity_exceeded, NoGraspReason::none,
                  "more occupied voxels than the build's FG_MAX_VOXELS");
  if (const char* outside = target_outside_workspace())
    return finish(out, tally, Status::invalid_argument, NoGraspReason::none, outside);
  const uint32_t nv = grid_.size();
  counts_.voxels = nv;
  if (nv == 0)
    return finish(out, tally, Status::no_grasp, NoGraspReason::no_points,
                  "no point is left after the range filter and the workspace crop box");

  // A.5 support plane
  {
    StageTimer t(out.stage_us, Stage::plane);
    support_ = find_support_plane(grid_, cfg_, state_);
    counts_.plane = support_.removed;
  }

  // A.6 target cluster
  ClusterParams cp = target_cluster_params(cfg_);
  cp.target = target_;
  // The breadth-first queue borrows the voxel count storage, idle after finalize().
  uint32_t* const queue = grid_.lend_count_storage();
  {
    StageTimer t(out.stage_us, Stage::cluster);
    const LentWords lent{view_words_, sizeof(view_words_) / sizeof(view_words_[0]), kViewWorkWordBits};
    find_target(grid_, state_, cp, queue, lent, object_voxel_, clusters_);
    join_fragments(grid_, state_, queue, cp, sensors_, fragment_gap(cfg_), lent, object_voxel_, kMaxObjectPoints,
                   clusters_);
    objects_ready_ = true;
    if (clusters_.target_size == 0) {
      const char* why = target_.kind == TargetKind::inside_box ? "no object has a voxel inside the target box"
                        : support_.found                       ? "no cluster large enough stands on the support plane"
                                                               : "no support plane and no cluster large enough";
      return finish(out, tally, Status::no_grasp, NoGraspReason::no_object, why);
    }
    if (clusters_.target_size > kMaxObjectPoints)
      return finish(out, tally, Status::capacity_exceeded, NoGraspReason::none,
                    "the target object has more voxels than the build's FG_MAX_OBJECT_POINTS");
    load_target(clusters_.target_size, queue);
  }

  // B-G on the target.
  NoGraspReason reason = NoGraspReason::none;
  const char* why = "";
  uint32_t found = search_grasp(out, reason, why);

  // The target-fragment fall-back (A.6): a target that yields no grasp and lies over
  // a larger cluster's footprint (the stand under a standing bat, a veil of mixed
  // pixels beside a bottle) gives way to that cluster, once. The checks' budget is the
  // plan's: the fall-back gets what the first search left. A target the caller chose
  // (a point, a box) is kept.
  if (found == kMaxCandidates && cfg_.extend_search && cp.rule == TargetRule::nearest_to_centre &&
      cp.target.kind == TargetKind::by_rule && clusters_.clusters > 1) {
    const uint32_t first_size = object_.size();
    uint32_t size = 0;
    {
      StageTimer t(out.stage_us, Stage::cluster);
      // The walks use the near list's storage as their queue: without a fall-back
      // nothing checks collisions after this, and with one load_target rebuilds it.
      size = find_covering_cluster(grid_, state_, queue, cp, object_, object_voxel_, clusters_);
      if (size > 0) load_target(size, queue);
    }
    if (size > 0) {
      tally.views_before = views_.n;
      tally.candidates_before = candidates_.n;
      NoGraspReason r2 = NoGraspReason::none;
      const char* why2 = "";
      const LookAdvice first_look = out.look;
      found = search_grasp(out, r2, why2);
      // Both failed: the target's own reason, size and advice are reported (the
      // fall-back was a second chance, not the target); the inspection shows the last
      // search.
      if (found == kMaxCandidates) counts_.object = first_size;
      out.look = found == kMaxCandidates ? first_look : LookAdvice{};
    }
  }
  return report_search(out, tally, found, reason, why);
}

Status Planner::plan_object(uint32_t k, PlanResult& out) {
  PlanTally tally;
  tally.t_start = platform::monotonic_us();
  begin_report(out);
  if (!objects_ready_)
    return finish(out, tally, Status::invalid_sequence, NoGraspReason::none,
                  "plan_object() needs a plan() that found the objects, since the last reset()");
  if (k >= clusters_.n_objects)
    return finish(out, tally, Status::invalid_argument, NoGraspReason::none,
                  "plan_object(): the object index is beyond the plan's list of objects");
  uint32_t* const queue = grid_.lend_count_storage();
  {
    StageTimer t(out.stage_us, Stage::cluster);
    const uint32_t size = mark_object(grid_, state_, queue, target_cluster_params(cfg_), clusters_.objects[k],
                                      object_voxel_, kMaxObjectPoints);
    counts_.object = size;
    if (size == 0)  // plan() left every listed seed in the visited or target state
      return finish(out, tally, Status::internal_error, NoGraspReason::none,
                    "plan_object(): the object list no longer matches the voxels");
    if (size > kMaxObjectPoints)
      return finish(out, tally, Status::capacity_exceeded, NoGraspReason::none,
                    "the object has more voxels than the build's FG_MAX_OBJECT_POINTS");
    load_target(size, queue);
  }
  NoGraspReason reason = NoGraspReason::none;
  const char* why = "";
  const uint32_t found = search_grasp(out, reason, why);
  return report_search(out, tally, found, reason, why);
}

void Planner::load_target(uint32_t size, uint32_t* storage) {
  object_.clear();
  for (uint32_t i = 0; i < size; ++i) (void)object_.push(grid_.centroid(object_voxel_[i]));
  counts_.object = size;
  checks_.begin_target(storage, near_tables_, body_scratch_);
}

void Planner::generate_family(const FamilySpec* specs, uint32_t n_specs, StageTimes& stage_us) {
  const uint32_t first_view = views_.n;
  {
    StageTimer t(stage_us, Stage::frame);
    for (uint32_t i = 0; i < n_specs; ++i) add_view_family(view_context(), specs[i], views_);
  }
  find_candidates(candidate_context(), views_, first_view, views_.n, view_, silhouette_, candidates_, stage_us);
}

uint32_t Planner::search_family(const FamilySpec* specs, uint32_t n_specs, PlanResult& out) {
  const uint32_t first_cand = candidates_.n;
  generate_family(specs, n_specs, out.stage_us);
  StageTimer t(out.stage_us, Stage::select);
  return selection_.first_pass(candidates_, first_cand, checks_, grasp_check_, out.rejected_by_check);
}

// The families of viewpoints in the order they are searched (algorithm.md C and G):
// the sensor arc; then, with the extension, the rest of the circle about Y and circles
// about the middle and the minor PCA axes; then circles about the support plane's axes.
bool Planner::next_family(FamilyCursor& cur, FamilySpec specs[2], uint32_t& n_specs, StageTimes& stage_us) {
  n_specs = 1;
  const Vec3* axes = frame_.axes;
  if (cur.next == 0) {
    cur.next = 1;
    specs[0] = FamilySpec{ViewFamily::sensor_arc, axes[0], frame_.X0, cur.arc_from, cur.arc_to};
    return true;
  }
  if (!cfg_.extend_search) return false;
  // The extension (algorithm.md G), one family at a time: the rest of the circle about
  // Y, then circles about the middle and the minor PCA axes.
  if (cur.next <= 3) {
    const int fam = cur.next++;
    if (fam == 1) {
      specs[0] =
          FamilySpec{ViewFamily::full_circle, axes[0], frame_.X0, 0.f, 2.f * kPiF, true, cur.arc_from, cur.arc_to};
      return true;
    }
    const Vec3 hint = sensors_.origin[sensors_.added[1] ? 1 : 0] - frame_.centroid;
    const Vec3 Xa = orthogonal_from(axes[fam - 1], hint);
    const ViewFamily vf = fam == 2 ? ViewFamily::middle_axis : ViewFamily::minor_axis;
    specs[0] = FamilySpec{vf, axes[fam - 1], Xa, 0.f, 2.f * kPiF};
    // The steps start from the sensor's direction, so they pass straight down only by
    // chance (5 deg off at worst), yet an object standing on the plane is grasped
    // best from straight above, its closing level: tilted 10 deg, the lower fingertip
    // of a grasp on a bottle's cap meets the unseen shoulder under it. The circle's
    // steepest approach joins the family as a viewpoint of its own.
    float th = 0.f;
    if (support_.found && steepest_theta(axes[fam - 1], Xa, support_.plane.n, cfg_.extension_dtheta_rad, th))
      specs[n_specs++] = FamilySpec{vf, axes[fam - 1], Xa, th, th};
    return true;
  }
  // Then (G, a tilted principal axis): circles about the support plane's axes. A
  // partial cloud (the top and one side of a box) tilts the PCA axes across it, and
  // then no family above approaches square to the faces of an object standing on the
  // plane: horizontal approaches all round, and approaches in the vertical planes
  // through the object's major and minor directions along the plane (top-down grasps
  // closing across the narrow side, or along the long one).
  if (!cur.sup_measured) {
    StageTimer t(stage_us, Stage::frame);
    cur.sup_measured = true;
    cur.have_sup = support_axes(object_, frame_.centroid, support_, cur.sup);
  }
  while (cur.have_sup && cur.next <= 6) {
    const int fam = cur.next++;
    // The footprint's sides, once, when the first circle that turns about them comes
    // (the per-view memory is idle between the families).
    if (fam >= 5 && !cur.foot_measured) {
      StageTimer t(stage_us, Stage::frame);
      cur.foot_measured = true;
      cur.have_foot = footprint_axes(object_, frame_.centroid, cur.sup, view_.proj, silhouette_.contour, cur.foot);
    }
    // Axis and start: the normal from the minor direction; the major direction from
    // the minor (theta 0: top-down, closing across the narrow side); the minor from
    // the major (theta pi: top-down, closing along the long side). The last two take
    // the footprint's sides when known (footprint_axes).
    const Vec3* in_plane = cur.have_foot ? cur.foot : cur.sup;
    const Vec3& axis = fam == 4 ? cur.sup[0] : in_plane[fam - 4];
    const Vec3& x0 = fam == 4 ? cur.sup[2] : fam == 6 ? in_plane[1] : in_plane[2];
    // A circle about (nearly) the same axis as one searched above is skipped: it would
    // search the same approaches again (an upright object's principal axis snaps to
    // the vertical, and its other axes are then horizontal too).
    bool searched = false;
    for (int a = 0; a < 3; ++a) searched = searched || std::fabs(axis.dot(axes[a])) > kSameAxisCos;
    if (searched) continue;
    specs[0] = FamilySpec{static_cast<ViewFamily>(fam), axis, x0, 0.f, 2.f * kPiF};
    return true;
  }
  return false;
}

// B-G for the current target: the object frame, the view families one at a time
// until one yields an executable grasp, then the second pass over the deferred grasps.
uint32_t Planner::search_grasp(PlanResult& out, NoGraspReason& reason, const char*& why) {
  views_.n = 0;
  candidates_.n = 0;
  selection_.begin_target();
  chosen_view_ = -1;
  families_.restart();
  // B. object frame, C. the sensor arc
  {
    StageTimer t(out.stage_us, Stage::frame);
    if (!build_object_frame(object_, sensors_, cfg_, frame_)) {
      reason = NoGraspReason::degenerate;
      why = "the object points have no defined principal axis (all identical)";
      return kMaxCandidates;
    }
    sensor_arc(view_context(), frame_.axes[0], frame_.X0, families_.arc_from, families_.arc_to);
  }
  uint32_t found = kMaxCandidates;
  FamilySpec specs[2];
  uint32_t n_specs = 0;
  while (found == kMaxCandidates && next_family(families_, specs, n_specs, out.stage_us))
    found = search_family(specs, n_specs, out);
  if (found == kMaxCandidates && cfg_.executability_checks) {
    StageTimer t(out.stage_us, Stage::select);
    found = selection_.second_pass(candidates_, checks_, grasp_check_, out.rejected_by_check);
  }

  if (found != kMaxCandidates) return found;
  bool any_kept = false;
  for (uint32_t v = 0; v < views_.n; ++v) any_kept = any_kept || views_.views[v].has_candidate;
  reason = NoGraspReason::collision;
  if (candidates_.n == 0) {
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
  const RejectCounts rj = RejectCounts::of(out.rejected_by_check);
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
    // Where a sensor would have to look: the hidden space of the first refused candidate
    // that has any (a thin grasp's refusal may be for space no sensor covered at all).
    const Vec3 up = support_.found ? Vec3(support_.plane.n.normalized()) : Vec3::UnitZ();
    Vec3 hidden = Vec3::Zero();
    for (uint32_t k = 0; k < selection_.n_occluded() && !out.look.valid; ++k)
      if (checks_.hidden_centre(candidates_.items[selection_.occluded(k)], hidden))
        out.look = advise_look(hidden, frame_.centroid, up, sensors_);
  } else {
    why = "every candidate hits the support plane or another object";
  }
  return kMaxCandidates;
}

Status Planner::analyze_view(uint32_t view_index, ViewDetail& out) {
  if (view_index >= views_.n) return Status::invalid_argument;
  const ViewRecord& v = views_.views[view_index];
  const Status s = trace_silhouette(candidate_context(), ViewFrame{v.X, v.Y, v.Z}, view_, 1, silhouette_);
  const uint32_t n = object_.size();
  for (uint32_t i = 0; i < n; ++i) out.points[i] = view_.proj[i];
  out.n_points = n;
  for (uint32_t i = 0; i < silhouette_.n_contour; ++i) out.contour[i] = silhouette_.contour[i];
  out.n_contour = silhouette_.n_contour;
  for (uint32_t i = 0; i < silhouette_.n_lines; ++i) out.lines[i] = silhouette_.lines[i];
  out.n_lines = silhouette_.n_lines;
  out.has_best = silhouette_.n_windows > 0;
  if (out.has_best) out.best = silhouette_.windows[0];
  return s;
}

Grasp Planner::grasp_of(const Candidate& c) const {
  const ViewRecord& v = views_.views[c.view];
  Grasp g;
  g.position = c.position;
  g.approach = c.Z.normalized();
  g.closing = c.X.normalized();
  g.width = c.width;
  g.beta = c.beta;
  g.dz = c.dz;
  g.viewpoint = v.theta;
  g.family = v.family;
  g.pregrasp = c.position - g.approach * (cfg_.gripper.finger_depth_m + cfg_.pregrasp_clearance_m);
  return g;
}

void Planner::fill_grasp(const Candidate& c, PlanResult& out) {
  chosen_view_ = static_cast<int32_t>(c.view);
  out.grasp = grasp_of(c);
}

uint32_t Planner::more_grasps(RankedGrasp* out, uint32_t max) {
  if (out == nullptr || chosen_candidate_ >= candidates_.n) return 0;
  const uint32_t before = n_alternates_;
  const uint32_t room = kMaxRankedGrasps - 1u - before;  // the returned grasp holds one place
  const uint32_t want = before + (max < room ? max : room);
  uint32_t n = selection_.alternates(candidates_, chosen_candidate_, checks_, grasp_check_, alternates_, before, want);
  // Too few among the candidates met so far: the families the search stopped before,
  // one at a time, until enough grasps are found or the families end. Their stage
  // times are not reported (the plan's report is written).
  StageTimes stage_us = {};
  FamilySpec specs[2];
  uint32_t n_specs = 0;
  while (n < want && next_family(families_, specs, n_specs, stage_us)) {
    generate_family(specs, n_specs, stage_us);
    n = selection_.alternates(candidates_, chosen_candidate_, checks_, grasp_check_, alternates_, n, want);
  }
  n_alternates_ = n;
  for (uint32_t k = before; k < n; ++k) {
    const Candidate& c = candidates_.items[alternates_[k]];
    out[k - before].grasp = grasp_of(c);
    checks_.margins(c, out[k - before].margins);
  }
  return n - before;
}

}  // namespace fg
