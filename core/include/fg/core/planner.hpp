// The grasp planner: one fixed-size workspace object that ingests the sensors'
// points and plans a force-balance grasp (design/algorithm.md A-F).
// It never allocates, throws or recurses; every loop is bounded by a capacity of
// fg_limits.h or a configured count. Construct it once (it is large: keep it static
// or in caller memory), configure(), then per plan: reset(), add_*(), plan().
#pragma once
#include <cstdint>

#include "fg/core/config.hpp"
#include "fg/core/grasp_check.hpp"
#include "fg/core/limits.hpp"
#include "fg/core/pinhole.hpp"
#include "fg/core/pipeline/candidates.hpp"
#include "fg/core/pipeline/fragments.hpp"
#include "fg/core/pipeline/grasp_checks.hpp"
#include "fg/core/pipeline/look_advice.hpp"
#include "fg/core/pipeline/object_frame.hpp"
#include "fg/core/pipeline/registration.hpp"
#include "fg/core/pipeline/selection.hpp"
#include "fg/core/pipeline/sensor_views.hpp"
#include "fg/core/pipeline/stage_timer.hpp"
#include "fg/core/pipeline/support_plane.hpp"
#include "fg/core/pipeline/target.hpp"
#include "fg/core/pipeline/viewpoints.hpp"
#include "fg/core/plane.hpp"
#include "fg/core/point_buffer.hpp"
#include "fg/core/status.hpp"
#include "fg/core/types.hpp"
#include "fg/core/voxel_grid.hpp"

namespace fg {
namespace ingest {
struct State;
}

struct Grasp {
  Vec3 position = Vec3::Zero();   //!< world, centre between the pads
  Vec3 approach = Vec3::UnitZ();  //!< world unit vector, palm towards object
  Vec3 closing = Vec3::UnitX();   //!< world unit vector, one finger towards the other
  float width = 0.f;              //!< object width between the contact regions (m)
  float beta = 0.f;               //!< XOY force balance (rad)
  float dz = 0.f;                 //!< XOZ force balance (m)
  float viewpoint = 0.f;          //!< rotation of the chosen viewpoint about its axis (rad)
  ViewFamily family = ViewFamily::sensor_arc;
  Vec3 pregrasp = Vec3::Zero();  //!< position backed off along -approach
};

//! A piece of a sensor's points, as a PointSource hands it over: point i's coordinates
//! are floats (host byte order, any alignment) at x + i * stride, y + i * stride and
//! z + i * stride.
struct PointPiece {
  const uint8_t* x = nullptr;
  const uint8_t* y = nullptr;
  const uint8_t* z = nullptr;
  uint32_t stride = 0;  //!< bytes from one point's coordinate to the next one's (>= 4)
  uint32_t count = 0;   //!< points in the piece; 0: the source has no more
};

//! A sensor's points in pieces that the planner pulls one after another: a file read in
//! bounded chunks, a driver's DMA buffers. A piece must stay valid until the next call.
class PointSource {
 public:
  //! The next piece (count 0 at the end); false when the source failed (it knows why).
  [[nodiscard]] virtual bool next(PointPiece& piece) = 0;
  //! A source that can start again from its first piece says so: the planner then
  //! reads a hand sensor's cloud twice, to register it first (A.4b). rewind() is
  //! called only when can_rewind() is true; false when it failed.
  virtual bool can_rewind() const { return false; }
  [[nodiscard]] virtual bool rewind() { return false; }

