// Quality on simulated two-sensor scenes, judged on the TRUE geometry (hal/sim):
// for each seeded scene, render both 640x480 depth images with Xtion-like noise, plan
// in-process through Planner::add_depth_image, and judge the grasp (both pads on the
// target, contact normals inside the mu = 0.5 cone, width within 1 cm, no collision at
// the open pose) or the no_grasp answer (right iff the target fits in no direction).
//   fg_quality [--count N] [--seed S] [--kinds a,b] [--min-rate R] [--verbose] [--sensors both|head|hand]
//              [--spread] [--head-at-workspace] [--noise-scale F] [--table-height H]
//              [--gripper OPENING,FINGER_WIDTH,FINGER_DEPTH] [--head-height LO,HI]
//              [--hand-distance LO,HI] [--hand-elevation LO_DEG,HI_DEG] [--export DIR]
//              [--distribution classic|cell]
// --spread puts the target anywhere in the scene contract's area (x 0.3..0.7, y
// -0.35..0.35) instead of near the workspace centre; --head-at-workspace keeps the head
// camera looking at the workspace centre instead of at the target; --noise-scale
// multiplies the depth noise's sigma (0: none); --table-height raises the table (m);
// --gripper gives planner and judge another gripper (metres; the default 0.085,0.022,0.04);
// --head-height, --hand-distance and --hand-elevation draw the cameras' placement from
// other ranges (defaults 0.75,0.9 m above the table; 0.35,0.55 m from the target, 25,60
// deg up); --export writes each scene judged wrong as DIR/<kind>-<seed>/ (scene.json,
// head.pcd, hand.pcd, truth.json), for `forcegrasp plan --pictures`. --distribution picks
// the scenes (hal/sim scene_gen.hpp): classic, the default here, which the seeds of the
// tests and of docs/quality.md are of, or cell; the options above then change its ranges
// (the camera ranges are classic's only).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "fg/core/planner.hpp"
#include "io/config_options.hpp"
#include "sim/grasp_judge.hpp"
#include "sim/pinhole.hpp"
#include "sim/scene_export.hpp"
#include "sim/scene_gen.hpp"

namespace {

struct Tally {
  int trials = 0, right = 0, grasps = 0;
  std::vector<double> plan_us;
  std::map<std::string, int> wrong;
};

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// What the command line asks for.
struct Options {
  int count = 110;
  uint64_t seed = 1000;
  double min_rate = -1;
  bool verbose = false;
  std::string export_dir;
  bool use_head = true, use_hand = true;  // --sensors: both (the default), head or hand
  std::vector<std::string> sets;
  fg::sim::SceneOptions scene_opt;
  std::vector<fg::sim::ObjectKind> kinds = fg::sim::all_kinds();
};

void print_usage() {
  std::fprintf(
      stderr,
      "usage: fg_quality [--count N] [--seed S] [--kinds a,b] [--min-rate R] [--verbose] [--set name=value] "
      "[--sensors both|head|hand] [--spread] [--head-at-workspace] [--noise-scale F] [--table-height H] [--gripper "
      "OPENING,FINGER_WIDTH,FINGER_DEPTH] [--head-height LO,HI] [--hand-distance LO,HI] [--hand-elevation "
      "LO_DEG,HI_DEG] [--export DIR] [--distribution classic|cell]\n");
}

// The distribution first: the other options change its ranges, whatever their order.
[[nodiscard]] bool read_distribution(int argc, char** argv, Options& o) {
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::string(argv[i]) != "--distribution") continue;
    fg::sim::Distribution d;
    if (!fg::sim::distribution_from_name(argv[i + 1], d)) {
      std::fprintf(stderr, "--distribution %s: expected classic or cell\n", argv[i + 1]);
      return false;
    }
    o.scene_opt = fg::sim::SceneOptions::of(d);
  }
  return true;
}

