// hal/: the clock the grasp task reads (NVI: firmware implements do_now_us()).
// Embedded side: no heap, no exceptions.
#pragma once
#include <cstdint>

namespace fg::hal {

//! A monotonic clock in microseconds (the task's timeouts and timestamps).
class Clock {
 public:
  //! Microseconds since an arbitrary origin; never decreases.
  uint64_t now_us() { return do_now_us(); }

 protected:
  // Not deleted through the interface: no virtual destructor, so no operator delete
  // reference in bare-metal images.
  ~Clock() = default;

 private:
  virtual uint64_t do_now_us() = 0;
};

}  // namespace fg::hal
