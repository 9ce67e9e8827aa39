// Worst-case timing harness (issue 4, item 4): the inputs. Each case is one complete
// planner input (configuration + the data of each sensor), built before any timing
// starts, and sized from the build's capacities (fg_limits.h through limits.hpp) and
// the default PlannerConfig. Host-only code (allocates freely).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "fg/core/config.hpp"
#include "fg/core/planner.hpp"

namespace fg::wcet {

//! The data one sensor contributes: either a cloud in its optical frame (add_points)
//! or a depth image (add_depth_image).
struct SensorInput {
  SensorRole role = SensorRole::head;
  Pose pose;                    //!< world_T_sensor
  std::vector<float> xyz;       //!< x y z per point, sensor frame (add_points) ...
  std::vector<uint16_t> depth;  //!< ... or depth in mm, row-major (add_depth_image)
  uint16_t width = 0, height = 0;
  PinholeIntrinsics k;
  bool is_image() const { return !depth.empty(); }
  uint32_t points() const {
    return is_image() ? static_cast<uint32_t>(depth.size()) : static_cast<uint32_t>(xyz.size() / 3);
  }
};

struct CaseInput {
  std::string name;
  PlannerConfig cfg;
  std::vector<std::string> overrides;  //!< configuration changes from the default, "name=value"
  std::vector<SensorInput> sensors;    //!< added in this order
  uint32_t distinct_cells = 0;         //!< distinct voxels the generator put points in (0: unknown)
  std::string note;                    //!< generator facts worth reporting (sizes, etc.)
};

struct CaseInfo {
  const char* name;
  const char* targets;  //!< the stage(s) it is built to load
  const char* what;     //!< one-line description
  bool typical;         //!< a "typical" reference case (the ratio's denominator candidate)
  bool smoke;           //!< cheap enough for the ctest smoke test in every configuration
};

//! Every case, in report order.
const std::vector<CaseInfo>& case_list();

//! Points per sensor of the adversarial cases: the input volume of this
//! configuration's typical case (host: two 640x480 sensors; small builds: 160x120).
uint32_t default_points_per_sensor();

//! Builds a case; false with a message when the name is unknown or the generator
//! cannot build it in this configuration. hash_cells: the colliding cells of
//! hash_collide (0: kMaxVoxels; fewer keep a callgrind run short, the cost is O(n^2)).
bool make_case(const std::string& name, uint32_t points_per_sensor, CaseInput& out, std::string& error,
               uint32_t hash_cells = 0);

//! The typical case this configuration's ratios are taken against.
const char* reference_typical_case();

}  // namespace fg::wcet