 protected:
  PointSource() = default;
  PointSource(const PointSource&) = default;
  PointSource& operator=(const PointSource&) = default;
  ~PointSource() = default;  // not owned through this interface
};

struct PointCounts {
  uint32_t input = 0;         //!< points offered by the sensors
  uint32_t finite = 0;        //!< finite points
  uint32_t after_filter = 0;  //!< inside the range filter and the crop box
  uint32_t voxels = 0;        //!< occupied voxels of the merged cloud
  uint32_t plane = 0;         //!< voxels of the support plane
  uint32_t object = 0;        //!< voxels of the target object
};

//! The crop box the grid was built in (x, y; world): the configured one, or a smaller
//! one about the workspace centre when the cloud needed more than kMaxVoxels voxels.
struct CropUsed {
  float min_x = 0, min_y = 0, max_x = 0, max_y = 0;
  uint32_t shrinks = 0;         //!< times it shrank (0: as configured)
  uint32_t points_dropped = 0;  //!< points kept before a shrink and outside the box after it
};

//! Why candidates were turned down during the checks, grouped as the report's
//! `search.rejected` gives them (CheckRejections has them per check).
struct RejectCounts {
  uint32_t table = 0, collision = 0, friction = 0, occluded = 0, unreachable = 0;
  static RejectCounts of(const CheckRejections& r);
};

//! One of the ranked grasps (Planner::more_grasps): the grasp and every check's margin.
struct RankedGrasp {
  Grasp grasp;
  CheckMargins margins;  //!< per check, in the check's unit; NaN: none measured
};

struct PlanResult {
  Status status = Status::internal_error;
  NoGraspReason reason = NoGraspReason::none;
  const char* message = "";  //!< static text naming the problem
  Grasp grasp;
  PointCounts points;
  CropUsed crop;
  RejectCounts rejected;
  CheckRejections rejected_by_check;
  CheckMargins margins;     //!< of the grasp (status ok), per check; NaN: none measured
  uint32_t viewpoints = 0;  //!< viewpoints analysed
  uint32_t candidates = 0;  //!< candidates ranked
  uint32_t stage_us[static_cast<uint32_t>(Stage::count)] = {};
  //! A.4b: how the hand sensor was registered to the head (not_run with one sensor).
  //! Its time is in stage_us's total (and its own `us`), not in another stage's.
  RegistrationResult registration;
  //! With reason occluded: which sensor would have to look where (look_advice.hpp).
  LookAdvice look;
};

//! A stage-by-stage picture of one viewpoint, recomputed on demand (host pictures).
struct ViewDetail {
  Vec2 points[kMaxObjectPoints];
  uint32_t n_points = 0;
  Vec2 contour[kMaxContourVertices];
  uint32_t n_contour = 0;
  ScanLine lines[kMaxScanLines];
  uint32_t n_lines = 0;
  SideFit best;
  bool has_best = false;
};

//! The check every add_* call makes of a sensor's pose: finite (non_finite), a rotation
//! (orthonormal within 1e-3, not a reflection) and within 100 m of the robot
//! (invalid_pose); ok otherwise. *message (when not null): static text naming the
//! problem, starting with "sensor pose", or "".
[[nodiscard]] Status validate_pose(const Pose& p, const char** message = nullptr);

class Planner {
 public:
  Planner() = default;
  Planner(const Planner&) = delete;
  Planner& operator=(const Planner&) = delete;

  //! Validates and installs cfg (invalid_config names the field via *field), and resets.
  [[nodiscard]] Status configure(const PlannerConfig& cfg, const char** field = nullptr);
  const PlannerConfig& config() const { return cfg_; }

  //! A check of the layers above (robot: IK, the whole tool) asked about every
  //! candidate that passes the core's checks; null (the default) for none. Not owned;
  //! it must outlive the plan() calls made while it is set.
  void set_grasp_check(GraspCheck* check) { grasp_check_ = check; }
  GraspCheck* grasp_check() const { return grasp_check_; }

  //! Forgets all sensor data.
  void reset();

  //! Adds `count` points (x, y, z floats, `stride_bytes` apart) given in the sensor's
  //! optical frame. Non-finite points and points outside the range filter or the crop
  //! box are dropped and counted. Each role may be added once per plan. When the merged
  //! cloud would need more than kMaxVoxels voxels the crop box shrinks (crop_shrink_min,
  //! PlanResult::crop); capacity_exceeded only when it cannot shrink further.
  [[nodiscard]] Status add_points(SensorRole role, const float* xyz, uint32_t count, uint32_t stride_bytes,
                                  const Pose& world_T_sensor);

