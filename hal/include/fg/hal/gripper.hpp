// hal/: a parallel (or underactuated) gripper (NVI: firmware implements the do_* calls).
// Embedded side: no heap, no exceptions.
#pragma once
#include <cmath>
#include <cstdint>

#include "fg/core/status.hpp"

namespace fg::hal {

struct GripperState {
  float width_m = 0.f;  //!< current distance between the pads
  bool moving = false;
  bool contact = false;  //!< both pads stopped on something while closing
  bool fault = false;
};

class Gripper {
 public:
  //! Opens (or moves) to `width_m`; invalid_argument when not finite or negative.
  [[nodiscard]] Status open_to(float width_m) {
    if (!(std::isfinite(width_m) && width_m >= 0.f)) return Status::invalid_argument;
    return do_open_to(width_m);
  }
  //! Closes until contact or fully closed, with at most `force_n` newtons.
  [[nodiscard]] Status close(float force_n) {
    if (!(std::isfinite(force_n) && force_n > 0.f)) return Status::invalid_argument;
    return do_close(force_n);
  }
  [[nodiscard]] Status read_state(GripperState& out) { return do_read_state(out); }

 protected:
  // Not deleted through the interface: no virtual destructor, so no operator delete
  // reference in bare-metal images.
  ~Gripper() = default;

 private:
  [[nodiscard]] virtual Status do_open_to(float width_m) = 0;
  [[nodiscard]] virtual Status do_close(float force_n) = 0;
  [[nodiscard]] virtual Status do_read_state(GripperState& out) = 0;
};

}  // namespace fg::hal
