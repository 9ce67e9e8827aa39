#include "sim_trial.hpp"

#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <map>
#include <stdexcept>

#include "fg/core/constants.hpp"
#include "fg/robot/grasp_motion.hpp"
#include "fg/robot/ur5.hpp"
#include "fg/robot/ur5_ik.hpp"
#include "fg/task/grasp_task.hpp"
#include "sim/calibration_error.hpp"
#include "sim/grasp_judge.hpp"
#include "sim/pinhole.hpp"
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
[[nodiscard]] bool capture_joints(const Rigid& world_T_camera, const Rigid& tool0_T_camera, double q[6]) {
  for (int i = 0; i < 6; ++i) q[i] = kHome[i];
  constexpr int kRolls = 12;
  for (int r = 0; r < kRolls; ++r) {
    // Rolls of 0, -30, +30, -60, +60, ... -180 deg: the nearest first. (The digits of pi
    // written here are those the pinned seeds' scenes were made with: fg::kPi differs
    // in the last bits, and so would the joints.)
    const int steps = (r + 1) / 2;
    const double roll = (r % 2 == 0 ? 1.0 : -1.0) * steps * (2.0 * 3.14159265358979 / kRolls);
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
[[nodiscard]] std::string open_pose_hit(const sim::World& world, int target, const Rigid& world_T_tool0,
                                        float tcp_offset, const GripperGeometry& g) {
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

//! The trial's scene. cell: the wrist camera only where the arm can put it.
sim::GeneratedScene make_trial_scene(sim::ObjectKind kind, uint64_t seed, const SimOptions& opt,
                                     const PlannerConfig& cfg, const Rigid& tool0_T_camera) {
  sim::SceneOptions so = sim::SceneOptions::of(opt.distribution);
  so.gripper = cfg.gripper;
  so.second_object_rate = opt.second_object_rate;
  const sim::WristPoseTest reachable = [&tool0_T_camera](const Rigid& world_T_camera) {
    double q[6];
    return capture_joints(world_T_camera, tool0_T_camera, q);
  };
  return sim::make_scene(kind, seed, so, reachable);
}

sim::SimGripperConfig gripper_config(const GripperGeometry& geometry) {
  sim::SimGripperConfig gc;
  gc.geometry = geometry;
  gc.initial_width_m = geometry.max_opening_m;
  return gc;
}

sim::SimDepthSensorConfig camera_config(const sim::GeneratedScene& scene, const sim::Camera& camera,
                                        uint64_t noise_seed) {
  sim::SimDepthSensorConfig c;
  c.K = camera.K;
  c.noise = scene.noise;
  c.seed = noise_seed;
  return c;
}

//! The hardware of one trial: the head camera on its mount, the wrist camera on a UR5
//! that follows joint commands (starting at q0), a 2F-85-class gripper closing on the
//! true geometry. Built in place: its parts hold pointers to each other.
struct TrialHardware {
  TrialHardware(const sim::GeneratedScene& scene, const double q0[6], float tcp_offset_m, const Rigid& tool0_T_camera,
                const GripperGeometry& geometry, const sim::SimArmConfig& arm_config)
      : arm(q0, arm_config, &clock),
        contact(scene.world, sim::mounted_on_tool0(arm, Rigid::translation(V3(0, 0, tcp_offset_m))), geometry),
        gripper(gripper_config(geometry), &contact),
        head(
            scene.world, clock, [pose = scene.head.world_T_sensor] { return pose; },
            camera_config(scene, scene.head, scene.head_noise_seed)),
        hand(scene.world, clock, sim::mounted_on_tool0(arm, tool0_T_camera),
             camera_config(scene, scene.hand, scene.hand_noise_seed)) {}

  sim::SimClock clock;
  sim::SimArm arm;
  sim::SdfContactModel contact;
  sim::SimGripper gripper;
  sim::SimDepthSensor head, hand;
  const task::TaskHal hal{clock, &head, &hand, arm, gripper};
};

//! What running the task left besides the task's own state.
struct TaskRun {
  uint32_t ticks = 0;
  double plan_wall_ms = 0.0;  // the plan step's wall time
  std::string way_in_hit;     // the open gripper's first collision on the way in, "" if none
};

//! The task, one step per tick; the open gripper judged on the way in.
TaskRun run_task(task::GraspTask& grasp_task, const task::TaskConfig& tc, TrialHardware& hw,
                 const sim::GeneratedScene& scene, Planner& planner, const GripperGeometry& geometry) {
  if (grasp_task.start(tc) != Status::ok) throw std::logic_error("the sim task configuration was refused");
  TaskRun run;
  uint32_t tick = 0;
  for (; tick < kMaxTicks; ++tick) {
    const task::TaskState before = grasp_task.state();
    const auto t0 = std::chrono::steady_clock::now();
    const task::TaskState s = grasp_task.step(planner, hw.hal);
    if (before == task::TaskState::planning)
      run.plan_wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (s == task::TaskState::succeeded || s == task::TaskState::failed) break;
    hw.clock.advance_us(kTickUs);
    hw.arm.tick(kTickUs * 1e-6);
    hw.gripper.tick(kTickUs * 1e-6);
    const bool way_in = s == task::TaskState::to_pregrasp || s == task::TaskState::approaching;
    if (way_in && run.way_in_hit.empty() && tick % kPathSampleTicks == 0) {
      const std::string hit =
          open_pose_hit(scene.world, scene.target, hw.arm.world_T_tool0(), tc.tcp_offset_m, geometry);
      if (!hit.empty()) run.way_in_hit = std::string(task::to_string(s)).append(":").append(hit);
    }
  }
  run.ticks = tick;
  return run;
}

//! The judge's verdict on a planned grasp, on the true geometry, by the criteria of a
//! grasp the task executes: both pads on the target, normals in the friction cone, no
//! collision, the width within the opening. The reported width is not one of them (the
//! gripper closes until contact): its error is only measured.
[[nodiscard]] sim::JudgeResult judge_as_executed(const Grasp& grasp, const sim::GeneratedScene& scene,
                                                 const PlannerConfig& cfg, const SimOptions& opt) {
  sim::Grasp g;
  g.position = grasp.position;
  g.approach = grasp.approach;
  g.closing = grasp.closing;
  g.width = grasp.width;
  sim::JudgeOptions jo;
  jo.mu = opt.mu;
  jo.width_tolerance = std::numeric_limits<double>::infinity();
  return sim::judge_grasp(scene.world, scene.target, g, cfg.gripper, jo);
}

//! The judge's verdict on the planned grasp (judge_as_executed); what it measured is
//! recorded in out.
[[nodiscard]] sim::JudgeResult judge_planned_grasp(SimTrial& out, const PlanResult& pr,
                                                   const sim::GeneratedScene& scene, const PlannerConfig& cfg,
                                                   const SimOptions& opt) {
  sim::JudgeResult j = judge_as_executed(pr.grasp, scene, cfg, opt);
  if (j.true_width >= 0.f) out.width_error_m = std::fabs(j.true_width - pr.grasp.width);
  out.has_grasp = true;
  out.grasp = pr.grasp;
  out.angle_left = j.angle_left;
  out.angle_right = j.angle_right;
  out.true_width = j.true_width;
  out.contact_left = j.contact_left;
  out.contact_right = j.contact_right;
  return j;
}

//! The verdict on the true geometry: a no_grasp is right on a target that fits nowhere;
//! a grasp must pass the judge, keep the open gripper clear on the way in and end the
//! task in success.
void give_verdict(SimTrial& out, const PlanResult& pr, const sim::GeneratedScene& scene, const PlannerConfig& cfg,
                  const SimOptions& opt, const TaskRun& run, task::TaskState final_state) {
  if (pr.status == Status::no_grasp) {
    out.success = !out.fits;
    out.verdict = out.fits ? std::string("no_grasp_on_fitting_target:") + out.plan_reason : "success";
    return;
  }
  if (pr.status != Status::ok) {
    out.verdict = std::string("plan_") + to_string(pr.status);
    return;
  }
  // A grasp on a target the truth says fits nowhere is judged too: that truth takes
  // the widths of whole parts, and a mesh part may have a thin piece (the blade of
  // the scissors) a grasp can hold. The judge fails any grasp on a primitive too wide.
  const sim::JudgeResult j = judge_planned_grasp(out, pr, scene, cfg, opt);
  if (!j.success) {
    out.verdict = out.fits ? j.reason : "grasp_on_target_that_fits_nowhere:" + j.reason;
  } else if (!run.way_in_hit.empty()) {
    out.verdict = "way_in:" + run.way_in_hit;
  } else if (final_state != task::TaskState::succeeded) {
    out.verdict = "task_" + out.task_state;
  } else {
    out.verdict = "success";
    out.success = true;
  }
}

//! Pictures of the plan and the scene as the task saw it (the images it captured, from
//! where it captured them), when asked for; failures are reported on stderr.
void write_trial_files(const std::string& name, const SimOptions& opt, Planner& planner, const PlanResult& pr,
                       const sim::GeneratedScene& scene, const TrialHardware& hw) {
  if (!opt.pictures_dir.empty() && (pr.status == Status::ok || pr.status == Status::no_grasp)) {
    std::string err;
    if (!write_pictures(planner, pr, opt.pictures_dir + "/" + name, err))
      std::cerr << "forcegrasp sim: pictures of " << name << ": " << err << "\n";
  }
  if (!opt.export_dir.empty()) {
    sim::GeneratedScene seen = scene;
    sim::SceneImages images;
    if (hw.head.captures() > 0) {
      seen.head = hw.head.last_camera();
      images.head = hw.head.last_image();
    }
    if (hw.hand.captures() > 0) {
      seen.hand = hw.hand.last_camera();
      images.hand = hw.hand.last_image();
    }
    if (hw.head.captures() == 0 || hw.hand.captures() == 0) images = sim::render_scene(seen);
    const ReadResult r = sim::export_scene(seen, images, opt.export_dir + "/" + name);
    if (!r.ok) std::cerr << "forcegrasp sim: export of " << name << ": " << r.error << "\n";
  }
}

//! One more plan after a refusal as occluded: the sensor the advice names looks from the
//! advised view at the advised point, the other sensor as it was (true poses; no arm and
//! no arm's check: it shows what the view shows, not whether the arm can put the camera
//! there). "success" when the judge passes the grasp on the gripper's criteria, else the
//! judge's or the planner's reason.
std::string plan_after_advised_look(const sim::GeneratedScene& scene, const LookAdvice& look, const SimOptions& opt,
                                    const PlannerConfig& cfg, Planner& planner) {
  constexpr uint64_t kRelookStream = 0xD1B54A32D192ED03ull;  // the new image's own noise
  planner.reset();
  for (const SensorRole role : {SensorRole::head, SensorRole::hand}) {  // the head first (A.4b)
    const bool head = role == SensorRole::head, advised = role == look.sensor;
    if (!advised && !(head ? opt.use_head : opt.use_hand)) continue;
    // The advised sensor renders from the advised view with noise of its own; the other
    // as the task saw it (render_scene's image).
    sim::Camera cam = head ? scene.head : scene.hand;
    uint64_t noise_seed = head ? scene.head_noise_seed : scene.hand_noise_seed;
    if (advised) {
      cam.world_T_sensor = sim::look_at(look.from.cast<double>(), look.at.cast<double>());
      noise_seed ^= kRelookStream;
    }
    const sim::DepthImage im = sim::render_depth(scene.world, cam, scene.noise, noise_seed);
    if (sim::add_rendered(planner, role, im, cam) != Status::ok) return "points_refused";
  }
  PlanResult r;
  const Status s = planner.plan(r);
  if (s == Status::no_grasp) return std::string("no_grasp:") + to_string(r.reason);
  if (s != Status::ok) return std::string("plan:") + to_string(s);
  const sim::JudgeResult j = judge_as_executed(r.grasp, scene, cfg, opt);
  return j.success ? "success" : j.reason.substr(0, j.reason.find(' '));
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
  const sim::GeneratedScene scene = make_trial_scene(kind, seed, opt, cfg, tool0_T_camera);
  out.fits = scene.truth.target_fits;

  double q0[6];
  out.wrist_view = capture_joints(scene.hand.world_T_sensor, tool0_T_camera, q0);
  task::TaskConfig tc;
  tc.use_head = opt.use_head;
  tc.use_hand = opt.use_hand;
  // What the task believes of the head's pose: off by the head error, in a direction of
  // its own (another stream of the trial's seed than the wrist's).
  constexpr uint64_t kHeadStream = 0x9E3779B97F4A7C15ull;
  tc.world_T_head =
      sim::with_calibration_error(scene.head.world_T_sensor, opt.head_error_mm, opt.head_error_deg, seed ^ kHeadStream)
          .to_pose();
  // What the task believes of the wrist sensor's mount: off by the calibration error.
  tc.tool0_T_hand =
      sim::with_calibration_error(tool0_T_camera, opt.calibration_error_mm, opt.calibration_error_deg, seed).to_pose();
  sim::SimArmConfig arm_config;
  arm_config.kinematics =
      sim::with_kinematic_error(arm_config.kinematics, opt.kinematic_error_mm, opt.kinematic_error_deg, seed);
  TrialHardware hw(scene, q0, tc.tcp_offset_m, tool0_T_camera, cfg.gripper, arm_config);
  task::GraspTask grasp_task;
  const TaskRun run = run_task(grasp_task, tc, hw, scene, planner, cfg.gripper);

  out.ticks = run.ticks;
  out.relooks = grasp_task.relooks();
  out.task_s = static_cast<double>(hw.clock.time_us()) * 1e-6;
  const PlanResult& pr = grasp_task.plan_result();
  out.plan_ms = pr.stage_us[static_cast<int>(Stage::total)] > 0 ? pr.stage_us[static_cast<int>(Stage::total)] * 1e-3
                                                                : run.plan_wall_ms;
  out.task_state = std::string(task::to_string(grasp_task.state()));
  if (grasp_task.state() == task::TaskState::failed)
    out.task_state += std::string(":") + task::to_string(grasp_task.failure());
  if (pr.status == Status::no_grasp) out.plan_reason = to_string(pr.reason);
  out.registration = to_string(pr.registration.outcome);
  if (pr.registration.outcome == RegistrationOutcome::sensor_disagreement)
    out.registration += pr.registration.left_out == SensorRole::head ? " (head left out)" : " (hand left out)";
  if (out.wrist_view && opt.use_hand) {
    // A target point seen by the hand: the truth maps it to the sensor frame, the
    // pose the planner used (and the one given: the correction undone) back to world.
    // Where the wrist camera was when it captured (the true arm's FK), or would be.
    const Pose truth =
        (hw.hand.captures() > 0 ? hw.hand.last_camera().world_T_sensor : scene.hand.world_T_sensor).to_pose();
    const Pose& used = planner.sensor_pose(SensorRole::hand);
    const Pose& c = pr.registration.correction;
    const Vec3 p = scene.truth.target_centre.cast<float>();
    const Vec3 in_sensor = truth.R.transpose() * (p - truth.t);
    const Vec3 at_used = used.apply(in_sensor);
    const Vec3 at_given = c.R.transpose() * (at_used - c.t);
    out.hand_error_used_mm = 1000.0 * static_cast<double>((at_used - p).norm());
    out.hand_error_given_mm = 1000.0 * static_cast<double>((at_given - p).norm());
  }
  give_verdict(out, pr, scene, cfg, opt, run, grasp_task.state());
  write_trial_files(kind_name + "-" + std::to_string(seed), opt, planner, pr, scene, hw);
  if (pr.status == Status::no_grasp && pr.reason == NoGraspReason::occluded && pr.look.valid) {
    const LookAdvice look = pr.look;  // pr is the planner's task's, which the next plan replaces
    out.relook = plan_after_advised_look(scene, look, opt, cfg, planner);
  }
  return out;
}

namespace {

using nlohmann::json;

//! Runs every trial: trial i is kind i % kinds, seed + i. A progress line on stderr
//! (rewritten in place on a terminal, else every 10 trials).
std::vector<SimTrial> run_trials(const SimOptions& opt, const PlannerConfig& cfg, Planner& planner) {
  const uint32_t n = opt.trials > 0 ? opt.trials : 20u * static_cast<uint32_t>(opt.kinds.size());
  std::vector<SimTrial> trials;
  trials.reserve(n);
  const bool tty = isatty(STDERR_FILENO) != 0;
  uint32_t ok = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const std::string& kind = opt.kinds[i % opt.kinds.size()];
    trials.push_back(run_sim_trial(kind, opt.seed + i, opt, cfg, planner));
    ok += trials.back().success ? 1u : 0u;
    if (opt.progress && (tty || (i + 1) % 10 == 0 || i + 1 == n)) {
      std::fprintf(stderr, "%s[%u/%u] %s-%llu %-40.40s  success so far %u/%u (%.1f%%)%s", tty ? "\r" : "", i + 1, n,
                   kind.c_str(), static_cast<unsigned long long>(opt.seed) + i, trials.back().verdict.c_str(), ok,
                   i + 1, 100.0 * ok / (i + 1), tty ? "" : "\n");
      std::fflush(stderr);
    }
  }
  if (opt.progress && tty) std::fprintf(stderr, "\n");
  return trials;
}

//! A row of the table: one kind's trials, or all of them.
struct TableRow {
  uint32_t trials = 0, success = 0, fits = 0;
  std::vector<double> plan_ms;
  std::map<std::string, uint32_t> failures;  // by the verdict's first word

  void add(const SimTrial& t) {
    ++trials;
    success += t.success ? 1u : 0u;
    fits += t.fits ? 1u : 0u;
    plan_ms.push_back(t.plan_ms);
    if (!t.success) {
      const std::string key = t.verdict.substr(0, t.verdict.find(' '));
      ++failures[key];
    }
  }
};

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

double max_of(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }

//! Prints the row on stdout and returns it as JSON.
json print_row(const std::string& name, const TableRow& r) {
  std::string fails;
  for (const auto& [k, c] : r.failures) fails += (fails.empty() ? "" : ", ") + k + " x" + std::to_string(c);
  const double rate = r.trials ? 100.0 * r.success / r.trials : 0.0;
  std::printf("%-22s %6u %5u %8u %8.1f%% %11s %9s  %s\n", name.c_str(), r.trials, r.fits, r.success, rate,
              fmt_ms(median(r.plan_ms)).c_str(), fmt_ms(max_of(r.plan_ms)).c_str(), fails.c_str());
  json f = json::object();
  for (const auto& [k, c] : r.failures) f[k] = c;
  return json{{"object", name},
              {"trials", r.trials},
              {"fits", r.fits},
              {"success", r.success},
              {"rate", r.trials ? static_cast<double>(r.success) / r.trials : 0.0},
              {"plan_ms_median", median(r.plan_ms)},
              {"plan_ms_max", max_of(r.plan_ms)},
              {"failures", f}};
}

//! The table: per kind (in the order the trials met them), then all. Printed on stdout
//! and returned as JSON.
json results_table(const std::vector<SimTrial>& trials, const SimOptions& opt) {
  std::map<std::string, TableRow> rows;
  std::vector<std::string> order;
  TableRow all;
  for (const SimTrial& t : trials) {
    if (!rows.count(t.kind)) order.push_back(t.kind);
    rows[t.kind].add(t);
    all.add(t);
  }
  json table = json::array();
  std::printf("distribution %s, seed %llu (trial i: seed + i; --distribution %s --seed %llu repeats it)\n",
              sim::distribution_name(opt.distribution), static_cast<unsigned long long>(opt.seed),
              sim::distribution_name(opt.distribution), static_cast<unsigned long long>(opt.seed));
  if (!(opt.use_head && opt.use_hand))
    std::printf("the %s sensor alone (--sensors)\n", opt.use_head ? "head" : "wrist");
  if (opt.calibration_error_mm > 0.0 || opt.calibration_error_deg > 0.0)
    std::printf("the wrist sensor's believed pose off by %g mm and %g deg in each trial\n", opt.calibration_error_mm,
                opt.calibration_error_deg);
  if (opt.head_error_mm > 0.0 || opt.head_error_deg > 0.0)
    std::printf("the head sensor's believed pose off by %g mm and %g deg in each trial\n", opt.head_error_mm,
                opt.head_error_deg);
  if (opt.kinematic_error_mm > 0.0 || opt.kinematic_error_deg > 0.0)
    std::printf("the arm's DH lengths off by up to %g mm and its joint zeros by up to %g deg in each trial\n",
                opt.kinematic_error_mm, opt.kinematic_error_deg);
  std::printf("%-22s %6s %5s %8s %9s %11s %9s  %s\n", "object", "trials", "fits", "success", "rate", "plan med ms",
              "max ms", "failures");
  for (const std::string& k : order) table.push_back(print_row(k, rows[k]));
  table.push_back(print_row("all", all));
  return table;
}

json vec_json(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }

//! The registration's outcomes, and the hand pose's error at the target as given and
//! as used (median and 90th percentile over the trials whose wrist looked from the
//! scene's viewpoint).
void print_registration(const std::vector<SimTrial>& trials) {
  std::map<std::string, uint32_t> outcomes;
  std::vector<double> given, used;
  for (const SimTrial& t : trials) {
    ++outcomes[t.registration];
    if (t.hand_error_given_mm < 0.0) continue;
    given.push_back(t.hand_error_given_mm);
    used.push_back(t.hand_error_used_mm);
  }
  std::string line;
  for (const auto& [k, c] : outcomes) line += (line.empty() ? "" : ", ") + k + " " + std::to_string(c);
  const auto pct = [](std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[static_cast<size_t>(q * static_cast<double>(v.size() - 1))];
  };
  std::printf("registration: %s\n", line.c_str());
  if (given.empty()) return;  // no trial used the wrist sensor
  std::printf("hand pose error at the target (mm), median / 90%%: given %.1f / %.1f, used %.1f / %.1f\n",
              pct(given, 0.5), pct(given, 0.9), pct(used, 0.5), pct(used, 0.9));
}

//! The refusals as occluded that advised a view, and one more plan from it.
void print_relook(const std::vector<SimTrial>& trials) {
  uint32_t advised = 0, fits_advised = 0, fits_grasped = 0, task_looked = 0, task_right = 0;
  for (const SimTrial& t : trials) {
    task_looked += t.relooks > 0 ? 1u : 0u;
    task_right += t.relooks > 0 && t.success ? 1u : 0u;
    advised += t.relook.empty() ? 0u : 1u;
    fits_advised += !t.relook.empty() && t.fits ? 1u : 0u;
    fits_grasped += t.fits && t.relook == "success" ? 1u : 0u;
  }
  if (task_looked > 0)
    std::printf("the task's wrist sensor looked again from an advised view in %u trials, %u of them right\n",
                task_looked, task_right);
  if (advised > 0)
    std::printf(
        "refused as occluded with a view advised: %u (%u fit); one more plan from that view grasped %u of "
        "those that fit\n",
        advised, fits_advised, fits_grasped);
}

//! One trial's record: its outcome and, with a grasp, the grasp and what the judge measured.
json trial_json(const SimTrial& t) {
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
         {"ticks", t.ticks},
         {"registration", t.registration}};
  if (!t.relook.empty()) r["relook"] = t.relook;
  if (t.relooks > 0) r["relooks"] = t.relooks;
  if (t.hand_error_given_mm >= 0.0)
    r["hand_error_mm"] = json{{"given", t.hand_error_given_mm}, {"used", t.hand_error_used_mm}};
  if (t.has_grasp) {
    r["grasp"] = json{{"position", vec_json(t.grasp.position)},
                      {"approach", vec_json(t.grasp.approach)},
                      {"closing", vec_json(t.grasp.closing)},
                      {"width", t.grasp.width},
                      {"beta", t.grasp.beta},
                      {"dz", t.grasp.dz},
                      {"family", static_cast<int>(t.grasp.family)}};
    r["judge"] = json{{"angle_left", t.angle_left}, {"angle_right", t.angle_right}, {"true_width", t.true_width}};
    if (t.true_width >= 0.f) {
      r["judge"]["contact_left"] = vec_json(t.contact_left);
      r["judge"]["contact_right"] = vec_json(t.contact_right);
    }
  }
  return r;
}

}  // namespace

const char* sensors_name(const SimOptions& opt) {
  return opt.use_head && opt.use_hand ? "both" : (opt.use_head ? "head" : "hand");
}

nlohmann::json run_sim(const SimOptions& opt, const PlannerConfig& cfg, Planner& planner) {
  const std::vector<SimTrial> trials = run_trials(opt, cfg, planner);
  json table = results_table(trials, opt);
  print_registration(trials);
  print_relook(trials);
  json records = json::array();
  for (const SimTrial& t : trials) records.push_back(trial_json(t));
  return json{{"distribution", sim::distribution_name(opt.distribution)},
              {"seed", opt.seed},
              {"sensors", sensors_name(opt)},
              {"calibration_error", json{{"mm", opt.calibration_error_mm}, {"deg", opt.calibration_error_deg}}},
              {"kinematic_error", json{{"mm", opt.kinematic_error_mm}, {"deg", opt.kinematic_error_deg}}},
              {"head_error", json{{"mm", opt.head_error_mm}, {"deg", opt.head_error_deg}}},
              {"trials", records},
              {"table", table}};
}

}  // namespace fg::host
