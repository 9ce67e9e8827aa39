// The C API of firmware_api/include/forcegrasp/forcegrasp.h over the C++ core.
// Embedded rules: no heap (the workspace is placement-constructed in caller memory),
// no exceptions, no global state.
#include <cstdint>
#include <new>

#include "fg/core/planner.hpp"
#include "fg/task/grasp_task.hpp"
#include "forcegrasp/forcegrasp.h"

namespace {
constexpr uint32_t kMagic = 0x46475753u;  // "FGWS"

// The firmware's callbacks behind the HAL interfaces the task drives. A callback's
// non-zero result is a refusal; a capture state outside FG_CAPTURE_* is a failure.
class OpsClock final : public fg::hal::Clock {
 public:
  const fg_hal_ops* ops = nullptr;

 private:
  uint64_t do_now_us() override { return ops->now_us(ops->ctx); }
};

class OpsSensor final : public fg::hal::DepthSensor {
 public:
  const fg_hal_ops* ops = nullptr;
  int32_t role = FG_SENSOR_HEAD;

 private:
  fg::Status do_request_capture() override {
    return ops->sensor_request(ops->ctx, role) == 0 ? fg::Status::ok : fg::Status::invalid_argument;
  }
  fg::hal::CaptureState do_poll(fg::hal::DepthFrame& out) override {
    fg_depth_frame f{};
    switch (ops->sensor_poll(ops->ctx, role, &f)) {
      case FG_CAPTURE_IDLE:
        return fg::hal::CaptureState::idle;
      case FG_CAPTURE_BUSY:
        return fg::hal::CaptureState::busy;
      case FG_CAPTURE_READY:
        out.depth_mm = f.depth_mm;
        out.width = f.width;
        out.height = f.height;
        out.k = fg::PinholeIntrinsics{f.k.fx, f.k.fy, f.k.cx, f.k.cy};
        return fg::hal::CaptureState::ready;
      default:
        return fg::hal::CaptureState::failed;
    }
  }
};

class OpsArm final : public fg::hal::ArmLink {
 public:
  const fg_hal_ops* ops = nullptr;

 private:
  fg::Status do_move_joints(const double q[6], double speed) override {
    return ops->arm_move(ops->ctx, q, speed) == 0 ? fg::Status::ok : fg::Status::invalid_argument;
  }
  fg::Status do_read_state(fg::hal::ArmState& out) override {
    fg_arm_state a{};
    if (ops->arm_read(ops->ctx, &a) != 0) return fg::Status::invalid_argument;
    for (int i = 0; i < 6; ++i) out.q[i] = a.q[i];
    out.moving = a.moving != 0;
    out.fault = a.fault != 0;
    return fg::Status::ok;
  }
  void do_stop() override { ops->arm_stop(ops->ctx); }
};

class OpsGripper final : public fg::hal::Gripper {
 public:
  const fg_hal_ops* ops = nullptr;

 private:
  fg::Status do_open_to(float w) override {
    return ops->gripper_open(ops->ctx, w) == 0 ? fg::Status::ok : fg::Status::invalid_argument;
  }
  fg::Status do_close(float f) override {
    return ops->gripper_close(ops->ctx, f) == 0 ? fg::Status::ok : fg::Status::invalid_argument;
  }
  fg::Status do_read_state(fg::hal::GripperState& out) override {
    fg_gripper_state g{};
    if (ops->gripper_read(ops->ctx, &g) != 0) return fg::Status::invalid_argument;
    out.width_m = g.width_m;
    out.moving = g.moving != 0;
    out.contact = g.contact != 0;
    out.fault = g.fault != 0;
    return fg::Status::ok;
  }
};

}  // namespace

struct fg_workspace {
  uint32_t magic;            // kMagic while the workspace is valid
  const fg_workspace* self;  // == this: a byte copy of a workspace is refused
  const char* message;       // static text of the last call
  fg::Planner planner;
  // The grasp task and the firmware's hardware behind the HAL interfaces.
  bool task_started;
  fg_hal_ops ops;
  OpsClock clock;
  OpsSensor head, hand;
  OpsArm arm;
  OpsGripper gripper;
  fg::task::GraspTask task;
};

// The budget is a byte count: comparing a sizeof with it is the point.
static_assert(sizeof(fg_workspace) <= FG_WORKSPACE_SIZE,  // NOLINT(bugprone-sizeof-expression)
              "the workspace outgrew the build configuration's FG_WORKSPACE_SIZE budget");
static_assert(alignof(fg_workspace) <= FG_WORKSPACE_ALIGN, "workspace alignment above FG_WORKSPACE_ALIGN");
static_assert(FG_MAX_OBJECTS == fg::kMaxObjects, "fg_objects' list is the planner's: FG_MAX_OBJECTS is kMaxObjects");

