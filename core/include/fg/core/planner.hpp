// The grasp planner: one fixed-size workspace object that ingests the sensors'
// points and plans a force-balance grasp (design/algorithm.md A-F).
// It never allocates, throws or recurses; every loop is bounded by a capacity of
// fg_limits.h or a configured count. Construct it once (it is large: keep it static
// or in caller memory), configure(), then per plan: reset(), add_*(), plan().
#pragma once
#include <cstdint>
#include "fg/core/cluster.hpp"
#include "fg/core/config.hpp"
#include "fg/core/force_balance.hpp"
#include "fg/core/grasp_check.hpp"
#include "fg/core/hull.hpp"
#include "fg/core/limits.hpp"
#include "fg/core/near_list.hpp"
#include "fg/core/plane.hpp"
#include "fg/core/point_buffer.hpp"
#include "fg/core/status.hpp"
#include "fg/core/types.hpp"
#include "fg/core/voxel_grid.hpp"

namespace fg {
namespace ingest {
struct State;
}

enum class SensorRole : uint8_t { head = 0, hand = 1 };

struct PinholeIntrinsics {
  float fx = 525.f, fy = 525.f, cx = 319.5f, cy = 239.5f;
};

//! Pipeline stages, each timed.
enum class Stage : uint8_t { ingest, plane, cluster, frame, xoy, xoz, select, total, count };
const char* to_string(Stage s);

//! Viewpoint families: the paper's arc between the sensors, then (extend_search)
//! the rest of the circle about the principal axis and circles about the other axes,
//! then circles about the support plane's axes (its normal, and the object's major
//! and minor directions along the plane).
enum class ViewFamily : uint8_t {
  sensor_arc = 0,
  full_circle = 1,
  middle_axis = 2,
  minor_axis = 3,
  support_normal = 4,
  support_major = 5,
  support_minor = 6,
};
inline constexpr int kViewFamilies = 7;
//! "sensor_arc", "full_circle", "middle_axis", "minor_axis", "support_normal",
//! "support_major", "support_minor".
const char* to_string(ViewFamily f);

struct Grasp {
  Vec3 position = Vec3::Zero();  //!< world, centre between the pads
  Vec3 approach = Vec3::UnitZ(); //!< world unit vector, palm towards object
  Vec3 closing = Vec3::UnitX();  //!< world unit vector, one finger towards the other
  float width = 0.f;             //!< object width between the contact regions (m)
  float beta = 0.f;              //!< XOY force balance (rad)
  float dz = 0.f;                //!< XOZ force balance (m)
  float viewpoint = 0.f;         //!< rotation of the chosen viewpoint about its axis (rad)
  ViewFamily family = ViewFamily::sensor_arc;
  Vec3 pregrasp = Vec3::Zero();  //!< position backed off along -approach
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

//! Why candidates were turned down during the checks (counts).
struct RejectCounts {
  uint32_t table = 0, collision = 0, friction = 0, occluded = 0, unreachable = 0;
};

struct PlanResult {
  Status status = Status::internal_error;
  NoGraspReason reason = NoGraspReason::none;
  const char* message = "";  //!< static text naming the problem
  Grasp grasp;
  PointCounts points;
  CropUsed crop;
  RejectCounts rejected;
  uint32_t viewpoints = 0;   //!< viewpoints analysed
  uint32_t candidates = 0;   //!< candidates ranked
  uint32_t stage_us[static_cast<uint32_t>(Stage::count)] = {};
};

//! Per-viewpoint summary kept for reports and pictures.
struct ViewRecord {
  ViewFamily family;
  float theta;      //!< rad about the family's axis
  Vec3 X, Y, Z;     //!< the virtual object frame (closing, axis, approach)
  bool has_candidate;
  float beta;       //!< best candidate's beta (when has_candidate)
  float dz;         //!< best candidate's dz
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

class Planner {
 public:
  Planner() = default;
  Planner(const Planner&) = delete;
  Planner& operator=(const Planner&) = delete;

  //! Validates and installs cfg (invalid_config names the field via *field), and resets.
  Status configure(const PlannerConfig& cfg, const char** field = nullptr);
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
  Status add_points(SensorRole role, const float* xyz, uint32_t count, uint32_t stride_bytes,
                    const Pose& world_T_sensor);

