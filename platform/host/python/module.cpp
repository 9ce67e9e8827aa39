// The Python module `forcegrasp` (docs/python.md): the planner and the robot's check
// that `forcegrasp plan` runs, with the program's option names and its JSON report.
// Host-only: it allocates and throws, and releases the GIL while the planner works.
#include <pybind11/pybind11.h>

#include <algorithm>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <new>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "fg/core/planner.hpp"
#include "fg/robot/ur5_grasp_check.hpp"
#include "inputs.hpp"
#include "io/big_buffer.hpp"
#include "io/config_options.hpp"
#include "io/text_parse.hpp"
#include "plan/plan_report.hpp"
#include "report.hpp"

namespace fg::python {
namespace {

// The planner's 4 MiB in the readers' huge-page memory, as the program places it:
// default-initialised (value-initialising would zero it all first) and two page faults
// instead of about a thousand.
struct PlannerDelete {
  void operator()(Planner* p) const noexcept {
    p->~Planner();
    host::big_deallocate(p);
  }
};
using PlannerPtr = std::unique_ptr<Planner, PlannerDelete>;

PlannerPtr new_planner() {
  void* memory = host::big_allocate(sizeof(Planner));
  return PlannerPtr(new (memory) Planner);
}

//! A planner of its own with the robot's check of its own: two of them plan on two
//! threads at once; one of them used from two threads plans once at a time (mutex_).
class PyPlanner {
 public:
  PyPlanner(const py::object& config, const py::object& gripper)
      : planner_(new_planner()), check_(std::make_unique<robot::Ur5GraspCheck>()) {
    // The program's order: the scene's gripper, then the options.
    apply_gripper(cfg_, gripper);
    apply_config(cfg_, config);
    const char* field = nullptr;
    if (planner_->configure(cfg_, &field) != Status::ok)
      throw py::value_error(std::string("invalid_config: configuration value out of range: ") + (field ? field : "?"));
  }

  py::dict plan(const py::object& head, const py::object& hand, const py::object& joints, const py::object& top,
                const py::object& objects, const py::object& target, const py::object& target_box) {
    std::vector<SensorInput> sensors;  // head first, as in the scene files
    if (!head.is_none()) sensors.push_back(read_sensor(SensorRole::head, head));
    if (!hand.is_none()) sensors.push_back(read_sensor(SensorRole::hand, hand));
    if (sensors.empty()) throw py::value_error("no_input: plan() needs head= or hand= (a sensor's points or depth)");
    std::optional<std::array<double, 6>> q;
    if (!joints.is_none()) q = read_joints(joints);
    uint32_t n_top = 0;  // none asked: no `grasps` list, as the program without --top
    if (!top.is_none()) {
      if (!py::isinstance<py::int_>(top) || py::isinstance<py::bool_>(top))
        throw py::type_error("top must be an int (the number of ranked grasps)");
      const long long t = top.cast<long long>();
      if (t < 1 || t > static_cast<long long>(kMaxRankedGrasps))
        throw py::value_error(host::text::cat("invalid_argument: top must be 1..", std::to_string(kMaxRankedGrasps),
                                              " (FG_MAX_RANKED_GRASPS), got ", std::to_string(t)));
      n_top = static_cast<uint32_t>(t);
    }
    bool all_objects = false;
    if (!objects.is_none()) {
      if (!py::isinstance<py::str>(objects) || objects.cast<std::string>() != "all")
        throw py::value_error("invalid_argument: objects must be None or \"all\", not " +
                              py::repr(objects).cast<std::string>());
      all_objects = true;
    }
    const TargetSpec tgt = read_target(target, target_box);
    nlohmann::json report;
    std::string error;
    Status st = Status::ok;
    {
      py::gil_scoped_release no_gil;  // every Python object was read above
      st = run(sensors, q ? q->data() : nullptr, Request{n_top, all_objects, tgt}, report, error);
    }
    if (st == Status::internal_error || st == Status::numeric_failure) throw std::runtime_error(error);
    if (!error.empty()) throw py::value_error(error);
    return report_to_python(report);
  }

  py::dict config() const { return to_python(host::config_json(cfg_)).cast<py::dict>(); }

 private:
  //! What a plan() call asks beyond the sensors.
  struct Request {
    uint32_t top = 0;  // 0: no `grasps` list
    bool all_objects = false;
    TargetSpec target;
  };

