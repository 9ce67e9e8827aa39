// The pipeline's stages as the report times them, and the timer that adds a scope's
// microseconds to a stage's slot.
#pragma once
#include <cstdint>

#include "fg/platform/platform.hpp"

namespace fg {

//! Pipeline stages, each timed.
enum class Stage : uint8_t { ingest, plane, cluster, frame, xoy, xoz, select, total, count };
const char* to_string(Stage s);

using StageTimes = uint32_t[static_cast<uint32_t>(Stage::count)];

class StageTimer {
 public:
  StageTimer(StageTimes& times, Stage s) : slot_(times[static_cast<uint32_t>(s)]), t0_(platform::monotonic_us()) {}
  ~StageTimer() { slot_ += static_cast<uint32_t>(platform::monotonic_us() - t0_); }
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;

 private:
  uint32_t& slot_;
  uint64_t t0_;
};

}  // namespace fg