  //! The same for a structure of arrays: point i is (x[i], y[i], z[i]) (a sensor SDK's
  //! planar buffers, a PCD file's binary_compressed block as decompressed: no copy into
  //! x y z triples first).
  [[nodiscard]] Status add_points_planar(SensorRole role, const float* x, const float* y, const float* z,
                                         uint32_t count, const Pose& world_T_sensor);

  //! The same for points that arrive in pieces (a file read chunk by chunk into one
  //! bounded buffer): one sensor's points, in their order, as if added in one call.
  //! invalid_argument when the source fails (its own message says why) or hands over a
  //! piece with a null coordinate or a stride under 4 bytes; the points before stay in.
  [[nodiscard]] Status add_point_source(SensorRole role, PointSource& source, const Pose& world_T_sensor);

  //! Adds a depth image (uint16 millimetres, 0 = no reading, row-major width x height).
  [[nodiscard]] Status add_depth_image(SensorRole role, const uint16_t* depth_mm, uint16_t width, uint16_t height,
                                       const PinholeIntrinsics& k, const Pose& world_T_sensor);

  //! The units of a sensor's points (add_points, add_points_planar, add_point_source):
  //! metres per unit, 1 (metres, the default) or 0.001 (millimetres), within 1e-6 .. 1e3.
  //! Kept across reset() and configure(). Depth images carry their millimetres and are
  //! not scaled. A sensor whose every point fails the range filter while most of its
  //! depths would pass it in other units (units.hpp) is refused with invalid_argument
  //! and a message naming the likely units, rather than planned as "no points".
  [[nodiscard]] Status set_sensor_units(SensorRole role, float metres_per_unit);
  float sensor_units(SensorRole role) const { return units_.m[static_cast<uint32_t>(role) % kMaxSensors]; }

  //! Whether the hand sensor is registered to the head before its points join the grid
  //! (registration.hpp; on by default). That happens when the hand is added after the
  //! head: its cloud is then read twice (its sight map, the registration, its points
  //! with the corrected pose); a point source must be able to rewind. Kept across
  //! reset() and configure().
  void set_registration(RegistrationMode mode) { registration_mode_ = mode; }
  RegistrationMode registration_mode() const { return registration_mode_; }
  //! The registration since reset() (also in plan()'s result).
  const RegistrationResult& registration() const { return registration_; }
  //! The last plan's advice after a refusal as occluded (also in its result).
  const LookAdvice& look() const { return look_; }

  //! This planner's ingest vector width: 0 (the default) the widest this CPU runs (8
  //! lanes on x86-64 with AVX2, else 4), 4 the path of every target. Every width gives
  //! the same grid, bit for bit; tests and benchmarks compare them. Kept across reset().
  void set_ingest_lanes(uint32_t lanes) { ingest_lanes_ = lanes; }
  //! The width this planner's next add_* call uses (4 or 8).
  uint32_t ingest_lanes() const;

  //! Plans on everything added since reset(). When the target cluster yields no grasp
  //! and lies over the footprint of a larger cluster, that cluster is searched once
  //! more (the target-fragment fall-back, docs/method.md A.6). The result's
  //! viewpoints, candidates, rejections and stage times then cover both searches; when
  //! both fail, its reason, message and points are the first target's, while the
  //! inspection below shows the last search (the fall-back cluster).
  [[nodiscard]] Status plan(PlanResult& out);

  //! After plan() returned ok, and before the next reset(): up to `max` more grasps on the
  //! same target, each passing every check (the robot's too) and distinct from the
  //! returned grasp and from each other (closing lines or approaches at least 15 deg
  //! apart, or centres 1 cm: selection.hpp). Best first, in the planner's own order
  //! (force balance, paper E.3) over the target's candidates; what is left of the plan's
  //! check budget bounds the search, and kMaxRankedGrasps (FG_MAX_RANKED_GRASPS) the
  //! count. Returns how many were written to `out` (0 when plan() did not return ok, or
  //! `out` is null). Set the same grasp check as for plan(); its recorded motion is then
  //! the last alternate's: read the returned grasp's before. A further call goes on
  //! where the last stopped: the grasps it returned do not come back, and all calls
  //! since plan() return at most kMaxRankedGrasps - 1.
  uint32_t more_grasps(RankedGrasp* out, uint32_t max);