// The C statuses and reasons are the core's values: one numbering, checked here.
#define FG_SAME(c_value, core_value) \
  static_assert(static_cast<int32_t>(c_value) == static_cast<int32_t>(core_value), #c_value)
FG_SAME(FG_OK, fg::Status::ok);
FG_SAME(FG_NO_GRASP, fg::Status::no_grasp);
FG_SAME(FG_ERR_INVALID_ARGUMENT, fg::Status::invalid_argument);
FG_SAME(FG_ERR_NON_FINITE, fg::Status::non_finite);
FG_SAME(FG_ERR_INVALID_POSE, fg::Status::invalid_pose);
FG_SAME(FG_ERR_INVALID_CONFIG, fg::Status::invalid_config);
FG_SAME(FG_ERR_NO_INPUT, fg::Status::no_input);
FG_SAME(FG_ERR_INVALID_SENSOR, fg::Status::invalid_sensor);
FG_SAME(FG_ERR_INVALID_SEQUENCE, fg::Status::invalid_sequence);
FG_SAME(FG_ERR_SENSOR_DISAGREEMENT, fg::Status::sensor_disagreement);
FG_SAME(FG_ERR_CAPACITY_EXCEEDED, fg::Status::capacity_exceeded);
FG_SAME(FG_ERR_NUMERIC_FAILURE, fg::Status::numeric_failure);
FG_SAME(FG_ERR_INTERNAL, fg::Status::internal_error);
FG_SAME(FG_REASON_NONE, fg::NoGraspReason::none);
FG_SAME(FG_REASON_NO_POINTS, fg::NoGraspReason::no_points);
FG_SAME(FG_REASON_NO_PLANE, fg::NoGraspReason::no_plane);
FG_SAME(FG_REASON_NO_OBJECT, fg::NoGraspReason::no_object);
FG_SAME(FG_REASON_TOO_FEW_POINTS, fg::NoGraspReason::too_few_points);
FG_SAME(FG_REASON_TOO_WIDE, fg::NoGraspReason::too_wide);
FG_SAME(FG_REASON_NO_CANDIDATE, fg::NoGraspReason::no_candidate);
FG_SAME(FG_REASON_COLLISION, fg::NoGraspReason::collision);
FG_SAME(FG_REASON_UNREACHABLE, fg::NoGraspReason::unreachable);
FG_SAME(FG_REASON_FRICTION, fg::NoGraspReason::friction);
FG_SAME(FG_REASON_DEGENERATE, fg::NoGraspReason::degenerate);
FG_SAME(FG_REASON_OCCLUDED, fg::NoGraspReason::occluded);
FG_SAME(FG_STAGE_INGEST, fg::Stage::ingest);
FG_SAME(FG_STAGE_TOTAL, fg::Stage::total);
FG_SAME(FG_REGISTRATION_NOT_RUN, fg::RegistrationOutcome::not_run);
FG_SAME(FG_REGISTRATION_CORRECTED, fg::RegistrationOutcome::corrected);
FG_SAME(FG_REGISTRATION_CALIBRATION_KEPT, fg::RegistrationOutcome::calibration_kept);
FG_SAME(FG_REGISTRATION_TOO_LITTLE_OVERLAP, fg::RegistrationOutcome::too_little_overlap);
FG_SAME(FG_REGISTRATION_IMPLAUSIBLE, fg::RegistrationOutcome::implausible);
FG_SAME(FG_REGISTRATION_HAND_ADDED_FIRST, fg::RegistrationOutcome::hand_added_first);
FG_SAME(FG_REGISTRATION_SENSOR_DISAGREEMENT, fg::RegistrationOutcome::sensor_disagreement);
FG_SAME(FG_REGISTRATION_MODE_OFF, fg::RegistrationMode::off);
FG_SAME(FG_REGISTRATION_MODE_ON, fg::RegistrationMode::on);
FG_SAME(FG_REGISTRATION_MODE_STRICT, fg::RegistrationMode::strict);
FG_SAME(FG_STAGE_COUNT, fg::Stage::count);
FG_SAME(FG_TASK_IDLE, fg::task::TaskState::idle);
FG_SAME(FG_TASK_CAPTURING, fg::task::TaskState::capturing);
FG_SAME(FG_TASK_PLANNING, fg::task::TaskState::planning);
FG_SAME(FG_TASK_OPENING, fg::task::TaskState::opening);
FG_SAME(FG_TASK_TO_PREGRASP, fg::task::TaskState::to_pregrasp);
FG_SAME(FG_TASK_APPROACHING, fg::task::TaskState::approaching);
FG_SAME(FG_TASK_CLOSING, fg::task::TaskState::closing);
FG_SAME(FG_TASK_LIFTING, fg::task::TaskState::lifting);
FG_SAME(FG_TASK_SUCCEEDED, fg::task::TaskState::succeeded);
FG_SAME(FG_TASK_FAILED, fg::task::TaskState::failed);
FG_SAME(FG_TASK_OK, fg::task::TaskFailure::none);
FG_SAME(FG_TASK_INVALID_CONFIG, fg::task::TaskFailure::invalid_config);
FG_SAME(FG_TASK_SENSOR_FAILED, fg::task::TaskFailure::sensor_failed);
FG_SAME(FG_TASK_SENSOR_TIMEOUT, fg::task::TaskFailure::sensor_timeout);
FG_SAME(FG_TASK_NO_GRASP, fg::task::TaskFailure::no_grasp);
FG_SAME(FG_TASK_UNREACHABLE, fg::task::TaskFailure::unreachable);
FG_SAME(FG_TASK_ARM_REFUSED, fg::task::TaskFailure::arm_refused);
FG_SAME(FG_TASK_ARM_FAULT, fg::task::TaskFailure::arm_fault);
FG_SAME(FG_TASK_ARM_TIMEOUT, fg::task::TaskFailure::arm_timeout);
FG_SAME(FG_TASK_GRIPPER_REFUSED, fg::task::TaskFailure::gripper_refused);
FG_SAME(FG_TASK_GRIPPER_FAULT, fg::task::TaskFailure::gripper_fault);
FG_SAME(FG_TASK_GRIPPER_TIMEOUT, fg::task::TaskFailure::gripper_timeout);
FG_SAME(FG_TASK_MISSED, fg::task::TaskFailure::missed);
FG_SAME(FG_TASK_ABORTED, fg::task::TaskFailure::aborted);
#undef FG_SAME

namespace {

[[nodiscard]] fg_status to_c(fg::Status s) { return static_cast<fg_status>(static_cast<int32_t>(s)); }

// One field list for both directions keeps the C struct and PlannerConfig in step.
// clang-format off
#define FG_CONFIG_FIELDS(X)                                                                   \
  X(range_min_m) X(range_max_m) X(crop_half_x_m) X(crop_half_y_m) X(crop_min_z_m)            \
  X(crop_max_z_m) X(voxel_leaf_m) X(plane_distance_m) X(ransac_iterations) X(ransac_seed)    \
  X(plane_max_tilt_rad) X(object_min_height_m) X(cluster_cells) X(min_object_points)         \
  X(workspace_centre_x_m) X(workspace_centre_y_m) X(dtheta_rad) X(single_sensor_arc_rad)     \
  X(vertical_snap_rad) X(axis_ratio_min) X(extension_dtheta_rad) X(approach_view_max_rad)    \
  X(scan_delta_m) X(dx_threshold_m) X(width_margin_m) X(hull_cell_m) X(hull_closing_cells)   \
  X(candidates_per_view) X(centre_weight) X(beta_max_rad) X(contact_band_m)                  \
  X(reach_width_ratio) X(friction_mu) X(table_clearance_m) X(collision_tolerance_m)          \
  X(pregrasp_clearance_m) X(palm_clearance_m)
#define FG_GRIPPER_FIELDS(X)                                                                  \
  X(max_opening_m) X(min_opening_m) X(finger_width_m) X(finger_depth_m) X(finger_thickness_m) \
  X(palm_depth_m) X(palm_width_m)
// clang-format on

void to_c(const fg::PlannerConfig& p, fg_config& c) {
#define X(f) c.f = p.f;
  FG_CONFIG_FIELDS(X)
#undef X
#define X(f) c.gripper.f = p.gripper.f;
  FG_GRIPPER_FIELDS(X)
#undef X
  c.target_rule = static_cast<uint32_t>(p.target_rule);
  c.extend_search = p.extend_search ? 1u : 0u;
  c.paper_depth = p.paper_depth ? 1u : 0u;
  c.executability_checks = p.executability_checks ? 1u : 0u;
}

// Flags must be 0 or 1 and the rule a known value: anything else is invalid_config.
[[nodiscard]] fg_status from_c(const fg_config& c, fg::PlannerConfig& p, const char** field) {
#define X(f) p.f = c.f;
  FG_CONFIG_FIELDS(X)
#undef X
#define X(f) p.gripper.f = c.gripper.f;
  FG_GRIPPER_FIELDS(X)
#undef X
  struct Flag {
    uint32_t value;
    bool* dst;
    const char* name;
  };
  const Flag flags[] = {{c.extend_search, &p.extend_search, "extend_search"},
                        {c.paper_depth, &p.paper_depth, "paper_depth"},
                        {c.executability_checks, &p.executability_checks, "executability_checks"}};
  for (const Flag& f : flags) {
    if (f.value > 1u) {
      if (field != nullptr) *field = f.name;
      return FG_ERR_INVALID_CONFIG;
    }
    *f.dst = f.value == 1u;
  }
  if (c.target_rule > 1u) {
    if (field != nullptr) *field = "target_rule";
    return FG_ERR_INVALID_CONFIG;
  }
  p.target_rule = static_cast<fg::TargetRule>(c.target_rule);
  return to_c(fg::validate(p, field));
}

[[nodiscard]] fg_status check_header(const fg_config* cfg, const char** field) {
  if (cfg == nullptr) return FG_ERR_INVALID_ARGUMENT;
  if (cfg->struct_size != sizeof(fg_config)) {
    if (field != nullptr) *field = "struct_size";
    return FG_ERR_CONFIG_SIZE;
  }
  if (cfg->abi_version != FG_ABI_VERSION) {
    if (field != nullptr) *field = "abi_version";
    return FG_ERR_ABI_MISMATCH;
  }
  return FG_OK;
}

bool valid(const fg_workspace* ws) { return ws != nullptr && ws->magic == kMagic && ws->self == ws; }

fg::Pose to_pose(const fg_pose& in) {
  fg::Pose out;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) out.R(i, j) = in.r[3 * i + j];
    out.t(i) = in.t[i];
  }
  return out;
}