// The value after option argv[i] (i moves onto it); a missing value ends the program.
std::string option_value(int argc, char** argv, int& i) {
  if (i + 1 >= argc) {
    std::fprintf(stderr, "%s needs a value\n", argv[i]);
    std::exit(2);
  }
  return argv[++i];
}

// A range LO,HI for the cameras' placement (scene_gen.hpp SceneOptions).
[[nodiscard]] bool read_camera_range(const std::string& a, const std::string& value, fg::sim::SceneOptions& so) {
  double lo = 0, hi = 0;
  if (std::sscanf(value.c_str(), "%lf,%lf", &lo, &hi) != 2 || !(lo <= hi)) {
    std::fprintf(stderr, "%s: expected LO,HI with LO <= HI\n", a.c_str());
    return false;
  }
  if (a == "--head-height")
    so.head_height_min = lo, so.head_height_max = hi;
  else if (a == "--hand-distance")
    so.hand_distance_min = lo, so.hand_distance_max = hi;
  else
    so.hand_elevation_min_deg = lo, so.hand_elevation_max_deg = hi;
  return true;
}

// Another gripper for both the planner and the judge (the scene contract's gripper
// block): max opening, finger width, finger depth in metres.
[[nodiscard]] bool read_gripper(const std::string& value, fg::sim::SceneOptions& so) {
  double m = 0, w = 0, d = 0;
  if (std::sscanf(value.c_str(), "%lf,%lf,%lf", &m, &w, &d) != 3) {
    std::fprintf(stderr, "--gripper: expected OPENING,FINGER_WIDTH,FINGER_DEPTH (m)\n");
    return false;
  }
  so.gripper.max_opening_m = static_cast<float>(m);
  so.gripper.finger_width_m = static_cast<float>(w);
  so.gripper.finger_depth_m = static_cast<float>(d);
  return true;
}

[[nodiscard]] bool read_sensors(const std::string& v, Options& o) {
  o.use_head = v == "both" || v == "head";
  o.use_hand = v == "both" || v == "hand";
  if (!o.use_head && !o.use_hand) {
    std::fprintf(stderr, "--sensors %s: expected both, head or hand\n", v.c_str());
    return false;
  }
  return true;
}

[[nodiscard]] bool read_kinds(const std::string& list, Options& o) {
  o.kinds.clear();
  std::stringstream ss(list);
  std::string k;
  while (std::getline(ss, k, ',')) {
    fg::sim::ObjectKind kind;
    if (!fg::sim::kind_from_name(k, kind)) {
      std::fprintf(stderr, "unknown kind %s\n", k.c_str());
      return false;
    }
    o.kinds.push_back(kind);
  }
  return true;
}

void scale_noise(double k, fg::sim::SceneOptions& so) {
  so.noise.sigma_a *= k;
  so.noise.sigma_b *= k;
  so.noise.gaussian = k > 0;
}

// Every option in its order; false (after a message) on the first one refused.
[[nodiscard]] bool parse_options(int argc, char** argv, Options& o) {
  if (!read_distribution(argc, argv, o)) return false;
  fg::sim::SceneOptions& so = o.scene_opt;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() { return option_value(argc, argv, i); };
    bool ok = true;
    if (a == "--count")
      o.count = std::atoi(next().c_str());
    else if (a == "--seed")
      o.seed = std::strtoull(next().c_str(), nullptr, 10);
    else if (a == "--min-rate")
      o.min_rate = std::atof(next().c_str());
    else if (a == "--verbose")
      o.verbose = true;
    else if (a == "--set")
      o.sets.push_back(next());
    else if (a == "--spread") {
      so.target_x_min = 0.3;
      so.target_x_max = 0.7;
      so.target_y_half = 0.35;
    } else if (a == "--head-at-workspace")
      so.head_at_workspace = true;
    else if (a == "--noise-scale")
      scale_noise(std::atof(next().c_str()), so);
    else if (a == "--table-height")
      so.table.height = std::atof(next().c_str());
    else if (a == "--export")
      o.export_dir = next();
    else if (a == "--distribution")
      next();  // read by read_distribution
    else if (a == "--head-height" || a == "--hand-distance" || a == "--hand-elevation")
      ok = read_camera_range(a, next(), so);
    else if (a == "--gripper")
      ok = read_gripper(next(), so);
    else if (a == "--sensors")
      ok = read_sensors(next(), o);
    else if (a == "--kinds")
      ok = read_kinds(next(), o);
    else {
      print_usage();
      ok = false;
    }
    if (!ok) return false;
  }
  return true;
}

