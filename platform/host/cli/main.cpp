// The `forcegrasp` host program.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <string>

#include "io/config_options.hpp"
#include "plan_command.hpp"
#include "sim/scene_gen.hpp"
#include "sim_trial.hpp"

namespace {

using namespace fg::host;

//! `forcegrasp plan`: its options as parsed.
struct PlanArgs {
  CLI::App* cmd = nullptr;
  PlanOptions po;
  bool json_out = false;
  std::string objects_arg;  // --objects: "all" or not given
};

//! `forcegrasp sim`: its options as parsed.
struct SimArgs {
  CLI::App* cmd = nullptr;
  SimOptions so;
  std::string kinds_arg = "all";
  std::string sim_config;
  std::vector<std::string> sim_sets;
  double min_rate = -1.0;
  bool quiet = false;
  CLI::Option* seed_opt = nullptr;
  std::string distribution_arg = "cell";
  std::vector<double> calibration_error;  // --calibration-error MM,DEG
  std::vector<double> kinematic_error;    // --kinematic-error MM,DEG
  std::vector<double> head_error;         // --head-error MM,DEG
};

//! Every object kind's name, comma-separated (the --objects help).
std::string kind_names() {
  std::string k;
  for (const auto* list : {&fg::sim::all_kinds(), &fg::sim::mesh_kinds()})
    for (const fg::sim::ObjectKind kind : *list) k += (k.empty() ? "" : ",") + std::string(fg::sim::kind_name(kind));
  return k;
}

//! --registration's value (checked to be on, off or strict).
fg::RegistrationMode registration_mode(const std::string& v) {
  return v == "off"      ? fg::RegistrationMode::off
         : v == "strict" ? fg::RegistrationMode::strict
                         : fg::RegistrationMode::on;
}

void add_plan_command(CLI::App& app, PlanArgs& a) {
  a.cmd = app.add_subcommand("plan", "plan a grasp on a scene manifest");
  a.cmd->add_option("scene", a.po.scene_path, "scene.json (spec/scene-and-cli.md)")->required();
  a.cmd->add_flag("--json", a.json_out, "print the JSON report of the contract");
  a.cmd->add_option("--pictures", a.po.pictures_dir, "write SVG pictures of the stages to this folder");
  a.cmd->add_option("--config", a.po.config_path, "JSON file of planner options");
  a.cmd->add_option("--set", a.po.sets, "override one option: name=value (repeatable)");
  a.cmd
      ->add_option("--top", a.po.top,
                   "report the N best distinct grasps, best first, in a `grasps` array (at most " +
                       std::to_string(fg::kMaxRankedGrasps) + ", FG_MAX_RANKED_GRASPS)")
      ->check(CLI::Range(1u, fg::kMaxRankedGrasps));
  a.cmd
      ->add_option("--objects", a.objects_arg,
                   "all: plan for every object on the support plane too, each in the `objects` array (at most " +
                       std::to_string(fg::kMaxObjects) + ", FG_MAX_OBJECTS: those nearest the workspace centre)")
      ->check(CLI::IsMember({"all"}));
  auto* target =
      a.cmd->add_option("--target", a.po.target, "x,y,z: the target is the object nearest this world point (metres)");
  auto* box = a.cmd->add_option("--target-box", a.po.target_box,
                                "xmin,ymin,zmin,xmax,ymax,zmax: the target is the object with the most voxels "
                                "inside this world box (metres)");
  target->excludes(box);
  a.cmd->add_option("--units", a.po.units,
                    "SENSOR=UNIT: the units of a sensor's cloud, m (the default), cm or mm, over the scene's "
                    "\"units\" (repeatable)");
  a.cmd
      ->add_option_function<std::string>(
          "--registration", [&a](const std::string& v) { a.po.registration = registration_mode(v); },
          "on (the default): register the hand sensor's cloud to the head's before fusing them, and plan from one "
          "sensor alone when they still disagree (the head, unless its table leans and the hand's does not); "
          "strict: the same, but a disagreement is an error; off: fuse them as calibrated")
      ->check(CLI::IsMember({"on", "off", "strict"}));
}

void add_sim_command(CLI::App& app, SimArgs& a) {
  CLI::App* sim_cmd =
      app.add_subcommand("sim", "run the whole grasp task on simulated hardware over objects and seeded poses");
  a.cmd = sim_cmd;
  SimOptions& so = a.so;
  sim_cmd->add_option("--objects", a.kinds_arg,
                      "comma-separated object kinds, or all, primitives, meshes (" + kind_names() + ")");
  sim_cmd->add_option("--trials", so.trials, "number of trials (default 20 per object kind); trial i: kind i % kinds");
  a.seed_opt = sim_cmd->add_option(
      "--seed", so.seed, "seed of the first trial (trial i uses seed + i); without it a seed is drawn and printed");
  sim_cmd
      ->add_option("--distribution", a.distribution_arg,
                   "cell: scenes as a user's robot cell shows them (the default); classic: the project's own "
                   "spread, which the tests' pinned seeds use")
      ->check(CLI::IsMember({"cell", "classic"}));
  sim_cmd->add_option("--mu", so.mu, "friction coefficient of the judge");
  sim_cmd->add_option("--second-object-rate", so.second_object_rate, "classic: share of scenes with a second object");
  sim_cmd
      ->add_option("--calibration-error", a.calibration_error,
                   "MM,DEG: the wrist sensor's pose the task believes is off by MM millimetres and DEG degrees in each "
                   "trial (a hand-eye error in a direction drawn from the trial's seed)")
      ->delimiter(',')
      ->expected(2)
      ->check(CLI::Range(0.0, 100.0));
  sim_cmd
      ->add_option("--head-error", a.head_error,
                   "MM,DEG: the head sensor's pose the task believes is off by MM millimetres and DEG degrees in each "
                   "trial (a head knocked out of its calibration, in a direction drawn from the trial's seed)")
      ->delimiter(',')
      ->expected(2)
      ->check(CLI::Range(0.0, 100.0));
  sim_cmd
      ->add_option("--kinematic-error", a.kinematic_error,
                   "MM,DEG: the arm's true kinematics off the nominal UR5 the task computes with, in each trial: every "
                   "DH length by up to MM millimetres and every joint's zero by up to DEG degrees (drawn from the "
                   "trial's seed)")
      ->delimiter(',')
      ->expected(2)
      ->check(CLI::Range(0.0, 100.0));
  sim_cmd
      ->add_option_function<std::string>(
          "--registration", [&so](const std::string& v) { so.registration = registration_mode(v); },
          "on (the default): the planner registers the wrist sensor's cloud to the head's (one sensor's alone when "
          "they disagree: the one whose table is level); strict: a disagreement is an error; off: fuses them as "
          "calibrated")
      ->check(CLI::IsMember({"on", "off", "strict"}));
  sim_cmd
      ->add_option_function<std::string>(
          "--sensors",
          [&so](const std::string& v) {
            so.use_head = v != "hand";
            so.use_hand = v != "head";
          },
          "both (the default): the task captures with the head and the wrist sensor and plans from both; head or "
          "hand: from that sensor alone (the arm still stands at the wrist's viewpoint)")
      ->check(CLI::IsMember({"both", "head", "hand"}));
  sim_cmd->add_option("--pictures", so.pictures_dir, "write SVG pictures of each trial's plan to DIR/<kind>-<seed>");
  sim_cmd->add_option("--export", so.export_dir,
                      "write each trial's scene (scene.json, PCD, truth.json) to DIR/<kind>-<seed>");
  sim_cmd->add_option("--json", so.json_path, "write every trial and the table as JSON to this file");
  sim_cmd->add_option("--config", a.sim_config, "JSON file of planner options");
  sim_cmd->add_option("--set", a.sim_sets, "override one planner option: name=value (repeatable)");
  sim_cmd->add_option("--min-rate", a.min_rate, "exit 4 when the overall success rate is below this (0..1)");
  sim_cmd->add_flag("--quiet", a.quiet, "no progress line");
}

//! A command-line error is invalid input too: with --json, stdout still carries the one
//! JSON object of the contract. Returns the exit code (0 after --help).
int report_parse_error(CLI::App& app, const CLI::ParseError& e, int argc, char** argv) {
  const int rc = app.exit(e);
  if (rc == 0) return 0;  // --help
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--json") {
      const nlohmann::json j{{"status", "invalid_input"}, {"error", std::string("command line: ") + e.what()}};
      std::cout << j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
      break;
    }
  return kExitInvalid;
}