// Roles outside the enum are refused before any cast can wrap them onto a valid one.
bool role_ok(int32_t role) { return role >= 0 && static_cast<uint32_t>(role) < fg::kMaxSensors; }

[[nodiscard]] fg_status fail(fg_workspace* ws, fg_status s, const char* message) {
  ws->message = message;
  return s;
}

void copy3(const fg::Vec3& v, float out[3]) {
  for (int i = 0; i < 3; ++i) out[i] = v(i);
}

void copy_pose(const fg::Grasp& g, fg_grasp& out) {
  copy3(g.position, out.position);
  copy3(g.approach, out.approach);
  copy3(g.closing, out.closing);
  copy3(g.pregrasp, out.pregrasp);
  out.width_m = g.width;
  out.beta_rad = g.beta;
  out.dz_m = g.dz;
}

void fill_grasp(const fg::PlanResult& r, fg_grasp& out) {
  out = fg_grasp{};
  out.reason = static_cast<int32_t>(r.reason);
  if (r.status == fg::Status::ok) copy_pose(r.grasp, out);
  out.points_input = r.points.input;
  out.points_finite = r.points.finite;
  out.points_kept = r.points.after_filter;
  out.voxels = r.points.voxels;
  out.plane_voxels = r.points.plane;
  out.object_voxels = r.points.object;
  out.viewpoints = r.viewpoints;
  out.candidates = r.candidates;
  for (uint32_t i = 0; i < FG_STAGE_COUNT; ++i) out.stage_us[i] = r.stage_us[i];
}