// The planner with the scene's gripper and the --set options; false when one is refused.
[[nodiscard]] bool configure_planner(fg::Planner& planner, const Options& o) {
  fg::PlannerConfig cfg;
  cfg.gripper = o.scene_opt.gripper;
  for (const std::string& kv : o.sets) {
    std::string err;
    const size_t eq = kv.find('=');
    if (eq == std::string::npos || !fg::host::set_config_option(cfg, kv.substr(0, eq), kv.substr(eq + 1), err)) {
      std::fprintf(stderr, "--set %s: %s\n", kv.c_str(), err.c_str());
      return false;
    }
  }
  return planner.configure(cfg) == fg::Status::ok;
}

// The scene's depth images (the sensors asked for) through the planner, then plan.
[[nodiscard]] fg::Status plan_scene(fg::Planner& planner, const Options& o, const fg::sim::GeneratedScene& scene,
                                    const fg::sim::SceneImages& img, fg::PlanResult& res) {
  planner.reset();
  fg::Status st = fg::Status::ok;
  if (o.use_head) st = fg::sim::add_rendered(planner, fg::SensorRole::head, img.head, scene.head);
  if (st == fg::Status::ok && o.use_hand)
    st = fg::sim::add_rendered(planner, fg::SensorRole::hand, img.hand, scene.hand);
  if (st == fg::Status::ok) st = planner.plan(res);
  return st;
}

void print_grasp_detail(const fg::Grasp& gp, const fg::sim::GroundTruth& truth, const fg::sim::JudgeResult& j) {
  std::printf(
      "  grasp pos (%.3f %.3f %.3f) app (%.2f %.2f %.2f) clo (%.2f %.2f %.2f) w %.3f beta %.3f dz %.4f view "
      "%.2f\n",
      gp.position.x(), gp.position.y(), gp.position.z(), gp.approach.x(), gp.approach.y(), gp.approach.z(),
      gp.closing.x(), gp.closing.y(), gp.closing.z(), gp.width, gp.beta, gp.dz, gp.viewpoint);
  std::printf("  truth centre (%.3f %.3f %.3f) min_width %.3f fits %d; true_width %.3f angles %.2f %.2f\n",
              truth.target_centre.x(), truth.target_centre.y(), truth.target_centre.z(), truth.target_min_width,
              truth.target_fits ? 1 : 0, j.true_width, j.angle_left, j.angle_right);
}

// Whether the planner's answer is right, and why (the judge's reason, the no_grasp
// reason or the failing status).
struct Verdict {
  bool right = false;
  std::string why;
};

// A grasp is judged on the true geometry; no_grasp is right iff the target fits nowhere.
[[nodiscard]] Verdict judge_answer(const Options& o, const fg::sim::GeneratedScene& scene, fg::Status st,
                                   const fg::PlanResult& res) {
  Verdict v;
  if (st == fg::Status::ok) {
    fg::sim::Grasp g;
    g.position = res.grasp.position;
    g.approach = res.grasp.approach;
    g.closing = res.grasp.closing;
    g.width = res.grasp.width;
    const fg::sim::JudgeResult j = fg::sim::judge_grasp(scene.world, scene.target, g, scene.gripper, 0.5);
    v.right = j.success;
    v.why = j.reason;
    if (o.verbose) print_grasp_detail(res.grasp, scene.truth, j);
  } else if (st == fg::Status::no_grasp) {
    v.right = !scene.truth.target_fits;
    v.why = std::string("no_grasp:") + fg::to_string(res.reason);
  } else {
    v.why = std::string("status:") + fg::to_string(st);
  }
  return v;
}

