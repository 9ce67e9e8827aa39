// Uses the installed fg::Planner: a 5 x 12 x 10 cm box on a table, seen by a head sensor
// from above and a hand sensor from the side; each sensor's points are ray-cast here, in
// the sensor's optical frame. Prints the plan and "ok" when it found a grasp.
#include <cmath>
#include <cstdio>
#include <vector>

#include "fg/core/planner.hpp"

namespace {

struct Box {
  fg::Vec3 lo, hi;
};

// world_T_sensor of an optical frame at `eye` looking at `target` (x right, y down).
fg::Pose look_at(const fg::Vec3& eye, const fg::Vec3& target) {
  const fg::Vec3 z = (target - eye).normalized();
  fg::Vec3 x = z.cross(fg::Vec3::UnitZ());
  x = x.norm() < 1e-6f ? fg::Vec3::UnitX() : x.normalized();
  fg::Pose pose;
  pose.R.col(0) = x;
  pose.R.col(1) = z.cross(x);
  pose.R.col(2) = z;
  pose.t = eye;
  return pose;
}

// Depth along the ray's sensor z of the first hit (the table z = 0 or the box); 0: none.
float cast(const fg::Pose& pose, const fg::Vec3& ray, const Box& box) {
  const fg::Vec3 o = pose.t, w = pose.R * ray;
  float best = w.z() < -1e-6f ? -o.z() / w.z() : 1e9f;
  float t0 = 0.f, t1 = 1e9f;
  bool hit = true;
  for (int i = 0; i < 3 && hit; ++i) {  // slab test
    if (std::fabs(w[i]) < 1e-9f) {
      hit = o[i] >= box.lo[i] && o[i] <= box.hi[i];
      continue;
    }
    float a = (box.lo[i] - o[i]) / w[i], b = (box.hi[i] - o[i]) / w[i];
    if (a > b) std::swap(a, b);
    t0 = std::fmax(t0, a);
    t1 = std::fmin(t1, b);
    hit = t0 <= t1;
  }
  if (hit && t0 > 0.f && t0 < best) best = t0;
  return best < 1e8f ? best : 0.f;  // the ray has z = 1: its parameter is the depth
}

// A 160 x 120 sensor's points (x y z, sensor frame); misses are left out.
std::vector<float> render(const fg::Pose& pose, const Box& box) {
  const float f = 131.25f, cx = 79.5f, cy = 59.5f;
  std::vector<float> xyz;
  for (int v = 0; v < 120; ++v)
    for (int u = 0; u < 160; ++u) {
      const fg::Vec3 ray((static_cast<float>(u) - cx) / f, (static_cast<float>(v) - cy) / f, 1.f);
      const float z = cast(pose, ray, box);
      if (z > 0.f) xyz.insert(xyz.end(), {ray.x() * z, ray.y() * z, z});
    }
  return xyz;
}

fg::Planner planner;  // large (fixed capacities): static, never on the stack

}  // namespace

int main() {
  const Box box{fg::Vec3(0.475f, -0.06f, 0.f), fg::Vec3(0.525f, 0.06f, 0.10f)};
  const fg::Vec3 target(0.5f, 0.f, 0.05f);
  const fg::Pose head = look_at(fg::Vec3(0.5f, 0.f, 0.9f), target);
  const fg::Pose hand = look_at(fg::Vec3(0.5f, -0.45f, 0.45f), target);
  const std::vector<float> head_xyz = render(head, box), hand_xyz = render(hand, box);

  fg::PlannerConfig cfg;
  cfg.crop_half_x_m = 0.25f;  // a small table patch
  cfg.crop_half_y_m = 0.25f;
  const char* field = "";
  fg::Status s = planner.configure(cfg, &field);
  if (s != fg::Status::ok) {
    std::printf("configure: %s (%s)\n", fg::to_string(s), field);
    return 1;
  }
  planner.reset();
  const uint32_t stride = 3 * sizeof(float);
  s = planner.add_points(fg::SensorRole::head, head_xyz.data(), static_cast<uint32_t>(head_xyz.size() / 3), stride,
                         head);
  if (s == fg::Status::ok)
    s = planner.add_points(fg::SensorRole::hand, hand_xyz.data(), static_cast<uint32_t>(hand_xyz.size() / 3), stride,
                           hand);
  fg::PlanResult r;
  if (s == fg::Status::ok) s = planner.plan(r);
  std::printf("planner: %s (%s), %u + %u points\n", fg::to_string(s), planner.last_message(),
              static_cast<unsigned>(head_xyz.size() / 3), static_cast<unsigned>(hand_xyz.size() / 3));
  if (s != fg::Status::ok) return 1;
  const fg::Grasp& g = r.grasp;
  std::printf("grasp: position %.3f %.3f %.3f approach %.2f %.2f %.2f width %.3f\n", g.position.x(), g.position.y(),
              g.position.z(), g.approach.x(), g.approach.y(), g.approach.z(), g.width);
  std::printf("ok\n");
  return 0;
}
