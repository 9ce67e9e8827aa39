// Stage F, the checks of one candidate grasp (algorithm.md F and G, docs/method.md):
// each has an id, and a candidate's verdict names the first check it failed, or that
// it waits for the second pass (selection.hpp). The checks read the scene through
// the stages' outputs they are bound to, and keep their own memory: the contact
// normals (computed on demand, once per target point) and the near list of the swept
// collision check.
#pragma once
#include <cstdint>

#include "fg/core/cluster.hpp"
#include "fg/core/config.hpp"
#include "fg/core/limits.hpp"
#include "fg/core/near_list.hpp"
#include "fg/core/pipeline/candidates.hpp"
#include "fg/core/pipeline/sensor_views.hpp"
#include "fg/core/pipeline/support_plane.hpp"
#include "fg/core/point_buffer.hpp"
#include "fg/core/voxel_grid.hpp"

namespace fg {

//! The checks, in the order a candidate meets them.
enum class CheckId : uint8_t {
  support_plane = 0,  //!< every corner of the swept fingers and palm table_clearance above the plane
  swept_collision,    //!< no voxel of the scene but the plane inside the swept fingers and palm
  local_hull,         //!< the open fingers outside the convex hull of the target's points about them
  under_target,       //!< the fingers clear of the space under the target, down to the plane
  unknown_space,      //!< the open fingers in space some sensor saw free, not hidden behind the object
  unseen_side,        //!< beside a partly hidden finger, the side no sensor saw clear of it
  friction_cone,      //!< each pad's contact normals within atan(mu) of the closing line
  robot_collision,    //!< the robot layer's check: the whole tool and arm along the motion
  robot_reach,        //!< the robot layer's check: joint solutions within the limits
  count
};
inline constexpr uint32_t kCheckCount = static_cast<uint32_t>(CheckId::count);
//! "support_plane", "swept_collision", ... (the JSON report's keys).
const char* to_string(CheckId id);

//! The unit of a check's margin: "m", "share" (of a finger's samples), "deg", or ""
//! where the check gives a verdict but no margin.
const char* margin_unit(CheckId id);

//! Per check, how far inside its bound a grasp lies, in the check's unit (positive:
//! inside; NaN: the check measures no margin, or does not apply to the grasp).
struct CheckMargins {
  float value[kCheckCount];
  float operator[](CheckId id) const { return value[static_cast<uint32_t>(id)]; }
};

//! A candidate's verdict: it passes, fails a check, or waits for the second pass
//! because of a check (a partly hidden finger, a pad closing through hidden space).
struct CheckVerdict {
  enum class Outcome : uint8_t { pass, fail, wait };
  Outcome outcome = Outcome::pass;
  CheckId check = CheckId::count;  //!< the check that failed or deferred it
  bool passed() const { return outcome == Outcome::pass; }
  static CheckVerdict pass() { return CheckVerdict{}; }
  static CheckVerdict fail(CheckId id) { return CheckVerdict{Outcome::fail, id}; }
  static CheckVerdict wait(CheckId id) { return CheckVerdict{Outcome::wait, id}; }
};

//! The stages' outputs the checks read (not owned; they outlive the checks' use).
struct CheckScene {
  const PlannerConfig& cfg;
  const PointSpan& object;       //!< the target's points
  const uint32_t* object_voxel;  //!< their voxels' indices in the grid
  const VoxelGrid& grid;         //!< every voxel, its state below
  const uint8_t* state;          //!< per voxel (cluster.hpp's VoxelState)
  const SupportPlane& support;
  const SensorViews& sensors;
};

// The near list's entries are cell << kNearIndexBits | voxel index, sorted with two
// tables of 2^kNearCellBits words lent by the per-view memory.
inline constexpr uint32_t kNearIndexBits = floor_log2(kMaxVoxels - 1u) + 1u;
inline constexpr uint32_t kViewWorkWordBits = floor_log2(sizeof(ViewWork) / sizeof(uint64_t));
inline constexpr uint32_t kNearCellBits =
    kViewWorkWordBits < 32u - kNearIndexBits ? kViewWorkWordBits : 32u - kNearIndexBits;
static_assert(kNearCellBits >= 3, "the near list needs at least one bit of cell per axis");

//! The most edges of the plausible body's hull (plausibly_solid); a target whose hull
//! has more is plausibly solid everywhere, as without a hull.
inline constexpr uint32_t kMaxBodyEdges = 128;

class GraspChecks {
 public:
  explicit GraspChecks(const CheckScene& scene)
      : cfg_(scene.cfg),
        object_(scene.object),
        object_voxel_(scene.object_voxel),
        grid_(scene.grid),
        state_(scene.state),
        support_(scene.support),
        sensors_(scene.sensors) {}
  GraspChecks(const GraspChecks&) = delete;
  GraspChecks& operator=(const GraspChecks&) = delete;

