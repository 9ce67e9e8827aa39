// Per-target services the embedded side calls. Each target provides one
// implementation (platform/targets/host for Linux hosts).
#pragma once
#include <cstdint>

namespace fg::platform {

//! Monotonic time in microseconds since an arbitrary origin.
uint64_t monotonic_us();

//! A free-running cycle (or tick) counter; 0 where the target has none.
uint64_t cycle_counter();

enum class LogLevel : uint8_t { debug, info, warning, error };

//! A sink for short diagnostic lines; the host writes to stderr, firmware to its log.
void log(LogLevel level, const char* message);

//! Called by FG_INTERNAL_CHECK when an invariant is broken (a bug, never bad input).
//! The host prints file:line and aborts in debug builds; it only logs in release.
void internal_error(const char* file, int line, const char* what);

}  // namespace fg::platform

#define FG_INTERNAL_CHECK(cond)                                             \
  do {                                                                      \
    if (!(cond)) ::fg::platform::internal_error(__FILE__, __LINE__, #cond); \
  } while (0)