// fg_plan_ranked and fg_plan_object_ranked: `plan` (the planner's plan or plan_object)
// fills out[0], then the alternates on its target fill out[1..].
template <typename Plan>
[[nodiscard]] fg_status plan_ranked(fg_workspace* ws, fg_grasp* out, uint32_t capacity, uint32_t* count,
                                    const Plan& plan) {
  if (count != nullptr) *count = 0;
  if (out == nullptr || count == nullptr || capacity == 0)
    return fail(ws, FG_ERR_INVALID_ARGUMENT, "ranked grasp array or count pointer is null, or capacity is 0");
  fg::PlanResult r;
  const fg::Status s = plan(r);
  fill_grasp(r, out[0]);
  ws->message = r.message;
  if (s != fg::Status::ok) return to_c(s);
  // One alternate a call: the planner goes on where the last call stopped, so no
  // array of them is needed here; each entry carries the plan's counts and times.
  uint32_t n = 1;
  const uint32_t cap = capacity < FG_MAX_RANKED_GRASPS ? capacity : FG_MAX_RANKED_GRASPS;
  fg::RankedGrasp next;
  while (n < cap && ws->planner.more_grasps(&next, 1) == 1) {
    out[n] = out[0];
    copy_pose(next.grasp, out[n]);
    ++n;
  }
  *count = n;
  return FG_OK;
}

// A target through the planner's own check (validate(TargetSpec)): refused, the one
// before stays and the message says why.
[[nodiscard]] fg_status set_target(fg_workspace* ws, const fg::TargetSpec& target) {
  const fg::Status s = ws->planner.set_target(target);
  ws->message = s == fg::Status::ok ? "" : ws->planner.last_message();
  return to_c(s);
}

fg::Vec3 to_vec3(const float v[3]) { return fg::Vec3(v[0], v[1], v[2]); }

void to_c(const fg::ObjectSummary& o, bool is_target, fg_object& out) {
  out = fg_object{};
  copy3(o.centroid, out.centroid);
  copy3(o.box_min, out.box_min);
  copy3(o.box_max, out.box_max);
  out.voxels = o.voxels;
  out.is_target = is_target ? 1u : 0u;
}

}  // namespace