  //! The plan as `forcegrasp plan` runs it, on inputs read before; no Python here.
  //! The report when the status is ok or no_grasp, else the error: the status's name
  //! and the planner's message.
  [[nodiscard]] Status run(const std::vector<SensorInput>& sensors, const double* joints, const Request& req,
                           nlohmann::json& report, std::string& error) {
    const std::lock_guard<std::mutex> lock(mutex_);
    Planner& p = *planner_;
    // Configured anew: every plan starts from the state a fresh program's has.
    Status st = p.configure(cfg_);
    if (st != Status::ok) error = std::string(to_string(st)) + ": the configuration was refused";
    if (st == Status::ok) {
      st = p.set_target(req.target);
      if (st != Status::ok) error = host::text::cat(to_string(st), ": ", p.last_message());
    }
    for (const SensorRole role : {SensorRole::head, SensorRole::hand})  // metres unless a sensor says otherwise
      if (st == Status::ok) st = p.set_sensor_units(role, 1.f);
    // The head first (head_first).
    const std::vector<size_t> order =
        host::head_first(sensors.size(), [&sensors](size_t i) { return sensors[i].role == SensorRole::head; });
    for (size_t k = 0; k < order.size() && st == Status::ok; ++k) {
      const SensorInput& s = sensors[order[k]];
      st = p.set_sensor_units(s.role, s.units_m);
      if (st == Status::ok)
        st = s.depth ? p.add_depth_image(s.role, s.depth, s.width, s.height, s.intrinsics, s.pose)
                     : p.add_points(s.role, s.xyz, s.count, s.stride, s.pose);
      if (st != Status::ok) error = host::text::cat(to_string(st), ": ", role_name(s.role), ": ", p.last_message());
    }
    if (st != Status::ok) return st;
    robot::GraspCheckConfig check_cfg;
    host::set_up_robot_check(*check_, cfg_, joints, check_cfg);
    PlanResult res;
    st = host::plan_target(p, cfg_, *check_, check_cfg, req.top, res, report);
    if (st != Status::ok && st != Status::no_grasp) {
      error = host::text::cat(to_string(st), ": ", *p.last_message() ? p.last_message() : res.message);
      return st;
    }
    if (req.all_objects) host::add_objects(report, p, cfg_, *check_, check_cfg, req.top);
    return st;
  }

  PlannerConfig cfg_;
  PlannerPtr planner_;
  std::unique_ptr<robot::Ur5GraspCheck> check_;  // 64 KiB of scratch: one per planner
  std::mutex mutex_;
};

const char* const kModuleDoc = R"(forcegrasp: force-balance grasp planning on partial point clouds.

    p = forcegrasp.Planner(config={"voxel_leaf": 0.005}, gripper={"max_opening": 0.085})
    r = p.plan(head=(xyz, world_T_head), hand=(xyz2, world_T_hand))
    r["status"], r["grasp"]["position"]

The planner and the robot's check of `forcegrasp plan`; the report is the program's
--json report as Python values. Reference: docs/python.md.)";

const char* const kPlannerDoc = R"(A grasp planner with its own workspace (4 MiB) and robot check.

config: dict of option name -> value, as `forcegrasp plan --set name=value` takes
them (forcegrasp.default_config() lists every option). gripper: dict of max_opening,
finger_width, finger_depth (m; defaults 0.085, 0.022, 0.04), applied before config.
Bad names or values raise ValueError.)";

const char* const kPlanDoc = R"(Plans a grasp on the sensors' data; returns the report as a dict.

head, hand: a sensor, as (points, pose) or {"points": points, "pose": pose} or
{"depth": depth, "intrinsics": (fx, fy, cx, cy), "pose": pose}. points: float32 or
float64, shape (N, 3) or (H, W, 3), in the sensor's optical frame (NaN: no return);
depth: uint16 (H, W) millimetres (0: no return); pose: 4x4 world_T_sensor.
joints: the arm's six current joint angles (UR5, radians, URDF order): the grasp's
reach is checked too and the report gains "joints".
top: the N best distinct grasps (1..FG_MAX_RANKED_GRASPS), best first, in the report's
"grasps" list, as `forcegrasp plan --top N` gives them.
objects: "all" plans for every object on the support plane too, each in the report's
"objects" list (centroid, box, voxels, status, grasp or reason), as --objects all.
target: (x, y, z), the target is the object nearest this world point (--target);
target_box: (xmin, ymin, zmin, xmax, ymax, zmax), the object with the most voxels in
this world box (--target-box). Neither: the object nearest the workspace centre.

The report's "status" is "ok" (with "grasp") or "no_grasp" (with "reason" and
"message"). Bad input raises TypeError or ValueError before planning; an internal
error raises RuntimeError. The GIL is released while the planner works.)";

}  // namespace
}  // namespace fg::python

PYBIND11_MODULE(forcegrasp, m) {
  namespace py = pybind11;
  using fg::python::PyPlanner;
  m.doc() = fg::python::kModuleDoc;
  m.attr("__version__") = FG_VERSION;
  py::class_<PyPlanner>(m, "Planner", fg::python::kPlannerDoc)
      .def(py::init<const py::object&, const py::object&>(), py::arg("config") = py::none(),
           py::arg("gripper") = py::none())
      .def("plan", &PyPlanner::plan, fg::python::kPlanDoc, py::kw_only(), py::arg("head") = py::none(),
           py::arg("hand") = py::none(), py::arg("joints") = py::none(), py::arg("top") = py::none(),
           py::arg("objects") = py::none(), py::arg("target") = py::none(), py::arg("target_box") = py::none())
      .def_property_readonly("config", &PyPlanner::config, "Every option's value in this planner (a dict).");
  m.def(
      "default_config", [] { return fg::python::to_python(fg::host::default_config_json()); },
      "Every planner option with its default value, as `forcegrasp config` prints them (a dict).");
}
