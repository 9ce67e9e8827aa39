// aarch64 Linux implementation of the platform services (an onboard controller
// running Linux). Heap-free: the log writes with write(2) from the caller's string,
// no stdio buffers.
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <ctime>

#include "fg/platform/platform.hpp"

namespace fg::platform {

uint64_t monotonic_us() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<uint64_t>(ts.tv_sec) * 1000000u + static_cast<uint64_t>(ts.tv_nsec) / 1000u;
}

uint64_t cycle_counter() {
  // The generic timer's virtual count: readable from user space, constant rate
  // (CNTFRQ_EL0, often 19.2 MHz to 1 GHz), not the core clock.
  uint64_t v = 0;
  __asm__ __volatile__("mrs %0, cntvct_el0" : "=r"(v));
  return v;
}

namespace {
void write_err(const char* s) {
  // A short diagnostic: a failed or partial write is not worth a retry loop.
  const ssize_t ignored = ::write(STDERR_FILENO, s, std::strlen(s));
  (void)ignored;
}
}  // namespace

void log(LogLevel level, const char* message) {
  static const char* const names[] = {"debug", "info", "warning", "error"};
  const auto i = static_cast<uint32_t>(level);
  write_err("forcegrasp ");
  write_err(i < 4 ? names[i] : "log");
  write_err(": ");
  write_err(message != nullptr ? message : "");
  write_err("\n");
}

void internal_error(const char* file, int line, const char* what) {
  // The line number without stdio: at most 10 digits and a sign.
  char num[12];
  uint32_t n = line < 0 ? 0u : static_cast<uint32_t>(line);
  int pos = static_cast<int>(sizeof(num)) - 1;
  num[pos] = '\0';
  do {
    num[--pos] = static_cast<char>('0' + n % 10u);
    n /= 10u;
  } while (n != 0 && pos > 0);
  write_err("forcegrasp internal error at ");
  write_err(file);
  write_err(":");
  write_err(num + pos);
  write_err(": ");
  write_err(what);
  write_err("\n");
#ifndef NDEBUG
  std::abort();
#endif
}

}  // namespace fg::platform
