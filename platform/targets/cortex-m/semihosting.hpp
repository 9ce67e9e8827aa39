// ARM semihosting (the host debugger or QEMU's -semihosting carries the calls): the
// two calls the image needs. Only for FG_SEMIHOSTING builds: without a debugger the
// BKPT instruction faults.
#pragma once
#include <cstdint>

namespace fg::cortex_m {

inline uint32_t semihost_call(uint32_t op, const void* arg) {
  register uint32_t r0 __asm__("r0") = op;
  register const void* r1 __asm__("r1") = arg;
  __asm__ __volatile__("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
  return r0;
}

//! SYS_WRITE0: writes a null-terminated string to the debug console.
inline void semihost_write0(const char* s) { semihost_call(0x04u, s); }

//! SYS_EXIT: ends the session; QEMU exits with status 0 for ok, 1 otherwise.
[[noreturn]] inline void semihost_exit(bool ok) {
  // ADP_Stopped_ApplicationExit, or ADP_Stopped_RunTimeErrorUnknown.
  const uintptr_t reason = ok ? 0x20026u : 0x20023u;
  semihost_call(0x18u, reinterpret_cast<const void*>(reason));
  for (;;) {
  }
}

}  // namespace fg::cortex_m
