#include "sim_trial.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <map>
#include <stdexcept>

#include "fg/robot/grasp_motion.hpp"
#include "fg/robot/ur5.hpp"
#include "fg/robot/ur5_ik.hpp"
#include "fg/task/grasp_task.hpp"
#include "sim/grasp_judge.hpp"
#include "sim/scene_export.hpp"
#include "sim/scene_gen.hpp"
#include "sim/sim_hal.hpp"
#include "svg_pictures.hpp"

namespace fg::host {
namespace {

using sim::Rigid;
using sim::V3;

// Where the arm waits when the wrist camera cannot reach the scene's viewpoint: tool0
// over the workspace, looking down.
constexpr double kHome[6] = {0.0, -1.9, 1.9, -1.57, -1.57, 0.0};
constexpr uint32_t kTickUs = 1000;         // the control tick
constexpr uint32_t kMaxTicks = 120000;     // 2 min of simulated time: every task ends before
constexpr uint32_t kPathSampleTicks = 10;  // the open gripper is judged every 10 ms on the way in

// Joints that put the wrist camera where the scene's hand camera is (turned about its
// optical axis if need be: the view is the same, the arm's reach is not), nearest home;
// home when the arm cannot get it there.
bool capture_joints(const Rigid& world_T_camera, const Rigid& tool0_T_camera, double q[6]) {
  for (int i = 0; i < 6; ++i) q[i] = kHome[i];
  constexpr int kRolls = 12;
  for (int r = 0; r < kRolls; ++r) {
    const double roll = (r % 2 == 0 ? 1.0 : -1.0) * ((r + 1) / 2) * (2.0 * 3.14159265358979 / kRolls);
    const Rigid tool0 = world_T_camera * Rigid::rot_z(roll) * tool0_T_camera.inverse();
    robot::PoseD target;
    target.R = tool0.R;
    target.t = tool0.t;
    robot::IkSolutions sols;
    if (!robot::ik_has_solution(robot::ur5_inverse(robot::ur5_nominal(), target, sols))) continue;
    const robot::IkChoice c = robot::choose_nearest(kHome, sols);
    if (c.status != robot::IkStatus::ok) continue;
    for (int i = 0; i < 6; ++i) q[i] = c.q[i];
    return true;
  }
  return false;
}

// The open gripper at tool0 (pads tcp_offset ahead): "" when clear of table and objects.
std::string open_pose_hit(const sim::World& world, int target, const Rigid& world_T_tool0, float tcp_offset,
                          const GripperGeometry& g) {
  sim::Grasp probe;
  probe.position = sim::to_vec3(world_T_tool0.apply(V3(0, 0, tcp_offset)));
  probe.approach = sim::to_vec3(world_T_tool0.R.col(2));
  probe.closing = sim::to_vec3(world_T_tool0.R.col(0));
  return sim::open_pose_collision(world, target, probe, g);
}

std::string fmt_ms(double ms) {
  char b[32];
  std::snprintf(b, sizeof b, "%.2f", ms);
  return b;
}

}  // namespace

SimTrial run_sim_trial(const std::string& kind_name, uint64_t seed, const SimOptions& opt, const PlannerConfig& cfg,
                       Planner& planner) {
  SimTrial out;
  out.kind = kind_name;
  out.seed = seed;
  sim::ObjectKind kind;
  if (!sim::kind_from_name(kind_name, kind)) throw std::invalid_argument("unknown object kind: " + kind_name);
  const Pose hand_eye = robot::default_hand_eye();
  const Rigid tool0_T_camera = Rigid::from_pose(hand_eye);
  sim::SceneOptions so = sim::SceneOptions::of(opt.distribution);
  so.gripper = cfg.gripper;
  so.second_object_rate = opt.second_object_rate;
  // cell: the wrist camera only where the arm can put it.
  const sim::WristPoseTest reachable = [&tool0_T_camera](const Rigid& world_T_camera) {
    double q[6];
    return capture_joints(world_T_camera, tool0_T_camera, q);
  };
  const sim::GeneratedScene scene = sim::make_scene(kind, seed, so, reachable);
  out.fits = scene.truth.target_fits;

  // The hardware.
  double q0[6];
  out.wrist_view = capture_joints(scene.hand.world_T_sensor, tool0_T_camera, q0);
  sim::SimClock clock;
  sim::SimArm arm(q0, sim::SimArmConfig{}, &clock);
  task::TaskConfig tc;
  tc.world_T_head = scene.head.world_T_sensor.to_pose();
  tc.tool0_T_hand = hand_eye;
  const Rigid tool0_T_grasp = Rigid::translation(V3(0, 0, tc.tcp_offset_m));
  sim::SdfContactModel contact(scene.world, sim::mounted_on_tool0(arm, tool0_T_grasp), cfg.gripper);
  sim::SimGripperConfig gc;
  gc.geometry = cfg.gripper;
  gc.initial_width_m = cfg.gripper.max_opening_m;
  sim::SimGripper gripper(gc, &contact);
  sim::SimDepthSensorConfig head_cfg, hand_cfg;
  head_cfg.K = scene.head.K;
  hand_cfg.K = scene.hand.K;
  head_cfg.noise = hand_cfg.noise = scene.noise;
  head_cfg.seed = scene.head_noise_seed;
  hand_cfg.seed = scene.hand_noise_seed;
  const Rigid head_pose = scene.head.world_T_sensor;
  sim::SimDepthSensor head(
      scene.world, clock, [head_pose] { return head_pose; }, head_cfg);
  sim::SimDepthSensor hand(scene.world, clock, sim::mounted_on_tool0(arm, tool0_T_camera), hand_cfg);
  const task::TaskHal hal{clock, &head, &hand, arm, gripper};

  // The task, one step per tick; the open gripper judged on the way in.
  task::GraspTask grasp_task;
  if (grasp_task.start(tc) != Status::ok) throw std::logic_error("the sim task configuration was refused");
  std::string way_in_hit;
  double plan_wall_ms = 0.0;
  uint32_t tick = 0;
  for (; tick < kMaxTicks; ++tick) {
    const task::TaskState before = grasp_task.state();
    const auto t0 = std::chrono::steady_clock::now();
    const task::TaskState s = grasp_task.step(planner, hal);
    if (before == task::TaskState::planning)
      plan_wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (s == task::TaskState::succeeded || s == task::TaskState::failed) break;
    clock.advance_us(kTickUs);
    arm.tick(kTickUs * 1e-6);
    gripper.tick(kTickUs * 1e-6);
    const bool way_in = s == task::TaskState::to_pregrasp || s == task::TaskState::approaching;
    if (way_in && way_in_hit.empty() && tick % kPathSampleTicks == 0) {
      way_in_hit = open_pose_hit(scene.world, scene.target, arm.world_T_tool0(), tc.tcp_offset_m, cfg.gripper);
      if (!way_in_hit.empty()) way_in_hit = std::string(task::to_string(s)) + ":" + way_in_hit;
    }
  }
  out.ticks = tick;
  out.task_s = static_cast<double>(clock.time_us()) * 1e-6;
  const PlanResult& pr = grasp_task.plan_result();
  out.plan_ms = pr.stage_us[static_cast<int>(Stage::total)] > 0 ? pr.stage_us[static_cast<int>(Stage::total)] * 1e-3
                                                                : plan_wall_ms;
  out.task_state = std::string(task::to_string(grasp_task.state()));
  if (grasp_task.state() == task::TaskState::failed)
    out.task_state += std::string(":") + task::to_string(grasp_task.failure());
  if (pr.status == Status::no_grasp) out.plan_reason = to_string(pr.reason);

  // The verdict on the true geometry.
  if (pr.status == Status::no_grasp) {
    out.success = !out.fits;
    out.verdict = out.fits ? std::string("no_grasp_on_fitting_target:") + out.plan_reason : "success";
  } else if (pr.status != Status::ok) {
    out.verdict = std::string("plan_") + to_string(pr.status);
  } else {
    // A grasp on a target the truth says fits nowhere is judged too: that truth takes
    // the widths of whole parts, and a mesh part may have a thin piece (the blade of
    // the scissors) a grasp can hold. The judge fails any grasp on a primitive too wide.
    sim::Grasp g;
    g.position = pr.grasp.position;
    g.approach = pr.grasp.approach;
    g.closing = pr.grasp.closing;
    g.width = pr.grasp.width;
    // The criteria of a grasp the task executes: both pads on the target, normals in the
    // friction cone, no collision, the width within the opening. The reported width is
    // not one of them (the gripper closes until contact): its error is recorded only.
    sim::JudgeOptions jo;
    jo.mu = opt.mu;
    jo.width_tolerance = std::numeric_limits<double>::infinity();
    const sim::JudgeResult j = sim::judge_grasp(scene.world, scene.target, g, cfg.gripper, jo);
    if (j.true_width >= 0.f) out.width_error_m = std::fabs(j.true_width - pr.grasp.width);
    out.has_grasp = true;
    out.grasp = pr.grasp;
    out.angle_left = j.angle_left;
    out.angle_right = j.angle_right;
    out.true_width = j.true_width;
    out.contact_left = j.contact_left;
    out.contact_right = j.contact_right;
    if (!j.success) {
      out.verdict = out.fits ? j.reason : "grasp_on_target_that_fits_nowhere:" + j.reason;
    } else if (!way_in_hit.empty()) {
      out.verdict = "way_in:" + way_in_hit;
    } else if (grasp_task.state() != task::TaskState::succeeded) {
      out.verdict = "task_" + out.task_state;
    } else {
      out.verdict = "success";
      out.success = true;
    }
  }

  const std::string name = kind_name + "-" + std::to_string(seed);
  if (!opt.pictures_dir.empty() && (pr.status == Status::ok || pr.status == Status::no_grasp)) {
    std::string err;
    if (!write_pictures(planner, pr, opt.pictures_dir + "/" + name, err))
      std::cerr << "forcegrasp sim: pictures of " << name << ": " << err << "\n";
  }
  if (!opt.export_dir.empty()) {
    // The scene as the task saw it: the images it captured, from where it captured them.
    sim::GeneratedScene seen = scene;
    sim::SceneImages images;
    if (head.captures() > 0) {
      seen.head = head.last_camera();
      images.head = head.last_image();
    }
    if (hand.captures() > 0) {
      seen.hand = hand.last_camera();
      images.hand = hand.last_image();
    }
    if (head.captures() == 0 || hand.captures() == 0) images = sim::render_scene(seen);
    const ReadResult r = sim::export_scene(seen, images, opt.export_dir + "/" + name);
    if (!r.ok) std::cerr << "forcegrasp sim: export of " << name << ": " << r.error << "\n";
  }
  return out;
}

nlohmann::json run_sim(const SimOptions& opt, const PlannerConfig& cfg, Planner& planner) {
  using nlohmann::json;
  const uint32_t n = opt.trials > 0 ? opt.trials : 20u * static_cast<uint32_t>(opt.kinds.size());
  std::vector<SimTrial> trials;
  const bool tty = isatty(STDERR_FILENO) != 0;
  uint32_t ok = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const std::string& kind = opt.kinds[i % opt.kinds.size()];
    trials.push_back(run_sim_trial(kind, opt.seed + i, opt, cfg, planner));
    ok += trials.back().success ? 1u : 0u;
    if (opt.progress && (tty || (i + 1) % 10 == 0 || i + 1 == n)) {
      std::fprintf(stderr, "%s[%u/%u] %s-%llu %-40.40s  success so far %u/%u (%.1f%%)%s", tty ? "\r" : "", i + 1, n,
                   kind.c_str(), static_cast<unsigned long long>(opt.seed + i), trials.back().verdict.c_str(), ok,
                   i + 1, 100.0 * ok / (i + 1), tty ? "" : "\n");
      std::fflush(stderr);
    }
  }
  if (opt.progress && tty) std::fprintf(stderr, "\n");

