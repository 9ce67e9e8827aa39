// hal/: the link to the UR5 controller (NVI: firmware implements the do_* calls).
// Embedded side: no heap, no exceptions.
#pragma once
#include <cmath>
#include <cstdint>

#include "fg/core/status.hpp"

namespace fg::hal {

struct ArmState {
  double q[6] = {0, 0, 0, 0, 0, 0};  //!< joint angles (rad), DH order base..wrist 3
  bool moving = false;               //!< a commanded motion is under way
  bool fault = false;                //!< protective stop, limit violation, lost link
  uint64_t stamp_us = 0;
};

//! The arm follows joint-space targets; its own controller plans the motion.
class ArmLink {
 public:
  //! Moves to `q` (rad) at `speed_fraction` (0, 1] of its maximum joint speed.
  //! invalid_argument for a non-finite target or speed; the driver refuses targets
  //! outside its limits the same way.
  [[nodiscard]] Status move_joints(const double q[6], double speed_fraction) {
    for (int i = 0; i < 6; ++i)
      if (!std::isfinite(q[i])) return Status::invalid_argument;
    if (!(speed_fraction > 0.0 && speed_fraction <= 1.0)) return Status::invalid_argument;
    return do_move_joints(q, speed_fraction);
  }
  [[nodiscard]] Status read_state(ArmState& out) { return do_read_state(out); }
  //! Stops any motion (always accepted).
  void stop() { do_stop(); }

 protected:
  // Not deleted through the interface: no virtual destructor, so no operator delete
  // reference in bare-metal images.
  ~ArmLink() = default;

 private:
  [[nodiscard]] virtual Status do_move_joints(const double q[6], double speed_fraction) = 0;
  [[nodiscard]] virtual Status do_read_state(ArmState& out) = 0;
  virtual void do_stop() = 0;
};

}  // namespace fg::hal