  //! The same for a structure of arrays: point i is (x[i], y[i], z[i]) (a sensor SDK's
  //! planar buffers, a PCD file's binary_compressed block as decompressed: no copy into
  //! x y z triples first).
  Status add_points_planar(SensorRole role, const float* x, const float* y, const float* z,
                           uint32_t count, const Pose& world_T_sensor);

  //! Adds a depth image (uint16 millimetres, 0 = no reading, row-major width x height).
  Status add_depth_image(SensorRole role, const uint16_t* depth_mm, uint16_t width,
                         uint16_t height, const PinholeIntrinsics& k, const Pose& world_T_sensor);

  //! The ingest's vector width for every planner of the process: 0 (the default) the
  //! widest this CPU runs (8 lanes on x86-64 with AVX2, else 4), 4 the path of every
  //! target. Every width gives the same grid, bit for bit; tests and benchmarks compare
  //! them. Not while another thread ingests.
  static void set_ingest_lanes(uint32_t lanes);
  //! The width the next add_* call uses (4 or 8).
  static uint32_t ingest_lanes();

  //! Plans on everything added since reset(). When the target cluster yields no grasp
  //! and lies over the footprint of a larger cluster, that cluster is searched once
  //! more (the target-fragment fall-back, docs/method.md A.6). The result's
  //! viewpoints, candidates, rejections and stage times then cover both searches; when
  //! both fail, its reason, message and points are the first target's, while the
  //! inspection below shows the last search (the fall-back cluster).
  Status plan(PlanResult& out);

  //! The message of the last add_* or plan failure (static text).
  const char* last_message() const { return message_; }

  // Inspection after plan(), for reports and pictures (host side).
  //! A sensor's nearest returns (mm, 0xFFFF = none) in kSightBins x kSightBins direction
  //! bins over x / z and y / z in [-1, 1), row by row (bin v * kSightBins + u): the
  //! visibility the checks ask about. Fed by every other point with a positive depth.
  const uint16_t* sight_map(SensorRole role) const { return sight_mm_[static_cast<uint32_t>(role) % kMaxSensors]; }
  const Plane& plane() const { return plane_; }
  bool plane_found() const { return plane_found_; }
  const PointSpan& object_points() const { return object_; }
  const VoxelGrid& voxels() const { return grid_; }
  uint8_t voxel_state(uint32_t i) const { return state_[i]; }
  uint32_t view_count() const { return n_views_; }
  const ViewRecord& view(uint32_t i) const { return views_[i]; }
  int32_t chosen_view() const { return chosen_view_; }
  const Vec3& object_centroid() const { return centroid_; }
  //! Recomputes the silhouette, contour, scan lines and best window of a viewpoint.
  Status analyze_view(uint32_t view_index, ViewDetail& out);

 private:
  struct Candidate {
    uint32_t view;
    float beta, dz, width;
    Vec3 position;  //!< world
    Vec3 X, Y, Z;   //!< grasp frame (closing, across, approach): the viewpoint's, or refined
    bool balanced;  //!< beta <= beta_max
    bool sides_in_cone;  //!< both fitted sides within atan(mu) of the closing normal (XOY)
    bool corners_clear;  //!< nothing beside the pads or just past their tips stands out past their contacts (xoz)
    bool tangent_contacts;  //!< the pads close on a round body's unseen tangents (grazed_round_body)
  };
  struct ViewFrame {
    Vec3 X, Y, Z;
  };

