// Host-only: the planner configuration as named options, settable from a JSON file
// (--config FILE) or from the command line (--set name=value), every value validated.
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "fg/core/config.hpp"

namespace fg::host {

struct ConfigOption {
  const char* name;
  const char* help;
  enum Kind { real, count, flag, rule } kind;
  void* field;  // points into a PlannerConfig
};

//! Every option, bound to `cfg`.
std::vector<ConfigOption> config_options(PlannerConfig& cfg);

//! Sets one option from text; false with a message naming the option and the problem.
[[nodiscard]] bool set_config_option(PlannerConfig& cfg, const std::string& name, const std::string& value,
                                     std::string& error);

//! Every option with its default value, as a JSON object (a valid --config file).
nlohmann::json default_config_json();
//! Every option's value in `cfg` by its name, as default_config_json() gives the
//! defaults (floats as their shortest faithful decimals).
[[nodiscard]] nlohmann::json config_json(PlannerConfig cfg);

//! Applies a JSON object of options (numbers, booleans, or strings for target_rule).
[[nodiscard]] bool load_config_file(PlannerConfig& cfg, const std::string& path, std::string& error);

}  // namespace fg::host
