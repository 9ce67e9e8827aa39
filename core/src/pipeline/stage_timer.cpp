// The stages' names (stage_timer.hpp).
#include "fg/core/pipeline/stage_timer.hpp"

namespace fg {

const char* to_string(Stage s) {
  switch (s) {
    case Stage::ingest:
      return "ingest";
    case Stage::plane:
      return "plane";
    case Stage::cluster:
      return "cluster";
    case Stage::frame:
      return "frame";
    case Stage::xoy:
      return "xoy";
    case Stage::xoz:
      return "xoz";
    case Stage::select:
      return "select";
    case Stage::total:
      return "total";
    case Stage::count:
      break;
  }
  return "unknown";
}

}  // namespace fg