  Status check_pose(const Pose& p);
  Status ingest_begin(SensorRole role, const Pose& world_T_sensor);
  Status end_ingest(uint32_t offered, uint32_t finite, uint32_t kept, uint64_t t0, Status st);
  // Before a block of n points: room for n more voxels, the crop box shrunk if need be
  // (at crop_shrink_min the block is added as far as the grid holds it).
  void make_room(ingest::State& in, uint32_t n);
  void shrink_crop(ingest::State& in);
  // The loop both point layouts share: coordinate k of point i at base[k] + i * stride.
  Status add_coordinates(SensorRole role, const uint8_t* const base[3], uint32_t count,
                         uint32_t stride_bytes, const Pose& world_T_sensor);
  void load_target(uint32_t size, uint32_t* storage);
  // Not inlined: its bitmap stays off plan()'s frame, which the deepest stack path holds.
  [[gnu::noinline]] ClusterResult label_clusters(const ClusterParams& cp, uint32_t* queue);
  uint32_t search_grasp(PlanResult& out, NoGraspReason& reason, const char*& why);
  bool build_object_frame(Vec3 axes[3], Vec3& X0);
  bool support_frame(Vec3 axes[3]) const;
  bool footprint_axes(const Vec3 sup[3], Vec3 foot[3]);  // the smallest rectangle's sides
  uint32_t add_family(ViewFamily fam, const Vec3& axis, const Vec3& X0, float from, float to,
                      bool skip_arc, float arc_from, float arc_to);
  void analyse_views(uint32_t first, uint32_t last, PlanResult& out);
  void project_depth(const ViewFrame& f);  // view_.depth: their Z (for the views with windows)
  Status silhouette_windows(const ViewFrame& f, Vec2* contour, uint32_t& n_contour, ScanLine* lines,
                            uint32_t& n_lines, SideFit* windows, uint32_t max_windows,
                            uint32_t& n_windows);
  bool seen_from_a_sensor(const Vec3& approach) const;
  bool xoz(const ViewFrame& f, const SideFit& w, Candidate& c);
  bool executable(Candidate& c, PlanResult& out);
  void build_near_list(uint32_t* storage);
  int first_failed_check(const Candidate& c);
  bool refine_closing(Candidate& c);
  bool grazed_round_body(const Candidate& c, Candidate& round);  // grazed_round.cpp
  struct ContactNormalStats {
    uint32_t total[2] = {0, 0};        //!< left, right
    uint32_t inside_cone[2] = {0, 0};
    Vec3 outward_sum[2] = {Vec3::Zero(), Vec3::Zero()};
    float z_first[2] = {1e9f, 1e9f};   //!< the shallowest contact point along the approach
    uint32_t level[2] = {0, 0};        //!< normals within 30 deg of the support plane's (a top)
    float top[2] = {-1e9f, -1e9f};     //!< the highest contact point above the support plane
  };
  void contact_normal_stats(const Vec3& pos, const ViewFrame& f, float width, ContactNormalStats& st);
  bool friction_ok(const Vec3& pos, const ViewFrame& f, float width);
  void footprint_extremes(const Vec3& pos, const ViewFrame& f, float ext[2]) const;
  void contact_tilt(const Vec3& pos, const ViewFrame& f, float one_minus_cos[2], bool valid[2], bool flat[2],
                    float near_face[2], float edge_face[2]);
  bool fingers_clear_of_hull(const Vec3& pos, const ViewFrame& f);
  bool fingers_clear_of_footprint(const Vec3& pos, const ViewFrame& f, float width);
  bool lower_tip_unseen(const Vec3& pos, const ViewFrame& f, float width);
  bool straight_down(const Vec3& approach) const;  //!< within kTopDownCos of the plane's down
  int fingers_in_seen_space(const Vec3& pos, const ViewFrame& f, float width, uint32_t& partly_hidden);
  bool unseen_side_clear(const Vec3& pos, const ViewFrame& f, int side);
  bool blind_side_mirrors_seen(const Vec3& pos, const ViewFrame& f, float width, uint32_t hidden_sides);
  bool round_front_clears_blind_side(const Vec3& pos, const ViewFrame& f, int blind_side);
  bool top_goes_on_past(const Vec3& pos, const ViewFrame& f, float width, int side);
  int visibility(const Vec3& q) const;
  bool normal_at(uint32_t object_index, Vec3& n);
  bool normal_planar(uint32_t object_index) const;  //!< after normal_at returned true
  uint32_t rank_and_check(uint32_t first_candidate, PlanResult& out);
  uint32_t check_deferred(PlanResult& out);
  void fill_grasp(const Candidate& c, PlanResult& out);

  PlannerConfig cfg_;
  GraspCheck* grasp_check_ = nullptr;
  const char* message_ = "";

