// fg_m7_image: the planner on a bare-metal Cortex-M7 (QEMU mps2-an500 or the board).
// Builds a small deterministic scene in code (a 6 x 4 x 8 cm box standing on a table,
// seen by one sensor 0.6 m behind and 0.45 m above it), plans once through the
// firmware C API (forcegrasp.h) in a static workspace, as firmware would, and prints
// the grasp, the point counts and the stage times through the platform log. It proves
// that firmware_api, core/ and robot/ link and run without heap, exceptions or RTTI
// (check_image.cmake checks the symbols); main() returns 0 on a grasp.
#include <cstdint>

#include "fg/core/planner.hpp"
#include "fg/core/prng.hpp"
#include "fg/platform/platform.hpp"
#include "fg/robot/ur5.hpp"
#include "forcegrasp/forcegrasp.h"
#include "text_line.hpp"

namespace {

using fg::Vec3;
using fg::cortex_m::TextLine;

// Static, never on the stack: the workspace is hundreds of KiB.
FG_WORKSPACE_STORAGE(g_workspace_memory);

constexpr uint32_t kMaxScenePoints = 4096;
float g_xyz[kMaxScenePoints * 3];  // the sensor's points, optical frame
uint32_t g_count = 0;

// world_T_sensor of a sensor at `eye` looking at `target` (optical frame: z forward,
// x right, y down).
fg::Pose look_at(const Vec3& eye, const Vec3& target) {
  const Vec3 z = (target - eye).normalized();
  const Vec3 x = z.cross(Vec3::UnitZ()).normalized();
  fg::Pose p;
  p.R.col(0) = x;
  p.R.col(1) = z.cross(x);
  p.R.col(2) = z;
  p.t = eye;
  return p;
}

float uniform(fg::Prng& rng) { return static_cast<float>(rng.next() >> 40) * (1.f / 16777216.f); }

void add_world_point(const fg::Pose& world_T_sensor, const Vec3& w) {
  if (g_count >= kMaxScenePoints) return;
  const Vec3 s = world_T_sensor.R.transpose() * (w - world_T_sensor.t);
  g_xyz[3 * g_count + 0] = s.x();
  g_xyz[3 * g_count + 1] = s.y();
  g_xyz[3 * g_count + 2] = s.z();
  ++g_count;
}

// One rectangular face o + [0,1] a + [0,1] b, one jittered sample per step x step cell.
void add_face(const fg::Pose& pose, fg::Prng& rng, const Vec3& o, const Vec3& a, const Vec3& b, float step) {
  const auto na = static_cast<uint32_t>(a.norm() / step + 0.5f);
  const auto nb = static_cast<uint32_t>(b.norm() / step + 0.5f);
  for (uint32_t i = 0; i < na; ++i)
    for (uint32_t k = 0; k < nb; ++k) {
      const float u = (static_cast<float>(i) + uniform(rng)) / static_cast<float>(na);
      const float v = (static_cast<float>(k) + uniform(rng)) / static_cast<float>(nb);
      add_world_point(pose, o + a * u + b * v);
    }
}

// A 0.36 x 0.36 m table top at z = 0 about (0.5, 0) with the box's footprint left out,
// and the five visible faces of the box standing at (0.5, 0).
void build_scene(const fg::Pose& pose) {
  fg::Prng rng(2024);
  const float sx = 0.06f, sy = 0.04f, sz = 0.08f, table_step = 0.0075f;
  for (float x = 0.32f; x < 0.68f; x += table_step)
    for (float y = -0.18f; y < 0.18f; y += table_step) {
      const float px = x + table_step * uniform(rng), py = y + table_step * uniform(rng);
      if (px > 0.5f - 0.5f * sx && px < 0.5f + 0.5f * sx && py > -0.5f * sy && py < 0.5f * sy) continue;
      add_world_point(pose, Vec3(px, py, 0.f));
    }
  const Vec3 lo(0.5f - 0.5f * sx, -0.5f * sy, 0.f);
  const Vec3 X(sx, 0.f, 0.f), Y(0.f, sy, 0.f), Z(0.f, 0.f, sz);
  const float step = 0.004f;
  add_face(pose, rng, lo + Z, X, Y, step);  // top
  add_face(pose, rng, lo, X, Z, step);      // y = min
  add_face(pose, rng, lo + Y, X, Z, step);  // y = max
  add_face(pose, rng, lo, Y, Z, step);      // x = min
  add_face(pose, rng, lo + X, Y, Z, step);  // x = max
}

void say(const TextLine& line) { fg::platform::log(fg::platform::LogLevel::info, line.c_str()); }

void report(fg_status status, const fg_grasp& g, const char* message, uint64_t cycles) {
  if (status == FG_OK) {
    TextLine line;
    line << "grasp: position ";
    line.fixed(g.position[0]) << " ";
    line.fixed(g.position[1]) << " ";
    line.fixed(g.position[2]) << " width ";
    line.fixed(g.width_m) << " closing ";
    line.fixed(g.closing[0]) << " ";
    line.fixed(g.closing[1]) << " ";
    line.fixed(g.closing[2]);
    say(line);
  } else {
    TextLine line;
    line << "no grasp: " << fg_status_str(status) << " " << fg_reason_str(g.reason) << " (" << message << ")";
    say(line);
  }
  TextLine pts;
  pts << "points: input " << g.points_input << " voxels " << g.voxels << " plane " << g.plane_voxels << " object "
      << g.object_voxels << " viewpoints " << g.viewpoints << " candidates " << g.candidates;
  say(pts);
  TextLine t;
  t << "stage_us:";
  for (uint32_t s = 0; s < FG_STAGE_COUNT; ++s)
    t << " " << fg::to_string(static_cast<fg::Stage>(s)) << " " << g.stage_us[s];
  say(t);
  TextLine c;
  c << "cycles (DWT) for add_points + plan: " << cycles;
  if (cycles == 0) c << " (the DWT cycle counter does not count here: QEMU does not model it)";
  say(c);
}

fg_pose to_c(const fg::Pose& p) {
  fg_pose c{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) c.r[3 * i + j] = p.R(i, j);
    c.t[i] = p.t(i);
  }
  return c;
}

}  // namespace

