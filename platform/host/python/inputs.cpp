#include "inputs.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "fg/core/types.hpp"
#include "io/config_options.hpp"
#include "io/scene.hpp"
#include "io/text_parse.hpp"

namespace fg::python {
namespace {

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

std::string dtype_text(const py::array& a) { return py::str(a.dtype()).cast<std::string>(); }

std::string type_text(const py::handle& v) { return py::str(py::type::of(v).attr("__name__")).cast<std::string>(); }

//! obj as a numpy array: itself, or what numpy.asarray makes of a sequence.
py::array as_array(const std::string& what, const py::handle& obj) {
  if (py::isinstance<py::array>(obj)) return py::reinterpret_borrow<py::array>(obj);
  py::array a = py::array::ensure(obj);
  if (!a) throw py::type_error(what + " must be a numpy array, not " + type_text(obj));
  return a;
}

//! v as a real number (a bool or a string is none); false when it is not one.
[[nodiscard]] bool real_number(const py::handle& v, double& out) {
  if (py::isinstance<py::bool_>(v) || py::isinstance<py::str>(v)) return false;
  out = PyFloat_AsDouble(v.ptr());
  if (out == -1.0 && PyErr_Occurred()) {
    PyErr_Clear();
    return false;
  }
  return true;
}

//! A 4x4 world_T_sensor, refused as the planner would refuse it (fg::validate_pose on
//! the same float pose), and when its last row is not 0 0 0 1.
Pose read_pose(const std::string& what, const py::handle& obj) {
  const py::array a = as_array(what + " pose", obj);
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw py::type_error(what + " pose must be a 4x4 array of numbers, not of " + dtype_text(a));
  if (a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4)
    throw py::value_error(what + " pose must have shape (4, 4), not " + shape_text(a));
  const auto m = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  const double* v = m.data();
  for (int i = 0; i < 16; ++i)
    if (!std::isfinite(v[i])) throw py::value_error("non_finite: " + what + " pose has a NaN or Inf value");
  if (std::fabs(v[12]) > 1e-6 || std::fabs(v[13]) > 1e-6 || std::fabs(v[14]) > 1e-6 || std::fabs(v[15] - 1.0) > 1e-6)
    throw py::value_error("invalid_pose: " + what + " pose's last row is not [0, 0, 0, 1]");
  Pose p;  // as the scene reader's to_pose: each double to the nearest float
  for (int i = 0; i < 3; ++i) {
    p.t(i) = static_cast<float>(v[4 * i + 3]);
    for (int j = 0; j < 3; ++j) p.R(i, j) = static_cast<float>(v[4 * i + j]);
  }
  const char* why = "";
  if (const Status s = validate_pose(p, &why); s != Status::ok) {
    // The core's "sensor pose ..." with the sensor named.
    const std::string text = why;
    const std::string subject = "sensor ";
    throw py::value_error(host::text::cat(to_string(s), ": ", what, " ",
                                          text.rfind(subject, 0) == 0 ? text.substr(subject.size()) : text));
  }
  return p;
}

//! The byte stride at which the planner can read the points in place: float32 in host
//! byte order, a point's x y z side by side, the points evenly spaced (the rows of an
//! organized cloud too) and at least three floats apart. 0 when it cannot.
py::ssize_t in_place_stride(const py::array& a) {
  if (!py::array_t<float>::check_(a) || a.strides(a.ndim() - 1) != 4) return 0;
  py::ssize_t stride = 12;  // a single point
  if (a.ndim() == 2) {
    if (a.shape(0) > 1) stride = a.strides(0);
  } else {
    const py::ssize_t rows = a.shape(0), cols = a.shape(1);
    if (rows > 1 && cols > 1) {
      if (a.strides(0) != cols * a.strides(1)) return 0;
      stride = a.strides(1);
    } else if (cols > 1) {
      stride = a.strides(1);
    } else if (rows > 1) {
      stride = a.strides(0);
    }
  }
  return stride >= 12 && stride <= 0xFFFFFFFF ? stride : 0;
}

void read_points(SensorInput& in, const std::string& what, const py::handle& obj) {
  const py::array a = as_array(what + " points", obj);
  if (a.dtype().kind() != 'f' || (a.itemsize() != 4 && a.itemsize() != 8))
    throw py::type_error(what + " points must be float32 or float64, not " + dtype_text(a));
  if ((a.ndim() != 2 && a.ndim() != 3) || a.shape(a.ndim() - 1) != 3)
    throw py::value_error(what + " points must have shape (N, 3) or (H, W, 3), not " + shape_text(a));
  const py::ssize_t n = a.size() / 3;
  if (n == 0) throw py::value_error(what + " points are empty (shape " + shape_text(a) + ")");
  if (n > 0xFFFFFFFF) throw py::value_error("capacity_exceeded: " + what + " has more than 2^32 - 1 points");
  in.count = static_cast<uint32_t>(n);
  if (const py::ssize_t stride = in_place_stride(a)) {
    in.held = a;
    in.stride = static_cast<uint32_t>(stride);
  } else {  // float64, or float32 laid out otherwise: one conversion into packed x y z
    in.held = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
    if (!in.held) throw py::type_error(what + " points cannot be converted to float32");
    in.stride = 3 * sizeof(float);
  }
  in.xyz = static_cast<const float*>(in.held.data());
}

PinholeIntrinsics read_intrinsics(const std::string& what, const py::handle& obj) {
  const std::string name = what + " depth intrinsics";
  if (obj.is_none())
    throw py::value_error("invalid_argument: " + what + " depth needs \"intrinsics\": (fx, fy, cx, cy)");
  if (!py::isinstance<py::sequence>(obj) || py::isinstance<py::str>(obj) || py::len(obj) != 4)
    throw py::type_error(name + " must be four numbers (fx, fy, cx, cy) in pixels");
  const py::sequence seq = py::reinterpret_borrow<py::sequence>(obj);
  double v[4];
  for (size_t i = 0; i < 4; ++i)
    if (!real_number(seq[i], v[i])) throw py::type_error(name + " must be four numbers (fx, fy, cx, cy) in pixels");
  PinholeIntrinsics k;
  k.fx = static_cast<float>(v[0]);
  k.fy = static_cast<float>(v[1]);
  k.cx = static_cast<float>(v[2]);
  k.cy = static_cast<float>(v[3]);
  // The core's own bounds (Planner::add_depth_image), checked here to name the sensor.
  if (!(std::isfinite(k.fx) && std::isfinite(k.fy) && std::isfinite(k.cx) && std::isfinite(k.cy)))
    throw py::value_error("non_finite: " + name + " have a NaN or Inf value");
  if (!(k.fx > 1.f && k.fy > 1.f && k.fx < 1e5f && k.fy < 1e5f) || std::fabs(k.cx) > 1e5f || std::fabs(k.cy) > 1e5f)
    throw py::value_error("invalid_argument: " + name + " are out of range (focal length must be 1..1e5 px)");
  return k;
}

void read_depth(SensorInput& in, const std::string& what, const py::handle& obj, const py::handle& intrinsics) {
  const py::array a = as_array(what + " depth", obj);
  if (a.dtype().kind() != 'u' || a.itemsize() != 2)
    throw py::type_error(what + " depth must be uint16 millimetres, not " + dtype_text(a));
  if (a.ndim() != 2) throw py::value_error(what + " depth must have shape (H, W), not " + shape_text(a));
  if (a.size() == 0) throw py::value_error(what + " depth is empty (shape " + shape_text(a) + ")");
  if (a.shape(0) > 0xFFFF || a.shape(1) > 0xFFFF)
    throw py::value_error(what + " depth is larger than 65535 pixels a side (shape " + shape_text(a) + ")");
  in.intrinsics = read_intrinsics(what, intrinsics);
  // Rows as the planner reads them: the caller's array, or a contiguous copy of it.
  in.held = py::array_t<uint16_t, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!in.held) throw py::type_error(what + " depth cannot be converted to uint16");
  in.depth = static_cast<const uint16_t*>(in.held.data());
  in.height = static_cast<uint16_t>(a.shape(0));
  in.width = static_cast<uint16_t>(a.shape(1));
}

void read_sensor_dict(SensorInput& in, const std::string& what, const py::dict& d) {
  py::handle points, depth, pose, intrinsics = py::none(), units = py::none();
  for (const auto& item : d) {
    const std::string key = py::str(item.first).cast<std::string>();
    if (key == "points")
      points = item.second;
    else if (key == "depth")
      depth = item.second;
    else if (key == "pose")
      pose = item.second;
    else if (key == "intrinsics")
      intrinsics = item.second;
    else if (key == "units")
      units = item.second;
    else
      throw py::value_error(
          host::text::cat(what, ": unknown key \"", key, "\" (points or depth, pose, intrinsics, units)"));
  }
  if (!units.is_none()) {
    double m = 1.0;
    if (!py::isinstance<py::str>(units) || !host::units_by_name(units.cast<std::string>(), m))
      throw py::value_error(what + ": units must be \"m\", \"cm\" or \"mm\", not " +
                            py::repr(units).cast<std::string>());
    if (depth) throw py::value_error(what + ": a depth image is in millimetres; \"units\" belong to points");
    in.units_m = static_cast<float>(m);
  }
  if (!pose) throw py::value_error(what + ": no \"pose\" (the 4x4 world_T_sensor)");
  if (bool(points) == bool(depth)) throw py::value_error(what + ": give \"points\" or \"depth\", one of them");
  in.pose = read_pose(what, pose);
  if (points) {
    if (!intrinsics.is_none()) throw py::value_error(what + ": \"intrinsics\" belong to a depth image, not to points");
    read_points(in, what, points);
  } else {
    read_depth(in, what, depth, intrinsics);
  }
}

}  // namespace