extern "C" {

uint32_t fg_version(void) {
  return (static_cast<uint32_t>(FG_VERSION_MAJOR) << 16) | (static_cast<uint32_t>(FG_VERSION_MINOR) << 8) |
         static_cast<uint32_t>(FG_VERSION_PATCH);
}

uint32_t fg_abi_version(void) { return FG_ABI_VERSION; }

size_t fg_workspace_size(void) { return sizeof(fg_workspace); }

size_t fg_workspace_align(void) { return FG_WORKSPACE_ALIGN; }

const char* fg_status_str(int32_t status) {
  switch (status) {
    case FG_OK:
      return "FG_OK";
    case FG_NO_GRASP:
      return "FG_NO_GRASP";
    case FG_ERR_INVALID_ARGUMENT:
      return "FG_ERR_INVALID_ARGUMENT";
    case FG_ERR_NON_FINITE:
      return "FG_ERR_NON_FINITE";
    case FG_ERR_INVALID_POSE:
      return "FG_ERR_INVALID_POSE";
    case FG_ERR_INVALID_CONFIG:
      return "FG_ERR_INVALID_CONFIG";
    case FG_ERR_NO_INPUT:
      return "FG_ERR_NO_INPUT";
    case FG_ERR_INVALID_SENSOR:
      return "FG_ERR_INVALID_SENSOR";
    case FG_ERR_INVALID_SEQUENCE:
      return "FG_ERR_INVALID_SEQUENCE";
    case FG_ERR_SENSOR_DISAGREEMENT:
      return "FG_ERR_SENSOR_DISAGREEMENT";
    case FG_ERR_WORKSPACE_TOO_SMALL:
      return "FG_ERR_WORKSPACE_TOO_SMALL";
    case FG_ERR_WORKSPACE_MISALIGNED:
      return "FG_ERR_WORKSPACE_MISALIGNED";
    case FG_ERR_ABI_MISMATCH:
      return "FG_ERR_ABI_MISMATCH";
    case FG_ERR_CONFIG_SIZE:
      return "FG_ERR_CONFIG_SIZE";
    case FG_ERR_NOT_A_WORKSPACE:
      return "FG_ERR_NOT_A_WORKSPACE";
    case FG_ERR_CAPACITY_EXCEEDED:
      return "FG_ERR_CAPACITY_EXCEEDED";
    case FG_ERR_NUMERIC_FAILURE:
      return "FG_ERR_NUMERIC_FAILURE";
    case FG_ERR_INTERNAL:
      return "FG_ERR_INTERNAL";
  }
  return "FG_UNKNOWN_STATUS";
}

const char* fg_reason_str(int32_t reason) {
  if (reason < FG_REASON_NONE || reason > FG_REASON_OCCLUDED) return "unknown_reason";
  return fg::to_string(static_cast<fg::NoGraspReason>(reason));
}

fg_status fg_config_default(fg_config* cfg) {
  if (cfg == nullptr) return FG_ERR_INVALID_ARGUMENT;
  *cfg = fg_config{};
  cfg->struct_size = sizeof(fg_config);
  cfg->abi_version = FG_ABI_VERSION;
  to_c(fg::PlannerConfig{}, *cfg);
  return FG_OK;
}

fg_status fg_config_check(const fg_config* cfg, const char** field) {
  if (field != nullptr) *field = "";
  const fg_status h = check_header(cfg, field);
  if (h != FG_OK) return h;
  fg::PlannerConfig p;
  const fg_status s = from_c(*cfg, p, field);
  if (field != nullptr && *field == nullptr) *field = "";  // the core leaves NULL when all is well
  return s;
}

fg_status fg_init(void* memory, size_t size, const fg_config* cfg, fg_workspace** out) {
  if (out == nullptr) return FG_ERR_INVALID_ARGUMENT;
  *out = nullptr;
  if (memory == nullptr) return FG_ERR_INVALID_ARGUMENT;
  if (reinterpret_cast<uintptr_t>(memory) % FG_WORKSPACE_ALIGN != 0) return FG_ERR_WORKSPACE_MISALIGNED;
  if (size < sizeof(fg_workspace)) return FG_ERR_WORKSPACE_TOO_SMALL;
  const fg_status h = check_header(cfg, nullptr);
  if (h != FG_OK) return h;
  fg::PlannerConfig p;
  const fg_status s = from_c(*cfg, p, nullptr);
  if (s != FG_OK) return s;
  fg_workspace* ws = new (memory) fg_workspace;  // placement: no allocation
  ws->magic = 0;
  ws->self = ws;
  ws->message = "";
  ws->task_started = false;
  if (ws->planner.configure(p) != fg::Status::ok) return FG_ERR_INTERNAL;  // validated above
  ws->magic = kMagic;
  *out = ws;
  return FG_OK;
}

fg_status fg_reset(fg_workspace* ws) {
  if (!valid(ws)) return FG_ERR_NOT_A_WORKSPACE;
  ws->planner.reset();
  ws->message = "";
  return FG_OK;
}

fg_status fg_add_depth_image(fg_workspace* ws, int32_t role, const uint16_t* depth_mm, uint16_t width, uint16_t height,
                             const fg_intrinsics* k, const fg_pose* world_T_sensor) {
  if (!valid(ws)) return FG_ERR_NOT_A_WORKSPACE;
  if (!role_ok(role)) return fail(ws, FG_ERR_INVALID_SENSOR, "unknown sensor role");
  if (k == nullptr) return fail(ws, FG_ERR_INVALID_ARGUMENT, "intrinsics pointer is null");
  if (world_T_sensor == nullptr) return fail(ws, FG_ERR_INVALID_ARGUMENT, "pose pointer is null");
  const fg::Pose pose = to_pose(*world_T_sensor);
  const fg::PinholeIntrinsics ki{k->fx, k->fy, k->cx, k->cy};
  const fg::Status s =
      ws->planner.add_depth_image(static_cast<fg::SensorRole>(role), depth_mm, width, height, ki, pose);
  ws->message = ws->planner.last_message();
  return to_c(s);
}

namespace {
// The checks both point calls make before the planner's own; FG_OK to go on.
[[nodiscard]] fg_status points_call_ok(fg_workspace* ws, int32_t role, size_t count, const fg_pose* world_T_sensor) {
  if (!valid(ws)) return FG_ERR_NOT_A_WORKSPACE;
  if (!role_ok(role)) return fail(ws, FG_ERR_INVALID_SENSOR, "unknown sensor role");
  if (world_T_sensor == nullptr) return fail(ws, FG_ERR_INVALID_ARGUMENT, "pose pointer is null");
  if (count > UINT32_MAX) return fail(ws, FG_ERR_CAPACITY_EXCEEDED, "more than 2^32 - 1 points in one call");
  return FG_OK;
}
}  // namespace

fg_status fg_add_points(fg_workspace* ws, int32_t role, const float* xyz, size_t count, size_t stride_bytes,
                        const fg_pose* world_T_sensor) {
  if (const fg_status c = points_call_ok(ws, role, count, world_T_sensor); c != FG_OK) return c;
  if (stride_bytes > UINT32_MAX) return fail(ws, FG_ERR_INVALID_ARGUMENT, "stride_bytes above 2^32 - 1");
  const fg::Pose pose = to_pose(*world_T_sensor);
  const fg::Status s = ws->planner.add_points(static_cast<fg::SensorRole>(role), xyz, static_cast<uint32_t>(count),
                                              static_cast<uint32_t>(stride_bytes), pose);
  ws->message = ws->planner.last_message();
  return to_c(s);
}

fg_status fg_set_sensor_units(fg_workspace* ws, int32_t role, float metres_per_unit) {
  if (!valid(ws)) return FG_ERR_NOT_A_WORKSPACE;
  if (!role_ok(role)) return fail(ws, FG_ERR_INVALID_SENSOR, "unknown sensor role");
  const fg::Status s = ws->planner.set_sensor_units(static_cast<fg::SensorRole>(role), metres_per_unit);
  ws->message = s == fg::Status::ok ? "" : ws->planner.last_message();
  return to_c(s);
}

fg_status fg_set_registration(fg_workspace* ws, int32_t on) {
  if (!valid(ws)) return FG_ERR_NOT_A_WORKSPACE;
  ws->planner.set_registration(on == FG_REGISTRATION_MODE_OFF      ? fg::RegistrationMode::off
                               : on == FG_REGISTRATION_MODE_STRICT ? fg::RegistrationMode::strict
                                                                   : fg::RegistrationMode::on);
  ws->message = "";
  return FG_OK;
}

fg_status fg_look_advice(fg_workspace* ws, fg_look_advice_result* out) {
  if (!valid(ws)) return FG_ERR_NOT_A_WORKSPACE;
  if (out == nullptr) return fail(ws, FG_ERR_INVALID_ARGUMENT, "look advice output pointer is null");
  const fg::LookAdvice& a = ws->planner.look();
  *out = fg_look_advice_result{};
  if (!a.valid) return FG_OK;
  out->valid = 1;
  out->sensor = static_cast<int32_t>(a.sensor);
  for (int i = 0; i < 3; ++i) {
    out->at[i] = a.at[i];
    out->from[i] = a.from[i];
  }
  return FG_OK;
}

fg_status fg_registration(fg_workspace* ws, fg_registration_result* out) {
  if (!valid(ws)) return FG_ERR_NOT_A_WORKSPACE;
  if (out == nullptr) return fail(ws, FG_ERR_INVALID_ARGUMENT, "registration output pointer is null");
  const fg::RegistrationResult& r = ws->planner.registration();
  *out = fg_registration_result{};
  out->outcome = static_cast<int32_t>(r.outcome);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) out->correction.r[3 * i + j] = r.correction.R(i, j);
    out->correction.t[i] = r.correction.t[i];
  }
  out->translation_mm = r.translation_mm;
  out->rotation_deg = r.rotation_deg;
  out->residual_before_mm = r.residual_before_mm;
  out->residual_mm = r.residual_mm;
  out->overlap = r.overlap;
  out->pairs = r.pairs;
  out->iterations = r.iterations;
  out->us = r.us;
  out->see_through = r.see_through;
  out->compared = r.compared;
  out->head_tilt_deg = r.head_tilt_deg;
  out->hand_tilt_deg = r.hand_tilt_deg;
  out->left_out =
      r.outcome == fg::RegistrationOutcome::sensor_disagreement ? static_cast<int32_t>(r.left_out) : int32_t{-1};
  return FG_OK;
}