int main() {
  {
    TextLine line;
    line << "fg_m7_image: forcegrasp " << (fg_version() >> 16) << "." << ((fg_version() >> 8) & 0xFFu) << "."
         << (fg_version() & 0xFFu) << ", workspace " << static_cast<uint32_t>(fg_workspace_size()) << " bytes (budget "
         << static_cast<uint32_t>(FG_WORKSPACE_SIZE) << ")";
    say(line);
  }
  // The robot layer links too: the nominal UR5 at its zero pose.
  fg::Pose tool0;
  const float q[6] = {0.f, 0.f, 0.f, 0.f, 0.f, 0.f};
  if (!fg::robot::ur5_forward(fg::robot::ur5_nominal(), q, tool0)) return 1;

  const fg::Pose pose = look_at(Vec3(-0.1f, 0.f, 0.45f), Vec3(0.5f, 0.f, 0.04f));
  build_scene(pose);
  {
    TextLine line;
    line << "scene: " << g_count << " points (box 0.06 x 0.04 x 0.08 m on a table)";
    say(line);
  }

  fg_config cfg;
  fg_workspace* ws = nullptr;
  fg_status init = fg_config_default(&cfg);
  if (init == FG_OK) init = fg_init(g_workspace_memory, sizeof g_workspace_memory, &cfg, &ws);
  if (init != FG_OK) {
    TextLine line;
    line << "fg_init failed: " << fg_status_str(init);
    say(line);
    return 1;
  }
  const fg_pose sensor = to_c(pose);
  const uint64_t c0 = fg::platform::cycle_counter();
  const fg_status added = fg_add_points(ws, FG_SENSOR_HEAD, g_xyz, g_count, 12, &sensor);
  if (added != FG_OK) {
    TextLine line;
    line << "fg_add_points failed: " << fg_status_str(added) << " (" << fg_last_message(ws) << ")";
    say(line);
    return 1;
  }
  fg_grasp grasp;
  const fg_status planned = fg_plan(ws, &grasp);
  report(planned, grasp, fg_last_message(ws), fg::platform::cycle_counter() - c0);
  return planned == FG_OK ? 0 : 1;
}