const char* role_name(SensorRole role) { return role == SensorRole::head ? "head" : "hand"; }

SensorInput read_sensor(SensorRole role, const py::handle& spec) {
  SensorInput in;
  in.role = role;
  const std::string what = role_name(role);
  if (py::isinstance<py::dict>(spec)) {
    read_sensor_dict(in, what, py::reinterpret_borrow<py::dict>(spec));
  } else if (py::isinstance<py::tuple>(spec) || py::isinstance<py::list>(spec)) {
    const py::sequence seq = py::reinterpret_borrow<py::sequence>(spec);
    if (py::len(seq) != 2)
      throw py::value_error(what + " must be (points, pose), not " + std::to_string(py::len(seq)) + " items");
    in.pose = read_pose(what, seq[1]);
    read_points(in, what, seq[0]);
  } else {
    throw py::type_error(what +
                         " must be a (points, pose) tuple or a dict with \"points\" or \"depth\" and \"pose\", not " +
                         type_text(spec));
  }
  return in;
}

std::array<double, 6> read_joints(const py::handle& joints) {
  const py::array a = as_array("joints", joints);
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u') throw py::type_error("joints must be numbers, not " + dtype_text(a));
  if (a.ndim() != 1 || a.shape(0) != 6)
    throw py::value_error("joints must be 6 angles (UR5, radians, URDF order), not shape " + shape_text(a));
  const auto q = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  std::array<double, 6> out{};
  for (size_t j = 0; j < 6; ++j) {
    out[j] = q.data()[j];
    if (!std::isfinite(out[j])) throw py::value_error("non_finite: joints have a NaN or Inf value");
  }
  return out;
}