fg_status fg_add_points_planar(fg_workspace* ws, int32_t role, const float* x, const float* y, const float* z,
                               size_t count, const fg_pose* world_T_sensor) {
  if (const fg_status c = points_call_ok(ws, role, count, world_T_sensor); c != FG_OK) return c;
  const fg::Pose pose = to_pose(*world_T_sensor);
  const fg::Status s =
      ws->planner.add_points_planar(static_cast<fg::SensorRole>(role), x, y, z, static_cast<uint32_t>(count), pose);
  ws->message = ws->planner.last_message();
  return to_c(s);
}

fg_status fg_plan(fg_workspace* ws, fg_grasp* out) {
  if (!valid(ws)) return FG_ERR_NOT_A_WORKSPACE;
  if (out == nullptr) return fail(ws, FG_ERR_INVALID_ARGUMENT, "grasp output pointer is null");
  fg::PlanResult r;
  const fg::Status s = ws->planner.plan(r);  // the same as r.status
  fill_grasp(r, *out);
  ws->message = r.message;
  return to_c(s);
}

fg_status fg_plan_ranked(fg_workspace* ws, fg_grasp* out, uint32_t capacity, uint32_t* count) {
  if (!valid(ws)) return FG_ERR_NOT_A_WORKSPACE;
  return plan_ranked(ws, out, capacity, count, [ws](fg::PlanResult& r) { return ws->planner.plan(r); });
}