// A scene judged wrong, written as DIR/<kind>-<seed>/ for `forcegrasp plan --pictures`.
void export_wrong(const std::string& export_dir, const std::string& name, uint64_t s,
                  const fg::sim::GeneratedScene& scene, const fg::sim::SceneImages& img) {
  std::string dir = export_dir;
  dir += '/';
  dir += name;
  dir += '-';
  dir += std::to_string(s);
  const auto w = fg::sim::export_scene(scene, img, dir);
  if (!w.ok) std::fprintf(stderr, "--export %s: %s\n", dir.c_str(), w.error.c_str());
}

void count_trial(Tally& tl, fg::Status st, const fg::PlanResult& res, const Verdict& v) {
  tl.trials++;
  tl.right += v.right ? 1 : 0;
  tl.grasps += st == fg::Status::ok ? 1 : 0;
  tl.plan_us.push_back(res.stage_us[static_cast<int>(fg::Stage::total)]);
  if (!v.right) tl.wrong[v.why]++;
}

// Trial t: the scene of kind t mod kinds and seed seed + t, planned, judged and counted.
void run_trial(fg::Planner& planner, const Options& o, int t, std::map<std::string, Tally>& by_kind, Tally& all) {
  const fg::sim::ObjectKind kind = o.kinds[static_cast<size_t>(t) % o.kinds.size()];
  const uint64_t s = o.seed + static_cast<uint64_t>(t);
  const fg::sim::GeneratedScene scene = fg::sim::make_scene(kind, s, o.scene_opt);
  const fg::sim::SceneImages img = fg::sim::render_scene(scene);
  fg::PlanResult res;
  const fg::Status st = plan_scene(planner, o, scene, img, res);
  const Verdict v = judge_answer(o, scene, st, res);
  const std::string name = fg::sim::kind_name(kind);
  if (!v.right && !o.export_dir.empty()) export_wrong(o.export_dir, name, s, scene, img);
  count_trial(by_kind[name], st, res, v);
  count_trial(all, st, res, v);
  if (o.verbose || !v.right)
    std::printf("%-15s seed %-6llu %-5s %s (objpts %u, views %u, fam %d, width %.3f)\n", name.c_str(),
                static_cast<unsigned long long>(s), v.right ? "right" : "WRONG", v.why.c_str(), res.points.object,
                res.viewpoints, static_cast<int>(res.grasp.family), res.grasp.width);
}

void print_row(const std::string& n, const Tally& t) {
  std::string w;
  for (const auto& kv : t.wrong) w += kv.first + " x" + std::to_string(kv.second) + "  ";
  std::printf("%-15s %7d %7d %7.1f%% %12.0f  %s\n", n.c_str(), t.trials, t.right,
              100.0 * t.right / std::max(1, t.trials), median(t.plan_us), w.c_str());
}

void print_report(const std::map<std::string, Tally>& by_kind, const Tally& all) {
  std::printf("\n%-15s %7s %7s %8s %12s  %s\n", "kind", "trials", "right", "rate", "median_us", "wrong answers");
  for (const auto& kv : by_kind) print_row(kv.first, kv.second);
  print_row("ALL", all);
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (!parse_options(argc, argv, o)) return 2;
  auto planner = std::make_unique<fg::Planner>();
  if (!configure_planner(*planner, o)) return 2;

  std::map<std::string, Tally> by_kind;
  Tally all;
  for (int t = 0; t < o.count; ++t) run_trial(*planner, o, t, by_kind, all);
  print_report(by_kind, all);
  const double rate = static_cast<double>(all.right) / std::max(1, all.trials);
  if (o.min_rate >= 0 && rate < o.min_rate) {
    std::printf("FAILED: %.1f%% right is below the required %.1f%%\n", 100 * rate, 100 * o.min_rate);
    return 1;
  }
  return 0;
}
