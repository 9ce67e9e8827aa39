// Cortex-M (ARMv7-M) implementation of the platform services: time from the DWT
// cycle counter, log and fault through the board hooks (fg/platform/board.h).
// No heap, no exceptions, no stdio. Not reentrant: call from one context (the
// planner's task), not from interrupts.
#include "fg/platform/board.h"
#include "fg/platform/platform.hpp"

#ifndef FG_CORE_CLOCK_HZ
#error "FG_CORE_CLOCK_HZ (core clock in Hz) must be defined: the cache variable of platform/CMakeLists.txt"
#endif

namespace fg::platform {

namespace {

// Data Watchpoint and Trace unit and its enable bit in the debug monitor register.
volatile uint32_t& reg(uintptr_t address) { return *reinterpret_cast<volatile uint32_t*>(address); }
constexpr uintptr_t kDemcr = 0xE000EDFCu;    // CoreDebug->DEMCR, TRCENA = bit 24
constexpr uintptr_t kDwtCtrl = 0xE0001000u;  // CYCCNTENA = bit 0
constexpr uintptr_t kDwtCyccnt = 0xE0001004u;
constexpr uintptr_t kDwtLar = 0xE0001FB0u;  // lock access (Cortex-M7 parts that lock the DWT)

bool g_started = false;
uint32_t g_last = 0;    // CYCCNT at the previous reading
uint64_t g_cycles = 0;  // cycles since the first reading, extended past 32 bits

// CYCCNT wraps every 2^32 cycles (about 20 s at 216 MHz): every reading adds the
// distance from the previous one modulo 2^32, so one wrap between two readings is
// counted right. Callers read at least once per wrap period (each plan stage does).
uint64_t cycles() {
  if (!g_started) {
    reg(kDemcr) |= 1u << 24;
    reg(kDwtLar) = 0xC5ACCE55u;
    reg(kDwtCyccnt) = 0;
    reg(kDwtCtrl) |= 1u;
    g_last = 0;
    g_started = true;
  }
  const uint32_t now = reg(kDwtCyccnt);
  g_cycles += static_cast<uint32_t>(now - g_last);
  g_last = now;
  return g_cycles;
}

}  // namespace

uint64_t monotonic_us() {
  constexpr uint64_t hz = FG_CORE_CLOCK_HZ;
  static_assert(hz >= 1000000u, "FG_CORE_CLOCK_HZ below 1 MHz");
  const uint64_t c = cycles();
  // Split so that c * 1e6 cannot overflow.
  return c / hz * 1000000u + c % hz * 1000000u / hz;
}

uint64_t cycle_counter() { return cycles(); }

void log(LogLevel level, const char* message) {
  static const char* const names[] = {"debug", "info", "warning", "error"};
  const auto i = static_cast<uint32_t>(level);
  char line[192];  // longer messages are cut, the newline kept
  uint32_t pos = 0;
  auto put = [&](const char* s) {
    while (s != nullptr && *s != '\0' && pos + 2 < sizeof(line)) line[pos++] = *s++;
  };
  put("forcegrasp ");
  put(i < 4 ? names[i] : "log");
  put(": ");
  put(message);
  line[pos++] = '\n';
  line[pos] = '\0';
  fg_board_log(line);
}

void internal_error(const char* file, int line, const char* what) { fg_board_fault(file, line, what); }

}  // namespace fg::platform