  //! What picks the target of the next plan() calls: by the configured rule (the
  //! default, TargetSpec{}), the cluster nearest a world point, or the cluster with the
  //! most voxels inside a world box (cluster.hpp). Kept across reset() and configure().
  //! A spec that fails validate(TargetSpec) is refused (its status; last_message() says
  //! why) and the one before stays. plan() answers invalid_argument when the point, or
  //! the whole box, lies outside the configured workspace crop box, and no_grasp
  //! (no_object) when no cluster has a voxel inside the box.
  [[nodiscard]] Status set_target(const TargetSpec& target);
  const TargetSpec& target() const { return target_; }

  //! The objects on the support plane that the last plan() found (clusters of at least
  //! min_object_points), nearest the workspace centre first: at most kMaxObjects
  //! (FG_MAX_OBJECTS); objects_dropped() counts those left out. Empty before a plan()
  //! reached its clustering stage, and after reset().
  uint32_t object_count() const { return objects_ready_ ? clusters_.n_objects : 0u; }
  //! Object k < object_count() (its centroid, box and voxel count; world frame).
  const ObjectSummary& object(uint32_t k) const { return clusters_.objects[k < kMaxObjects ? k : 0u]; }
  uint32_t objects_dropped() const { return objects_ready_ ? clusters_.objects_dropped : 0u; }
  //! The index in that list of the cluster the last plan() or plan_object() searched
  //! (the target; after the fall-back, its cluster), or -1 (none, or not listed).
  int32_t target_object() const;

  //! After plan(), and before the next reset(): plans again, stages B-G, for object k of
  //! its list, with every other voxel above the plane as an obstacle and the same
  //! support plane. The result is as plan() fills it for its target (no fall-back: each
  //! object answers for itself); its stage times cover this call alone (no ingest or
  //! plane). invalid_sequence when no plan() reached the objects, invalid_argument when
  //! k >= object_count(). more_grasps() and the inspection then refer to this object.
  [[nodiscard]] Status plan_object(uint32_t k, PlanResult& out);

  //! The message of the last add_* or plan failure (static text).
  const char* last_message() const { return message_; }

  // Inspection after plan(), for reports and pictures (host side).
  //! A sensor's nearest returns (mm, 0xFFFF = none) in kSightBins x kSightBins direction
  //! bins over x / z and y / z in [-1, 1), row by row (bin v * kSightBins + u): the
  //! visibility the checks ask about. Fed by every other point with a positive depth.
  //! A sensor's pose as the planner uses it: as given, or the hand's as registered.
  const Pose& sensor_pose(SensorRole role) const { return sensors_.pose[static_cast<uint32_t>(role) % kMaxSensors]; }
  const uint16_t* sight_map(SensorRole role) const {
    return sensors_.sight_mm[static_cast<uint32_t>(role) % kMaxSensors];
  }
  const Plane& plane() const { return support_.plane; }
  bool plane_found() const { return support_.found; }
  const PointSpan& object_points() const { return object_; }
  const VoxelGrid& voxels() const { return grid_; }
  uint8_t voxel_state(uint32_t i) const { return state_[i]; }
  uint32_t view_count() const { return views_.n; }
  const ViewRecord& view(uint32_t i) const { return views_.views[i]; }
  int32_t chosen_view() const { return chosen_view_; }
  const Vec3& object_centroid() const { return frame_.centroid; }
  //! Recomputes the silhouette, contour, scan lines and best window of a viewpoint.
  [[nodiscard]] Status analyze_view(uint32_t view_index, ViewDetail& out);