  //! The start of a target: its normals forgotten, the voxels a gripper at any of its
  //! candidates could touch listed in `storage` (grid.size() entries: the grid's lent
  //! count storage), sorted by cell with `tables` (2 << kNearCellBits words, lent), and
  //! its plausible body built in `scratch` (2 * kMaxObjectPoints points, lent; it may be
  //! the tables' memory, which the sort is done with by then).
  void begin_target(uint32_t* storage, uint32_t* tables, Vec2* scratch);
  //! No near list (before a target is loaded): the swept check walks every voxel.
  void forget_target() {
    n_near_ = 0;
    near_ = nullptr;
  }

  //! The checks in order, up to the first that fails or defers the candidate. In the
  //! first pass (first_pass) a finger partly in hidden space, or a pad whose closing
  //! stroke passes through it, defers; in the second it is judged.
  [[nodiscard]] CheckVerdict evaluate(const Candidate& c, bool first_pass);

  //! Every check's margin for a candidate (the returned grasp): measured once, after
  //! the selection, so the search pays nothing for it.
  void margins(const Candidate& c, CheckMargins& out);

  //! Closing along the contact normals' mean direction, kept orthogonal to the
  //! approach, when that turn is at most kMaxClosingTurn; width and centre measured
  //! again along it. False when there are too few normals or the turn is too large.
  [[nodiscard]] bool refine_closing(Candidate& c);
  //! A round body whose flanks were seen only to a grazing edge: the grasp on its
  //! unseen tangents (grazed_round.cpp). False when the model does not apply.
  [[nodiscard]] bool grazed_round_body(const Candidate& c, Candidate& round);
  //! The target could be solid at q: q lies in its plausible body, the prism over the
  //! convex hull, on the support plane, of its points and their mirror images through
  //! the hull's centre (the seen part completed by the symmetry of a body about its
  //! vertical axis), from the plane up to its highest point, grown by half a voxel.
  //! Everywhere true without a support plane or without such a hull.
  [[nodiscard]] bool plausibly_solid(const Vec3& q) const;
  //! A hidden q (visibility) could be solid: it lies inside the target's plausible
  //! body, or something else than the target hides it (another object, whose unseen
  //! part no body bounds).
  [[nodiscard]] bool could_be_solid(const Vec3& q) const;
  //! The outward normal (horizontal) of the plausible body's wall nearest q, when q lies
  //! within a voxel of it; false without a body. A flat-sided body's unseen side is
  //! that wall.
  [[nodiscard]] bool plausible_wall(const Vec3& q, Vec3& outward) const;

  //! The centre of the space that refused a candidate for occlusion: its open-finger
  //! samples hidden where something could be solid (the unknown-space check's samples),
  //! or for a thin grasp a finger's samples no sensor saw free. False when it has none.
  [[nodiscard]] bool hidden_centre(const Candidate& c, Vec3& centre);

  //! Within kTopDownCos of the support plane's downward normal.
  [[nodiscard]] bool straight_down(const Vec3& approach) const;

  CheckScene scene() const { return CheckScene{cfg_, object_, object_voxel_, grid_, state_, support_, sensors_}; }

