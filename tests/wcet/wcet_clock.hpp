// Worst-case timing harness: the clock the planner's stage timers read.
//
// fg_wcet is linked with --wrap=fg::platform::monotonic_us (tests/CMakeLists.txt), so
// every stage timer of the planner (PlanResult::stage_us, the ingest timer) calls
// wcet_clock.cpp instead of the platform's clock. Normally that forwards to the real
// clock. Under callgrind (--ir PREFIX) it dumps callgrind's counters at each reading
// and returns the instructions executed so far instead of microseconds: the planner
// then accounts instructions per stage exactly as it accounts time, with the same
// stage boundaries, and core/ knows nothing about valgrind.
#pragma once
#include <cstdint>
#include <string>

namespace fg::wcet {

//! In instruction mode the planner's uint32 stage slots count units of this many
//! instructions (up to 68.7 G instructions per stage). Whole-call counts are exact.
constexpr uint64_t kIrUnit = 16;

//! True when running under valgrind and the harness was built with its headers.
bool under_valgrind();
bool valgrind_headers_available();

//! Instruction mode: callgrind was started with --collect-atstart=no and
//! --callgrind-out-file=PREFIX; the counters of each dump are read back from
//! PREFIX.<n>. False (with a message) when not under valgrind.
bool use_instruction_clock(const std::string& dump_prefix, std::string& error);
bool instruction_clock();

//! Starts / stops callgrind's collection around the measured calls (no-ops natively).
void collect_begin();
void collect_end();

//! Instruction mode: exact instructions collected so far (uint64). Otherwise the real
//! clock in microseconds.
uint64_t counter_now();

}  // namespace fg::wcet