 private:
  [[nodiscard]] Status check_pose(const Pose& p);
  // A sensor's start: the role once per capture, before plan(), with a rigid pose;
  // then its ingest state (the transform to cells, the crop box, its direction bins).
  // `in_sensor_units`: the points are in the sensor's units (set_sensor_units); false for
  // a depth image's, in metres.
  [[nodiscard]] Status ingest_begin(SensorRole role, const Pose& world_T_sensor, ingest::State& in,
                                    bool in_sensor_units = true);
  [[nodiscard]] Status end_ingest(uint32_t offered, uint32_t finite, uint32_t kept, uint64_t t0, Status st);
  // After a sensor's points (not a depth image's): st, or invalid_argument when none
  // passed the range filter and their depths name other units (units.hpp).
  [[nodiscard]] Status check_units(const ingest::State& in, SensorRole role, Status st);
  // Before a block of n points: room for n more voxels, the crop box shrunk if need be
  // (at crop_shrink_min the block is added as far as the grid holds it).
  void make_room(ingest::State& in, uint32_t n);
  //! The empty grid over the configured crop box (reset(), leave_out_head()).
  void reset_grid();
  //! A.4c: the head's points out of the grid, the hand's to plan from alone.
  void leave_out_head();
  void shrink_crop(ingest::State& in);
  // The loop every point layout shares: coordinate k of point i at base[k] + i * stride.
  [[nodiscard]] Status add_coordinates(SensorRole role, const uint8_t* const base[3], uint32_t count,
                                       uint32_t stride_bytes, const Pose& world_T_sensor);
  // One piece of a sensor's points into the grid; false when the grid is full.
  [[nodiscard]] bool ingest_piece(ingest::State& in, const uint8_t* const base[3], uint32_t count,
                                  uint32_t stride_bytes);
  // What a plan's report counts from its start: the clock, the time of work before it
  // (ingest, for plan()), and the viewpoints and candidates of a first search that gave
  // way to the fall-back.
  struct PlanTally {
    uint64_t t_start = 0;
    uint32_t earlier_us = 0;
    uint32_t views_before = 0, candidates_before = 0;
  };
  // Fills the report's status, counts and total time; returns s.
  Status finish(PlanResult& out, const PlanTally& tally, Status s, NoGraspReason r, const char* msg);
  // The start of plan() and plan_object(): an empty report and a fresh search state.
  void begin_report(PlanResult& out);
  // The end of plan() and plan_object(), after the search: the grasp of candidate
  // `found` (ok), or no_grasp for `reason` when found is kMaxCandidates.
  Status report_search(PlanResult& out, const PlanTally& tally, uint32_t found, NoGraspReason reason, const char* why);
  // The crop box as configured (world; before any shrink).
  void configured_crop(Vec3& lo, Vec3& hi) const;
  // A target outside the configured crop box: the message, or null.
  const char* target_outside_workspace() const;
  // The target's voxels (object_voxel_[0, size)) become the object points, and the
  // checks' near list is built around them in `storage`.
  void load_target(uint32_t size, uint32_t* storage);
  // Stages B-G for the loaded target: the index of the grasp's candidate, or
  // kMaxCandidates with the no_grasp reason and message.
  uint32_t search_grasp(PlanResult& out, NoGraspReason& reason, const char*& why);
  // Stages C-G for one family of viewpoints (its circle, and a viewpoint of its own
  // where one is added): the grasp's candidate, or kMaxCandidates.
  uint32_t search_family(const FamilySpec* specs, uint32_t n_specs, PlanResult& out);
  // Stages C-E for one family: its viewpoints and their candidates, unchecked.
  void generate_family(const FamilySpec* specs, uint32_t n_specs, StageTimes& stage_us);
  // Where the search of a target stands in its sequence of view families.
  struct FamilyCursor {
    int next = 0;                        // 0 the sensor arc, 1-3 the PCA circles, 4-6 the support's
    float arc_from = 0.f, arc_to = 0.f;  // the sensor arc (C)
    Vec3 sup[3], foot[3];                // the support plane's axes, the footprint's sides
    bool sup_measured = false, have_sup = false, foot_measured = false, have_foot = false;
    // The start of a target's search (the axes are measured again when needed). Not an
    // assignment of a fresh cursor: clang-tidy takes the loop variable of the implicit
    // copy of the arrays for a reserved identifier.
    void restart() {
      next = 0;
      arc_from = arc_to = 0.f;
      sup_measured = have_sup = foot_measured = have_foot = false;
    }
  };
  // The next family of the target's search order into specs (1 or 2 of them); false
  // when every family was searched.
  [[nodiscard]] bool next_family(FamilyCursor& cur, FamilySpec specs[2], uint32_t& n_specs, StageTimes& stage_us);
  void fill_grasp(const Candidate& c, PlanResult& out);
  Grasp grasp_of(const Candidate& c) const;
  ViewContext view_context() const { return ViewContext{cfg_, support_, sensors_, frame_.centroid}; }
  CandidateContext candidate_context() const { return CandidateContext{cfg_, object_, frame_.centroid, support_}; }