fg_status fg_set_target_point(fg_workspace* ws, const float xyz[3]) {
  if (!valid(ws)) return FG_ERR_NOT_A_WORKSPACE;
  if (xyz == nullptr) return fail(ws, FG_ERR_INVALID_ARGUMENT, "target point pointer is null");
  fg::TargetSpec t;
  t.kind = fg::TargetKind::nearest_point;
  t.point = to_vec3(xyz);
  return set_target(ws, t);
}

fg_status fg_set_target_box(fg_workspace* ws, const float box_min[3], const float box_max[3]) {
  if (!valid(ws)) return FG_ERR_NOT_A_WORKSPACE;
  if (box_min == nullptr || box_max == nullptr) return fail(ws, FG_ERR_INVALID_ARGUMENT, "target box pointer is null");
  fg::TargetSpec t;
  t.kind = fg::TargetKind::inside_box;
  t.box_min = to_vec3(box_min);
  t.box_max = to_vec3(box_max);
  return set_target(ws, t);
}

fg_status fg_clear_target(fg_workspace* ws) {
  if (!valid(ws)) return FG_ERR_NOT_A_WORKSPACE;
  return set_target(ws, fg::TargetSpec{});
}

fg_status fg_objects(fg_workspace* ws, fg_object* out, uint32_t capacity, uint32_t* count, uint32_t* dropped) {
  if (!valid(ws)) return FG_ERR_NOT_A_WORKSPACE;
  if (count != nullptr) *count = 0;
  if (dropped != nullptr) *dropped = 0;
  if (out == nullptr || count == nullptr || capacity == 0)
    return fail(ws, FG_ERR_INVALID_ARGUMENT, "object array or count pointer is null, or capacity is 0");
  const fg::Planner& planner = ws->planner;
  const uint32_t n = planner.object_count();
  const uint32_t written = n < capacity ? n : capacity;
  const int32_t target = planner.target_object();
  for (uint32_t k = 0; k < written; ++k) to_c(planner.object(k), static_cast<int32_t>(k) == target, out[k]);
  *count = written;
  if (dropped != nullptr) *dropped = planner.objects_dropped() + (n - written);
  return FG_OK;
}

fg_status fg_plan_object(fg_workspace* ws, uint32_t index, fg_grasp* out) {
  if (!valid(ws)) return FG_ERR_NOT_A_WORKSPACE;
  if (out == nullptr) return fail(ws, FG_ERR_INVALID_ARGUMENT, "grasp output pointer is null");
  fg::PlanResult r;
  const fg::Status s = ws->planner.plan_object(index, r);  // the same as r.status
  fill_grasp(r, *out);
  ws->message = r.message;
  return to_c(s);
}

fg_status fg_plan_object_ranked(fg_workspace* ws, uint32_t index, fg_grasp* out, uint32_t capacity, uint32_t* count) {
  if (!valid(ws)) return FG_ERR_NOT_A_WORKSPACE;
  return plan_ranked(ws, out, capacity, count,
                     [ws, index](fg::PlanResult& r) { return ws->planner.plan_object(index, r); });
}

fg_status fg_task_config_default(fg_task_config* cfg) {
  if (cfg == nullptr) return FG_ERR_INVALID_ARGUMENT;
  const fg::task::TaskConfig d;
  *cfg = fg_task_config{};
  cfg->struct_size = sizeof(fg_task_config);
  const fg_pose identity = {{1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 0, 0}};
  cfg->world_T_base = cfg->world_T_head = cfg->tool0_T_hand = identity;
  cfg->use_head = d.use_head ? 1u : 0u;
  cfg->use_hand = d.use_hand ? 1u : 0u;
  cfg->tcp_offset_m = d.tcp_offset_m;
  cfg->lift_m = d.lift_m;
  cfg->grip_force_n = d.grip_force_n;
  cfg->speed_fraction = d.speed_fraction;
  cfg->joint_tolerance_rad = d.joint_tolerance_rad;
  cfg->capture_timeout_us = d.capture_timeout_us;
  cfg->move_timeout_us = d.move_timeout_us;
  cfg->gripper_timeout_us = d.gripper_timeout_us;
  return FG_OK;
}

