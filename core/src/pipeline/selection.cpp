// Stage G: ranking and selection (selection.hpp).
#include "fg/core/pipeline/selection.hpp"

#include <algorithm>
#include <cmath>

namespace fg {
namespace {
// Smaller turns of a passing grasp's closing towards its contact normals are not worth
// a second check (rad).
constexpr float kMarginTurn = 0.05f;
}  // namespace

CheckVerdict Selection::judge(Candidate& c, bool first, GraspChecks& checks, GraspCheck* robot) {
  const CheckScene scene = checks.scene();
  const PlannerConfig& cfg = scene.cfg;
  CheckVerdict verdict = checks.evaluate(c, first);
  const auto outside_cone = [&verdict] {
    return verdict.outcome == CheckVerdict::Outcome::fail && verdict.check == CheckId::friction_cone;
  };
  // An alternative to a candidate outside the cone, checked from the start, replaces it
  // when it passes or waits for the second pass.
  const auto take_if_it_passes = [&](const Candidate& alt) {
    const CheckVerdict t = checks.evaluate(alt, first);
    if (t.outcome != CheckVerdict::Outcome::fail) {
      c = alt;
      verdict = t;
    }
  };
  // A contact a little outside the cone (closing across a prism's diagonal, a tilted
  // handle): turn the closing direction about the approach towards the contact
  // normals, and check the turned grasp from the start.
  if (outside_cone()) {
    Candidate turned = c;
    if (checks.refine_closing(turned)) take_if_it_passes(turned);
  }
  // Still outside the cone: a round body whose flanks were seen only to a grazing edge
  // (grazed_round.cpp) closes on its tangents beyond them, with the width between them.
  if (outside_cone()) {
    Candidate round;
    if (checks.grazed_round_body(c, round)) take_if_it_passes(round);
  }
  // A grasp that passes with its contact normals off the closing line: closing along
  // them gives friction margin, when the turned grasp passes too.
  if (verdict.passed() && cfg.friction_mu > 0.f) {
    Candidate turned = c;
    if (checks.refine_closing(turned) && turned.X.dot(c.X) < std::cos(kMarginTurn) &&
        checks.evaluate(turned, first).passed())
      c = turned;
  }
  // Then the check of the layers above (robot: inverse kinematics, the whole tool).
  if (verdict.passed() && robot != nullptr) {
    const Vec3 z = c.Z.normalized();
    const GraspQuery q{c.position,
                       z,
                       c.X.normalized(),
                       c.position - z * (cfg.gripper.finger_depth_m + cfg.pregrasp_clearance_m),
                       c.width,
                       scene.support.found ? &scene.support.plane : nullptr,
                       &scene.object[0],
                       scene.object.size(),
                       scene.grid.centroids(),
                       scene.state,
                       scene.grid.size()};
    const GraspVerdict v = robot->check(q);
    if (v == GraspVerdict::collision) verdict = CheckVerdict::fail(CheckId::robot_collision);
    // An unknown verdict never passes.
    else if (v != GraspVerdict::pass)
      verdict = CheckVerdict::fail(CheckId::robot_reach);
  }
  return verdict;
}

bool distinct_grasps(const Vec3& pos_a, const Vec3& closing_a, const Vec3& approach_a, const Vec3& pos_b,
                     const Vec3& closing_b, const Vec3& approach_b) {
  const float cos_min = std::cos(kDistinctAngleRad);
  // A parallel gripper's closing is a line: X and -X close alike.
  return std::fabs(closing_a.normalized().dot(closing_b.normalized())) < cos_min ||
         approach_a.normalized().dot(approach_b.normalized()) < cos_min || (pos_a - pos_b).norm() >= kDistinctDistanceM;
}

uint32_t Selection::rank(const CandidateList& list, uint32_t first) {
  const uint32_t m = list.n - first;
  for (uint32_t i = 0; i < m; ++i) order_[i] = static_cast<uint16_t>(first + i);
  // Paper E.3: balanced candidates (beta <= beta_max) by dZ, then the rest by beta.
  // The index breaks ties, so the order is total and the result deterministic. A heap
  // sort: O(m log m) at worst and no recursion.
  const Candidate* cs = list.items;
  const auto before = [cs](uint16_t a, uint16_t b) {
    const Candidate &ca = cs[a], &cb = cs[b];
    if (ca.balanced != cb.balanced) return ca.balanced;
    const float ka = ca.balanced ? ca.dz : ca.beta, kb = cb.balanced ? cb.dz : cb.beta;
    if (ka != kb) return ka < kb;
    return a < b;
  };
  std::make_heap(order_, order_ + m, before);
  std::sort_heap(order_, order_ + m, before);
  return m;
}

uint32_t Selection::first_pass(CandidateList& list, uint32_t first, GraspChecks& checks, GraspCheck* robot,
                               CheckRejections& rejected) {
  ranked_all_ = 0;  // order_ is this family's now
  const uint32_t m = rank(list, first);
  if (!checks.scene().cfg.executability_checks) return m > 0 ? order_[0] : kMaxCandidates;
  for (uint32_t i = 0; i < m && checks_left_ > 0; ++i) {
    Candidate& c = list.items[order_[i]];
    // A pad's corner meets a surface beside it (xoz_candidate): the grasp waits
    // unchecked, so the budget goes to the others first.
    if (!c.corners_clear) {
      deferred_[n_deferred_++] = order_[i];
      continue;
    }
    --checks_left_;
    judged_[order_[i]] = 1;
    const CheckVerdict v = judge(c, true, checks, robot);
    if (v.passed()) return order_[i];
    if (v.outcome == CheckVerdict::Outcome::wait)
      deferred_[n_deferred_++] = order_[i];
    else
      count_failure(order_[i], v, rejected);
  }
  return kMaxCandidates;
}

void Selection::count_failure(uint16_t index, const CheckVerdict& v, CheckRejections& rejected) {
  ++rejected.by_check[static_cast<uint32_t>(v.check)];
  if ((v.check == CheckId::unknown_space || v.check == CheckId::unseen_side) && n_occluded_ < kOccludedKept)
    occluded_[n_occluded_++] = index;
}

uint32_t Selection::second_pass(CandidateList& list, GraspChecks& checks, GraspCheck* robot,
                                CheckRejections& rejected) {
  for (int down = 1; down >= 0; --down)
    for (uint32_t i = 0; i < n_deferred_ && checks_left_ > 0; ++i) {
      Candidate& c = list.items[deferred_[i]];
      if (checks.straight_down(c.Z) != (down == 1)) continue;
      --checks_left_;
      judged_[deferred_[i]] = 1;
      const CheckVerdict v = judge(c, false, checks, robot);
      if (v.passed()) return deferred_[i];
      count_failure(deferred_[i], v, rejected);
    }
  return kMaxCandidates;
}

uint32_t Selection::alternates(CandidateList& list, uint32_t chosen, GraspChecks& checks, GraspCheck* robot,
                               uint32_t* out, uint32_t taken, uint32_t max) {
  if (taken >= max || chosen >= list.n || !checks.scene().cfg.executability_checks) return taken;
  // order_ holds every candidate's rank from the last call while no candidate was added
  // since (a caller asking for one alternate at a time ranks once per family).
  if (ranked_all_ != list.n) ranked_all_ = rank(list, 0);
  const uint32_t m = ranked_all_;
  uint32_t n = taken;
  const auto distinct_from_taken = [&](const Candidate& c) {
    const Candidate& best = list.items[chosen];
    if (!distinct_grasps(c.position, c.X, c.Z, best.position, best.X, best.Z)) return false;
    for (uint32_t k = 0; k < n; ++k) {
      const Candidate& t = list.items[out[k]];
      if (!distinct_grasps(c.position, c.X, c.Z, t.position, t.X, t.Z)) return false;
    }
    return true;
  };
  for (uint32_t i = 0; i < m && n < max && checks_left_ > 0; ++i) {
    const uint16_t idx = order_[i];
    Candidate& c = list.items[idx];
    // Judged already (failed, or the chosen one), or one the first pass would defer: a
    // pad's corner meets a surface beside it, which only the second pass may allow.
    if (judged_[idx] || !c.corners_clear || !distinct_from_taken(c)) continue;
    --checks_left_;
    judged_[idx] = 1;
    // The checks may turn the closing (judge): still distinct after that?
    if (judge(c, true, checks, robot).passed() && distinct_from_taken(c)) out[n++] = idx;
  }
  return n;
}

}  // namespace fg
