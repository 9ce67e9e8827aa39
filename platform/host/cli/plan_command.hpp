// Host-only: `forcegrasp plan` — read a scene, run the planner, report (spec/scene-and-cli.md).
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "fg/core/config.hpp"
#include "fg/core/planner.hpp"

namespace fg::host {

struct PlanOptions {
  std::string scene_path;
  std::string config_path;         //!< optional JSON of options
  std::vector<std::string> sets;   //!< name=value overrides
  std::string pictures_dir;        //!< write SVG pictures here when set
  uint32_t top = 0;                //!< --top N: the N best distinct grasps in `grasps` (0: not asked)
  bool all_objects = false;        //!< --objects all: every object on the plane in `objects`
  std::string target;              //!< --target x,y,z: the object nearest this world point
  std::string target_box;          //!< --target-box xmin,ymin,zmin,xmax,ymax,zmax: the object inside
  std::vector<std::string> units;  //!< --units SENSOR=UNIT (m, cm, mm), over the manifest's
  RegistrationMode registration = RegistrationMode::on;  //!< --registration on|off|strict
};

//! The target of --target or --target-box (both empty: the configured rule); false
//! with err naming the option and the problem.
[[nodiscard]] bool parse_target(const PlanOptions& opts, TargetSpec& target, std::string& err);

//! Exit codes of the contract.
enum ExitCode : int { kExitOk = 0, kExitInternal = 1, kExitInvalid = 2, kExitNoGrasp = 3 };

// clang-tidy finds a throwing path in the implicit noexcept move of nlohmann::json,
// whose move constructor and assignment are noexcept.
struct PlanOutcome {  // NOLINT(bugprone-exception-escape)
  int exit_code = kExitInternal;
  nlohmann::json report;  //!< the JSON object the contract prints
};

//! The whole command; never throws (internal errors become exit code 1).
[[nodiscard]] PlanOutcome run_plan(const PlanOptions& opts);

//! The planner is large (a few MiB): one instance per process, created on first use.
Planner& planner_instance();

//! Applies a --config file, then the --set name=value overrides; false with err set.
[[nodiscard]] bool apply_options(PlannerConfig& cfg, const std::string& config_path,
                                 const std::vector<std::string>& sets, std::string& err);

//! The short human summary printed without --json.
std::string human_summary(const nlohmann::json& report);

}  // namespace fg::host