  // The table: per kind, then all.
  struct Row {
    uint32_t trials = 0, success = 0, fits = 0;
    std::vector<double> plan_ms;
    std::map<std::string, uint32_t> failures;
  };
  std::map<std::string, Row> rows;
  std::vector<std::string> order;
  Row all;
  for (const SimTrial& t : trials) {
    if (!rows.count(t.kind)) order.push_back(t.kind);
    for (Row* r : {&rows[t.kind], &all}) {
      ++r->trials;
      r->success += t.success ? 1u : 0u;
      r->fits += t.fits ? 1u : 0u;
      r->plan_ms.push_back(t.plan_ms);
      if (!t.success) {
        const std::string key = t.verdict.substr(0, t.verdict.find(' '));
        ++r->failures[key];
      }
    }
  }
  const auto median = [](std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  };
  const auto max_of = [](const std::vector<double>& v) {
    return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
  };
  json table = json::array();
  std::printf("distribution %s, seed %llu (trial i: seed + i; --distribution %s --seed %llu repeats it)\n",
              sim::distribution_name(opt.distribution), static_cast<unsigned long long>(opt.seed),
              sim::distribution_name(opt.distribution), static_cast<unsigned long long>(opt.seed));
  std::printf("%-22s %6s %5s %8s %9s %11s %9s  %s\n", "object", "trials", "fits", "success", "rate", "plan med ms",
              "max ms", "failures");
  const auto print_row = [&](const std::string& name, const Row& r) {
    std::string fails;
    for (const auto& [k, c] : r.failures) fails += (fails.empty() ? "" : ", ") + k + " x" + std::to_string(c);
    const double rate = r.trials ? 100.0 * r.success / r.trials : 0.0;
    std::printf("%-22s %6u %5u %8u %8.1f%% %11s %9s  %s\n", name.c_str(), r.trials, r.fits, r.success, rate,
                fmt_ms(median(r.plan_ms)).c_str(), fmt_ms(max_of(r.plan_ms)).c_str(), fails.c_str());
    json f = json::object();
    for (const auto& [k, c] : r.failures) f[k] = c;
    table.push_back(json{{"object", name},
                         {"trials", r.trials},
                         {"fits", r.fits},
                         {"success", r.success},
                         {"rate", r.trials ? static_cast<double>(r.success) / r.trials : 0.0},
                         {"plan_ms_median", median(r.plan_ms)},
                         {"plan_ms_max", max_of(r.plan_ms)},
                         {"failures", f}});
  };
  for (const std::string& k : order) print_row(k, rows[k]);
  print_row("all", all);
  json records = json::array();
  const auto vec = [](const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); };
  for (const SimTrial& t : trials) {
    json r{{"kind", t.kind},
           {"seed", t.seed},
           {"fits", t.fits},
           {"success", t.success},
           {"verdict", t.verdict},
           {"task", t.task_state},
           {"plan_reason", t.plan_reason},
           {"plan_ms", t.plan_ms},
           {"width_error_m", t.width_error_m},
           {"wrist_view", t.wrist_view},
           {"task_s", t.task_s},
           {"ticks", t.ticks}};
    if (t.has_grasp) {
      r["grasp"] = json{{"position", vec(t.grasp.position)},
                        {"approach", vec(t.grasp.approach)},
                        {"closing", vec(t.grasp.closing)},
                        {"width", t.grasp.width},
                        {"beta", t.grasp.beta},
                        {"dz", t.grasp.dz},
                        {"family", static_cast<int>(t.grasp.family)}};
      r["judge"] = json{{"angle_left", t.angle_left}, {"angle_right", t.angle_right}, {"true_width", t.true_width}};
      if (t.true_width >= 0.f) {
        r["judge"]["contact_left"] = vec(t.contact_left);
        r["judge"]["contact_right"] = vec(t.contact_right);
      }
    }
    records.push_back(r);
  }
  return json{{"distribution", sim::distribution_name(opt.distribution)},
              {"seed", opt.seed},
              {"trials", records},
              {"table", table}};
}

}  // namespace fg::host
