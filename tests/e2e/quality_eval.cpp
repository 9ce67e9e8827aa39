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

}  // namespace

int main(int argc, char** argv) {
  int count = 110;
  uint64_t seed = 1000;
  double min_rate = -1;
  bool verbose = false;
  std::string export_dir;
  bool use_head = true, use_hand = true;  // --sensors: both (the default), head or hand
  std::vector<std::string> sets;
  fg::sim::SceneOptions scene_opt;
  // The distribution first: the other options change its ranges, whatever their order.
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::string(argv[i]) != "--distribution") continue;
    fg::sim::Distribution d;
    if (!fg::sim::distribution_from_name(argv[i + 1], d)) {
      std::fprintf(stderr, "--distribution %s: expected classic or cell\n", argv[i + 1]);
      return 2;
    }
    scene_opt = fg::sim::SceneOptions::of(d);
  }
  std::vector<fg::sim::ObjectKind> kinds = fg::sim::all_kinds();
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "%s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--count")
      count = std::atoi(next().c_str());
    else if (a == "--seed")
      seed = std::strtoull(next().c_str(), nullptr, 10);
    else if (a == "--min-rate")
      min_rate = std::atof(next().c_str());
    else if (a == "--verbose")
      verbose = true;
    else if (a == "--set")
      sets.push_back(next());
    else if (a == "--spread") {
      scene_opt.target_x_min = 0.3;
      scene_opt.target_x_max = 0.7;
      scene_opt.target_y_half = 0.35;
    } else if (a == "--head-at-workspace")
      scene_opt.head_at_workspace = true;
    else if (a == "--noise-scale") {
      const double k = std::atof(next().c_str());
      scene_opt.noise.sigma_a *= k;
      scene_opt.noise.sigma_b *= k;
      scene_opt.noise.gaussian = k > 0;
    } else if (a == "--table-height")
      scene_opt.table.height = std::atof(next().c_str());
    else if (a == "--export")
      export_dir = next();
    else if (a == "--distribution")
      next();  // read above
    else if (a == "--head-height" || a == "--hand-distance" || a == "--hand-elevation") {
      // A range LO,HI for the cameras' placement (scene_gen.hpp SceneOptions).
      double lo = 0, hi = 0;
      if (std::sscanf(next().c_str(), "%lf,%lf", &lo, &hi) != 2 || !(lo <= hi)) {
        std::fprintf(stderr, "%s: expected LO,HI with LO <= HI\n", a.c_str());
        return 2;
      }
      if (a == "--head-height")
        scene_opt.head_height_min = lo, scene_opt.head_height_max = hi;
      else if (a == "--hand-distance")
        scene_opt.hand_distance_min = lo, scene_opt.hand_distance_max = hi;
      else
        scene_opt.hand_elevation_min_deg = lo, scene_opt.hand_elevation_max_deg = hi;
    } else if (a == "--gripper") {
      // Another gripper for both the planner and the judge (the scene contract's
      // gripper block): max opening, finger width, finger depth in metres.
      double m = 0, w = 0, d = 0;
      if (std::sscanf(next().c_str(), "%lf,%lf,%lf", &m, &w, &d) != 3) {
        std::fprintf(stderr, "--gripper: expected OPENING,FINGER_WIDTH,FINGER_DEPTH (m)\n");
        return 2;
      }
      scene_opt.gripper.max_opening_m = static_cast<float>(m);
      scene_opt.gripper.finger_width_m = static_cast<float>(w);
      scene_opt.gripper.finger_depth_m = static_cast<float>(d);
    } else if (a == "--sensors") {
      const std::string v = next();
      use_head = v == "both" || v == "head";
      use_hand = v == "both" || v == "hand";
      if (!use_head && !use_hand) {
        std::fprintf(stderr, "--sensors %s: expected both, head or hand\n", v.c_str());
        return 2;
      }
    } else if (a == "--kinds") {
      kinds.clear();
      std::stringstream ss(next());
      std::string k;
      while (std::getline(ss, k, ',')) {
        fg::sim::ObjectKind kind;
        if (!fg::sim::kind_from_name(k, kind)) {
          std::fprintf(stderr, "unknown kind %s\n", k.c_str());
          return 2;
        }
        kinds.push_back(kind);
      }
    } else {
      std::fprintf(
          stderr,
          "usage: fg_quality [--count N] [--seed S] [--kinds a,b] [--min-rate R] [--verbose] [--set name=value] "
          "[--sensors both|head|hand] [--spread] [--head-at-workspace] [--noise-scale F] [--table-height H] [--gripper "
          "OPENING,FINGER_WIDTH,FINGER_DEPTH] [--head-height LO,HI] [--hand-distance LO,HI] [--hand-elevation "
          "LO_DEG,HI_DEG] [--export DIR] [--distribution classic|cell]\n");
      return 2;
    }
  }
  auto planner = std::make_unique<fg::Planner>();
  fg::PlannerConfig cfg;
  cfg.gripper = scene_opt.gripper;
  for (const std::string& kv : sets) {
    std::string err;
    const size_t eq = kv.find('=');
    if (eq == std::string::npos || !fg::host::set_config_option(cfg, kv.substr(0, eq), kv.substr(eq + 1), err)) {
      std::fprintf(stderr, "--set %s: %s\n", kv.c_str(), err.c_str());
      return 2;
    }
  }
  if (planner->configure(cfg) != fg::Status::ok) return 2;

  std::map<std::string, Tally> by_kind;
  Tally all;
  for (int t = 0; t < count; ++t) {
    const fg::sim::ObjectKind kind = kinds[static_cast<size_t>(t) % kinds.size()];
    const uint64_t s = seed + static_cast<uint64_t>(t);
    const fg::sim::GeneratedScene scene = fg::sim::make_scene(kind, s, scene_opt);
    const fg::sim::SceneImages img = fg::sim::render_scene(scene);
    planner->reset();
    fg::Status st = fg::Status::ok;
    if (use_head) st = fg::sim::add_rendered(*planner, fg::SensorRole::head, img.head, scene.head);
    if (st == fg::Status::ok && use_hand)
      st = fg::sim::add_rendered(*planner, fg::SensorRole::hand, img.hand, scene.hand);
    fg::PlanResult res;
    if (st == fg::Status::ok) st = planner->plan(res);
    bool right = false;
    std::string why;
    if (st == fg::Status::ok) {
      fg::sim::Grasp g;
      g.position = res.grasp.position;
      g.approach = res.grasp.approach;
      g.closing = res.grasp.closing;
      g.width = res.grasp.width;
      const fg::sim::JudgeResult j = fg::sim::judge_grasp(scene.world, scene.target, g, scene.gripper, 0.5);
      right = j.success;
      why = j.reason;
      if (verbose) {
        const auto& gp = res.grasp;
        std::printf(
            "  grasp pos (%.3f %.3f %.3f) app (%.2f %.2f %.2f) clo (%.2f %.2f %.2f) w %.3f beta %.3f dz %.4f view "
            "%.2f\n",
            gp.position.x(), gp.position.y(), gp.position.z(), gp.approach.x(), gp.approach.y(), gp.approach.z(),
            gp.closing.x(), gp.closing.y(), gp.closing.z(), gp.width, gp.beta, gp.dz, gp.viewpoint);
        std::printf("  truth centre (%.3f %.3f %.3f) min_width %.3f fits %d; true_width %.3f angles %.2f %.2f\n",
                    scene.truth.target_centre.x(), scene.truth.target_centre.y(), scene.truth.target_centre.z(),
                    scene.truth.target_min_width, scene.truth.target_fits ? 1 : 0, j.true_width, j.angle_left,
                    j.angle_right);
      }
    } else if (st == fg::Status::no_grasp) {
      right = !scene.truth.target_fits;
      why = std::string("no_grasp:") + fg::to_string(res.reason);
    } else {
      why = std::string("status:") + fg::to_string(st);
    }
    const std::string name = fg::sim::kind_name(kind);
    if (!right && !export_dir.empty()) {
      const std::string dir = export_dir + "/" + name + "-" + std::to_string(s);
      const auto w = fg::sim::export_scene(scene, img, dir);
      if (!w.ok) std::fprintf(stderr, "--export %s: %s\n", dir.c_str(), w.error.c_str());
    }
    for (Tally* tl : {&by_kind[name], &all}) {
      tl->trials++;
      tl->right += right ? 1 : 0;
      tl->grasps += st == fg::Status::ok ? 1 : 0;
      tl->plan_us.push_back(res.stage_us[static_cast<int>(fg::Stage::total)]);
      if (!right) tl->wrong[why]++;
    }
    if (verbose || !right)
      std::printf("%-15s seed %-6llu %-5s %s (objpts %u, views %u, fam %d, width %.3f)\n", name.c_str(),
                  static_cast<unsigned long long>(s), right ? "right" : "WRONG", why.c_str(), res.points.object,
                  res.viewpoints, static_cast<int>(res.grasp.family), res.grasp.width);
  }
  std::printf("\n%-15s %7s %7s %8s %12s  %s\n", "kind", "trials", "right", "rate", "median_us", "wrong answers");
  auto row = [](const std::string& n, const Tally& t) {
    std::string w;
    for (const auto& kv : t.wrong) w += kv.first + " x" + std::to_string(kv.second) + "  ";
    std::printf("%-15s %7d %7d %7.1f%% %12.0f  %s\n", n.c_str(), t.trials, t.right,
                100.0 * t.right / std::max(1, t.trials), median(t.plan_us), w.c_str());
  };
  for (const auto& kv : by_kind) row(kv.first, kv.second);
  row("ALL", all);
  const double rate = static_cast<double>(all.right) / std::max(1, all.trials);
  if (min_rate >= 0 && rate < min_rate) {
    std::printf("FAILED: %.1f%% right is below the required %.1f%%\n", 100 * rate, 100 * min_rate);
    return 1;
  }
  return 0;
}
