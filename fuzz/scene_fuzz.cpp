// Fuzz target: fg::host::parse_scene on the bytes as the manifest text (JSON syntax,
// nesting, sensor names, poses, joints, hand_eye, gripper ranges). Findings: crashes,
// sanitizer reports, leaks, hangs, and breaches of what parse_scene promises
// (platform/host/io/scene.hpp: a validated scene, or an error naming the file).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_check.hpp"
#include "io/scene.hpp"

namespace {
bool finite_pose(const fg::host::PoseD& p) {
  for (double v : p.position)
    if (!std::isfinite(v)) return false;
  for (const auto& row : p.rotation)
    for (double v : row)
      if (!std::isfinite(v)) return false;
  return true;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path = "fuzz/scene.json";
  const std::string text(reinterpret_cast<const char*>(data), size);
  fg::host::Scene scene;
  const fg::host::ReadResult r = fg::host::parse_scene(text, path, scene);
  if (!r.ok) {
    FG_FUZZ_CHECK(r.error.rfind(path + ": ", 0) == 0, "error message does not start with the manifest path");
    return 0;
  }
  FG_FUZZ_CHECK(!scene.sensors.empty() && scene.sensors.size() <= 2, "a valid scene has one or two sensors");
  for (size_t i = 0; i < scene.sensors.size(); ++i) {
    const fg::host::SceneSensor& s = scene.sensors[i];
    FG_FUZZ_CHECK(s.name == "head" || s.name == "hand", "sensor named neither head nor hand");
    for (size_t j = 0; j < i; ++j) FG_FUZZ_CHECK(scene.sensors[j].name != s.name, "a sensor name appears twice");
    FG_FUZZ_CHECK(!s.cloud_path.empty(), "empty cloud path");
    FG_FUZZ_CHECK(s.pose.has_value() != s.joints.has_value(), "a sensor needs exactly one of pose and joints");
    FG_FUZZ_CHECK(!s.hand_eye || s.joints, "hand_eye without joints");
    if (s.pose) FG_FUZZ_CHECK(finite_pose(*s.pose), "a non-finite pose was accepted");
    if (s.hand_eye) FG_FUZZ_CHECK(finite_pose(*s.hand_eye), "a non-finite hand_eye was accepted");
    if (s.joints)
      for (double q : *s.joints) FG_FUZZ_CHECK(std::isfinite(q), "a non-finite joint angle was accepted");
  }
  const fg::host::SceneGripper& g = scene.gripper;
  FG_FUZZ_CHECK(g.max_opening >= 0.005 && g.max_opening <= 0.5, "gripper.max_opening out of range");
  FG_FUZZ_CHECK(g.finger_width >= 0.002 && g.finger_width <= 0.2, "gripper.finger_width out of range");
  FG_FUZZ_CHECK(g.finger_depth >= 0.005 && g.finger_depth <= 0.3, "gripper.finger_depth out of range");
  return 0;
}
