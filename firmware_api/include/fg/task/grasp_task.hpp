// The grasp task: capture both sensors, plan, open, move to the pre-grasp, approach,
// close, lift. A non-blocking state machine: step() does one control tick's worth of
// work and returns; every state has a timeout. It is what controller firmware calls
// (through the C API or directly): no heap, no exceptions, the planner and the
// hardware are the caller's.
#pragma once
#include <cstdint>

#include "fg/core/planner.hpp"
#include "fg/hal/arm_link.hpp"
#include "fg/hal/clock.hpp"
#include "fg/hal/depth_sensor.hpp"
#include "fg/hal/gripper.hpp"
#include "fg/robot/ur5.hpp"
#include "fg/robot/ur5_grasp_check.hpp"
#include "fg/robot/ur5_ik.hpp"

namespace fg::task {

enum class TaskState : uint8_t {
  idle,         //!< not started (or reset)
  capturing,    //!< both sensors asked for an image; waiting for them
  planning,     //!< one tick: plan, then inverse kinematics of the motion
  opening,      //!< gripper to its full opening
  to_pregrasp,  //!< arm to the pre-grasp pose (backed off along the approach)
  approaching,  //!< arm to the grasp pose, along the approach line in short steps
  closing,      //!< gripper closes until contact
  lifting,      //!< arm lifts the object straight up
  succeeded,
  failed,  //!< see failure()
};
const char* to_string(TaskState s);

//! Why the task stopped in TaskState::failed. Values are explicit and never reused.
enum class TaskFailure : uint8_t {
  none = 0,
  invalid_config = 1,  //!< start() refused the configuration
  sensor_failed = 2,   //!< a sensor refused or failed a capture, or its image was refused
  sensor_timeout = 3,
  no_grasp = 4,     //!< the planner found none: plan_result() says why
  unreachable = 5,  //!< no inverse kinematics solution inside the joint limits
  arm_refused = 6,  //!< the arm refused a motion command
  arm_fault = 7,    //!< the arm reported a fault
  arm_timeout = 8,
  gripper_refused = 9,
  gripper_fault = 10,
  gripper_timeout = 11,
  missed = 12,   //!< the gripper closed without touching anything
  aborted = 13,  //!< abort() by the caller
};
const char* to_string(TaskFailure f);

struct TaskConfig {
  Pose world_T_base;  //!< the arm's base (DH base frame) in the world
  Pose world_T_head;  //!< the head sensor (fixed mount)
  Pose tool0_T_hand;  //!< the wrist sensor on the flange (hand-eye)
  bool use_head = true, use_hand = true;
  float tcp_offset_m = 0.15f;    //!< flange (tool0) to the pads' centre along tool0 +z
  float lift_m = 0.10f;          //!< lift straight up (world z) after closing
  double speed_fraction = 0.25;  //!< of the arm's maximum joint speed
  float grip_force_n = 40.f;
  double joint_tolerance_rad = 2e-3;  //!< a motion is done when every joint is this close
  uint32_t capture_timeout_us = 2000000;
  uint32_t move_timeout_us = 20000000;
  uint32_t gripper_timeout_us = 3000000;
  robot::Ur5Params robot = robot::ur5_nominal();
  robot::IkOptions ik;
  //! The tool (fingers, palm, and the body behind them up to the flange) checked against
  //! the support plane and the target with libccd, where the build has it.
  bool check_tool_collision = true;
  float tool_body_half_width_m = 0.032f;
  //! After a refusal as occluded, the wrist sensor looks again from the view the plan
  //! advises (PlanResult::look: along its line, at the wrist's own distance) and the task
  //! captures and plans once more: at most this many times (0: never).
  uint32_t max_relooks = 1;
};

//! The hardware the task drives; a sensor pointer may be null when it is not used.
struct TaskHal {
  hal::Clock& clock;
  hal::DepthSensor* head;
  hal::DepthSensor* hand;
  hal::ArmLink& arm;
  hal::Gripper& gripper;
};

class GraspTask {
 public:
  //! Checks the configuration and starts a grasp (state capturing).
  [[nodiscard]] Status start(const TaskConfig& cfg);
  //! One control tick. Blocks only in `planning` (one plan, milliseconds).
  TaskState step(Planner& planner, const TaskHal& hal);
  //! Stops the arm and ends a running task as failed(aborted) (e.g. an operator stop).
  void abort(const TaskHal& hal);

  TaskState state() const { return state_; }
  TaskFailure failure() const { return failure_; }
  const char* message() const { return message_; }
  const PlanResult& plan_result() const { return plan_; }
  //! Joint targets of the motion (valid from `opening` on): pre-grasp, grasp, lift.
  const double* pregrasp_joints() const { return q_pre_; }
  const double* grasp_joints() const { return q_grasp_; }
  const double* lift_joints() const { return q_lift_; }
  //! Ticks spent in step() since start() (bounded work per tick, but how many ticks
  //! a grasp takes depends on the hardware).
  uint32_t ticks() const { return ticks_; }
  //! Times the wrist sensor looked again from an advised view since start(), and the
  //! advice it followed last (invalid before any).
  uint32_t relooks() const { return relooks_; }
  const LookAdvice& followed_advice() const { return followed_; }

 private:
  void enter(TaskState s, uint64_t now_us);
  TaskState fail(TaskFailure f, const char* message);
  bool timed_out(uint64_t now_us, uint32_t timeout_us) const;
  TaskState step_capture(Planner& planner, const TaskHal& hal, uint64_t now_us);
  TaskState step_plan(Planner& planner, const TaskHal& hal, uint64_t now_us);
  TaskState step_move(const TaskHal& hal, uint64_t now_us, const double* target, TaskState next);
  [[nodiscard]] bool relook_joints(double q[6]) const;

  TaskConfig cfg_;
  TaskState state_ = TaskState::idle;
  TaskFailure failure_ = TaskFailure::none;
  const char* message_ = "";
  uint64_t entered_us_ = 0;
  bool entry_done_ = false;  // the current state's one-time action was issued
  uint32_t ticks_ = 0;
  bool pending_[2] = {false, false};  // head, hand captures still awaited
  double q_capture_[6] = {};          // the arm's joints when the images were taken
  double q_pre_[6] = {}, q_grasp_[6] = {}, q_lift_[6] = {};
  double q_approach_[robot::GraspMotion::kApproachSteps][6] = {};  // the last one is q_grasp_
  int waypoint_ = 0;                                               // of the approach
  uint32_t relooks_ = 0;
  LookAdvice followed_;
  bool move_first_ = false;  // capturing: the arm first takes q_relook_
  double q_relook_[6] = {};
  PlanResult plan_;
  robot::Ur5GraspCheck check_;
};

}  // namespace fg::task
