/* forcegrasp: the C API that robot-controller firmware links.
 *
 * The planner lives in one opaque workspace in memory the caller owns: no heap, no
 * global state (two workspaces work side by side), no callbacks, no errno. Every call
 * returns an fg_status; values are explicit and never reused. Compiles as C99 and C++.
 *
 * A capture cycle:
 *   static FG_WORKSPACE_STORAGE(mem);                      (or any aligned buffer)
 *   fg_config cfg; fg_config_default(&cfg);               (then change fields)
 *   fg_workspace *ws; fg_init(mem, sizeof mem, &cfg, &ws);
 *   fg_add_depth_image(ws, FG_SENSOR_HEAD, ...); fg_add_points(ws, FG_SENSOR_HAND, ...);
 *   fg_grasp g; fg_plan(ws, &g);                           (FG_OK or FG_NO_GRASP + g.reason)
 *   fg_reset(ws);                                          (next capture)
 *
 * Frames: poses are world_T_sensor (a sensor-frame point p maps to R p + t, metres);
 * grasp vectors are in the world frame. Sensor frames are optical: +z along the view.
 * Not thread-safe per workspace; different workspaces are independent. */
#ifndef FORCEGRASP_H
#define FORCEGRASP_H

#include <stddef.h>
#include <stdint.h>

#include "fg_limits.h" /* the build configuration's capacities and workspace budget */