namespace {
//! `n` finite numbers from a sequence or array named `name` (its meaning in `what`).
void read_numbers(const char* name, const py::handle& obj, size_t n, const char* what, float* out) {
  const py::array a = as_array(name, obj);
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw py::type_error(std::string(name) + " must be numbers, not " + dtype_text(a));
  if (a.ndim() != 1 || a.shape(0) != static_cast<py::ssize_t>(n))
    throw py::value_error(std::string("invalid_argument: ") + name + " must be " + what + ", not shape " +
                          shape_text(a));
  const auto v = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  for (size_t j = 0; j < n; ++j) {
    if (!std::isfinite(v.data()[j]) || std::fabs(v.data()[j]) > 1e6)
      throw py::value_error(std::string("non_finite: ") + name + " has a NaN, Inf or absurd value");
    out[j] = static_cast<float>(v.data()[j]);
  }
}
}  // namespace

TargetSpec read_target(const py::handle& target, const py::handle& target_box) {
  TargetSpec t;
  if (!target.is_none() && !target_box.is_none())
    throw py::value_error("invalid_argument: give target or target_box, not both");
  float v[6];
  if (!target.is_none()) {
    read_numbers("target", target, 3, "3 numbers (x, y, z; metres, world frame)", v);
    t.kind = TargetKind::nearest_point;
    t.point = Vec3(v[0], v[1], v[2]);
  } else if (!target_box.is_none()) {
    read_numbers("target_box", target_box, 6, "6 numbers (xmin, ymin, zmin, xmax, ymax, zmax; metres, world frame)", v);
    t.kind = TargetKind::inside_box;
    t.box_min = Vec3(v[0], v[1], v[2]);
    t.box_max = Vec3(v[3], v[4], v[5]);
  }
  const char* why = "";
  const Status s = validate(t, &why);
  if (s != Status::ok) throw py::value_error(std::string(to_string(s)) + ": " + why);
  return t;
}

