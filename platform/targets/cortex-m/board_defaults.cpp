// Weak default board hooks (fg/platform/board.h): a firmware replaces them by
// defining its own. Heap-free, exception-free.
#include <cstdint>

#include "fg/platform/board.h"

#ifdef FG_SEMIHOSTING
#include "semihosting.hpp"
#endif

namespace {

// Appends s to buf[pos..cap) without overflowing; returns the new length.
uint32_t append(char* buf, uint32_t pos, uint32_t cap, const char* s) {
  while (s != nullptr && *s != '\0' && pos + 1 < cap) buf[pos++] = *s++;
  buf[pos] = '\0';
  return pos;
}

}  // namespace

extern "C" __attribute__((weak)) void fg_board_log(const char* line) {
#ifdef FG_SEMIHOSTING
  fg::cortex_m::semihost_write0(line);
#else
  (void)line;
#endif
}

extern "C" __attribute__((weak)) void fg_board_fault(const char* file, int line, const char* what) {
  char num[12];
  uint32_t n = line < 0 ? 0u : static_cast<uint32_t>(line);
  uint32_t d = sizeof(num) - 1;
  num[d] = '\0';
  do {
    num[--d] = static_cast<char>('0' + n % 10u);
    n /= 10u;
  } while (n != 0 && d > 0);
  char msg[160];
  uint32_t pos = append(msg, 0, sizeof(msg), "forcegrasp internal error at ");
  pos = append(msg, pos, sizeof(msg), file);
  pos = append(msg, pos, sizeof(msg), ":");
  pos = append(msg, pos, sizeof(msg), num + d);
  pos = append(msg, pos, sizeof(msg), ": ");
  pos = append(msg, pos, sizeof(msg), what);
  append(msg, pos, sizeof(msg), "\n");
  fg_board_log(msg);
#if defined(FG_SEMIHOSTING)
  fg::cortex_m::semihost_exit(false);
#elif !defined(NDEBUG)
  for (;;) __asm__ __volatile__("bkpt 0");  // stop here under a debugger
#endif
}
