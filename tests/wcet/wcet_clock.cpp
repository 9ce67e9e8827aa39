// Worst-case timing harness: the wrapped platform clock (see wcet_clock.hpp).
#include "wcet_clock.hpp"

#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#if defined(__has_include)
#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#define FG_WCET_HAVE_VALGRIND 1
#endif
#endif
#ifndef FG_WCET_HAVE_VALGRIND
#define FG_WCET_HAVE_VALGRIND 0
#define RUNNING_ON_VALGRIND 0
#define CALLGRIND_TOGGLE_COLLECT
#define CALLGRIND_DUMP_STATS_AT(s) ((void)(s))
#endif

// The real clock (platform/targets/host) and the wrapper the linker routes the
// planner's calls to (-Wl,--wrap=_ZN2fg8platform12monotonic_usEv).
extern "C" uint64_t __real__ZN2fg8platform12monotonic_usEv();
extern "C" uint64_t __wrap__ZN2fg8platform12monotonic_usEv();

namespace fg::wcet {
namespace {
bool g_ir = false;          // instruction mode
bool g_collecting = false;  // inside collect_begin() .. collect_end()
std::string g_prefix;
uint64_t g_dumps = 0;  // dumps written so far: the next one is PREFIX.<g_dumps + 1>
uint64_t g_total = 0;  // instructions collected so far

// Reads the "summary: <Ir>" line of dump n, then removes the file.
uint64_t read_dump(uint64_t n) {
  const std::string path = g_prefix + "." + std::to_string(n);
  FILE* f = std::fopen(path.c_str(), "r");
  if (f == nullptr) {
    std::fprintf(stderr, "fg_wcet: cannot open callgrind dump %s\n", path.c_str());
    std::exit(3);
  }
  char line[4096];
  uint64_t v = 0;
  bool found = false;
  while (std::fgets(line, sizeof line, f) != nullptr) {
    if (std::strncmp(line, "summary:", 8) == 0) {
      v = std::strtoull(line + 8, nullptr, 10);
      found = true;
      break;
    }
  }
  std::fclose(f);
  if (!found) {
    std::fprintf(stderr, "fg_wcet: no summary line in %s\n", path.c_str());
    std::exit(3);
  }
  std::remove(path.c_str());
  return v;
}

// One reading: dump (callgrind writes the instructions since the previous dump and
// zeroes its counters), then read the dump back with collection off, so the reading
// itself is not counted.
uint64_t ir_reading() {
  if (!g_collecting) return g_total;
  CALLGRIND_DUMP_STATS_AT("fg_wcet");
  CALLGRIND_TOGGLE_COLLECT;
  g_total += read_dump(++g_dumps);
  CALLGRIND_TOGGLE_COLLECT;
  return g_total;
}
}  // namespace

bool under_valgrind() { return RUNNING_ON_VALGRIND != 0; }
bool valgrind_headers_available() { return FG_WCET_HAVE_VALGRIND != 0; }

bool use_instruction_clock(const std::string& dump_prefix, std::string& error) {
  if (!valgrind_headers_available()) {
    error = "built without valgrind/callgrind.h (apt-get install valgrind, then rebuild)";
    return false;
  }
  if (!under_valgrind()) {
    error = "--ir needs valgrind --tool=callgrind --collect-atstart=no --callgrind-out-file=PREFIX";
    return false;
  }
  g_ir = true;
  g_prefix = dump_prefix;
  return true;
}

bool instruction_clock() { return g_ir; }

void collect_begin() {
  if (!under_valgrind() || g_collecting) return;
  CALLGRIND_TOGGLE_COLLECT;
  g_collecting = true;
  if (g_ir) (void)ir_reading();  // start from a clean interval
}

void collect_end() {
  if (!under_valgrind() || !g_collecting) return;
  if (g_ir) (void)ir_reading();
  CALLGRIND_TOGGLE_COLLECT;
  g_collecting = false;
}

uint64_t counter_now() {
  if (g_ir) return ir_reading();
  return __real__ZN2fg8platform12monotonic_usEv();
}

}  // namespace fg::wcet

extern "C" uint64_t __wrap__ZN2fg8platform12monotonic_usEv() {
  if (fg::wcet::instruction_clock()) return fg::wcet::counter_now() / fg::wcet::kIrUnit;
  return __real__ZN2fg8platform12monotonic_usEv();
}
