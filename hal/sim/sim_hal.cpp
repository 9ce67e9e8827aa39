// Host-only simulation of the hardware interfaces; see sim_hal.hpp.
#include "sim/sim_hal.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "fg/robot/ur5.hpp"
#include "fg/robot/ur5_ik.hpp"
#include "sim/pinhole.hpp"
#include "sim/sim_rng.hpp"

namespace fg::sim {

using fg::Status;
using fg::hal::CaptureState;

// ---------------------------------------------------------------------------------------
// SimArm

SimArm::SimArm(const double q0_rad[6], const SimArmConfig& config, const SimClock* clock)
    : config_(config), clock_(clock) {
  for (int i = 0; i < 6; ++i) {
    q_[i] = q0_rad != nullptr ? q0_rad[i] : 0.0;
    start_[i] = target_[i] = q_[i];
  }
}

Rigid SimArm::tool0() const {
  fg::robot::PoseD base_T_tool0;
  Rigid r;
  // q_ is always finite (targets are checked), so the FK cannot fail here.
  if (fg::robot::ur5_forward_d(config_.kinematics, q_, base_T_tool0)) {
    r.R = base_T_tool0.R;
    r.t = base_T_tool0.t;
  }
  return r;
}

Status SimArm::do_move_joints(const double q[6], double speed_fraction) {
  if (fault_) return Status::invalid_sequence;  // a protective stop must be cleared first
  for (int i = 0; i < 6; ++i) {
    if (!std::isfinite(q[i]) || q[i] < config_.lower_rad[i] || q[i] > config_.upper_rad[i])
      return Status::invalid_argument;
    if (!(config_.max_speed_rad_s[i] > 0.0)) return Status::invalid_argument;
  }
  // The slowest joint sets the duration; the others are scaled to arrive with it.
  double duration_s = 0.0;
  for (int i = 0; i < 6; ++i)
    duration_s = std::max(duration_s, std::abs(q[i] - q_[i]) / (speed_fraction * config_.max_speed_rad_s[i]));
  for (int i = 0; i < 6; ++i) {
    start_[i] = q_[i];
    target_[i] = q[i];
  }
  duration_s_ = duration_s;
  elapsed_s_ = 0.0;
  path_.clear();
  path_.push_back(world_T_tool0());
  moving_ = duration_s > 0.0;  // a zero-length move is over at once
  return Status::ok;
}

void SimArm::tick(double dt_s) {
  if (!moving_ || fault_ || !std::isfinite(dt_s) || dt_s <= 0.0) return;
  elapsed_s_ += dt_s;
  const double s = duration_s_ > 0.0 ? std::min(1.0, elapsed_s_ / duration_s_) : 1.0;
  double err = 0.0;
  for (int i = 0; i < 6; ++i) {
    q_[i] = start_[i] + s * (target_[i] - start_[i]);
    err = std::max(err, std::abs(target_[i] - q_[i]));
  }
  if (err <= config_.arrive_tol_rad) {
    for (int i = 0; i < 6; ++i) q_[i] = target_[i];  // rounding of the sum of ticks
    moving_ = false;
  }
  path_.push_back(world_T_tool0());
}

void SimArm::do_stop() {
  if (moving_) {
    for (int i = 0; i < 6; ++i) target_[i] = q_[i];
    moving_ = false;
  }
}

void SimArm::inject_fault() {
  do_stop();
  fault_ = true;
}

void SimArm::clear_fault() { fault_ = false; }

Status SimArm::do_read_state(fg::hal::ArmState& out) {
  for (int i = 0; i < 6; ++i) out.q[i] = q_[i];
  out.moving = moving_;
  out.fault = fault_;
  out.stamp_us = clock_ != nullptr ? clock_->time_us() : 0;
  return Status::ok;
}

std::function<Rigid()> mounted_on_tool0(const SimArm& arm, const Rigid& tool0_T_frame) {
  return [&arm, tool0_T_frame] { return arm.world_T_tool0() * tool0_T_frame; };
}

// ---------------------------------------------------------------------------------------
// SdfContactModel

SdfContactModel::SdfContactModel(const World& world, std::function<Rigid()> world_T_grasp,
                                 const fg::GripperGeometry& geometry, double sample_spacing_m, double step_m)
    : world_(world),
      world_T_grasp_(std::move(world_T_grasp)),
      geometry_(geometry),
      step_m_(step_m > 1e-6 ? step_m : 0.5e-3) {
  // Enough samples that neighbours are at most the spacing apart (at least the corners;
  // at most 64 per side, whatever the spacing asked).
  const double spacing = sample_spacing_m > 1e-4 ? sample_spacing_m : 2.5e-3;
  const auto count = [spacing](double length) {
    const double intervals = std::ceil(std::max(0.0, length) / spacing);
    return static_cast<int>(std::min(63.0, std::max(1.0, intervals))) + 1;
  };
  samples_y_ = count(geometry.finger_width_m);
  samples_z_ = count(geometry.finger_depth_m);
}

bool SdfContactModel::pad_touches(const Rigid& G, double face_x_m) const {
  const double fw = geometry_.finger_width_m;
  const double fd = geometry_.finger_depth_m;
  for (int iy = 0; iy < samples_y_; ++iy) {
    const double y = -0.5 * fw + fw * iy / (samples_y_ - 1);
    for (int iz = 0; iz < samples_z_; ++iz) {
      const double z = -0.5 * fd + fd * iz / (samples_z_ - 1);
      if (world_.sdf_objects(G.apply(V3(face_x_m, y, z))) <= 0.0) return true;
    }
  }
  return false;
}

double SdfContactModel::pad_travel(const Rigid& G, double opening_m, int side, double max_travel_m) const {
  const double sx = side == 0 ? -1.0 : 1.0;  // face at sx * opening / 2, moving towards -sx
  auto face_x = [&](double travel) { return sx * (0.5 * opening_m - travel); };
  if (!(max_travel_m > 0.0)) return 0.0;
  if (pad_touches(G, face_x(0.0))) return 0.0;
  // March in steps (an object thinner than a step could be skipped: 0.5 mm is below what
  // the planner resolves), then bisect the last step.
  const int steps = static_cast<int>(std::min(1e6, std::ceil(max_travel_m / step_m_)));
  double clear_m = 0.0;  // the pad is free of objects up to this travel
  for (int k = 1; k <= steps; ++k) {
    const double t = std::min(max_travel_m, k * step_m_);
    if (!pad_touches(G, face_x(t))) {
      clear_m = t;
      continue;
    }
    double hit_m = t;
    for (int it = 0; it < 40; ++it) {  // 0.5 mm / 2^40: far below any use
      const double mid = 0.5 * (clear_m + hit_m);
      (pad_touches(G, face_x(mid)) ? hit_m : clear_m) = mid;
    }
    return clear_m;
  }
  return max_travel_m;
}

double SdfContactModel::contact_width(double opening_m) const {
  if (!(opening_m > 0.0)) return -1.0;
  const Rigid G = world_T_grasp_();
  const double left = pad_travel(G, opening_m, 0, opening_m);
  if (left >= opening_m) return -1.0;
  // The right pad can only move until it meets the left one.
  const double right = pad_travel(G, opening_m, 1, opening_m - left);
  if (right >= opening_m - left) return -1.0;
  return opening_m - left - right;
}

// ---------------------------------------------------------------------------------------
// SimGripper

SimGripper::SimGripper(const SimGripperConfig& config, const ContactModel* contact)
    : config_(config), contact_(contact) {
  const double max_m = config_.geometry.max_opening_m;
  width_m_ = target_m_ = std::clamp(config_.initial_width_m, 0.0, max_m);
}

Status SimGripper::do_open_to(float width_m) {
  if (fault_) return Status::invalid_sequence;
  target_m_ = std::clamp(static_cast<double>(width_m), 0.0, static_cast<double>(config_.geometry.max_opening_m));
  closing_to_contact_ = false;
  contact_now_ = false;
  moving_ = target_m_ != width_m_;
  return Status::ok;
}

Status SimGripper::do_close(float force_n) {
  if (fault_) return Status::invalid_sequence;
  force_n_ = force_n;
  const double cw = contact_ != nullptr ? contact_->contact_width(width_m_) : -1.0;
  closing_to_contact_ = cw >= 0.0 && cw <= width_m_;
  target_m_ = closing_to_contact_ ? cw : 0.0;
  moving_ = target_m_ != width_m_;
  contact_now_ = !moving_ && closing_to_contact_;
  return Status::ok;
}

void SimGripper::tick(double dt_s) {
  if (!moving_ || fault_ || !std::isfinite(dt_s) || dt_s <= 0.0) return;
  const double step_m = config_.speed_m_s * dt_s;
  const double left_m = target_m_ - width_m_;
  if (std::abs(left_m) <= step_m) {
    width_m_ = target_m_;
    moving_ = false;
    contact_now_ = closing_to_contact_;
  } else {
    width_m_ += left_m > 0.0 ? step_m : -step_m;
  }
}

void SimGripper::inject_fault() {
  fault_ = true;
  moving_ = false;
  target_m_ = width_m_;
}

void SimGripper::clear_fault() { fault_ = false; }

Status SimGripper::do_read_state(fg::hal::GripperState& out) {
  out.width_m = static_cast<float>(width_m_);
  out.moving = moving_;
  out.contact = contact_now_;
  out.fault = fault_;
  return Status::ok;
}

// ---------------------------------------------------------------------------------------
// SimDepthSensor

SimDepthSensor::SimDepthSensor(const World& world, const SimClock& clock, std::function<Rigid()> world_T_sensor,
                               const SimDepthSensorConfig& config)
    : world_(world), clock_(clock), world_T_sensor_(std::move(world_T_sensor)), config_(config) {
  camera_.K = config_.K;
}

Status SimDepthSensor::do_request_capture() {
  camera_.K = config_.K;
  camera_.world_T_sensor = world_T_sensor_();
  requested_at_us_ = clock_.time_us();
  pending_ = true;
  // A pose the simulation cannot render from (a broken provider) is a failed capture.
  const bool pose_ok = camera_.world_T_sensor.R.allFinite() && camera_.world_T_sensor.t.allFinite();
  failing_ = fail_next_ || !pose_ok;
  fail_next_ = false;
  // Each capture its own noise, the same on every run.
  const uint64_t seed = splitmix64(config_.seed ^ splitmix64(captures_));
  ++captures_;
  if (failing_)
    image_ = DepthImage{};
  else
    image_ = render_depth(world_, camera_, config_.noise, seed);
  return Status::ok;
}

CaptureState SimDepthSensor::do_poll(fg::hal::DepthFrame& out) {
  if (!pending_) return CaptureState::idle;
  if (clock_.time_us() - requested_at_us_ < config_.latency_us) return CaptureState::busy;
  if (failing_) return CaptureState::failed;
  out.depth_mm = image_.mm.data();
  out.width = static_cast<uint16_t>(image_.width);
  out.height = static_cast<uint16_t>(image_.height);
  out.k = to_pinhole(camera_.K);
  out.stamp_us = requested_at_us_;
  return CaptureState::ready;
}

}  // namespace fg::sim
