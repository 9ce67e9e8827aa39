// hal/: a depth sensor, non-blocking (NVI: firmware implements the do_* calls).
// Embedded side: no heap, no exceptions; the frame memory belongs to the driver.
#pragma once
#include <cstdint>

#include "fg/core/pinhole.hpp"
#include "fg/core/status.hpp"

namespace fg::hal {

//! One depth image as the driver holds it: valid until the next request_capture().
struct DepthFrame {
  const uint16_t* depth_mm = nullptr;  //!< row-major, 0 = no return
  uint16_t width = 0, height = 0;
  PinholeIntrinsics k;
  uint64_t stamp_us = 0;  //!< when the image was taken (driver clock)
};

enum class CaptureState : uint8_t { idle, busy, ready, failed };

//! A depth camera. The pose is not its business: the task knows where the head sensor
//! is mounted and computes the wrist sensor's pose from the arm's joints.
class DepthSensor {
 public:
  //! Starts a capture; Status::ok when accepted.
  [[nodiscard]] Status request_capture() { return do_request_capture(); }
  //! Progress of the last request; on `ready`, `out` views the frame.
  [[nodiscard]] CaptureState poll(DepthFrame& out) {
    const CaptureState s = do_poll(out);
    if (s == CaptureState::ready && (out.depth_mm == nullptr || out.width == 0 || out.height == 0))
      return CaptureState::failed;  // a driver bug is a failed capture, not a crash
    return s;
  }

 protected:
  // Not deleted through the interface: no virtual destructor, so no operator delete
  // reference in bare-metal images.
  ~DepthSensor() = default;

 private:
  [[nodiscard]] virtual Status do_request_capture() = 0;
  [[nodiscard]] virtual CaptureState do_poll(DepthFrame& out) = 0;
};

}  // namespace fg::hal