  PlannerConfig cfg_;
  GraspCheck* grasp_check_ = nullptr;
  const char* message_ = "";

  // Ingest (A.1-A.4): what the sensors saw, and the merged cloud's voxel grid.
  SensorViews sensors_;
  PointCounts counts_;
  // The crop box in the grid's cell units, as the ingest tests points against it (its
  // world bounds are in crop_used_): the configured box, or after shrink_crop() one of
  // whole cells (lo <= f <= hi, hi just below a cell boundary).
  float crop_lo_cells_[3] = {}, crop_hi_cells_[3] = {};
  CropUsed crop_used_;
  uint32_t ingest_us_ = 0;
  bool overflow_ = false;
  uint32_t ingest_lanes_ = 0;  // the width asked for (set_ingest_lanes)
  struct SensorUnits {         // metres per unit of each sensor's points (set_sensor_units)
    float m[kMaxSensors];
    SensorUnits() {
      for (float& v : m) v = 1.f;
    }
  } units_;
  VoxelGrid grid_;
  uint8_t state_[kMaxVoxels];  // per voxel (cluster.hpp's VoxelState)
  // A.4b registration of the hand sensor to the head.
  RegistrationMode registration_mode_ = RegistrationMode::on;
  RegistrationResult registration_;
  LookAdvice look_;  // the last plan's (PlanResult::look)
  bool registers(SensorRole role) const;
  void begin_hand_pass(ingest::State& in);
  //! False when the hand's points are to stay out (sensor_disagreement).
  [[nodiscard]] bool register_hand(ingest::State& in, bool in_sensor_units);
  Status read_source(ingest::State& in, PointSource& source, uint32_t& offered);
  Status depth_pass(ingest::State& in, const uint16_t* depth_mm, uint16_t width, uint16_t height,
                    const PinholeIntrinsics& k);

  // A.5 support plane, A.6 target, B object frame, C viewpoints.
  SupportPlane support_;
  TargetSpec target_;       // set_target()
  ClusterResult clusters_;  // the last plan()'s labelling: its objects, and the fall-back's list
  bool objects_ready_ = false;
  uint32_t object_voxel_[kMaxObjectPoints];
  PointBuffer<kMaxObjectPoints> object_;
  ObjectFrame frame_;
  ViewList views_;
  int32_t chosen_view_ = -1;
  uint32_t chosen_candidate_ = kMaxCandidates;  // the returned grasp's, while plan()'s result stands
  FamilyCursor families_;                       // the current target's search, resumed by more_grasps()
  uint32_t alternates_[kMaxRankedGrasps];       // candidates more_grasps() returned since plan()
  uint32_t n_alternates_ = 0;

  // D/E per-viewpoint work memory. Idle before the views, it is lent to the
  // clustering's lookup filter (as 64-bit words) and to the near list's sort.
  union {
    ViewWork view_;
    uint64_t view_words_[sizeof(ViewWork) / sizeof(uint64_t)];
    uint32_t near_tables_[2u << kNearCellBits];
    Vec2 body_scratch_[2 * kMaxObjectPoints];  // the checks' plausible body (begin_target)
  };
  static_assert(sizeof(Vec2) * 2 * kMaxObjectPoints <= sizeof(ViewWork),
                "the plausible body's scratch borrows the per-view memory without growing it");
  Silhouette silhouette_;
  CandidateList candidates_;

  // F checks, G selection.
  GraspChecks checks_{CheckScene{cfg_, object_, object_voxel_, grid_, state_, support_, sensors_}};
  Selection selection_;
};

}  // namespace fg