int run_plan_command(PlanArgs& a) {
  a.po.all_objects = a.objects_arg == "all";
  const PlanOutcome o = run_plan(a.po);
  if (a.json_out)
    std::cout << o.report.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
  else
    std::cout << human_summary(o.report);
  return o.exit_code;
}

//! The object kinds --objects names: all, primitives, meshes or a comma-separated list.
//! False (and a message on stderr) on an unknown kind.
[[nodiscard]] bool parse_kinds(const std::string& kinds_arg, std::vector<std::string>& kinds) {
  if (kinds_arg == "all") {
    for (const auto* list : {&fg::sim::all_kinds(), &fg::sim::mesh_kinds()})
      for (const fg::sim::ObjectKind kind : *list) kinds.push_back(fg::sim::kind_name(kind));
  } else if (kinds_arg == "primitives" || kinds_arg == "meshes") {
    for (const fg::sim::ObjectKind kind : kinds_arg == "meshes" ? fg::sim::mesh_kinds() : fg::sim::all_kinds())
      kinds.push_back(fg::sim::kind_name(kind));
  } else {
    std::string k;
    std::istringstream in(kinds_arg);
    while (std::getline(in, k, ',')) {
      fg::sim::ObjectKind kind;
      if (!fg::sim::kind_from_name(k, kind)) {
        std::cerr << "forcegrasp sim: unknown object kind \"" << k << "\"\n";
        return false;
      }
      kinds.push_back(k);
    }
  }
  return true;
}

