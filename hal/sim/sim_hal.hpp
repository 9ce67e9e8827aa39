// Host-only simulation: the hardware interfaces of hal/include/fg/hal/ (Clock, ArmLink,
// Gripper, DepthSensor) implemented against a simulated world, so the grasp task can run
// on a PC. Simulated time only: nothing here reads the wall clock or sleeps. The caller
// drives time: SimClock::advance_us(), then SimArm::tick() / SimGripper::tick() with the
// same step in seconds. Depth captures read the clock they were given.
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "fg/core/gripper.hpp"
#include "fg/hal/arm_link.hpp"
#include "fg/hal/clock.hpp"
#include "fg/hal/depth_sensor.hpp"
#include "fg/hal/gripper.hpp"
#include "fg/robot/ur5.hpp"
#include "sim/depth_render.hpp"
#include "sim/sim_world.hpp"

namespace fg::sim {

// ---------------------------------------------------------------------------------------
//! Simulated monotonic time, starting at 0; only advance_us() moves it.
class SimClock final : public fg::hal::Clock {
 public:
  void advance_us(uint64_t dt_us) { now_us_ += dt_us; }
  //! The same value as now_us(), readable through a const reference.
  uint64_t time_us() const { return now_us_; }

 private:
  uint64_t do_now_us() override { return now_us_; }
  uint64_t now_us_ = 0;
};

// ---------------------------------------------------------------------------------------
struct SimArmConfig {
  //! Maximum joint speeds (rad/s); 3.15 rad/s is the UR5's (datasheet: 180 deg/s).
  double max_speed_rad_s[6] = {3.15, 3.15, 3.15, 3.15, 3.15, 3.15};
  //! Joint limits (rad); default the URDF's +-2 pi on every joint.
  double lower_rad[6] = {-6.283185307179586, -6.283185307179586, -6.283185307179586,
                         -6.283185307179586, -6.283185307179586, -6.283185307179586};
  double upper_rad[6] = {6.283185307179586, 6.283185307179586, 6.283185307179586,
                         6.283185307179586, 6.283185307179586, 6.283185307179586};
  //! A motion ends when every joint is this close to its target (rad).
  double arrive_tol_rad = 1e-9;
  //! The arm's true kinematics (where tool0 really is for given joints): the nominal
  //! UR5 unless a simulation perturbs it (with_kinematic_error).
  fg::robot::Ur5Params kinematics = fg::robot::ur5_nominal();
};

//! The UR5 in joint space. A move is a straight line in joint space: every joint starts and
//! arrives together, the slowest joint (largest |dq| / max speed) at speed_fraction of its
//! maximum speed, the others proportionally slower. No acceleration phase (the real
//! controller ramps; here the duration is |dq|max / (fraction * speed) exactly).
class SimArm final : public fg::hal::ArmLink {
 public:
  //! q0_rad: the start joints (nullptr: all zero). clock: stamps read_state() (may be null:
  //! stamp 0); it must outlive the arm.
  explicit SimArm(const double q0_rad[6] = nullptr, const SimArmConfig& config = SimArmConfig{},
                  const SimClock* clock = nullptr);

  //! Advances the motion by dt_s seconds (<= 0 or non-finite: nothing happens).
  void tick(double dt_s);

  //! Protective stop: stops where it is and refuses moves until clear_fault().
  void inject_fault();
  void clear_fault();

  const double* q_rad() const { return q_; }
  const double* target_rad() const { return target_; }
  bool moving() const { return moving_; }
  bool fault() const { return fault_; }
  //! Seconds the current (or last) motion takes in total.
  double motion_duration_s() const { return duration_s_; }

  //! Where the arm's base stands in the world (default identity).
  void set_world_T_base(const Rigid& world_T_base) { world_T_base_ = world_T_base; }
  const Rigid& world_T_base() const { return world_T_base_; }
  //! base_T_tool0 by the FK (ur5_forward_d) of config().kinematics; base = URDF base_link.
  Rigid tool0() const;
  Rigid world_T_tool0() const { return world_T_base_ * tool0(); }

  //! world_T_tool0 along the last accepted motion: the start pose, then one pose per tick
  //! while moving (the last one at the target or where it stopped). For collision judging.
  const std::vector<Rigid>& tool0_path() const { return path_; }

  const SimArmConfig& config() const { return config_; }

 private:
  [[nodiscard]] fg::Status do_move_joints(const double q[6], double speed_fraction) override;
  [[nodiscard]] fg::Status do_read_state(fg::hal::ArmState& out) override;
  void do_stop() override;