fg_status fg_task_start(fg_workspace* ws, const fg_task_config* cfg, const fg_hal_ops* hal) {
  if (!valid(ws)) return FG_ERR_NOT_A_WORKSPACE;
  ws->task_started = false;  // a refused start leaves no task to step, old or new
  if (cfg == nullptr || hal == nullptr) return fail(ws, FG_ERR_INVALID_ARGUMENT, "task config or hal pointer is null");
  if (cfg->struct_size != sizeof(fg_task_config))
    return fail(ws, FG_ERR_CONFIG_SIZE, "fg_task_config.struct_size is not this library's");
  if (hal->now_us == nullptr || hal->sensor_request == nullptr || hal->sensor_poll == nullptr ||
      hal->arm_move == nullptr || hal->arm_read == nullptr || hal->arm_stop == nullptr ||
      hal->gripper_open == nullptr || hal->gripper_close == nullptr || hal->gripper_read == nullptr)
    return fail(ws, FG_ERR_INVALID_ARGUMENT, "a callback of fg_hal_ops is null");
  if (cfg->use_head > 1u || cfg->use_hand > 1u)
    return fail(ws, FG_ERR_INVALID_CONFIG, "use_head and use_hand must be 0 or 1");
  fg::task::TaskConfig t;
  t.world_T_base = to_pose(cfg->world_T_base);
  t.world_T_head = to_pose(cfg->world_T_head);
  t.tool0_T_hand = to_pose(cfg->tool0_T_hand);
  t.use_head = cfg->use_head == 1u;
  t.use_hand = cfg->use_hand == 1u;
  t.tcp_offset_m = cfg->tcp_offset_m;
  t.lift_m = cfg->lift_m;
  t.grip_force_n = cfg->grip_force_n;
  t.speed_fraction = cfg->speed_fraction;
  t.joint_tolerance_rad = cfg->joint_tolerance_rad;
  t.capture_timeout_us = cfg->capture_timeout_us;
  t.move_timeout_us = cfg->move_timeout_us;
  t.gripper_timeout_us = cfg->gripper_timeout_us;
  ws->ops = *hal;  // the workspace keeps its own copy: the caller's struct may go
  ws->clock.ops = ws->head.ops = ws->hand.ops = ws->arm.ops = ws->gripper.ops = &ws->ops;
  ws->head.role = FG_SENSOR_HEAD;
  ws->hand.role = FG_SENSOR_HAND;
  const fg::Status s = ws->task.start(t);
  ws->task_started = s == fg::Status::ok;
  ws->message = ws->task.message();
  return to_c(s);
}

fg_status fg_task_step(fg_workspace* ws, fg_task_status* out) {
  if (!valid(ws)) return FG_ERR_NOT_A_WORKSPACE;
  if (!ws->task_started) return fail(ws, FG_ERR_INVALID_SEQUENCE, "fg_task_step before fg_task_start");
  const fg::task::TaskHal hal{ws->clock, &ws->head, &ws->hand, ws->arm, ws->gripper};
  const fg::task::TaskState st = ws->task.step(ws->planner, hal);
  ws->message = ws->task.message();
  if (out != nullptr) {
    *out = fg_task_status{};
    out->state = static_cast<int32_t>(st);
    out->failure = static_cast<int32_t>(ws->task.failure());
    out->ticks = ws->task.ticks();
    fill_grasp(ws->task.plan_result(), out->grasp);
    if (st >= fg::task::TaskState::opening && st != fg::task::TaskState::failed) {
      for (int i = 0; i < 6; ++i) {
        out->q_pregrasp[i] = ws->task.pregrasp_joints()[i];
        out->q_grasp[i] = ws->task.grasp_joints()[i];
        out->q_lift[i] = ws->task.lift_joints()[i];
      }
    }
  }
  return FG_OK;
}

fg_status fg_task_abort(fg_workspace* ws) {
  if (!valid(ws)) return FG_ERR_NOT_A_WORKSPACE;
  if (!ws->task_started) return fail(ws, FG_ERR_INVALID_SEQUENCE, "fg_task_abort before fg_task_start");
  const fg::task::TaskHal hal{ws->clock, &ws->head, &ws->hand, ws->arm, ws->gripper};
  ws->task.abort(hal);
  ws->message = ws->task.message();
  return FG_OK;
}

const char* fg_last_message(const fg_workspace* ws) {
  if (!valid(ws)) return "not a workspace made by fg_init";
  return ws->message;
}

}  // extern "C"
