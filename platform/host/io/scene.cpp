// Host-only scene manifest reader/writer (spec/scene-and-cli.md).
#include "scene.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <utility>

#include "text_parse.hpp"

namespace fg::host {

Pose to_pose(const PoseD& p) {
  Pose out;
  for (int i = 0; i < 3; ++i) {
    out.t(i) = static_cast<float>(p.position[i]);
    for (int j = 0; j < 3; ++j) out.R(i, j) = static_cast<float>(p.rotation[i][j]);
  }
  return out;
}

namespace {
using nlohmann::json;
using text::cat;
using text::fail;

constexpr size_t kMaxManifestBytes = 1u << 20;  // a manifest is a few hundred bytes
constexpr int kMaxNesting = 32;
constexpr size_t kMaxSensors = 8;  // more is never a valid scene; keeps errors short

std::string dir_of(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

// Depth of [ and { outside strings: rejects absurd nesting before parsing.
int max_nesting(const std::string& s) {
  int depth = 0, worst = 0;
  bool in_str = false, esc = false;
  for (char ch : s) {
    if (in_str) {
      if (esc)
        esc = false;
      else if (ch == '\\')
        esc = true;
      else if (ch == '"')
        in_str = false;
      continue;
    }
    if (ch == '"')
      in_str = true;
    else if (ch == '[' || ch == '{')
      worst = std::max(worst, ++depth);
    else if (ch == ']' || ch == '}')
      --depth;
  }
  return worst;
}

struct Ctx {
  std::string file;
  std::string err;
  [[nodiscard]] bool fail(const std::string& what) {
    if (err.empty()) err = file + ": " + what;
    return false;
  }
};

[[nodiscard]] bool finite_number(const json& v, double& out) {
  if (!v.is_number()) return false;
  out = v.get<double>();
  return std::isfinite(out);
}

[[nodiscard]] bool read_vec(const json& v, size_t n, double* out, Ctx& c, const std::string& what) {
  if (!v.is_array() || v.size() != n) return c.fail(what + " must be an array of " + std::to_string(n) + " numbers");
  for (size_t i = 0; i < n; ++i)
    if (!finite_number(v[i], out[i]))
      return c.fail(what + " has a value that is not a finite number (NaN, Inf or not a number)");
  return true;
}

[[nodiscard]] bool read_pose(const json& v, PoseD& p, Ctx& c, const std::string& what) {
  if (!v.is_object()) return c.fail(what + " must be an object with position and rotation");
  if (!v.contains("position")) return c.fail(what + " has no position");
  if (!v.contains("rotation")) return c.fail(what + " has no rotation");
  if (!read_vec(v["position"], 3, p.position.data(), c, what + ".position")) return false;
  const json& r = v["rotation"];
  if (!r.is_array() || r.size() != 3) return c.fail(what + ".rotation must be 3 rows of 3 numbers");
  for (size_t i = 0; i < 3; ++i)
    if (!read_vec(r[i], 3, p.rotation[i].data(), c, what + ".rotation row " + std::to_string(i))) return false;
  double worst = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double dot = 0;
      for (int k = 0; k < 3; ++k) dot += p.rotation[k][i] * p.rotation[k][j];
      worst = std::max(worst, std::fabs(dot - (i == j ? 1.0 : 0.0)));
    }
  if (worst > 1e-3)
    return c.fail(what + ".rotation is not orthonormal (R^T R differs from identity by " + std::to_string(worst) + ")");
  const auto& R = p.rotation;
  const double det = R[0][0] * (R[1][1] * R[2][2] - R[1][2] * R[2][1]) -
                     R[0][1] * (R[1][0] * R[2][2] - R[1][2] * R[2][0]) +
                     R[0][2] * (R[1][0] * R[2][1] - R[1][1] * R[2][0]);
  if (det < 0) return c.fail(what + ".rotation is a reflection (determinant -1)");
  for (double x : p.position)
    if (std::fabs(x) > 100.0) return c.fail(what + ".position is more than 100 m from the robot");
  return true;
}

[[nodiscard]] bool read_gripper(const json& v, SceneGripper& g, Ctx& c) {
  if (!v.is_object()) return c.fail("gripper must be an object");
  for (const char* name : {"max_opening", "finger_width", "finger_depth"}) {
    if (!v.contains(name)) continue;
    double x = 0;
    if (!finite_number(v[name], x)) return c.fail(std::string("gripper.") + name + " must be a finite number");
    std::string err;
    if (!set_gripper_value(g, name, x, err)) return c.fail(err);
  }
  return true;
}

//! The manifest's text as JSON: bounded in size and nesting before it is parsed.
[[nodiscard]] ReadResult parse_json(const std::string& text, const std::string& manifest_path, json& root) {
  if (text.size() > kMaxManifestBytes) return fail(manifest_path, "manifest is larger than 1 MiB");
  if (max_nesting(text) > kMaxNesting)
    return fail(manifest_path, "JSON nesting deeper than " + std::to_string(kMaxNesting) + " levels");
  try {
    root = json::parse(text);
  } catch (const json::exception& e) {
    return fail(manifest_path, cat("invalid JSON: ", e.what()));
  }
  return {};
}

//! A sensor's "pose", or its "joints" with an optional "hand_eye"; `sw` names the
//! sensor in messages.
[[nodiscard]] ReadResult read_sensor_pose(const json& s, const std::string& sw, Ctx& c, SceneSensor& ss) {
  if (s.contains("pose")) {
    PoseD p;
    if (!read_pose(s["pose"], p, c, sw + " pose")) return ReadResult::failure(c.err);
    ss.pose = p;
  } else if (s.contains("joints")) {
    std::array<double, 6> q{};
    if (!read_vec(s["joints"], 6, q.data(), c, sw + " joints")) return ReadResult::failure(c.err);
    ss.joints = q;
    if (s.contains("hand_eye")) {
      PoseD he;
      if (!read_pose(s["hand_eye"], he, c, sw + " hand_eye")) return ReadResult::failure(c.err);
      ss.hand_eye = he;
    }
  } else {
    return fail(c.file, cat(sw, " has neither \"pose\" nor \"joints\""));
  }
  return {};
}

//! Entry i of "sensors": a name (head or hand, not taken by an earlier entry), a cloud
//! file (resolved against the manifest's folder `base`) and a pose.
[[nodiscard]] ReadResult read_sensor(const json& s, size_t i, const std::string& base,
                                     const std::vector<SceneSensor>& earlier, Ctx& c, SceneSensor& ss) {
  const std::string& manifest_path = c.file;
  const std::string where = cat("sensors[", std::to_string(i), "]");
  if (!s.is_object()) return fail(manifest_path, cat(where, " must be an object"));
  if (!s.contains("name") || !s["name"].is_string()) return fail(manifest_path, cat(where, " has no name string"));
  ss.name = s["name"].get<std::string>();
  if (ss.name != "head" && ss.name != "hand")
    return fail(manifest_path, cat(where, " is named \"", ss.name, "\"; sensors must be named head or hand"));
  for (const SceneSensor& prev : earlier)
    if (prev.name == ss.name) return fail(manifest_path, cat("sensor \"", ss.name, "\" appears twice"));
  const std::string sw = cat("sensor \"", ss.name, "\"");
  if (!s.contains("cloud") || !s["cloud"].is_string() || s["cloud"].get<std::string>().empty())
    return fail(manifest_path, cat(sw, " has no \"cloud\" file name"));
  const std::string cloud = s["cloud"].get<std::string>();
  if (cloud.find('\0') != std::string::npos) return fail(manifest_path, cat(sw, " cloud path has a NUL byte"));
  ss.cloud_path = (!cloud.empty() && cloud[0] == '/') ? cloud : base + cloud;
  if (s.contains("units")) {
    const json& u = s["units"];
    if (!u.is_string() || !units_by_name(u.get<std::string>(), ss.units_m))
      return fail(manifest_path, cat(sw, " units must be \"m\", \"cm\" or \"mm\""));
  }
  return read_sensor_pose(s, sw, c, ss);
}
}  // namespace

bool units_by_name(const std::string& name, double& metres_per_unit) {
  if (name == "m") {
    metres_per_unit = 1.0;
  } else if (name == "cm") {
    metres_per_unit = 0.01;
  } else if (name == "mm") {
    metres_per_unit = 0.001;
  } else {
    return false;
  }
  return true;
}

ReadResult parse_scene(const std::string& text, const std::string& manifest_path, Scene& out) {
  Ctx c{manifest_path, {}};
  out = Scene{};
  out.manifest_path = manifest_path;
  json root;
  if (ReadResult r = parse_json(text, manifest_path, root); !r.ok) return r;
  if (!root.is_object()) return fail(manifest_path, "the manifest must be a JSON object");
  if (!root.contains("sensors")) return fail(manifest_path, "no \"sensors\" array");
  const json& sensors = root["sensors"];
  if (!sensors.is_array() || sensors.empty()) return fail(manifest_path, "\"sensors\" must be a non-empty array");
  if (sensors.size() > kMaxSensors || sensors.size() > 2)
    return fail(manifest_path, std::to_string(sensors.size()) + " sensors; at most two (head and hand) are supported");
  const std::string base = dir_of(manifest_path);
  for (size_t i = 0; i < sensors.size(); ++i) {
    SceneSensor ss;
    if (ReadResult r = read_sensor(sensors[i], i, base, out.sensors, c, ss); !r.ok) return r;
    out.sensors.push_back(ss);
  }
  if (root.contains("gripper") && !read_gripper(root["gripper"], out.gripper, c)) return ReadResult::failure(c.err);
  return {};
}

bool set_gripper_value(SceneGripper& g, const std::string& key, double value, std::string& err) {
  const struct Field {
    const char* name;
    double* out;
    double lo, hi;
  } fields[] = {{"max_opening", &g.max_opening, 0.005, 0.5},
                {"finger_width", &g.finger_width, 0.002, 0.2},
                {"finger_depth", &g.finger_depth, 0.005, 0.3}};
  for (const Field& f : fields) {
    if (key != f.name) continue;
    if (!std::isfinite(value)) {
      err = "gripper." + key + " must be a finite number";
      return false;
    }
    if (value < f.lo || value > f.hi) {
      err = "gripper." + key + " = " + std::to_string(value) + " is outside " + std::to_string(f.lo) + ".." +
            std::to_string(f.hi) + " m";
      return false;
    }
    *f.out = value;
    return true;
  }
  err = "gripper: unknown key \"" + key + "\" (max_opening, finger_width, finger_depth)";
  return false;
}

ReadResult read_scene(const std::string& path, Scene& out) {
  BigBuffer<uint8_t> bytes;  // refuses directories, devices and FIFOs, bounds the size
  if (ReadResult r = read_file_bytes(path, bytes, kMaxManifestBytes); !r.ok)
    return ReadResult::failure(r.error + " (scene manifest)");
  return parse_scene(std::string(bytes.begin(), bytes.end()), path, out);
}

namespace {
json pose_json(const PoseD& p) {
  json r = json::array();
  for (const auto& row : p.rotation) r.push_back({row[0], row[1], row[2]});
  return json{{"position", {p.position[0], p.position[1], p.position[2]}}, {"rotation", r}};
}
}  // namespace

ReadResult write_scene(const std::string& path, const Scene& scene) {
  json sensors = json::array();
  const std::string base = dir_of(path);
  for (const SceneSensor& s : scene.sensors) {
    std::string cloud = s.cloud_path;
    if (!base.empty() && cloud.rfind(base, 0) == 0) cloud = cloud.substr(base.size());
    json js{{"name", s.name}, {"cloud", cloud}};
    if (s.pose) js["pose"] = pose_json(*s.pose);
    if (s.joints) js["joints"] = *s.joints;
    if (s.hand_eye) js["hand_eye"] = pose_json(*s.hand_eye);
    if (s.units_m == 0.001) js["units"] = "mm";
    if (s.units_m == 0.01) js["units"] = "cm";
    sensors.push_back(js);
  }
  json root{{"sensors", sensors},
            {"gripper",
             {{"max_opening", scene.gripper.max_opening},
              {"finger_width", scene.gripper.finger_width},
              {"finger_depth", scene.gripper.finger_depth}}}};
  std::ofstream f(path);
  if (!f) return ReadResult::failure(path + ": cannot write the scene manifest");
  f << root.dump(1) << "\n";
  if (!f) return ReadResult::failure(path + ": write failed");
  return {};
}

}  // namespace fg::host
