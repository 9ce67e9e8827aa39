// The grasp task state machine (grasp_task.hpp). Embedded rules: no heap, no
// exceptions; every state ends by success, failure or its timeout.
#include "fg/task/grasp_task.hpp"

#include <cmath>

#include "fg/core/constants.hpp"
#include "fg/robot/ur5_ik.hpp"

namespace fg::task {
namespace {

using robot::compose;
using robot::to_d;
using robot::to_f;

bool all_finite(const Pose& p) { return p.R.allFinite() && p.t.allFinite(); }

}  // namespace

const char* to_string(TaskState s) {
  switch (s) {
    case TaskState::idle:
      return "idle";
    case TaskState::capturing:
      return "capturing";
    case TaskState::planning:
      return "planning";
    case TaskState::opening:
      return "opening";
    case TaskState::to_pregrasp:
      return "to_pregrasp";
    case TaskState::approaching:
      return "approaching";
    case TaskState::closing:
      return "closing";
    case TaskState::lifting:
      return "lifting";
    case TaskState::succeeded:
      return "succeeded";
    case TaskState::failed:
      return "failed";
  }
  return "unknown_state";
}

const char* to_string(TaskFailure f) {
  switch (f) {
    case TaskFailure::none:
      return "none";
    case TaskFailure::invalid_config:
      return "invalid_config";
    case TaskFailure::sensor_failed:
      return "sensor_failed";
    case TaskFailure::sensor_timeout:
      return "sensor_timeout";
    case TaskFailure::no_grasp:
      return "no_grasp";
    case TaskFailure::unreachable:
      return "unreachable";
    case TaskFailure::arm_refused:
      return "arm_refused";
    case TaskFailure::arm_fault:
      return "arm_fault";
    case TaskFailure::arm_timeout:
      return "arm_timeout";
    case TaskFailure::gripper_refused:
      return "gripper_refused";
    case TaskFailure::gripper_fault:
      return "gripper_fault";
    case TaskFailure::gripper_timeout:
      return "gripper_timeout";
    case TaskFailure::missed:
      return "missed";
    case TaskFailure::aborted:
      return "aborted";
  }
  return "unknown_failure";
}

Status GraspTask::start(const TaskConfig& cfg) {
  state_ = TaskState::idle;
  ticks_ = 0;
  relooks_ = 0;
  followed_ = LookAdvice{};
  move_first_ = false;
  plan_ = PlanResult{};
  const bool ok = all_finite(cfg.world_T_base) && all_finite(cfg.world_T_head) && all_finite(cfg.tool0_T_hand) &&
                  (cfg.use_head || cfg.use_hand) && std::isfinite(cfg.tcp_offset_m) && cfg.tcp_offset_m >= 0.f &&
                  cfg.tcp_offset_m < 1.f && std::isfinite(cfg.lift_m) && cfg.lift_m >= 0.f && cfg.lift_m < 1.f &&
                  cfg.speed_fraction > 0.0 && cfg.speed_fraction <= 1.0 && std::isfinite(cfg.grip_force_n) &&
                  cfg.grip_force_n > 0.f && cfg.joint_tolerance_rad > 0.0 && cfg.joint_tolerance_rad < 0.5 &&
                  cfg.capture_timeout_us > 0 && cfg.move_timeout_us > 0 && cfg.gripper_timeout_us > 0;
  if (!ok) {
    state_ = TaskState::failed;
    failure_ = TaskFailure::invalid_config;
    message_ = "task configuration: a pose is not finite, no sensor is used, or a value is out of range";
    return Status::invalid_config;
  }
  cfg_ = cfg;
  robot::GraspCheckConfig check;
  check.motion.robot = cfg.robot;
  check.motion.world_T_base = cfg.world_T_base;
  check.motion.tcp_offset_m = cfg.tcp_offset_m;
  check.motion.lift_m = cfg.lift_m;
  check.motion.ik = cfg.ik;
  check.tool.body_half_width_m = cfg.tool_body_half_width_m;
  check.check_tool = cfg.check_tool_collision;
  check_.configure(check);
  failure_ = TaskFailure::none;
  message_ = "";
  state_ = TaskState::capturing;
  entry_done_ = false;
  entered_us_ = 0;  // set by the first step, which reads the clock
  return Status::ok;
}

void GraspTask::enter(TaskState s, uint64_t now_us) {
  state_ = s;
  entered_us_ = now_us;
  entry_done_ = false;
}

TaskState GraspTask::fail(TaskFailure f, const char* message) {
  state_ = TaskState::failed;
  failure_ = f;
  message_ = message;
  return state_;
}

bool GraspTask::timed_out(uint64_t now_us, uint32_t timeout_us) const { return now_us - entered_us_ > timeout_us; }

void GraspTask::abort(const TaskHal& hal) {
  hal.arm.stop();
  if (state_ != TaskState::succeeded && state_ != TaskState::failed)
    fail(TaskFailure::aborted, "aborted by the caller");
}

TaskState GraspTask::step(Planner& planner, const TaskHal& hal) {
  if (state_ == TaskState::idle || state_ == TaskState::succeeded || state_ == TaskState::failed) return state_;
  ++ticks_;
  const uint64_t now = hal.clock.now_us();
  if (ticks_ == 1) entered_us_ = now;
  switch (state_) {
    case TaskState::capturing:
      return step_capture(planner, hal, now);
    case TaskState::planning:
      return step_plan(planner, hal, now);
    case TaskState::opening:
    case TaskState::closing: {
      const bool opening = state_ == TaskState::opening;
      if (!entry_done_) {
        const float open_m = planner.config().gripper.max_opening_m;
        const Status s = opening ? hal.gripper.open_to(open_m) : hal.gripper.close(cfg_.grip_force_n);
        if (s != Status::ok) return fail(TaskFailure::gripper_refused, "the gripper refused the command");
        entry_done_ = true;
        return state_;
      }
      hal::GripperState g;
      if (hal.gripper.read_state(g) != Status::ok || g.fault)
        return fail(TaskFailure::gripper_fault, "the gripper reported a fault");
      if (!g.moving) {
        if (opening) {
          enter(TaskState::to_pregrasp, now);
        } else if (g.contact) {
          enter(TaskState::lifting, now);
        } else {
          return fail(TaskFailure::missed, "the gripper closed without touching the object");
        }
        return state_;
      }
      if (timed_out(now, cfg_.gripper_timeout_us))
        return fail(TaskFailure::gripper_timeout, "the gripper did not finish in time");
      return state_;
    }
    case TaskState::to_pregrasp:
      return step_move(hal, now, q_pre_, TaskState::approaching);
    case TaskState::approaching: {
      // One waypoint after the other; each has the move timeout.
      const bool last = waypoint_ + 1 >= robot::GraspMotion::kApproachSteps;
      const bool moving = entry_done_;
      const TaskState s =
          step_move(hal, now, q_approach_[waypoint_], last ? TaskState::closing : TaskState::approaching);
      if (s == TaskState::approaching && moving && !entry_done_) ++waypoint_;  // arrived at a waypoint
      return s;
    }
    case TaskState::lifting:
      return step_move(hal, now, q_lift_, TaskState::succeeded);
    default:
      return state_;
  }
}

TaskState GraspTask::step_capture(Planner& planner, const TaskHal& hal, uint64_t now) {
  // Looking again from an advised view: the arm takes the wrist sensor there first.
  if (move_first_) {
    const bool moving = entry_done_;
    const TaskState s = step_move(hal, now, q_relook_, TaskState::capturing);
    if (s == TaskState::capturing && moving && !entry_done_) move_first_ = false;  // there
    return s;
  }
  hal::DepthSensor* sensors[2] = {hal.head, hal.hand};
  const bool used[2] = {cfg_.use_head, cfg_.use_hand};
  if (!entry_done_) {
    // The wrist sensor's pose comes from the arm: it must stand still for the image.
    hal::ArmState arm;
    if (hal.arm.read_state(arm) != Status::ok || arm.fault)
      return fail(TaskFailure::arm_fault, "the arm reported a fault before the capture");
    if (arm.moving) {
      if (timed_out(now, cfg_.capture_timeout_us))
        return fail(TaskFailure::sensor_timeout, "the arm kept moving: no still image for the wrist sensor");
      return state_;
    }
    for (int i = 0; i < 6; ++i) q_capture_[i] = arm.q[i];
    planner.reset();
    for (int r = 0; r < 2; ++r) {
      pending_[r] = used[r];
      if (!used[r]) continue;
      if (sensors[r] == nullptr) return fail(TaskFailure::sensor_failed, "a configured sensor has no driver");
      if (sensors[r]->request_capture() != Status::ok)
        return fail(TaskFailure::sensor_failed, "a sensor refused the capture request");
    }
    entry_done_ = true;
    return state_;
  }
  for (int r = 0; r < 2; ++r) {
    if (!pending_[r]) continue;
    hal::DepthFrame frame;
    const hal::CaptureState cs = sensors[r]->poll(frame);
    if (cs == hal::CaptureState::failed || cs == hal::CaptureState::idle)
      return fail(TaskFailure::sensor_failed, "a sensor failed its capture");
    if (cs != hal::CaptureState::ready) continue;
    Pose world_T_sensor = cfg_.world_T_head;
    if (r == 1) {
      robot::PoseD base_T_tool0;
      if (!robot::ur5_forward_d(cfg_.robot, q_capture_, base_T_tool0))
        return fail(TaskFailure::arm_fault, "the arm reported non-finite joints");
      world_T_sensor = to_f(compose(compose(to_d(cfg_.world_T_base), base_T_tool0), to_d(cfg_.tool0_T_hand)));
    }
    const Status s = planner.add_depth_image(r == 0 ? SensorRole::head : SensorRole::hand, frame.depth_mm, frame.width,
                                             frame.height, frame.k, world_T_sensor);
    if (s != Status::ok) return fail(TaskFailure::sensor_failed, planner.last_message());
    pending_[r] = false;
  }
  if (!pending_[0] && !pending_[1]) {
    enter(TaskState::planning, now);
    return state_;
  }
  if (timed_out(now, cfg_.capture_timeout_us))
    return fail(TaskFailure::sensor_timeout, "a sensor gave no image in time");
  return state_;
}

TaskState GraspTask::step_plan(Planner& planner, const TaskHal&, uint64_t now) {
  // The robot's check makes the planner move on to the next candidate when the arm
  // cannot reach one or the tool would hit something; it keeps the joints of the one
  // it accepts.
  robot::GraspCheckConfig check = check_.config();
  check.tool.gripper = planner.config().gripper;
  check_.configure(check);
  check_.set_current_joints(q_capture_);
  GraspCheck* const callers_check = planner.grasp_check();
  planner.set_grasp_check(&check_);
  const Status planned = planner.plan(plan_);  // the same as plan_.status
  planner.set_grasp_check(callers_check);
  if (planned != Status::ok) {
    if (plan_.reason == NoGraspReason::unreachable) return fail(TaskFailure::unreachable, plan_.message);
    // Refused as occluded: the robot can look from elsewhere and plan again, from the
    // view the plan advises, when the arm can put the wrist sensor there.
    if (plan_.reason == NoGraspReason::occluded && plan_.look.valid && cfg_.use_hand && relooks_ < cfg_.max_relooks &&
        relook_joints(q_relook_)) {
      ++relooks_;
      followed_ = plan_.look;
      move_first_ = true;
      enter(TaskState::capturing, now);
      return state_;
    }
    return fail(TaskFailure::no_grasp, plan_.message);
  }
  if (!check_.has_motion())
    return fail(TaskFailure::unreachable, "no joint solution inside the limits for the pre-grasp, grasp or lift pose");
  const robot::GraspMotion& m = check_.motion();
  for (int i = 0; i < 6; ++i) {
    q_pre_[i] = m.pregrasp[i];
    q_grasp_[i] = m.grasp[i];
    q_lift_[i] = m.lift[i];
    for (int k = 0; k < robot::GraspMotion::kApproachSteps; ++k) q_approach_[k][i] = m.approach[k][i];
  }
  waypoint_ = 0;
  enter(TaskState::opening, now);
  return state_;
}

// The joints that put the wrist sensor on the advised view's line through the hidden
// space (PlanResult::look), at its distance from that space when it captured, looking
// at it: rolls about the optical axis of 0, -30, +30, ... deg, each the IK solution
// nearest the capture joints inside the limits.
bool GraspTask::relook_joints(double q[6]) const {
  const LookAdvice& a = plan_.look;
  robot::PoseD base_T_tool0;
  if (!robot::ur5_forward_d(cfg_.robot, q_capture_, base_T_tool0)) return false;
  const robot::PoseD world_T_hand = compose(compose(to_d(cfg_.world_T_base), base_T_tool0), to_d(cfg_.tool0_T_hand));
  const Eigen::Vector3d at = a.at.cast<double>();
  Eigen::Vector3d back = (a.from - a.at).cast<double>();
  const double dist = (world_T_hand.t - at).norm();
  if (!(back.norm() > 1e-9) || !(dist > 1e-6)) return false;
  back.normalize();
  const Eigen::Vector3d z = -back;  // the optical axis, towards the hidden space
  const Eigen::Vector3d x0 = z.unitOrthogonal(), y0 = z.cross(x0);
  const robot::PoseD base_T_world = robot::inverse(to_d(cfg_.world_T_base));
  const robot::PoseD hand_T_tool0 = robot::inverse(to_d(cfg_.tool0_T_hand));
  constexpr int kRolls = 12;
  for (int r = 0; r < kRolls; ++r) {
    const int steps = (r + 1) / 2;  // 0, 1, 1, 2, 2, ...: the nearest rolls first
    const double roll = (r % 2 == 0 ? 1.0 : -1.0) * static_cast<double>(steps) * (2.0 * kPi / kRolls);
    robot::PoseD world_T_camera;
    world_T_camera.R.col(0) = std::cos(roll) * x0 + std::sin(roll) * y0;
    world_T_camera.R.col(2) = z;
    world_T_camera.R.col(1) = z.cross(world_T_camera.R.col(0));
    world_T_camera.t = at + back * dist;
    robot::IkSolutions sols;
    const robot::PoseD target = compose(base_T_world, compose(world_T_camera, hand_T_tool0));
    if (!robot::ik_has_solution(robot::ur5_inverse(cfg_.robot, target, sols, cfg_.ik))) continue;
    const robot::IkChoice c = robot::choose_nearest(q_capture_, sols, cfg_.ik.limits);
    if (c.status != robot::IkStatus::ok) continue;
    for (int i = 0; i < 6; ++i) q[i] = c.q[i];
    return true;
  }
  return false;
}

TaskState GraspTask::step_move(const TaskHal& hal, uint64_t now, const double* target, TaskState next) {
  if (!entry_done_) {
    if (hal.arm.move_joints(target, cfg_.speed_fraction) != Status::ok)
      return fail(TaskFailure::arm_refused, "the arm refused the joint target");
    entry_done_ = true;
    return state_;
  }
  hal::ArmState arm;
  if (hal.arm.read_state(arm) != Status::ok || arm.fault)
    return fail(TaskFailure::arm_fault, "the arm reported a fault");
  bool there = !arm.moving;
  for (int i = 0; i < 6 && there; ++i) there = std::fabs(arm.q[i] - target[i]) <= cfg_.joint_tolerance_rad;
  if (there) {
    enter(next, now);
    return state_;
  }
  if (timed_out(now, cfg_.move_timeout_us)) {
    hal.arm.stop();
    return fail(TaskFailure::arm_timeout, "the arm did not reach its target in time");
  }
  return state_;
}

}  // namespace fg::task
