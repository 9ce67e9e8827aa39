#include "plan_command.hpp"

#include <algorithm>
#include <cmath>
#include <future>
#include <memory>
#include <new>
#include <sstream>

#include "fg/platform/platform.hpp"
#include "fg/robot/ur5.hpp"
#include "fg/robot/ur5_grasp_check.hpp"
#include "io/big_buffer.hpp"
#include "io/config_options.hpp"
#include "io/pcd.hpp"
#include "io/pcd_stream.hpp"
#include "io/ply.hpp"
#include "io/scene.hpp"
#include "io/text_parse.hpp"
#include "plan/plan_report.hpp"
#include "svg_pictures.hpp"

namespace fg::host {
namespace {
using nlohmann::json;

PlanOutcome invalid(const std::string& error) {
  PlanOutcome o;
  o.exit_code = kExitInvalid;
  o.report = json{{"status", "invalid_input"}, {"error", error}};
  return o;
}

}  // namespace

Planner& planner_instance() {
  // Default-initialised, as firmware places it (fg_api.cpp): value-initialising would
  // zero all 4 MiB first, a page fault per 4 KiB the plan may never touch. In the
  // readers' huge-page memory: the plan touches most of its 4 MiB, two page faults
  // instead of about a thousand. Never freed (one per process).
  static Planner* p = new (big_allocate(sizeof(Planner))) Planner;
  return *p;
}

bool apply_options(PlannerConfig& cfg, const std::string& config_path, const std::vector<std::string>& sets,
                   std::string& err) {
  if (!config_path.empty() && !load_config_file(cfg, config_path, err)) return false;
  for (const std::string& s : sets) {
    const size_t eq = s.find('=');
    if (eq == std::string::npos) {
      err = "--set " + s + ": expected name=value";
      return false;
    }
    if (!set_config_option(cfg, s.substr(0, eq), s.substr(eq + 1), err)) return false;
  }
  return true;
}

namespace {

//! Reads the scene, takes its gripper, applies the options and configures the planner;
//! false with err set.
[[nodiscard]] bool read_and_configure(const PlanOptions& opts, Scene& scene, PlannerConfig& cfg, std::string& err) {
  if (ReadResult r = read_scene(opts.scene_path, scene); !r.ok) {
    err = r.error;
    return false;
  }
  // --units SENSOR=UNIT over the manifest's "units".
  for (const std::string& u : opts.units) {
    const size_t eq = u.find('=');
    const std::string name = u.substr(0, eq), unit = eq == std::string::npos ? "" : u.substr(eq + 1);
    double m = 1.0;
    if (eq == std::string::npos || !units_by_name(unit, m)) {
      err = "command line: --units " + text::printable(u) + ": expected SENSOR=UNIT, UNIT m, cm or mm";
      return false;
    }
    bool found = false;
    for (SceneSensor& s : scene.sensors)
      if (s.name == name) s.units_m = m, found = true;
    if (!found) {
      err =
          "command line: --units " + text::printable(u) + ": the scene has no sensor \"" + text::printable(name) + "\"";
      return false;
    }
  }
  cfg.gripper.max_opening_m = static_cast<float>(scene.gripper.max_opening);
  cfg.gripper.finger_width_m = static_cast<float>(scene.gripper.finger_width);
  cfg.gripper.finger_depth_m = static_cast<float>(scene.gripper.finger_depth);
  if (!apply_options(cfg, opts.config_path, opts.sets, err)) return false;
  const char* field = nullptr;
  if (planner_instance().configure(cfg, &field) != Status::ok) {
    err = std::string("configuration value out of range: ") + (field ? field : "?");
    return false;
  }
  return true;
}

//! A sensor's world pose: given, or the arm's joints through the UR5's forward
//! kinematics and the hand-eye transform; false when the joints are not finite.
[[nodiscard]] bool sensor_pose(const SceneSensor& s, Pose& pose) {
  if (s.pose) {
    pose = to_pose(*s.pose);
    return true;
  }
  float q[6];
  for (int j = 0; j < 6; ++j) q[j] = static_cast<float>((*s.joints)[j]);
  Pose tool0;
  if (!robot::ur5_forward(robot::ur5_nominal(), q, tool0)) return false;
  const Pose he = s.hand_eye ? to_pose(*s.hand_eye) : robot::default_hand_eye();
  pose.R = tool0.R * he.R;
  pose.t = tool0.R * he.t + tool0.t;
  return true;
}

SensorRole role_of(const SceneSensor& s) { return s.name == "head" ? SensorRole::head : SensorRole::hand; }

//! Adds one decoded cloud to the planner: "" or the error.
[[nodiscard]] std::string add_cloud(Planner& planner, const SceneSensor& s, const PointCloud& c, const Pose& pose) {
  const uint64_t points = c.size();  // (a size_t of 32 bits cannot exceed the bound)
  if (points > 0xFFFFFFFFull) return s.cloud_path + ": too many points";
  const uint32_t n = static_cast<uint32_t>(c.size());
  const Status st = c.planar() ? planner.add_points_planar(role_of(s), c.planar_array(0), c.planar_array(1),
                                                           c.planar_array(2), n, pose)
                               : planner.add_points(role_of(s), c.xyz.data(), n, 3 * sizeof(float), pose);
  if (st != Status::ok) return s.cloud_path + ": " + planner.last_message() + " (" + to_string(st) + ")";
  return std::string();
}

//! Streams one DATA binary cloud into the planner. False on a file error (err set);
//! true otherwise, with the planner's own error, if any, in add_error.
[[nodiscard]] bool stream_cloud(Planner& planner, const SceneSensor& s, PcdStream& stream, const Pose& pose,
                                std::string& add_error, std::string& err) {
  const Status st = planner.add_point_source(role_of(s), stream, pose);
  if (!stream.error().empty()) {
    err = stream.error();
    return false;
  }
  if (st != Status::ok) add_error = s.cloud_path + ": " + planner.last_message() + " (" + to_string(st) + ")";
  return true;
}

//! Reads every sensor's cloud and adds it to the planner; false with err set. t_plan:
//! when the last cloud was read (the end of process_read).
//!
//! A DATA binary cloud of float coordinates goes from the file into the planner in
//! bounded chunks (PcdStream): its reading is part of the ingest. Every other cloud is
//! decoded whole on a thread of its own, all at once, and added as soon as it and the
//! clouds before it are in: the first cloud's ingest overlaps the decoding of the
//! next. The outcome is the one of reading every cloud first: a file or pose error of
//! any sensor is reported before an error the planner gave for an earlier sensor's
//! points (which then waits in add_error).
[[nodiscard]] bool read_and_add_clouds(const PlanOptions& opts, const Scene& scene, Planner& planner,
                                       uint64_t t_process, uint64_t& t_plan, std::string& err) {
  const size_t n_sensors = scene.sensors.size();
  std::vector<PointCloud> clouds(n_sensors);
  std::vector<PcdStream> streams(n_sensors);
  std::vector<uint64_t> read_done_us(n_sensors, t_process);
  std::vector<std::future<ReadResult>> reads(n_sensors);
  std::vector<uint8_t> streamed(n_sensors, 0);
  for (size_t i = 0; i < n_sensors; ++i) {
    streamed[i] = streams[i].open(scene.sensors[i].cloud_path) ? 1 : 0;
    if (streamed[i]) continue;
    reads[i] = std::async(std::launch::async, [&clouds, &read_done_us, &scene, i] {
      ReadLimits limits;
      limits.planar = true;  // binary_compressed x, y, z go to the planner as decompressed
      ReadResult r = read_cloud(scene.sensors[i].cloud_path, clouds[i], limits);
      read_done_us[i] = platform::monotonic_us();
      return r;
    });
  }
  // Every thread is joined before `clouds` goes out of scope, whichever way we leave.
  struct JoinAll {
    std::vector<std::future<ReadResult>>& f;
    ~JoinAll() {
      for (auto& r : f)
        if (r.valid()) r.wait();
    }
  } join_all{reads};
  std::string add_error;
  // The head first, whatever the scene's order (head_first).
  for (const size_t i :
       head_first(n_sensors, [&scene](size_t k) { return role_of(scene.sensors[k]) == SensorRole::head; })) {
    const SceneSensor& s = scene.sensors[i];
    if (!streamed[i]) {
      if (ReadResult r = reads[i].get(); !r.ok) {
        err = r.error;
        return false;
      }
    }
    Pose pose;
    if (!sensor_pose(s, pose)) {
      err = opts.scene_path + ": sensor \"" + s.name + "\" joints are not finite";
      return false;
    }
    if (!add_error.empty()) continue;  // only the later sensors' file errors matter now
    if (planner.set_sensor_units(role_of(s), static_cast<float>(s.units_m)) != Status::ok) {
      err = opts.scene_path + ": sensor \"" + s.name + "\": " + planner.last_message();
      return false;
    }
    if (streamed[i]) {  // read while ingested
      if (!stream_cloud(planner, s, streams[i], pose, add_error, err)) return false;
      read_done_us[i] = platform::monotonic_us();
      continue;
    }
    add_error = add_cloud(planner, s, clouds[i], pose);
    clouds[i] = PointCloud{};  // its memory is no longer needed
  }
  if (!add_error.empty()) {
    err = add_error;
    return false;
  }
  // process_read ends when the last cloud is read; process_plan is the rest, with
  // whatever ingest of earlier clouds was still running then.
  t_plan = t_process;
  for (uint64_t t : read_done_us) t_plan = std::max(t_plan, t);
  return true;
}

//! `n` comma-separated finite numbers; false when the text is anything else.
[[nodiscard]] bool parse_numbers(const std::string& text, float* out, size_t n) {
  size_t k = 0, from = 0;
  for (; k < n; ++k) {
    const size_t comma = text.find(',', from);
    const bool last = k + 1 == n;
    if (last != (comma == std::string::npos)) return false;  // too few or too many
    const std::string_view part = std::string_view(text).substr(from, last ? std::string::npos : comma - from);
    double v = 0.0;
    if (!text::parse_real(text::trim(part), v) || !std::isfinite(v) || std::fabs(v) > 1e6) return false;
    out[k] = static_cast<float>(v);
    from = comma + 1;
  }
  return true;
}

//! The whole command, which may throw.
PlanOutcome plan_scene(const PlanOptions& opts) {
  const uint64_t t_process = platform::monotonic_us();
  PlannerConfig cfg;
  Scene scene;
  std::string err;
  TargetSpec target;
  if (!parse_target(opts, target, err)) return invalid("command line: " + err);
  if (!read_and_configure(opts, scene, cfg, err)) return invalid(err);
  Planner& planner = planner_instance();
  if (planner.set_target(target) != Status::ok) return invalid(planner.last_message());
  planner.set_registration(opts.registration);
  uint64_t t_plan = t_process;
  if (!read_and_add_clouds(opts, scene, planner, t_process, t_plan, err)) return invalid(err);
  robot::GraspCheckConfig check_cfg;
  const double* joints = nullptr;
  for (const SceneSensor& s : scene.sensors)
    if (s.joints) joints = s.joints->data();
  static robot::Ur5GraspCheck check;  // one per process, like the planner
  set_up_robot_check(check, cfg, joints, check_cfg);
  PlanResult res;
  json report;
  std::vector<Grasp> alternates;
  const Status st = plan_target(planner, cfg, check, check_cfg, opts.top, res, report, &alternates);

  PlanOutcome o;
  if (st == Status::ok) {
    o.exit_code = kExitOk;
  } else if (st == Status::no_grasp) {
    o.exit_code = kExitNoGrasp;
  } else if (st == Status::internal_error || st == Status::numeric_failure) {
    o.exit_code = kExitInternal;
  } else {
    return invalid(opts.scene_path + ": " + res.message + " (" + to_string(st) + ")");
  }
  json& j = o.report;
  j = std::move(report);
  if (st == Status::internal_error || st == Status::numeric_failure)  // plan_target reports ok and no_grasp
    j = plan_report(planner, res, st, cfg, check_cfg, check);
  const uint64_t t_done = platform::monotonic_us();
  j["timing_us"]["process_plan"] = t_done - t_plan;
  j["timing_us"]["process_read"] = t_plan - t_process;
  if (!opts.pictures_dir.empty()) {
    std::string perr;
    if (!write_pictures(planner, res, opts.pictures_dir, perr, alternates))
      j["pictures_error"] = perr;
    else
      j["pictures"] = opts.pictures_dir;
  }
  // After the pictures, which show the target's search: each object's plan replaces it.
  if (opts.all_objects) add_objects(j, planner, cfg, check, check_cfg, opts.top);
  return o;
}

}  // namespace

bool parse_target(const PlanOptions& opts, TargetSpec& target, std::string& err) {
  target = TargetSpec{};
  float v[6];
  if (!opts.target.empty() && !opts.target_box.empty()) {
    err = "--target and --target-box: give one of them";
    return false;
  }
  if (!opts.target.empty()) {
    if (!parse_numbers(opts.target, v, 3)) {
      err = "--target: expected x,y,z (three finite numbers, metres, world frame), got \"" +
            text::printable(opts.target) + "\"";
      return false;
    }
    target.kind = TargetKind::nearest_point;
    target.point = Vec3(v[0], v[1], v[2]);
  } else if (!opts.target_box.empty()) {
    if (!parse_numbers(opts.target_box, v, 6)) {
      err = "--target-box: expected xmin,ymin,zmin,xmax,ymax,zmax (six finite numbers, metres, world frame), got \"" +
            text::printable(opts.target_box) + "\"";
      return false;
    }
    target.kind = TargetKind::inside_box;
    target.box_min = Vec3(v[0], v[1], v[2]);
    target.box_max = Vec3(v[3], v[4], v[5]);
  }
  const char* why = "";
  if (validate(target, &why) != Status::ok) {
    err = std::string(opts.target.empty() ? "--target-box: " : "--target: ") + why;
    return false;
  }
  return true;
}

PlanOutcome run_plan(const PlanOptions& opts) {
  try {
    return plan_scene(opts);
  } catch (const std::exception& e) {
    PlanOutcome o;
    o.exit_code = kExitInternal;
    o.report = json{{"status", "internal_error"}, {"error", e.what()}};
    return o;
  }
}

std::string human_summary(const json& r) {
  std::ostringstream os;
  os.setf(std::ios::fixed);
  os.precision(3);
  const std::string status = r.value("status", "?");
  if (status == "ok") {
    const json& g = r["grasp"];
    auto v3 = [&](const char* k) {
      std::ostringstream s;
      s.setf(std::ios::fixed);
      s.precision(3);
      s << "(" << g[k][0].get<double>() << ", " << g[k][1].get<double>() << ", " << g[k][2].get<double>() << ")";
      return s.str();
    };
    os << "grasp found\n  position " << v3("position") << " m\n  approach " << v3("approach") << "\n  closing  "
       << v3("closing") << "\n  width    " << g["width"].get<double>() * 1000.0 << " mm\n  beta     "
       << g["beta"].get<double>() << " rad, dz " << g["dz"].get<double>() * 1000.0 << " mm, viewpoint "
       << g["viewpoint"].get<double>() << " rad (" << g["family"].get<std::string>() << ")\n";
  } else if (status == "no_grasp") {
    os << "no grasp: " << r.value("reason", "") << " - " << r.value("message", "") << "\n";
  } else {
    os << status << ": " << r.value("error", "") << "\n";
  }
  if (r.contains("points")) {
    const json& p = r["points"];
    os << "  points   " << p["input"] << " input, " << p["after_filter"] << " after filters, " << p["voxels"]
       << " voxels, " << p["object"] << " on the object\n";
  }
  if (r.contains("crop") && r["crop"].value("shrinks", 0) > 0) {
    const json& c = r["crop"];
    os << "  crop     shrunk to x " << c["min"][0].get<double>() << ".." << c["max"][0].get<double>() << ", y "
       << c["min"][1].get<double>() << ".." << c["max"][1].get<double>() << " m (too many voxels; "
       << c["points_dropped"] << " points dropped)\n";
  }
  if (r.contains("timing_us")) os << "  time     " << r["timing_us"]["total"] << " us in the planner\n";
  if (r.contains("pictures")) os << "  pictures " << r["pictures"].get<std::string>() << "\n";
  return os.str();
}

}  // namespace fg::host