void apply_gripper(PlannerConfig& cfg, const py::handle& gripper) {
  host::SceneGripper g;  // the scene file's defaults and ranges, as `forcegrasp plan` applies them
  if (!gripper.is_none()) {
    if (!py::isinstance<py::dict>(gripper)) throw py::type_error("gripper must be a dict, not " + type_text(gripper));
    for (const auto& item : py::reinterpret_borrow<py::dict>(gripper)) {
      const std::string key = py::str(item.first).cast<std::string>();
      double x = 0;
      std::string err;
      if (!real_number(item.second, x)) x = std::numeric_limits<double>::quiet_NaN();  // named below
      if (!host::set_gripper_value(g, key, x, err)) throw py::value_error(err);
    }
  }
  cfg.gripper.max_opening_m = static_cast<float>(g.max_opening);
  cfg.gripper.finger_width_m = static_cast<float>(g.finger_width);
  cfg.gripper.finger_depth_m = static_cast<float>(g.finger_depth);
}

namespace {
//! An option's value as the text --set would give it: numbers in Python's shortest
//! round-trip form, booleans as true/false, strings as they are.
std::string option_text(const std::string& name, const py::handle& v) {
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>() ? "true" : "false";
  if (py::hasattr(v, "dtype") && py::str(v.attr("dtype").attr("kind")).cast<std::string>() == "b")
    return v.cast<bool>() ? "true" : "false";  // numpy.bool_
  if (py::isinstance<py::str>(v)) return v.cast<std::string>();
  if (PyIndex_Check(v.ptr())) return py::str(py::int_(py::reinterpret_borrow<py::object>(v))).cast<std::string>();
  double x = 0;
  if (real_number(v, x)) return py::repr(py::float_(x)).cast<std::string>();
  throw py::value_error("option " + name + " must be a number, boolean or string, not " + type_text(v));
}
}  // namespace

void apply_config(PlannerConfig& cfg, const py::handle& config) {
  if (config.is_none()) return;
  if (!py::isinstance<py::dict>(config)) throw py::type_error("config must be a dict, not " + type_text(config));
  for (const auto& item : py::reinterpret_borrow<py::dict>(config)) {
    if (!py::isinstance<py::str>(item.first))
      throw py::value_error("config keys are option names (str), not " + type_text(item.first));
    const std::string name = item.first.cast<std::string>();
    std::string error;
    if (!host::set_config_option(cfg, name, option_text(name, item.second), error)) throw py::value_error(error);
  }
}

}  // namespace fg::python