//! A fresh sample each run; the seed is printed so that --seed repeats it. Twelve
//! digits at most: easy to retype, and seed + i stays exact in JSON readers' doubles.
uint64_t draw_seed() {
  std::random_device entropy;
  const uint64_t drawn = (static_cast<uint64_t>(entropy()) << 32) ^ entropy() ^
                         static_cast<uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count());
  return drawn % 1000000000000ull;
}

int run_sim_command(SimArgs& a) {
  SimOptions& so = a.so;
  std::string err;
  fg::PlannerConfig cfg;
  if (!apply_options(cfg, a.sim_config, a.sim_sets, err)) {
    std::cerr << "forcegrasp sim: " << err << "\n";
    return kExitInvalid;
  }
  if (!parse_kinds(a.kinds_arg, so.kinds)) return kExitInvalid;
  if (so.kinds.empty()) {
    std::cerr << "forcegrasp sim: no object kinds\n";
    return kExitInvalid;
  }
  so.progress = !a.quiet;
  // --calibration-error, --head-error and --kinematic-error: MM,DEG, both finite.
  const auto error_pair = [](const std::vector<double>& v, const char* option, double& mm, double& deg) {
    if (v.size() != 2) return true;
    if (!std::isfinite(v[0]) || !std::isfinite(v[1])) {
      std::cerr << "forcegrasp sim: " << option << ": MM and DEG must be finite numbers (0..100)\n";
      return false;
    }
    mm = v[0];
    deg = v[1];
    return true;
  };
  if (!error_pair(a.calibration_error, "--calibration-error", so.calibration_error_mm, so.calibration_error_deg) ||
      !error_pair(a.kinematic_error, "--kinematic-error", so.kinematic_error_mm, so.kinematic_error_deg) ||
      !error_pair(a.head_error, "--head-error", so.head_error_mm, so.head_error_deg))
    return kExitInvalid;
  // The parser let only the distributions' names through (CLI::IsMember).
  if (!fg::sim::distribution_from_name(a.distribution_arg, so.distribution)) {
    std::cerr << "forcegrasp sim: unknown distribution \"" << a.distribution_arg << "\"\n";
    return kExitInvalid;
  }
  if (a.seed_opt->count() == 0) so.seed = draw_seed();
  fg::Planner& planner = planner_instance();
  const char* field = nullptr;
  if (planner.configure(cfg, &field) != fg::Status::ok) {
    std::cerr << "forcegrasp sim: configuration value out of range: " << (field ? field : "?") << "\n";
    return kExitInvalid;
  }
  planner.set_registration(so.registration);
  const nlohmann::json report = run_sim(so, cfg, planner);
  if (!so.json_path.empty()) {
    std::ofstream f(so.json_path);
    f << report.dump(1) << "\n";
    if (!f) {
      std::cerr << "forcegrasp sim: cannot write " << so.json_path << "\n";
      return kExitInternal;
    }
  }
  const nlohmann::json& all = report["table"].back();
  if (a.min_rate >= 0.0 && all["rate"].get<double>() < a.min_rate) return 4;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    CLI::App app{"forcegrasp: force-balance grasp planning from partial point clouds"};
    app.require_subcommand(1);
    PlanArgs plan;
    add_plan_command(app, plan);
    SimArgs sim;
    add_sim_command(app, sim);
    CLI::App* config =
        app.add_subcommand("config", "print every planner option with its default, as a --config JSON file");
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      return report_parse_error(app, e, argc, argv);
    }
    if (plan.cmd->parsed()) return run_plan_command(plan);
    if (sim.cmd->parsed()) return run_sim_command(sim);
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