  // Sensors
  bool role_added_[kMaxSensors] = {};
  Vec3 sensor_origin_[kMaxSensors];
  Pose sensor_pose_[kMaxSensors];
  // What each sensor saw: the nearest return (mm) per direction bin over
  // x/z, y/z in [-1, 1) (a 90 deg cone), 0xFFFF where nothing returned. It tells space
  // seen to be free (a return behind it) from space hidden behind a surface.
  uint16_t sight_mm_[kMaxSensors][kSightBins * kSightBins];
  PointCounts counts_;
  // The crop box in the grid's cell units, as the ingest tests points against it (its
  // world bounds are in crop_used_): the configured box, or after shrink_crop() one of whole cells (lo <= f <= hi, hi just
  // below a cell boundary).
  float crop_lo_cells_[3] = {}, crop_hi_cells_[3] = {};
  CropUsed crop_used_;
  uint32_t ingest_us_ = 0;
  bool overflow_ = false;

  // A. partial model
  VoxelGrid grid_;
  uint8_t state_[kMaxVoxels];
  uint32_t object_voxel_[kMaxObjectPoints];
  PointBuffer<kMaxObjectPoints> object_;
  Plane plane_;
  bool plane_found_ = false;

  // B/C. frames and viewpoints
  Vec3 centroid_ = Vec3::Zero();
  ViewRecord views_[kMaxViewpoints];
  uint32_t n_views_ = 0;
  int32_t chosen_view_ = -1;

  // D/E. per-viewpoint work memory: the object's projection and the hull's raster.
  // Idle before the views, so the clustering's voxel lookup filter borrows it as
  // 64-bit words (plan()).
  struct ViewWork {
    Vec2 proj[kMaxObjectPoints];
    float depth[kMaxObjectPoints];
    // The hull's scratch is idle once the view's silhouette is traced: xoz() lists
    // there the points near a window's centre line.
    union {
      ConcaveHullScratch hull;
      uint32_t slab[kMaxObjectPoints];
    };
  };
  static_assert(sizeof(uint32_t) * kMaxObjectPoints <= sizeof(ConcaveHullScratch),
                "xoz()'s list borrows the hull's scratch without growing the workspace");
  static constexpr uint32_t kViewWorkWordBits = floor_log2(sizeof(ViewWork) / sizeof(uint64_t));
  // The near list (below) is sorted with two tables of 2^kNearCellBits words, which
  // borrow this memory too (build_near_list, between the clustering and the views).
  static constexpr uint32_t kNearIndexBits = floor_log2(kMaxVoxels - 1u) + 1u;
  static constexpr uint32_t kNearCellBits =
      kViewWorkWordBits < 32u - kNearIndexBits ? kViewWorkWordBits : 32u - kNearIndexBits;
  static_assert(kNearCellBits >= 3, "the near list needs at least one bit of cell per axis");
  union {
    ViewWork view_;
    uint64_t view_words_[sizeof(ViewWork) / sizeof(uint64_t)];
    uint32_t near_tables_[2u << kNearCellBits];
  };
  Vec2 contour_[kMaxContourVertices];
  ScanLine lines_[kMaxScanLines];
  SideFit windows_[16];
  Candidate candidates_[kMaxCandidates];
  uint32_t n_candidates_ = 0;
  uint32_t checks_left_ = 0;  // candidates the checks may still examine in this plan()
  bool first_pass_ = false;  // partly hidden fingers and pads whose corners meet a surface wait (check 7)
  bool deferred_ = false;      // the last executable() call deferred its candidate
  uint16_t deferred_list_[kMaxCandidates];  // candidates deferred by rank_and_check
  uint32_t n_deferred_ = 0;
  // Voxels within the gripper's reach of the object (build_near_list), in the lent
  // count storage of the grid, sorted by their cell of a coarse grid over the cube
  // around the reach sphere (near_list.hpp): an entry is cell << kNearIndexBits |
  // voxel index, so the collision check reads only the cells under each box.
  uint32_t* near_ = nullptr;
  uint32_t n_near_ = 0;
  Vec3 near_centre_ = Vec3::Zero();
  float near_slack_ = 0.f;
  NearGrid near_grid_{};
  uint16_t order_[kMaxCandidates];

  // Normals of object points, computed on demand for the friction test.
  Vec3 normals_[kMaxObjectPoints];
  uint8_t normal_state_[kMaxObjectPoints];  // 0 unknown, 1 valid, 2 undefined, 3 valid, not planar
  Vec3 local_[kMaxObjectPoints];            // object points near the hand, grasp frame
};

}  // namespace fg
