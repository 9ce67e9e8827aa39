// The `forcegrasp` host program.
#include <cstdio>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include "io/config_options.hpp"
#include "plan_command.hpp"

int main(int argc, char** argv) {
  using namespace fg::host;
  try {
    CLI::App app{"forcegrasp: force-balance grasp planning from partial point clouds"};
    app.require_subcommand(1);
    PlanOptions po;
    bool json_out = false;
    CLI::App* plan = app.add_subcommand("plan", "plan a grasp on a scene manifest");
    plan->add_option("scene", po.scene_path, "scene.json (spec/scene-and-cli.md)")->required();
    plan->add_flag("--json", json_out, "print the JSON report of the contract");
    plan->add_option("--pictures", po.pictures_dir, "write SVG pictures of the stages to this folder");
    plan->add_option("--config", po.config_path, "JSON file of planner options");
    plan->add_option("--set", po.sets, "override one option: name=value (repeatable)");
    CLI::App* config = app.add_subcommand(
        "config", "print every planner option with its default, as a --config JSON file");
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      const int rc = app.exit(e);
      if (rc == 0) return 0;  // --help
      // A command-line error is invalid input too: with --json, stdout still carries
      // the one JSON object of the contract.
      for (int i = 1; i < argc; ++i)
        if (std::string(argv[i]) == "--json") {
          const nlohmann::json j{{"status", "invalid_input"}, {"error", std::string("command line: ") + e.what()}};
          std::cout << j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
          break;
        }
      return kExitInvalid;
    }
    if (plan->parsed()) {
      const PlanOutcome o = run_plan(po);
      if (json_out)
        std::cout << o.report.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
      else
        std::cout << human_summary(o.report);
      return o.exit_code;
    }
    if (config->parsed()) {
      std::cout << default_config_json().dump(1) << "\n";
      return 0;
    }
    return kExitInvalid;
  } catch (const std::exception& e) {
    std::cout << "{\"status\":\"internal_error\",\"error\":\"unexpected exception\"}\n";
    std::cerr << "forcegrasp: internal error: " << e.what() << "\n";
    return kExitInternal;
  }
}
