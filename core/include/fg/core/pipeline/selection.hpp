// Stage G, ranking and selection: candidates ranked by force balance (paper E.3) and
// checked in that order until one passes; the candidates the checks deferred wait for
// a second pass. The checks' budget (kMaxCheckedCandidates per plan) bounds both.
#pragma once
#include <cstdint>

#include "fg/core/grasp_check.hpp"
#include "fg/core/limits.hpp"
#include "fg/core/pipeline/candidates.hpp"
#include "fg/core/pipeline/grasp_checks.hpp"

namespace fg {

//! Per check, the candidates it rejected.
struct CheckRejections {
  uint32_t by_check[kCheckCount] = {};
  uint32_t operator[](CheckId id) const { return by_check[static_cast<uint32_t>(id)]; }
};

//! Two grasps are distinct when their closing lines or their approach directions lie at
//! least kDistinctAngle apart, or their centres kDistinctDistance: the gripper then
//! holds the object differently, not the same grasp a little moved.
inline constexpr float kDistinctAngleRad = 15.f * 3.14159265f / 180.f;
inline constexpr float kDistinctDistanceM = 0.01f;
[[nodiscard]] bool distinct_grasps(const Vec3& pos_a, const Vec3& closing_a, const Vec3& approach_a, const Vec3& pos_b,
                                   const Vec3& closing_b, const Vec3& approach_b);

class Selection {
 public:
  //! The start of a plan: the whole check budget, nothing deferred.
  void begin_plan() {
    checks_left_ = kMaxCheckedCandidates;
    begin_target();
  }
  //! Another target within the plan (the fall-back): nothing deferred or judged; the
  //! budget goes on.
  void begin_target() {
    n_deferred_ = 0;
    ranked_all_ = 0;
    n_occluded_ = 0;
    for (uint8_t& j : judged_) j = 0;
  }

  //! The first candidates (up to kOccludedKept, in the order judged) that the passes
  //! refused for occlusion (unknown_space, unseen_side): where a sensor would have to
  //! look (look_advice.hpp).
  static constexpr uint32_t kOccludedKept = 4;
  uint32_t n_occluded() const { return n_occluded_; }
  uint32_t occluded(uint32_t k) const { return occluded_[k]; }

  //! The first pass over candidates [first, list.n) (one family's): ranked, balanced
  //! ones (beta <= beta_max) by dZ, then the rest by beta, and checked in that order.
  //! A grasp with a finger partly in hidden space, or a pad whose corner meets a
  //! surface beside it, waits for the second pass. The passing candidate's index, or
  //! kMaxCandidates. With executability_checks off: the best ranked, unchecked.
  uint32_t first_pass(CandidateList& list, uint32_t first, GraspChecks& checks, GraspCheck* robot,
                      CheckRejections& rejected);

  //! The second pass, once every family is searched: the deferred candidates with the
  //! hidden samples the visibility check allows and the pads' corners let be, those
  //! straight down first, then the others, each in the order they were met. Straight
  //! down the pads close level and meet the sides they were fitted to; tilted, the lower
  //! pad reaches past them, where the sensors may not have seen.
  uint32_t second_pass(CandidateList& list, GraspChecks& checks, GraspCheck* robot, CheckRejections& rejected);

  //! After a grasp was chosen (index `chosen`): more grasps on the same target that pass
  //! every check, each distinct from the chosen one and from each other, in the first
  //! pass's order over all the target's candidates. Candidates the passes judged are
  //! not judged again; the plan's check budget bounds the rest. out[0, taken) holds
  //! the alternates taken before (by an earlier call); appends to them up to `max` in
  //! all and returns how many `out` then holds.
  uint32_t alternates(CandidateList& list, uint32_t chosen, GraspChecks& checks, GraspCheck* robot, uint32_t* out,
                      uint32_t taken, uint32_t max);

 private:
  //! The first pass's order (paper E.3) of candidates [first, list.n) into order_;
  //! returns their count.
  uint32_t rank(const CandidateList& list, uint32_t first);
  //! A candidate's checks with its repairs (a closing turned towards the contact
  //! normals, a round body's tangents), then the robot layer's check. It may replace c.
  [[nodiscard]] CheckVerdict judge(Candidate& c, bool first, GraspChecks& checks, GraspCheck* robot);

  uint16_t order_[kMaxCandidates];
  uint16_t deferred_[kMaxCandidates];  // deferred by the first pass, in the order met
  uint32_t n_deferred_ = 0;
  uint32_t checks_left_ = 0;             // candidates the checks may still examine in this plan
  uint8_t judged_[kMaxCandidates] = {};  // per candidate of this target: judged by a pass
  uint32_t ranked_all_ = 0;              // candidates order_ ranks as a whole (alternates), 0: none
  uint16_t occluded_[kOccludedKept] = {};
  uint32_t n_occluded_ = 0;
  // Counts a failed verdict under its check, and keeps the first refusals for occlusion.
  void count_failure(uint16_t index, const CheckVerdict& v, CheckRejections& rejected);
};

}  // namespace fg