#ifdef __cplusplus
extern "C" {
#endif

#define FG_VERSION_MAJOR 0
#define FG_VERSION_MINOR 2
#define FG_VERSION_PATCH 0
/** Bumped whenever a struct below changes layout or a function changes meaning. */
#define FG_ABI_VERSION 1u

#ifndef FG_WORKSPACE_SIZE
#error "fg_limits.h of the build configuration must define FG_WORKSPACE_SIZE"
#endif
/** Alignment the workspace memory needs (bytes). */
/* Every call returns a status the caller must read: the compiler warns when one is
 * dropped. Define FG_NODISCARD empty before including this header to turn that off. */
#ifndef FG_NODISCARD
#if defined(__cplusplus) && __cplusplus >= 201703L
#define FG_NODISCARD [[nodiscard]]
#elif defined(__GNUC__) || defined(__clang__)
#define FG_NODISCARD __attribute__((warn_unused_result))
#else
#define FG_NODISCARD
#endif
#endif

#define FG_WORKSPACE_ALIGN 16u
/** A buffer that always fits: `static FG_WORKSPACE_STORAGE(mem);` then fg_init(mem, sizeof mem, ...). */
#if defined(__GNUC__)
#define FG_WORKSPACE_STORAGE(name) unsigned char name[FG_WORKSPACE_SIZE] __attribute__((aligned(16)))
#elif defined(__cplusplus)
#define FG_WORKSPACE_STORAGE(name) unsigned char name alignas(16)[FG_WORKSPACE_SIZE]
#else
#define FG_WORKSPACE_STORAGE(name) unsigned char name[FG_WORKSPACE_SIZE] /* align it yourself */
#endif

/** The opaque planner workspace, inside caller-owned memory. */
typedef struct fg_workspace fg_workspace;

/** Outcome of every call: 0 ok, positive = ordinary outcome, negative = error by cause. */
typedef enum fg_status {
  FG_OK = 0,
  FG_NO_GRASP = 1, /**< valid input, but no grasp fits: see fg_grasp.reason */

  /* -100..-109: the caller's data */
  FG_ERR_INVALID_ARGUMENT = -100,    /**< null pointer, zero size, bad stride, bad enum */
  FG_ERR_NON_FINITE = -101,          /**< NaN or Inf where a finite number is required */
  FG_ERR_INVALID_POSE = -102,        /**< rotation not orthonormal / right-handed, absurd translation */
  FG_ERR_INVALID_CONFIG = -103,      /**< a configuration value out of its documented range */
  FG_ERR_NO_INPUT = -104,            /**< fg_plan before any sensor data */
  FG_ERR_INVALID_SENSOR = -105,      /**< unknown sensor role, or the same role twice per capture */
  FG_ERR_INVALID_SEQUENCE = -106,    /**< sensor data after fg_plan without fg_reset */
  FG_ERR_SENSOR_DISAGREEMENT = -107, /**< the clouds disagree after the registration
                                          (FG_REGISTRATION_MODE_STRICT) */

  /* -110..-119: the workspace and the API contract */
  FG_ERR_WORKSPACE_TOO_SMALL = -110,  /**< size < fg_workspace_size() */
  FG_ERR_WORKSPACE_MISALIGNED = -111, /**< memory not aligned to FG_WORKSPACE_ALIGN */
  FG_ERR_ABI_MISMATCH = -112,         /**< header and library disagree (FG_ABI_VERSION) */
  FG_ERR_CONFIG_SIZE = -113,          /**< fg_config.struct_size is not this library's */
  FG_ERR_NOT_A_WORKSPACE = -114,      /**< pointer is not a workspace made by fg_init */

  /* -200: capacity */
  FG_ERR_CAPACITY_EXCEEDED = -200, /**< more data than the build configuration holds */
  /* -300: numerics */
  FG_ERR_NUMERIC_FAILURE = -300, /**< a computation produced a non-finite result */
  /* -900: bugs */
  FG_ERR_INTERNAL = -900
} fg_status;

/** Why a valid input produced FG_NO_GRASP. */
typedef enum fg_no_grasp_reason {
  FG_REASON_NONE = 0,
  FG_REASON_NO_POINTS = 1,      /**< nothing left after the range filter and crop box */
  FG_REASON_NO_PLANE = 2,       /**< no support plane was found */
  FG_REASON_NO_OBJECT = 3,      /**< nothing stands on the support plane */
  FG_REASON_TOO_FEW_POINTS = 4, /**< the target cluster is too small to analyse */
  FG_REASON_TOO_WIDE = 5,       /**< wider than the opening from every viewpoint */
  FG_REASON_NO_CANDIDATE = 6,   /**< no candidate passed the force-balance filters */
  FG_REASON_COLLISION = 7,      /**< every candidate hit the support plane or another object */
  FG_REASON_UNREACHABLE = 8,    /**< every candidate failed inverse kinematics */
  FG_REASON_FRICTION = 9,       /**< every candidate's contact normals left the friction cone */
  FG_REASON_DEGENERATE = 10,    /**< the object cloud has no defined principal axis */
  FG_REASON_OCCLUDED = 11       /**< every candidate put a finger in space the sensors saw only
                                     behind the object: a view from elsewhere may find a grasp */
} fg_no_grasp_reason;

typedef enum fg_sensor_role { FG_SENSOR_HEAD = 0, FG_SENSOR_HAND = 1 } fg_sensor_role;

typedef enum fg_target_rule { FG_TARGET_NEAREST_TO_CENTRE = 0, FG_TARGET_LARGEST = 1 } fg_target_rule;

/** Stages timed by fg_plan (fg_grasp.stage_us). */
enum {
  FG_STAGE_INGEST = 0,
  FG_STAGE_PLANE,
  FG_STAGE_CLUSTER,
  FG_STAGE_FRAME,
  FG_STAGE_XOY,
  FG_STAGE_XOZ,
  FG_STAGE_SELECT,
  FG_STAGE_TOTAL,
  FG_STAGE_COUNT
};

/** A rigid transform: rotation row-major (r[3*i + j] = R(i, j)) and translation (m). */
typedef struct fg_pose {
  float r[9];
  float t[3];
} fg_pose;

/** Pinhole intrinsics of a depth image (pixels). */
typedef struct fg_intrinsics {
  float fx, fy, cx, cy;
} fg_intrinsics;

/** Parallel-gripper geometry (metres); grasp frame: +z approach, +x closing. */
typedef struct fg_gripper {
  float max_opening_m, min_opening_m;
  float finger_width_m, finger_depth_m, finger_thickness_m;
  float palm_depth_m, palm_width_m;
} fg_gripper;

/** Planner configuration; fill with fg_config_default() and change what you need.
 *  The meaning and range of each field is in docs/configuration.md (same names). */
typedef struct fg_config {
  uint32_t struct_size; /**< sizeof(fg_config) as the caller compiled it */
  uint32_t abi_version; /**< FG_ABI_VERSION as the caller compiled it */
  fg_gripper gripper;
  /* A. partial model */
  float range_min_m, range_max_m;
  float crop_half_x_m, crop_half_y_m, crop_min_z_m, crop_max_z_m;
  float voxel_leaf_m, plane_distance_m;
  uint32_t ransac_iterations, ransac_seed;
  float plane_max_tilt_rad, object_min_height_m;
  uint32_t cluster_cells, min_object_points;
  float workspace_centre_x_m, workspace_centre_y_m;
  uint32_t target_rule; /**< fg_target_rule */
  /* B/C. object frame and viewpoints */
  float dtheta_rad, single_sensor_arc_rad, vertical_snap_rad, axis_ratio_min;
  uint32_t extend_search; /**< 0 or 1 */
  float extension_dtheta_rad, approach_view_max_rad;
  /* D. XOY force balance */
  float scan_delta_m, dx_threshold_m, width_margin_m, hull_cell_m;
  uint32_t hull_closing_cells, candidates_per_view;
  float centre_weight;
  /* E/F. XOZ balance, selection, checks */
  float beta_max_rad, contact_band_m, reach_width_ratio, friction_mu;
  float table_clearance_m, collision_tolerance_m, pregrasp_clearance_m, palm_clearance_m;
  uint32_t paper_depth;          /**< 0 or 1 */
  uint32_t executability_checks; /**< 0 or 1 */
} fg_config;

/** The planner's answer. Vectors are world-frame; units metres and radians. */
typedef struct fg_grasp {
  int32_t reason;    /**< fg_no_grasp_reason when fg_plan returned FG_NO_GRASP */
  float position[3]; /**< between the pads */
  float approach[3]; /**< unit, palm towards the object */
  float closing[3];  /**< unit, one finger towards the other */
  float pregrasp[3]; /**< position backed off along -approach */
  float width_m;     /**< object width between the contact regions */
  float beta_rad;    /**< XOY force balance */
  float dz_m;        /**< XOZ force balance */
  uint32_t points_input, points_finite, points_kept, voxels, plane_voxels, object_voxels;
  uint32_t viewpoints, candidates;
  uint32_t stage_us[FG_STAGE_COUNT]; /**< time per stage (platform clock) */
} fg_grasp;

/** (major << 16) | (minor << 8) | patch of the library. */
uint32_t fg_version(void);
/** FG_ABI_VERSION compiled into the library. */
uint32_t fg_abi_version(void);
/** Bytes the workspace needs (never more than FG_WORKSPACE_SIZE). */
size_t fg_workspace_size(void);
/** Alignment the workspace needs (FG_WORKSPACE_ALIGN). */
size_t fg_workspace_align(void);
/* Enumerations the caller passes in travel as int32_t: any value a C caller can form
 * is defined input (refused with a status), and the ABI does not depend on enum size. */

/** Static name of an fg_status, e.g. "FG_ERR_INVALID_POSE"; "FG_UNKNOWN_STATUS" otherwise. */
const char *fg_status_str(int32_t status);
/** Static name of an fg_no_grasp_reason, e.g. "too_wide"; "unknown_reason" otherwise. */
const char *fg_reason_str(int32_t reason);

/** Fills the defaults of docs/configuration.md, struct_size and abi_version. */
FG_NODISCARD fg_status fg_config_default(fg_config *cfg);

/** Checks every value of cfg without a workspace; on an error, *field (when field is
 *  not NULL) names the first offending field as docs/configuration.md and
 *  `forcegrasp config` name its option: without the unit suffix ("voxel_leaf" for
 *  voxel_leaf_m, "gripper.max_opening"), static text; "" when all is well. */
FG_NODISCARD fg_status fg_config_check(const fg_config *cfg, const char **field);

/** Builds a workspace in `memory` (size bytes, FG_WORKSPACE_ALIGN-aligned) and checks
 *  cfg (struct_size, abi_version, every value). On success *out points into memory;
 *  the memory is the workspace until the caller reuses it (no fg_deinit needed).
 *  On failure *out is NULL (when out is not NULL). */
FG_NODISCARD fg_status fg_init(void *memory, size_t size, const fg_config *cfg, fg_workspace **out);

/** Starts the next capture: forgets the sensor data of the previous one. */
FG_NODISCARD fg_status fg_reset(fg_workspace *ws);

/** Adds one sensor's depth image (uint16 millimetres, 0 = no return, row-major,
 *  width x height) for this capture. role: an fg_sensor_role, each at most once per
 *  capture (others: FG_ERR_INVALID_SENSOR). */
FG_NODISCARD fg_status fg_add_depth_image(fg_workspace *ws, int32_t role, const uint16_t *depth_mm, uint16_t width,
                                          uint16_t height, const fg_intrinsics *k, const fg_pose *world_T_sensor);

/** The units of a sensor's points (fg_add_points, fg_add_points_planar): metres per
 *  unit, 1.0f (metres, the default) or 0.001f (millimetres), within 1e-6 .. 1e3
 *  (FG_ERR_INVALID_ARGUMENT; NaN: FG_ERR_NON_FINITE). Kept across fg_reset. Depth
 *  images are in millimetres whatever this says. Points all outside the depth range that
 *  would lie within it in other units are refused with FG_ERR_INVALID_ARGUMENT and a
 *  message naming those units. */
FG_NODISCARD fg_status fg_set_sensor_units(fg_workspace *ws, int32_t role, float metres_per_unit);

/** What the registration did with the hand sensor's pose (fg_registration). */
typedef enum fg_registration_outcome {
  FG_REGISTRATION_NOT_RUN = 0,            /**< one sensor, registration off, or nothing added yet */
  FG_REGISTRATION_CORRECTED = 1,          /**< the hand's points were moved by the correction */
  FG_REGISTRATION_CALIBRATION_KEPT = 2,   /**< the calibration agreed: the correction found was noise */
  FG_REGISTRATION_TOO_LITTLE_OVERLAP = 3, /**< too few surfaces both sensors saw: fused as calibrated */
  FG_REGISTRATION_IMPLAUSIBLE = 4,        /**< the alignment found lies beyond the capture range (5 cm,
                                               6 deg): fused as calibrated */
  FG_REGISTRATION_HAND_ADDED_FIRST = 5,   /**< the hand's points came before the head's: fused as calibrated */
  FG_REGISTRATION_SENSOR_DISAGREEMENT = 6 /**< as fused, the hand saw through the head's surfaces
                                               (see_through): one sensor's points are left out
                                               (left_out: the hand, unless the head's table is off
                                               level and the hand's is not), the plan is the
                                               other's alone (strict: an error) */
} fg_registration_outcome;

/** The hand sensor's registration to the head (docs/method.md A.4b). */
typedef struct fg_registration_result {
  int32_t outcome;          /**< an fg_registration_outcome */
  fg_pose correction;       /**< world frame: corrected world_T_hand = correction * world_T_hand as given;
                                 identity unless corrected. Firmware may fold it into its hand-eye
                                 calibration. */
  float translation_mm;     /**< how far the correction moves the hand sensor's origin */
  float rotation_deg;       /**< the correction's angle */
  float residual_before_mm; /**< RMS point-to-plane distance of the pairs, as calibrated */
  float residual_mm;        /**< the same after the correction */
  float overlap;            /**< share of the head's samples the hand saw within the final gate */
  uint32_t pairs;           /**< those pairs */
  uint32_t iterations;
  uint32_t us;       /**< the stage's time (inside the hand's fg_add_* call) */
  float see_through; /**< of the head's samples where the hand saw a surface (compared), the share
                          2 cm or more in front of it, as the clouds would be fused */
  uint32_t compared;
  float head_tilt_deg; /**< on a disagreement: the head's table off level (degrees); else NaN */
  float hand_tilt_deg; /**< the same for the hand's table, at its pose as given */
  int32_t left_out;    /**< on a disagreement: the fg_sensor_role whose points are left out; else -1 */
} fg_registration_result;

/** How the hand sensor's cloud joins the head's (fg_set_registration). */
typedef enum fg_registration_mode {
  FG_REGISTRATION_MODE_OFF = 0,   /**< fused through the calibration alone */
  FG_REGISTRATION_MODE_ON = 1,    /**< registered to the head first (the default) */
  FG_REGISTRATION_MODE_STRICT = 2 /**< the same, and a disagreement fails fg_plan with
                                       FG_ERR_SENSOR_DISAGREEMENT rather than planning from the head */
} fg_registration_mode;

/** Whether the hand sensor's cloud is registered to the head's before it joins the
 *  capture: an fg_registration_mode (any other nonzero value: on, the default). It runs
 *  when the hand is added after the head: its points are then read twice. Kept across
 *  fg_reset. */
FG_NODISCARD fg_status fg_set_registration(fg_workspace *ws, int32_t on);

/** The registration of the capture since the last fg_reset (outcome
 *  FG_REGISTRATION_NOT_RUN until the hand is added after the head). A null out:
 *  FG_ERR_INVALID_ARGUMENT. */
FG_NODISCARD fg_status fg_registration(fg_workspace *ws, fg_registration_result *out);

/** After a plan refused its target as occluded (FG_REASON_OCCLUDED): which sensor would
 *  have to look where (docs/method.md, "The report": look). */
typedef struct fg_look_advice_result {
  int32_t valid;  /**< 1 when the last plan was refused as occluded and showed the hidden
                       space; else 0 and the rest zero */
  int32_t sensor; /**< an fg_sensor_role: the one whose direction from `at` lies nearest the
                       advised view (the one that turns least) */
  float at[3];    /**< world: the centre of the space that refused the first candidate */
  float from[3];  /**< world: where that sensor would look from, beyond `at` and 45 deg above
                       it, at its present distance */
} fg_look_advice_result;

/** The advice of the last fg_plan, fg_plan_ranked, fg_plan_object or
 *  fg_plan_object_ranked call (valid 0 after any other outcome). A null out:
 *  FG_ERR_INVALID_ARGUMENT. */
FG_NODISCARD fg_status fg_look_advice(fg_workspace *ws, fg_look_advice_result *out);

/** Adds one sensor's points: count xyz triples of float (sensor frame, metres), the
 *  first float of point i at xyz + i * stride_bytes (stride >= 12; any alignment).
 *  NaN points are skipped. role: an fg_sensor_role, each at most once per capture. */
FG_NODISCARD fg_status fg_add_points(fg_workspace *ws, int32_t role, const float *xyz, size_t count,
                                     size_t stride_bytes, const fg_pose *world_T_sensor);

/** The same for planar buffers (structure of arrays): point i is (x[i], y[i], z[i]).
 *  Null arrays only with count 0. */
FG_NODISCARD fg_status fg_add_points_planar(fg_workspace *ws, int32_t role, const float *x, const float *y,
                                            const float *z, size_t count, const fg_pose *world_T_sensor);

/** Plans a grasp on this capture. FG_OK: *out holds the grasp. FG_NO_GRASP:
 *  out->reason says why. Errors leave out's counts and times filled where known. */
FG_NODISCARD fg_status fg_plan(fg_workspace *ws, fg_grasp *out);

/** Plans like fg_plan and ranks: on FG_OK, out[0] is fg_plan's grasp and out[1..] more
 *  grasps on the same target that pass every check, each distinct from the others
 *  (closing lines or approaches at least 15 degrees apart, or centres 1 cm), best
 *  first in the planner's order; *count (1..capacity, at most FG_MAX_RANKED_GRASPS) says
 *  how many. Each entry carries the plan's counts and stage times. FG_NO_GRASP:
 *  out[0].reason says why and *count is 0. A null array or count, or capacity 0:
 *  FG_ERR_INVALID_ARGUMENT. No heap: the caller's array is the only output. */
FG_NODISCARD fg_status fg_plan_ranked(fg_workspace *ws, fg_grasp *out, uint32_t capacity, uint32_t *count);

/* ---- The target and the objects on the table ----------------------------------------
 * fg_plan picks its target by fg_config.target_rule unless a target is set here: the
 * object nearest a world point, or the object with the most voxels inside a world box.
 * A target is kept across fg_reset and applies to every later plan of the workspace
 * (fg_plan, fg_plan_ranked, the grasp task's) until fg_clear_target or another one.
 * fg_plan then answers FG_ERR_INVALID_ARGUMENT when the point, or the whole box, lies
 * outside the workspace crop box (fg_last_message says which), and FG_NO_GRASP with
 * reason FG_REASON_NO_OBJECT when no object has a voxel inside the box. A refused
 * target leaves the one before in place. */

#ifndef FG_MAX_OBJECTS
#define FG_MAX_OBJECTS 8u /* the core's default when fg_limits.h leaves it out */
#endif

/** The target: the object nearest xyz (world, metres). Refused: NULL
 *  (FG_ERR_INVALID_ARGUMENT), a NaN or Inf coordinate (FG_ERR_NON_FINITE). */
FG_NODISCARD fg_status fg_set_target_point(fg_workspace *ws, const float xyz[3]);

/** The target: the object with the most voxels inside [box_min, box_max] (world,
 *  metres, inclusive). Refused: NULL (FG_ERR_INVALID_ARGUMENT), a NaN or Inf coordinate
 *  (FG_ERR_NON_FINITE), a minimum above its maximum (FG_ERR_INVALID_ARGUMENT). */
FG_NODISCARD fg_status fg_set_target_box(fg_workspace *ws, const float box_min[3], const float box_max[3]);

/** Back to the default: the target picked by fg_config.target_rule. */
FG_NODISCARD fg_status fg_clear_target(fg_workspace *ws);

/** One object on the support plane, as the last fg_plan found it (world frame). */
typedef struct fg_object {
  float centroid[3]; /**< the mean of its voxels' centroids */
  float box_min[3];  /**< the box of its voxels' cells */
  float box_max[3];
  uint32_t voxels;    /**< its occupied voxels */
  uint32_t is_target; /**< 1 for the object the last fg_plan or fg_plan_object searched */
} fg_object;

/** The objects the last fg_plan found standing on the support plane (clusters of at
 *  least min_object_points voxels), nearest the workspace centre first: out[k] is the
 *  object fg_plan_object(ws, k, ...) plans for. *count (at most capacity and
 *  FG_MAX_OBJECTS) says how many were written; *dropped (optional: may be NULL) how
 *  many more the plan found, beyond FG_MAX_OBJECTS or capacity. FG_OK with *count 0
 *  before an fg_plan that reached its clustering stage, after fg_reset, and when
 *  nothing stands on the plane. A null array or count, or capacity 0:
 *  FG_ERR_INVALID_ARGUMENT. fg_last_message is left as it was on success. */
FG_NODISCARD fg_status fg_objects(fg_workspace *ws, fg_object *out, uint32_t capacity, uint32_t *count,
                                  uint32_t *dropped);

/** After fg_plan, and before the next fg_reset: plans a grasp on object `index` of
 *  fg_objects' list, every other object an obstacle, on the same capture and support
 *  plane. FG_OK: *out holds the grasp; FG_NO_GRASP: out->reason says why; out's counts
 *  are the capture's, its stage times this call's. FG_ERR_INVALID_SEQUENCE before an
 *  fg_plan that listed the objects (since fg_init or fg_reset), FG_ERR_INVALID_ARGUMENT
 *  for a null output or an index at or beyond the list's count. The objects' list stays;
 *  their is_target then marks this object. */
FG_NODISCARD fg_status fg_plan_object(fg_workspace *ws, uint32_t index, fg_grasp *out);

/** fg_plan_object, ranked as fg_plan_ranked ranks fg_plan's grasp: out[0] the grasp,
 *  out[1..] distinct alternates on the same object, *count of them (FG_NO_GRASP or an
 *  error: *count 0). A null array or count, or capacity 0: FG_ERR_INVALID_ARGUMENT. */
FG_NODISCARD fg_status fg_plan_object_ranked(fg_workspace *ws, uint32_t index, fg_grasp *out, uint32_t capacity,
                                             uint32_t *count);

/** The last call's message naming the problem (static text, never NULL). */
const char *fg_last_message(const fg_workspace *ws);

/* ---- The grasp task: capture, plan, open, pre-grasp, approach, close, lift ----------
 * A non-blocking state machine in the workspace: fg_task_step() does one control tick
 * of work and returns (only the planning tick takes milliseconds); every state has a
 * timeout. The firmware's hardware comes in as callbacks on its own context; they
 * must not block. */

/** Progress of a capture (fg_hal_ops.sensor_poll). */
enum { FG_CAPTURE_IDLE = 0, FG_CAPTURE_BUSY = 1, FG_CAPTURE_READY = 2, FG_CAPTURE_FAILED = 3 };

/** A depth image the driver holds, valid until its next capture request. */
typedef struct fg_depth_frame {
  const uint16_t *depth_mm; /**< row-major millimetres, 0 = no return */
  uint16_t width, height;
  fg_intrinsics k;
} fg_depth_frame;

typedef struct fg_arm_state {
  double q[6];     /**< joint angles (rad), base .. wrist 3 */
  uint32_t moving; /**< 1 while a commanded motion is under way */
  uint32_t fault;  /**< 1 on a protective stop, limit violation or lost link */
} fg_arm_state;

typedef struct fg_gripper_state {
  float width_m;
  uint32_t moving, contact, fault; /**< 0 or 1 each */
} fg_gripper_state;

/** The hardware, as callbacks; every one is required. Calls returning int32_t return
 *  0 when the command was accepted (or the state read), anything else otherwise. */
typedef struct fg_hal_ops {
  void *ctx;                                                                /**< passed back to every callback */
  uint64_t (*now_us)(void *ctx);                                            /**< monotonic microseconds */
  int32_t (*sensor_request)(void *ctx, int32_t role);                       /**< start a capture */
  int32_t (*sensor_poll)(void *ctx, int32_t role, fg_depth_frame *out);     /**< FG_CAPTURE_* */
  int32_t (*arm_move)(void *ctx, const double q[6], double speed_fraction); /**< joint target */
  int32_t (*arm_read)(void *ctx, fg_arm_state *out);
  void (*arm_stop)(void *ctx);
  int32_t (*gripper_open)(void *ctx, float width_m);
  int32_t (*gripper_close)(void *ctx, float force_n);
  int32_t (*gripper_read)(void *ctx, fg_gripper_state *out);
} fg_hal_ops;

typedef struct fg_task_config {
  uint32_t struct_size;        /**< sizeof(fg_task_config) as the caller compiled it */
  fg_pose world_T_base;        /**< the arm's base (DH base frame) in the world */
  fg_pose world_T_head;        /**< the head sensor's fixed mount */
  fg_pose tool0_T_hand;        /**< the wrist sensor on the flange (hand-eye) */
  uint32_t use_head, use_hand; /**< 0 or 1; at least one */
  float tcp_offset_m;          /**< flange to the pads' centre along tool0 +z */
  float lift_m;                /**< lift straight up after closing */
  float grip_force_n;
  double speed_fraction; /**< (0, 1] of the arm's maximum joint speed */
  double joint_tolerance_rad;
  uint32_t capture_timeout_us, move_timeout_us, gripper_timeout_us;
} fg_task_config;

typedef enum fg_task_state {
  FG_TASK_IDLE = 0,
  FG_TASK_CAPTURING = 1,
  FG_TASK_PLANNING = 2,
  FG_TASK_OPENING = 3,
  FG_TASK_TO_PREGRASP = 4,
  FG_TASK_APPROACHING = 5,
  FG_TASK_CLOSING = 6,
  FG_TASK_LIFTING = 7,
  FG_TASK_SUCCEEDED = 8,
  FG_TASK_FAILED = 9
} fg_task_state;

typedef enum fg_task_failure {
  FG_TASK_OK = 0,
  FG_TASK_INVALID_CONFIG = 1,
  FG_TASK_SENSOR_FAILED = 2,
  FG_TASK_SENSOR_TIMEOUT = 3,
  FG_TASK_NO_GRASP = 4,
  FG_TASK_UNREACHABLE = 5,
  FG_TASK_ARM_REFUSED = 6,
  FG_TASK_ARM_FAULT = 7,
  FG_TASK_ARM_TIMEOUT = 8,
  FG_TASK_GRIPPER_REFUSED = 9,
  FG_TASK_GRIPPER_FAULT = 10,
  FG_TASK_GRIPPER_TIMEOUT = 11,
  FG_TASK_MISSED = 12,
  FG_TASK_ABORTED = 13
} fg_task_failure;

typedef struct fg_task_status {
  int32_t state;   /**< fg_task_state */
  int32_t failure; /**< fg_task_failure when state is FG_TASK_FAILED */
  uint32_t ticks;  /**< fg_task_step calls since fg_task_start */
  fg_grasp grasp;  /**< the planned grasp, from FG_TASK_OPENING on (reason on FG_TASK_NO_GRASP) */
  double q_pregrasp[6], q_grasp[6], q_lift[6]; /**< joint targets, from FG_TASK_OPENING on */
} fg_task_status;

/** Defaults: identity poses, both sensors, tcp 0.15 m, lift 0.10 m, 40 N, speed 0.25,
 *  tolerance 2 mrad, timeouts 2 s (capture), 20 s (each motion), 3 s (gripper). */
FG_NODISCARD fg_status fg_task_config_default(fg_task_config *cfg);

/** Starts a grasp: checks cfg (struct_size and values) and hal (every callback set).
 *  The workspace's planner does the planning: one task per workspace at a time. A
 *  refused start also ends the previous task (fg_task_step: FG_ERR_INVALID_SEQUENCE). */
FG_NODISCARD fg_status fg_task_start(fg_workspace *ws, const fg_task_config *cfg, const fg_hal_ops *hal);

/** One control tick. FG_OK while the task runs and when it has ended (out->state says
 *  which); FG_ERR_INVALID_SEQUENCE before fg_task_start. out may be NULL. */
FG_NODISCARD fg_status fg_task_step(fg_workspace *ws, fg_task_status *out);

/** Stops the arm and ends a running task as failed. */
FG_NODISCARD fg_status fg_task_abort(fg_workspace *ws);

#ifdef __cplusplus
}
#endif

#endif /* FORCEGRASP_H */
