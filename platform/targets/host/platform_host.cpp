// Host (Linux) implementation of the platform services.
#include <cstdio>
#include <cstdlib>
#include <ctime>

#include "fg/platform/platform.hpp"

namespace fg::platform {

uint64_t monotonic_us() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<uint64_t>(ts.tv_sec) * 1000000u + static_cast<uint64_t>(ts.tv_nsec) / 1000u;
}

uint64_t cycle_counter() {
#if defined(__x86_64__)
  uint32_t lo = 0, hi = 0;
  __asm__ __volatile__("rdtsc" : "=a"(lo), "=d"(hi));
  return (static_cast<uint64_t>(hi) << 32) | lo;
#elif defined(__aarch64__)
  uint64_t v = 0;
  __asm__ __volatile__("mrs %0, cntvct_el0" : "=r"(v));
  return v;
#else
  return 0;
#endif
}

void log(LogLevel level, const char* message) {
  static const char* const names[] = {"debug", "info", "warning", "error"};
  std::fprintf(stderr, "forcegrasp %s: %s\n", names[static_cast<int>(level)], message);
}

void internal_error(const char* file, int line, const char* what) {
  std::fprintf(stderr, "forcegrasp internal error at %s:%d: %s\n", file, line, what);
#ifndef NDEBUG
  std::abort();
#endif
}

}  // namespace fg::platform