 private:
  // clang-tidy reports the loop index of the copy the compiler generates for the array
  // members as a reserved identifier; nothing here is reserved.
  struct ContactNormalStats {    // NOLINT(bugprone-reserved-identifier)
    uint32_t total[2] = {0, 0};  //!< left, right
    uint32_t inside_cone[2] = {0, 0};
    Vec3 outward_sum[2] = {Vec3::Zero(), Vec3::Zero()};
    float z_first[2] = {1e9f, 1e9f};  //!< the shallowest contact point along the approach
    uint32_t level[2] = {0, 0};       //!< normals within 30 deg of the support plane's (a top)
    float top[2] = {-1e9f, -1e9f};    //!< the highest contact point above the support plane
  };
  void contact_normal_stats(const Vec3& pos, const ViewFrame& f, float width, ContactNormalStats& st);
  [[nodiscard]] bool friction_ok(const Vec3& pos, const ViewFrame& f, float width);
  void footprint_extremes(const Vec3& pos, const ViewFrame& f, float ext[2]) const;
  void contact_tilt(const Vec3& pos, const ViewFrame& f, float one_minus_cos[2], bool valid[2], bool flat[2],
                    float near_face[2], float edge_face[2]);
  // grow: the fingers' boxes grown by this much (m) on every side (margins()).
  [[nodiscard]] bool fingers_clear_of_hull(const Vec3& pos, const ViewFrame& f, float grow = 0.f);
  [[nodiscard]] bool footprint_applies(const ViewFrame& f, float width) const;
  [[nodiscard]] bool fingers_clear_of_footprint(const Vec3& pos, const ViewFrame& f, float width, float grow = 0.f);
  // hidden_sum: the sum of the hidden samples that count (world), hidden_share their share
  // of all; a thin grasp refused for too little space seen free: that finger's samples
  // not seen free.
  [[nodiscard]] int fingers_in_seen_space(const Vec3& pos, const ViewFrame& f, float width, uint32_t& partly_hidden,
                                          float* hidden_share = nullptr, Vec3* hidden_sum = nullptr);
  [[nodiscard]] uint32_t hidden_in_strokes(const Vec3& pos, const ViewFrame& f, float width) const;
  float swept_clearance(const Candidate& c) const;
  float friction_margin_deg(const Candidate& c);
  [[nodiscard]] bool unseen_side_clear(const Vec3& pos, const ViewFrame& f, int side);
  [[nodiscard]] bool blind_side_mirrors_seen(const Vec3& pos, const ViewFrame& f, float width, uint32_t hidden_sides);
  [[nodiscard]] bool round_front_clears_blind_side(const Vec3& pos, const ViewFrame& f, int blind_side);
  [[nodiscard]] bool top_goes_on_past(const Vec3& pos, const ViewFrame& f, float width, int side);
  //! +1 seen free, -1 hidden, 0 unknown (SensorViews::visibility).
  int visibility(const Vec3& q) const { return static_cast<int>(sensors_.visibility(q)); }
  [[nodiscard]] bool normal_at(uint32_t object_index, Vec3& n);
  [[nodiscard]] bool normal_planar(uint32_t object_index) const;  //!< after normal_at returned true

  const PlannerConfig& cfg_;
  const PointSpan& object_;
  const uint32_t* object_voxel_;
  const VoxelGrid& grid_;
  const uint8_t* state_;
  const SupportPlane& support_;
  const SensorViews& sensors_;

  // Voxels within the gripper's reach of the object (begin_target), sorted by their
  // cell of a coarse grid over the cube around the reach sphere (near_list.hpp), so
  // the swept check reads only the cells under each box.
  uint32_t* near_ = nullptr;
  uint32_t n_near_ = 0;
  Vec3 near_centre_ = Vec3::Zero();
  float near_slack_ = 0.f;
  float near_reach_ = 0.f;   // the farthest corner of the swept boxes from the grasp point
  float near_radius_ = 0.f;  // the list holds every voxel within this of near_centre_
  NearGrid near_grid_{};

  // The plausible body (plausibly_solid): its hull's edges as inward unit normals and
  // offsets in the plane's (u, v) frame, n . p >= d inside, and its height.
  void build_plausible_body(Vec2* scratch);
  [[nodiscard]] bool in_body(const Vec3& q, float grow) const;
  //! q within the outline's prism grown by half a voxel, for any body (false without one).
  [[nodiscard]] bool in_outline(const Vec3& q) const;
  Vec3 body_u_ = Vec3::UnitX(), body_v_ = Vec3::UnitY();
  Vec2 body_normal_[kMaxBodyEdges];
  float body_offset_[kMaxBodyEdges];
  uint32_t n_body_edges_ = 0;
  bool flat_sided_ = false;  // the outline is the body's (plausibly_solid)
  float body_top_ = 0.f;
  float body_lo_[2] = {0.f, 0.f}, body_hi_[2] = {0.f, 0.f};  // the hull's bounding box

  // Normals of object points, computed on demand for the friction test.
  Vec3 normals_[kMaxObjectPoints];
  uint8_t normal_state_[kMaxObjectPoints];  // 0 unknown, 1 valid, 2 undefined, 3 valid, not planar
  Vec3 local_[kMaxObjectPoints];            // object points near the hand, grasp frame
};

}  // namespace fg