  SimArmConfig config_;
  const SimClock* clock_;
  Rigid world_T_base_;
  double q_[6] = {0, 0, 0, 0, 0, 0};
  double start_[6] = {0, 0, 0, 0, 0, 0};
  double target_[6] = {0, 0, 0, 0, 0, 0};
  double duration_s_ = 0.0;  // of the current motion
  double elapsed_s_ = 0.0;   // since its start
  bool moving_ = false;
  bool fault_ = false;
  std::vector<Rigid> path_;
};

//! A provider of world_T_frame for a frame rigidly mounted on tool0 (a wrist camera, the
//! grasp frame): world_T_base * base_T_tool0(q now) * tool0_T_frame. The arm must outlive it.
std::function<Rigid()> mounted_on_tool0(const SimArm& arm, const Rigid& tool0_T_frame);

// ---------------------------------------------------------------------------------------
//! Where closing pads meet an object.
class ContactModel {
 public:
  virtual ~ContactModel() = default;
  //! The width at which both pads touch when closing from opening_m (m), or -1 when
  //! closing to zero touches nothing (or only one pad touches).
  virtual double contact_width(double opening_m) const = 0;
};

//! Contact on the true geometry: each pad face (finger_width x finger_depth in the grasp
//! frame's y and z, centred on its origin) is sampled on a grid (samples at most
//! sample_spacing_m apart, edges included: a thin part under the fingertips, such as
//! a pair of scissors lying flat, is touched as a real pad touches it) and moved inwards along
//! the grasp x axis until one of its samples is inside an object (sdf <= 0). The pads are
//! judged separately (an off-centre object is touched first by the nearer pad; the
//! simulated gripper centres on it, as if the object or the wrist gave way). The table is
//! not an obstacle here (World::sdf_objects).
class SdfContactModel final : public ContactModel {
 public:
  //! world: must outlive the model. world_T_grasp: read at every contact_width() call
  //! (grasp frame: origin at the pads' centre, +x closing from the left pad to the right
  //! one, +z approach, +y = z x x).
  SdfContactModel(const World& world, std::function<Rigid()> world_T_grasp,
                  const fg::GripperGeometry& geometry = fg::GripperGeometry{}, double sample_spacing_m = 2.5e-3,
                  double step_m = 0.5e-3);

  double contact_width(double opening_m) const override;

  //! How far the pad (side 0 = left at x = -opening/2, side 1 = right at +opening/2) moves
  //! inwards, at most max_travel_m, before it touches; max_travel_m when it touches nothing.
  double pad_travel(const Rigid& world_T_grasp, double opening_m, int side, double max_travel_m) const;

 private:
  bool pad_touches(const Rigid& world_T_grasp, double face_x_m) const;

  const World& world_;
  std::function<Rigid()> world_T_grasp_;
  fg::GripperGeometry geometry_;
  int samples_y_, samples_z_;  // across (grasp y) and along (grasp z) the pad
  double step_m_;
};

struct SimGripperConfig {
  fg::GripperGeometry geometry{};  //!< max_opening_m bounds the width
  double speed_m_s = 0.15;         //!< pad-to-pad speed (2F-85: 20..150 mm/s)
  double initial_width_m = 0.085;
};

//! A 2F-85-class parallel gripper. open_to() targets are clamped to [0, max_opening] (as
//! the real driver clamps its position byte). close() asks the contact model once, at the
//! width it starts from (the world is assumed still while the gripper closes), and then
//! moves there; contact becomes true on arrival.
class SimGripper final : public fg::hal::Gripper {
 public:
  //! contact: may be null (closing then never touches anything); must outlive the gripper.
  explicit SimGripper(const SimGripperConfig& config = SimGripperConfig{}, const ContactModel* contact = nullptr);

  void set_contact_model(const ContactModel* contact) { contact_ = contact; }
  void tick(double dt_s);

  void inject_fault();
  void clear_fault();

  double width_m() const { return width_m_; }
  double target_width_m() const { return target_m_; }
  bool moving() const { return moving_; }
  bool contact() const { return contact_now_; }
  //! The force of the last close() (N); the simulation does not model force otherwise.
  double last_force_n() const { return force_n_; }

 private:
  [[nodiscard]] fg::Status do_open_to(float width_m) override;
  [[nodiscard]] fg::Status do_close(float force_n) override;
  [[nodiscard]] fg::Status do_read_state(fg::hal::GripperState& out) override;

  SimGripperConfig config_;
  const ContactModel* contact_;
  double width_m_;
  double target_m_;
  double force_n_ = 0.0;
  bool moving_ = false;
  bool closing_to_contact_ = false;  // the current motion ends on an object
  bool contact_now_ = false;
  bool fault_ = false;
};

// ---------------------------------------------------------------------------------------
struct SimDepthSensorConfig {
  Intrinsics K{};
  NoiseModel noise{};
  uint64_t latency_us = 33000;  //!< from request to ready (one 30 Hz frame)
  uint64_t seed = 1;            //!< capture i uses a seed derived from (seed, i)
};

//! A depth camera rendering a World (render_depth). The pose is read from the provider at
//! request time (the image is "taken" then: stamp_us = request time) and the frame
//! becomes ready latency_us later on the SimClock. A new request replaces the frame (and
//! a capture still in progress). Before any request poll() says idle. A non-finite pose
//! from the provider makes the capture fail, like set_fail_next().
class SimDepthSensor final : public fg::hal::DepthSensor {
 public:
  //! world and clock must outlive the sensor.
  SimDepthSensor(const World& world, const SimClock& clock, std::function<Rigid()> world_T_sensor,
                 const SimDepthSensorConfig& config = SimDepthSensorConfig{});

  //! The next capture fails (poll says failed after the latency, no frame).
  void set_fail_next() { fail_next_ = true; }

  //! The camera (intrinsics, world_T_sensor) of the last capture.
  const Camera& last_camera() const { return camera_; }
  const DepthImage& last_image() const { return image_; }
  uint64_t captures() const { return captures_; }

 private:
  [[nodiscard]] fg::Status do_request_capture() override;
  [[nodiscard]] fg::hal::CaptureState do_poll(fg::hal::DepthFrame& out) override;

  const World& world_;
  const SimClock& clock_;
  std::function<Rigid()> world_T_sensor_;
  SimDepthSensorConfig config_;
  Camera camera_;
  DepthImage image_;
  uint64_t captures_ = 0;
  uint64_t requested_at_us_ = 0;
  bool pending_ = false;  // a request was made
  bool failing_ = false;  // the current request fails
  bool fail_next_ = false;
};

}  // namespace fg::sim
