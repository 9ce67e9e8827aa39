// The C API compiled as C++, checked against the C++ Planner it wraps (the oracle):
// on the shipped two-sensor example and the real captures, fg_plan's answer equals
// Planner::plan's bit for bit; configurations round-trip; the workspace budget holds;
// on three boxes standing apart, the objects, each object's plan and the targets by a
// point or a box answer as the Planner does, and on the right box.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "fg/core/planner.hpp"
#include "forcegrasp/forcegrasp.h"
#include "io/pcd.hpp"
#include "io/ply.hpp"
#include "io/scene.hpp"
#include "sim/pinhole.hpp"
#include "sim/scene_gen.hpp"
#include "synthetic_scene.hpp"

namespace {

using fg::test::look_at;

struct SceneData {
  std::vector<fg::host::PointCloud> clouds;
  std::vector<fg::Pose> poses;
  std::vector<fg::SensorRole> roles;
};

bool load(const std::string& path, SceneData& out) {
  fg::host::Scene scene;
  if (!fg::host::read_scene(path, scene).ok) return false;
  for (const auto& s : scene.sensors) {
    if (!s.pose) return false;
    fg::host::PointCloud c;
    if (!fg::host::read_cloud(s.cloud_path, c).ok) return false;
    out.clouds.push_back(std::move(c));
    out.poses.push_back(fg::host::to_pose(*s.pose));
    out.roles.push_back(s.name == "head" ? fg::SensorRole::head : fg::SensorRole::hand);
  }
  return true;
}

fg_pose to_c(const fg::Pose& p) {
  fg_pose c{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) c.r[3 * i + j] = p.R(i, j);
    c.t[i] = p.t(i);
  }
  return c;
}

// Three floats bit for bit (NaN and -0 included), as their bit patterns.
bool same_bits(const float* a, const float* b) {
  for (int i = 0; i < 3; ++i) {
    uint32_t x = 0, y = 0;
    std::memcpy(&x, &a[i], sizeof x);
    std::memcpy(&y, &b[i], sizeof y);
    if (x != y) return false;
  }
  return true;
}

struct Memory {
  alignas(FG_WORKSPACE_ALIGN) unsigned char bytes[FG_WORKSPACE_SIZE];
};

class FirmwareApiScenes : public ::testing::TestWithParam<const char*> {};

TEST_P(FirmwareApiScenes, SameAnswerAsThePlanner) {
  SceneData d;
  const std::string path = GetParam();
  ASSERT_TRUE(load(path, d)) << path;

  auto oracle = std::make_unique<fg::Planner>();
  ASSERT_EQ(oracle->configure(fg::PlannerConfig{}), fg::Status::ok);
  for (size_t i = 0; i < d.clouds.size(); ++i)
    ASSERT_EQ(oracle->add_points(d.roles[i], d.clouds[i].xyz.data(), static_cast<uint32_t>(d.clouds[i].size()), 12,
                                 d.poses[i]),
              fg::Status::ok);
  fg::PlanResult want;
  const fg::Status want_status = oracle->plan(want);
  EXPECT_EQ(want_status, want.status);

  auto mem = std::make_unique<Memory>();
  fg_config cfg;
  ASSERT_EQ(fg_config_default(&cfg), FG_OK);
  fg_workspace* ws = nullptr;
  ASSERT_EQ(fg_init(mem->bytes, sizeof mem->bytes, &cfg, &ws), FG_OK);
  for (size_t i = 0; i < d.clouds.size(); ++i) {
    const fg_pose pose = to_c(d.poses[i]);
    ASSERT_EQ(
        fg_add_points(ws, static_cast<int32_t>(d.roles[i]), d.clouds[i].xyz.data(), d.clouds[i].size(), 12, &pose),
        FG_OK);
  }
  fg_grasp got;
  const fg_status s = fg_plan(ws, &got);
  EXPECT_EQ(static_cast<int32_t>(s), static_cast<int32_t>(want.status)) << fg_last_message(ws);
  EXPECT_STREQ(fg_last_message(ws), want.message);
  EXPECT_EQ(got.reason, static_cast<int32_t>(want.reason));
  EXPECT_EQ(got.voxels, want.points.voxels);
  EXPECT_EQ(got.object_voxels, want.points.object);
  EXPECT_EQ(got.points_input, want.points.input);
  EXPECT_EQ(got.viewpoints, want.viewpoints);
  if (want.status == fg::Status::ok) {
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(got.position[i], want.grasp.position(i));
      EXPECT_EQ(got.approach[i], want.grasp.approach(i));
      EXPECT_EQ(got.closing[i], want.grasp.closing(i));
      EXPECT_EQ(got.pregrasp[i], want.grasp.pregrasp(i));
    }
    EXPECT_EQ(got.width_m, want.grasp.width);
    EXPECT_EQ(got.beta_rad, want.grasp.beta);
    EXPECT_EQ(got.dz_m, want.grasp.dz);
  }

  // The same clouds as x, y and z arrays (fg_add_points_planar): the same plan.
  ASSERT_EQ(fg_reset(ws), FG_OK);
  for (size_t i = 0; i < d.clouds.size(); ++i) {
    const size_t n = d.clouds[i].size();
    std::vector<float> planar(3 * n);
    for (size_t j = 0; j < n; ++j)
      for (size_t k = 0; k < 3; ++k) planar[k * n + j] = d.clouds[i].xyz[j * 3 + k];
    const fg_pose pose = to_c(d.poses[i]);
    ASSERT_EQ(fg_add_points_planar(ws, static_cast<int32_t>(d.roles[i]), planar.data(), planar.data() + n,
                                   planar.data() + 2 * n, n, &pose),
              FG_OK);
  }
  fg_grasp planar_got;
  EXPECT_EQ(fg_plan(ws, &planar_got), s);
  EXPECT_EQ(planar_got.voxels, got.voxels);
  EXPECT_EQ(planar_got.object_voxels, got.object_voxels);
  EXPECT_TRUE(same_bits(planar_got.position, got.position));
  EXPECT_TRUE(same_bits(planar_got.closing, got.closing));
  EXPECT_EQ(planar_got.width_m, got.width_m);
  const float none[1] = {0.f};
  const fg_pose pose = to_c(d.poses[0]);
  ASSERT_EQ(fg_reset(ws), FG_OK);
  EXPECT_EQ(fg_add_points_planar(ws, FG_SENSOR_HEAD, nullptr, none, none, 1, &pose), FG_ERR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(fg_last_message(ws)).find("null"), std::string::npos) << fg_last_message(ws);

  // Ranked (fg_plan_ranked) against the planner's more_grasps: the first entry is
  // fg_plan's grasp, the others the alternates in order.
  ASSERT_EQ(fg_reset(ws), FG_OK);
  for (size_t i = 0; i < d.clouds.size(); ++i) {
    const fg_pose p = to_c(d.poses[i]);
    ASSERT_EQ(fg_add_points(ws, static_cast<int32_t>(d.roles[i]), d.clouds[i].xyz.data(), d.clouds[i].size(), 12, &p),
              FG_OK);
  }
  fg_grasp ranked[FG_MAX_RANKED_GRASPS];
  uint32_t count = 99;
  EXPECT_EQ(fg_plan_ranked(ws, ranked, 4, &count), s);
  if (want.status != fg::Status::ok) {
    EXPECT_EQ(count, 0u);
    return;
  }
  fg::RankedGrasp more[4];
  const uint32_t n_more = oracle->more_grasps(more, 3);
  ASSERT_EQ(count, 1 + n_more);
  EXPECT_TRUE(same_bits(ranked[0].position, got.position));
  EXPECT_TRUE(same_bits(ranked[0].closing, got.closing));
  for (uint32_t k = 0; k < n_more; ++k) {
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(ranked[k + 1].position[i], more[k].grasp.position(i));
      EXPECT_EQ(ranked[k + 1].closing[i], more[k].grasp.closing(i));
    }
    EXPECT_EQ(ranked[k + 1].width_m, more[k].grasp.width);
    EXPECT_EQ(ranked[k + 1].voxels, got.voxels);  // the plan's counts in every entry
  }
  EXPECT_EQ(fg_plan_ranked(ws, nullptr, 4, &count), FG_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(fg_plan_ranked(ws, ranked, 0, &count), FG_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(fg_plan_ranked(ws, ranked, 4, nullptr), FG_ERR_INVALID_ARGUMENT);
}

INSTANTIATE_TEST_SUITE_P(Shipped, FirmwareApiScenes,
                         ::testing::Values(FG_SOURCE_DIR "/examples/two-sensor-box/scene.json",
                                           FG_SHARED_DIR "/data/scenes/learn3-obj3/scene.json",
                                           FG_SHARED_DIR "/data/scenes/learn42-obj3/scene.json"));

// The example with its hand's pose off by `shift` (m, in the hand's frame) and turned by
// `angle` (rad) about `axis` (the hand's frame).
void move_hand(SceneData& d, const fg::Vec3& shift, float angle, const fg::Vec3& axis) {
  for (size_t i = 0; i < d.poses.size(); ++i) {
    if (d.roles[i] != fg::SensorRole::hand) continue;
    d.poses[i].t += d.poses[i].R * shift;
    d.poses[i].R = d.poses[i].R * Eigen::AngleAxisf(angle, axis).toRotationMatrix();
  }
}

// The example with its hand pose 8 mm and half a degree off: fg_registration reports
// what Planner::registration() does, field for field; off, it reports not_run.
TEST(FirmwareApiRegistration, ReportsThePlannersRegistration) {
  SceneData d;
  ASSERT_TRUE(load(FG_SOURCE_DIR "/examples/two-sensor-box/scene.json", d));
  move_hand(d, fg::Vec3(0.008f, 0.f, 0.f), 0.0087f, fg::Vec3::UnitY());
  auto oracle = std::make_unique<fg::Planner>();
  ASSERT_EQ(oracle->configure(fg::PlannerConfig{}), fg::Status::ok);
  auto mem = std::make_unique<Memory>();
  fg_config cfg;
  ASSERT_EQ(fg_config_default(&cfg), FG_OK);
  fg_workspace* ws = nullptr;
  ASSERT_EQ(fg_init(mem->bytes, sizeof mem->bytes, &cfg, &ws), FG_OK);
  fg_registration_result got;
  ASSERT_EQ(fg_registration(ws, &got), FG_OK);
  EXPECT_EQ(got.outcome, FG_REGISTRATION_NOT_RUN);
  EXPECT_EQ(fg_registration(ws, nullptr), FG_ERR_INVALID_ARGUMENT);
  for (size_t i = 0; i < d.clouds.size(); ++i) {  // the head first in the example
    ASSERT_EQ(oracle->add_points(d.roles[i], d.clouds[i].xyz.data(), static_cast<uint32_t>(d.clouds[i].size()), 12,
                                 d.poses[i]),
              fg::Status::ok);
    const fg_pose pose = to_c(d.poses[i]);
    ASSERT_EQ(
        fg_add_points(ws, static_cast<int32_t>(d.roles[i]), d.clouds[i].xyz.data(), d.clouds[i].size(), 12, &pose),
        FG_OK);
  }
  const fg::RegistrationResult& want = oracle->registration();
  ASSERT_EQ(fg_registration(ws, &got), FG_OK);
  EXPECT_EQ(got.outcome, static_cast<int32_t>(want.outcome));
  EXPECT_NE(got.outcome, FG_REGISTRATION_NOT_RUN);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(got.correction.t[i], want.correction.t[i]);
    for (int j = 0; j < 3; ++j) EXPECT_EQ(got.correction.r[3 * i + j], want.correction.R(i, j));
  }
  EXPECT_EQ(got.translation_mm, want.translation_mm);
  EXPECT_EQ(got.rotation_deg, want.rotation_deg);
  EXPECT_EQ(got.residual_mm, want.residual_mm);
  EXPECT_EQ(got.pairs, want.pairs);
  EXPECT_EQ(got.iterations, want.iterations);
  EXPECT_EQ(got.see_through, want.see_through);
  EXPECT_EQ(got.compared, want.compared);
  EXPECT_GT(got.compared, 0u);
  // Measured on a disagreement only: NaN, and no sensor left out.
  EXPECT_TRUE(std::isnan(got.head_tilt_deg) && std::isnan(got.hand_tilt_deg));
  EXPECT_EQ(got.left_out, -1);

  ASSERT_EQ(fg_reset(ws), FG_OK);
  ASSERT_EQ(fg_set_registration(ws, 0), FG_OK);
  for (size_t i = 0; i < d.clouds.size(); ++i) {
    const fg_pose pose = to_c(d.poses[i]);
    ASSERT_EQ(
        fg_add_points(ws, static_cast<int32_t>(d.roles[i]), d.clouds[i].xyz.data(), d.clouds[i].size(), 12, &pose),
        FG_OK);
  }
  ASSERT_EQ(fg_registration(ws, &got), FG_OK);
  EXPECT_EQ(got.outcome, FG_REGISTRATION_NOT_RUN);
  EXPECT_EQ(fg_set_registration(nullptr, 1), FG_ERR_NOT_A_WORKSPACE);
}

// After a refusal as occluded: the advice Planner::look() gives, field for field, bit for
// bit; after a plan that found a grasp, none. Scenes of round bodies rendered by hal/sim
// for the head alone, until one of each outcome was compared.
TEST(FirmwareApiLookAdvice, ReportsThePlannersAdvice) {
  auto mem = std::make_unique<Memory>();
  fg_config cfg;
  ASSERT_EQ(fg_config_default(&cfg), FG_OK);
  fg_workspace* ws = nullptr;
  ASSERT_EQ(fg_init(mem->bytes, sizeof mem->bytes, &cfg, &ws), FG_OK);
  fg_look_advice_result got;
  ASSERT_EQ(fg_look_advice(ws, &got), FG_OK);
  EXPECT_EQ(got.valid, 0);
  EXPECT_EQ(fg_look_advice(ws, nullptr), FG_ERR_INVALID_ARGUMENT);
  auto oracle = std::make_unique<fg::Planner>();
  ASSERT_EQ(oracle->configure(fg::PlannerConfig{}), fg::Status::ok);
  int advised = 0, grasped = 0;
  for (const fg::sim::ObjectKind kind : {fg::sim::ObjectKind::bottle, fg::sim::ObjectKind::ellipsoid})
    for (uint64_t seed = 1; seed <= 20 && (advised == 0 || grasped == 0); ++seed) {
      SCOPED_TRACE(std::string(fg::sim::kind_name(kind)) + " seed " + std::to_string(seed));
      const fg::sim::GeneratedScene s =
          fg::sim::make_scene(kind, seed, fg::sim::SceneOptions::of(fg::sim::Distribution::cell));
      const fg::sim::SceneImages img = fg::sim::render_scene(s);
      oracle->reset();
      ASSERT_EQ(fg::sim::add_rendered(*oracle, fg::SensorRole::head, img.head, s.head), fg::Status::ok);
      fg::PlanResult r;
      const fg::Status want_status = oracle->plan(r);
      ASSERT_EQ(fg_reset(ws), FG_OK);
      const fg_intrinsics k{static_cast<float>(s.head.K.fx), static_cast<float>(s.head.K.fy),
                            static_cast<float>(s.head.K.cx), static_cast<float>(s.head.K.cy)};
      const fg_pose pose = to_c(s.head.world_T_sensor.to_pose());
      ASSERT_EQ(fg_add_depth_image(ws, FG_SENSOR_HEAD, img.head.mm.data(), static_cast<uint16_t>(img.head.width),
                                   static_cast<uint16_t>(img.head.height), &k, &pose),
                FG_OK);
      fg_grasp g;
      const fg_status st = fg_plan(ws, &g);
      ASSERT_EQ(fg_look_advice(ws, &got), FG_OK);
      const fg::LookAdvice& want = oracle->look();
      ASSERT_EQ(got.valid, want.valid ? 1 : 0);
      if (!want.valid) {
        grasped += st == FG_OK && want_status == fg::Status::ok ? 1 : 0;
        continue;
      }
      ++advised;
      EXPECT_EQ(st, FG_NO_GRASP);
      EXPECT_EQ(g.reason, FG_REASON_OCCLUDED);
      EXPECT_EQ(got.sensor, static_cast<int32_t>(want.sensor));
      EXPECT_TRUE(same_bits(got.at, want.at.data()));
      EXPECT_TRUE(same_bits(got.from, want.from.data()));
    }
  EXPECT_GT(advised, 0) << "no scene was refused as occluded: the advice was not compared";
  EXPECT_GT(grasped, 0);
}

// The example's hand 12 cm and 8 degrees off, beyond the registration's reach: on, the
// hand is left out (the plan is the head's); strict, fg_plan fails naming it.
TEST(FirmwareApiRegistration, StrictModeRefusesCloudsThatDisagree) {
  SceneData d;
  ASSERT_TRUE(load(FG_SOURCE_DIR "/examples/two-sensor-box/scene.json", d));
  move_hand(d, fg::Vec3(0.085f, 0.085f, 0.f), 0.14f, fg::Vec3::UnitZ());
  auto mem = std::make_unique<Memory>();
  fg_config cfg;
  ASSERT_EQ(fg_config_default(&cfg), FG_OK);
  fg_workspace* ws = nullptr;
  ASSERT_EQ(fg_init(mem->bytes, sizeof mem->bytes, &cfg, &ws), FG_OK);
  for (const int32_t mode : {FG_REGISTRATION_MODE_ON, FG_REGISTRATION_MODE_STRICT}) {
    ASSERT_EQ(fg_reset(ws), FG_OK);
    ASSERT_EQ(fg_set_registration(ws, mode), FG_OK);
    for (size_t i = 0; i < d.clouds.size(); ++i) {  // the head first in the example
      const fg_pose pose = to_c(d.poses[i]);
      ASSERT_EQ(
          fg_add_points(ws, static_cast<int32_t>(d.roles[i]), d.clouds[i].xyz.data(), d.clouds[i].size(), 12, &pose),
          FG_OK);
    }
    fg_registration_result reg;
    ASSERT_EQ(fg_registration(ws, &reg), FG_OK);
    EXPECT_EQ(reg.outcome, FG_REGISTRATION_SENSOR_DISAGREEMENT) << mode << ": see-through " << reg.see_through;
    // The hand moved, not turned off level: the head's table and the hand's are level
    // alike, and the head, the reference, is kept.
    EXPECT_EQ(reg.left_out, FG_SENSOR_HAND);
    EXPECT_LT(reg.head_tilt_deg, 2.f);
    fg_grasp g;
    const fg_status s = fg_plan(ws, &g);
    if (mode == FG_REGISTRATION_MODE_STRICT) {
      EXPECT_EQ(s, FG_ERR_SENSOR_DISAGREEMENT);
      EXPECT_NE(std::string(fg_last_message(ws)).find("disagrees"), std::string::npos) << fg_last_message(ws);
    } else {
      EXPECT_TRUE(s == FG_OK || s == FG_NO_GRASP) << fg_status_str(s);
    }
  }
}

// The example's clouds in millimetres: refused naming the units, then with the sensors'
// units set planned as the planner plans them with the same units.
TEST(FirmwareApi, SensorUnits) {
  SceneData d;
  ASSERT_TRUE(load(FG_SOURCE_DIR "/examples/two-sensor-box/scene.json", d));
  std::vector<std::vector<float>> mm;
  for (const auto& c : d.clouds) {
    mm.emplace_back(c.xyz.begin(), c.xyz.end());
    for (float& v : mm.back()) v *= 1000.f;
  }
  auto mem = std::make_unique<Memory>();
  fg_config cfg;
  ASSERT_EQ(fg_config_default(&cfg), FG_OK);
  fg_workspace* ws = nullptr;
  ASSERT_EQ(fg_init(mem->bytes, sizeof mem->bytes, &cfg, &ws), FG_OK);
  const fg_pose pose0 = to_c(d.poses[0]);
  EXPECT_EQ(fg_add_points(ws, static_cast<int32_t>(d.roles[0]), mm[0].data(), mm[0].size() / 3, 12, &pose0),
            FG_ERR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(fg_last_message(ws)).find("millimetres"), std::string::npos) << fg_last_message(ws);

  auto oracle = std::make_unique<fg::Planner>();
  ASSERT_EQ(oracle->configure(fg::PlannerConfig{}), fg::Status::ok);
  ASSERT_EQ(fg_reset(ws), FG_OK);
  for (size_t i = 0; i < d.clouds.size(); ++i) {
    ASSERT_EQ(oracle->set_sensor_units(d.roles[i], 0.001f), fg::Status::ok);
    ASSERT_EQ(oracle->add_points(d.roles[i], mm[i].data(), static_cast<uint32_t>(mm[i].size() / 3), 12, d.poses[i]),
              fg::Status::ok);
    ASSERT_EQ(fg_set_sensor_units(ws, static_cast<int32_t>(d.roles[i]), 0.001f), FG_OK);
    const fg_pose pose = to_c(d.poses[i]);
    ASSERT_EQ(fg_add_points(ws, static_cast<int32_t>(d.roles[i]), mm[i].data(), mm[i].size() / 3, 12, &pose), FG_OK);
  }
  fg::PlanResult want;
  ASSERT_EQ(oracle->plan(want), fg::Status::ok);
  fg_grasp got;
  ASSERT_EQ(fg_plan(ws, &got), FG_OK);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(got.position[i], want.grasp.position(i));
  EXPECT_EQ(got.width_m, want.grasp.width);

  // Only the hand's cloud in millimetres, after the head's in metres: its units are
  // named whatever the registration mode (its surfaces a thousand times too far would
  // otherwise look like a sensor disagreement).
  for (const int32_t mode : {FG_REGISTRATION_MODE_ON, FG_REGISTRATION_MODE_STRICT, FG_REGISTRATION_MODE_OFF}) {
    ASSERT_EQ(fg_reset(ws), FG_OK);
    ASSERT_EQ(fg_set_registration(ws, mode), FG_OK);
    for (size_t i = 0; i < d.clouds.size(); ++i) {
      ASSERT_EQ(fg_set_sensor_units(ws, static_cast<int32_t>(d.roles[i]), 1.f), FG_OK);
      const fg_pose pose = to_c(d.poses[i]);
      const bool hand = d.roles[i] == fg::SensorRole::hand;
      const float* xyz = hand ? mm[i].data() : d.clouds[i].xyz.data();
      const fg_status s = fg_add_points(ws, static_cast<int32_t>(d.roles[i]), xyz, d.clouds[i].size(), 12, &pose);
      EXPECT_EQ(s, hand ? FG_ERR_INVALID_ARGUMENT : FG_OK) << mode;
      if (hand) {
        EXPECT_NE(std::string(fg_last_message(ws)).find("millimetres"), std::string::npos) << fg_last_message(ws);
      }
    }
  }
  ASSERT_EQ(fg_set_registration(ws, FG_REGISTRATION_MODE_ON), FG_OK);
}

// Every field of fg_config reaches the planner: default -> C -> check is ok, and a
// value out of range in each field is refused under its option name.
TEST(FirmwareApi, EveryConfigFieldIsChecked) {
  fg_config cfg;
  ASSERT_EQ(fg_config_default(&cfg), FG_OK);
  const char* field = nullptr;
  ASSERT_EQ(fg_config_check(&cfg, &field), FG_OK);
  struct Case {
    float* value;
    const char* name;
  };
  const Case cases[] = {{&cfg.voxel_leaf_m, "voxel_leaf"},
                        {&cfg.range_max_m, "range_max"},
                        {&cfg.dtheta_rad, "dtheta"},
                        {&cfg.beta_max_rad, "beta_max"},
                        {&cfg.scan_delta_m, "scan_delta"},
                        {&cfg.friction_mu, "friction_mu"},
                        {&cfg.gripper.finger_depth_m, "gripper.finger_depth"}};
  for (const Case& c : cases) {
    const float keep = *c.value;
    *c.value = -1.f;
    EXPECT_EQ(fg_config_check(&cfg, &field), FG_ERR_INVALID_CONFIG) << c.name;
    EXPECT_STREQ(field, c.name);
    *c.value = keep;
  }
  EXPECT_EQ(fg_config_check(&cfg, &field), FG_OK);
}

TEST(FirmwareApi, WorkspaceBudgetAndStorageMacro) {
  EXPECT_LE(fg_workspace_size(), static_cast<size_t>(FG_WORKSPACE_SIZE));
  EXPECT_GE(fg_workspace_size(), sizeof(fg::Planner));
  static FG_WORKSPACE_STORAGE(storage);
  EXPECT_EQ(reinterpret_cast<uintptr_t>(storage) % FG_WORKSPACE_ALIGN, 0u);
  fg_config cfg;
  ASSERT_EQ(fg_config_default(&cfg), FG_OK);
  fg_workspace* ws = nullptr;
  EXPECT_EQ(fg_init(storage, sizeof storage, &cfg, &ws), FG_OK);
  EXPECT_EQ(static_cast<void*>(ws), static_cast<void*>(storage));
}

// ---- Objects on the table: three boxes standing apart ----------------------------

// A box standing on the table: its centre (x, y) and its sizes.
struct BoxSpec {
  float cx, cy, sx, sy, sz;
};
// The first nearest the workspace centre (0.5, 0), the others 25 cm and more away.
constexpr BoxSpec kBoxes[3] = {
    {0.5f, 0.f, 0.05f, 0.07f, 0.12f}, {0.34f, 0.22f, 0.05f, 0.06f, 0.10f}, {0.68f, -0.21f, 0.06f, 0.05f, 0.09f}};

// The three boxes on the table as test_ranked_grasps.cpp's two sensors give them (a
// head sensor in front and above, a wrist sensor from the side): each sensor's points
// in its own frame, and each box's sampled surface mean (its expected centroid).
struct ThreeBoxes {
  fg::Pose poses[2];
  std::vector<float> xyz[2];
  uint32_t count = 0;
  fg::Vec3 surface_mean[3];
};

ThreeBoxes three_boxes() {
  ThreeBoxes scene;
  std::mt19937 rng(11);
  std::vector<fg::Vec3> world;
  fg::test::add_table(world, rng, 0.004f);
  for (int b = 0; b < 3; ++b) {
    const size_t first = world.size();
    const BoxSpec& s = kBoxes[b];
    fg::test::add_box(world, rng, s.cx, s.cy, s.sx, s.sy, s.sz, 0.0025f);
    fg::Vec3 sum = fg::Vec3::Zero();
    for (size_t i = first; i < world.size(); ++i) sum += world[i];
    scene.surface_mean[b] = sum / static_cast<float>(world.size() - first);
  }
  scene.poses[0] = look_at(fg::Vec3(-0.2f, -0.1f, 0.6f), fg::Vec3(0.5f, 0.f, 0.06f));
  scene.poses[1] = look_at(fg::Vec3(0.55f, -0.45f, 0.35f), fg::Vec3(0.5f, 0.f, 0.06f));
  for (int s = 0; s < 2; ++s)
    for (const fg::Vec3& w : world) {
      const fg::Vec3 p = scene.poses[s].R.transpose() * (w - scene.poses[s].t);
      scene.xyz[s].insert(scene.xyz[s].end(), {p.x(), p.y(), p.z()});
    }
  scene.count = static_cast<uint32_t>(world.size());
  return scene;
}

// The scene in a workspace and in the Planner it wraps (the oracle), each planned once.
struct ObjectsRig {
  ThreeBoxes scene = three_boxes();
  std::unique_ptr<fg::Planner> oracle = std::make_unique<fg::Planner>();
  std::unique_ptr<Memory> mem = std::make_unique<Memory>();
  fg_workspace* ws = nullptr;
  fg::PlanResult want;
  fg_grasp got{};
  fg_status got_status = FG_ERR_INTERNAL;

  // The capture into both (the workspace after fg_reset); false on a refusal.
  [[nodiscard]] bool capture() {
    const fg::SensorRole roles[2] = {fg::SensorRole::head, fg::SensorRole::hand};
    if (fg_reset(ws) != FG_OK) return false;
    oracle->reset();
    for (int s = 0; s < 2; ++s) {
      const fg_pose pose = to_c(scene.poses[s]);
      if (oracle->add_points(roles[s], scene.xyz[s].data(), scene.count, 12, scene.poses[s]) != fg::Status::ok ||
          fg_add_points(ws, static_cast<int32_t>(roles[s]), scene.xyz[s].data(), scene.count, 12, &pose) != FG_OK)
        return false;
    }
    return true;
  }

  // Configures both, captures and plans in both; false when a step was refused.
  [[nodiscard]] bool plan() {
    fg_config cfg;
    if (fg_config_default(&cfg) != FG_OK || fg_init(mem->bytes, sizeof mem->bytes, &cfg, &ws) != FG_OK) return false;
    if (oracle->configure(fg::PlannerConfig{}) != fg::Status::ok || !capture()) return false;
    (void)oracle->plan(want);  // its status is want.status
    got_status = fg_plan(ws, &got);
    return true;
  }
};

// Two grasps' poses bit for bit (the C struct's floats against the Planner's).
void expect_same_grasp(const fg_grasp& got, const fg::Grasp& want) {
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(got.position[i], want.position(i));
    EXPECT_EQ(got.approach[i], want.approach(i));
    EXPECT_EQ(got.closing[i], want.closing(i));
    EXPECT_EQ(got.pregrasp[i], want.pregrasp(i));
  }
  EXPECT_EQ(got.width_m, want.width);
  EXPECT_EQ(got.beta_rad, want.beta);
  EXPECT_EQ(got.dz_m, want.dz);
}

// The grasp's centre inside a world box grown by `margin` on every side.
bool inside(const float p[3], const float lo[3], const float hi[3], float margin) {
  for (int i = 0; i < 3; ++i)
    if (p[i] < lo[i] - margin || p[i] > hi[i] + margin) return false;
  return true;
}

// The index of the listed object whose centroid lies within 1 cm of box b's, or -1.
int32_t object_of_box(const fg_object* objects, uint32_t n, const ThreeBoxes& scene, int b) {
  for (uint32_t k = 0; k < n; ++k) {
    const fg::Vec3 c(objects[k].centroid[0], objects[k].centroid[1], objects[k].centroid[2]);
    if ((c - scene.surface_mean[b]).norm() < 0.01f) return static_cast<int32_t>(k);
  }
  return -1;
}

TEST(FirmwareApiObjects, ThreeBoxesListedAndEachPlannedAsThePlannerDoes) {
  ObjectsRig rig;
  ASSERT_TRUE(rig.plan());
  ASSERT_EQ(rig.want.status, fg::Status::ok) << rig.want.message;
  ASSERT_EQ(rig.got_status, FG_OK) << fg_last_message(rig.ws);
  expect_same_grasp(rig.got, rig.want.grasp);

  fg_object objects[FG_MAX_OBJECTS];
  uint32_t n = 0, dropped = 99;
  ASSERT_EQ(fg_objects(rig.ws, objects, FG_MAX_OBJECTS, &n, &dropped), FG_OK);
  ASSERT_EQ(n, 3u);
  EXPECT_EQ(dropped, 0u);
  ASSERT_EQ(rig.oracle->object_count(), n);
  int32_t of_box[3];
  for (int b = 0; b < 3; ++b) {
    of_box[b] = object_of_box(objects, n, rig.scene, b);
    EXPECT_GE(of_box[b], 0) << "no object's centroid within 1 cm of box " << b;
  }
  EXPECT_EQ(of_box[0], 0) << "the box nearest the workspace centre comes first";
  for (uint32_t k = 0; k < n; ++k) {
    const fg::ObjectSummary& o = rig.oracle->object(k);
    EXPECT_EQ(objects[k].voxels, o.voxels);
    EXPECT_TRUE(same_bits(objects[k].centroid, o.centroid.data()));
    EXPECT_TRUE(same_bits(objects[k].box_min, o.box_min.data()));
    EXPECT_TRUE(same_bits(objects[k].box_max, o.box_max.data()));
    // fg_plan's target (by rule: nearest the workspace centre) is box 0.
    EXPECT_EQ(objects[k].is_target, static_cast<int32_t>(k) == of_box[0] ? 1u : 0u) << k;
  }

  // Every object planned for itself: the Planner's grasp bit for bit, on that object.
  for (uint32_t k = 0; k < n; ++k) {
    SCOPED_TRACE("object " + std::to_string(k));
    fg::PlanResult want;
    const fg::Status want_status = rig.oracle->plan_object(k, want);
    fg_grasp got;
    const fg_status s = fg_plan_object(rig.ws, k, &got);
    ASSERT_EQ(want_status, fg::Status::ok) << want.message;
    ASSERT_EQ(static_cast<int32_t>(s), static_cast<int32_t>(want_status)) << fg_last_message(rig.ws);
    EXPECT_STREQ(fg_last_message(rig.ws), want.message);
    expect_same_grasp(got, want.grasp);
    EXPECT_EQ(got.object_voxels, objects[k].voxels);
    EXPECT_EQ(got.viewpoints, want.viewpoints);
    EXPECT_TRUE(inside(got.position, objects[k].box_min, objects[k].box_max, 0.01f))
        << got.position[0] << " " << got.position[1] << " " << got.position[2];
    // The list stays; is_target follows the object planned.
    fg_object again[FG_MAX_OBJECTS];
    uint32_t n_again = 0;
    ASSERT_EQ(fg_objects(rig.ws, again, FG_MAX_OBJECTS, &n_again, nullptr), FG_OK);
    ASSERT_EQ(n_again, n);
    for (uint32_t j = 0; j < n; ++j) EXPECT_EQ(again[j].is_target, j == k ? 1u : 0u) << j;

    // Ranked: the same grasp first, then the Planner's alternates on this object.
    ASSERT_EQ(rig.oracle->plan_object(k, want), fg::Status::ok);
    fg::RankedGrasp more[3];
    const uint32_t n_more = rig.oracle->more_grasps(more, 3);
    fg_grasp ranked[4];
    uint32_t count = 0;
    ASSERT_EQ(fg_plan_object_ranked(rig.ws, k, ranked, 4, &count), FG_OK);
    ASSERT_EQ(count, 1 + n_more);
    expect_same_grasp(ranked[0], want.grasp);
    for (uint32_t i = 0; i < n_more; ++i) expect_same_grasp(ranked[i + 1], more[i].grasp);
  }
}

TEST(FirmwareApiObjects, ASmallerCapacityListsTheNearestAndCountsTheRest) {
  ObjectsRig rig;
  ASSERT_TRUE(rig.plan());
  fg_object all[FG_MAX_OBJECTS], two[2];
  uint32_t n = 0, n_two = 0, dropped = 0;
  ASSERT_EQ(fg_objects(rig.ws, all, FG_MAX_OBJECTS, &n, nullptr), FG_OK);
  ASSERT_EQ(fg_objects(rig.ws, two, 2, &n_two, &dropped), FG_OK);
  EXPECT_EQ(n_two, 2u);
  EXPECT_EQ(dropped, n - 2);
  for (uint32_t k = 0; k < n_two; ++k) {
    EXPECT_TRUE(same_bits(two[k].centroid, all[k].centroid));
    EXPECT_TRUE(same_bits(two[k].box_min, all[k].box_min));
    EXPECT_TRUE(same_bits(two[k].box_max, all[k].box_max));
    EXPECT_EQ(two[k].voxels, all[k].voxels);
    EXPECT_EQ(two[k].is_target, all[k].is_target);
  }
}

TEST(FirmwareApiObjects, ATargetPointOrBoxPicksThatBox) {
  ObjectsRig rig;
  ASSERT_TRUE(rig.plan());
  ASSERT_EQ(rig.got_status, FG_OK);
  const fg_grasp by_rule = rig.got;
  for (int b = 1; b < 3; ++b) {
    SCOPED_TRACE("box " + std::to_string(b));
    const BoxSpec& s = kBoxes[b];
    const float lo[3] = {s.cx - 0.5f * s.sx, s.cy - 0.5f * s.sy, 0.f};
    const float hi[3] = {s.cx + 0.5f * s.sx, s.cy + 0.5f * s.sy, s.sz};
    // A point beside the box, 2 cm off its side towards the workspace centre.
    const float near_box[3] = {s.cx, s.cy + (s.cy > 0.f ? -1.f : 1.f) * (0.5f * s.sy + 0.02f), 0.05f};
    // A box around it, 1 cm larger every way.
    const float around_lo[3] = {lo[0] - 0.01f, lo[1] - 0.01f, -0.01f};
    const float around_hi[3] = {hi[0] + 0.01f, hi[1] + 0.01f, hi[2] + 0.01f};
    for (int kind = 0; kind < 2; ++kind) {
      SCOPED_TRACE(kind == 0 ? "point" : "box");
      ASSERT_EQ(kind == 0 ? fg_set_target_point(rig.ws, near_box) : fg_set_target_box(rig.ws, around_lo, around_hi),
                FG_OK);
      fg::TargetSpec spec;
      spec.kind = kind == 0 ? fg::TargetKind::nearest_point : fg::TargetKind::inside_box;
      spec.point = fg::Vec3(near_box[0], near_box[1], near_box[2]);
      spec.box_min = fg::Vec3(around_lo[0], around_lo[1], around_lo[2]);
      spec.box_max = fg::Vec3(around_hi[0], around_hi[1], around_hi[2]);
      ASSERT_EQ(rig.oracle->set_target(spec), fg::Status::ok);
      // The target is kept across fg_reset: a new capture plans on it too.
      ASSERT_TRUE(rig.capture());
      fg::PlanResult want;
      ASSERT_EQ(rig.oracle->plan(want), fg::Status::ok) << want.message;
      fg_grasp got;
      ASSERT_EQ(fg_plan(rig.ws, &got), FG_OK) << fg_last_message(rig.ws);
      expect_same_grasp(got, want.grasp);
      EXPECT_TRUE(inside(got.position, lo, hi, 0.01f))
          << got.position[0] << " " << got.position[1] << " " << got.position[2];
      fg_object objects[FG_MAX_OBJECTS];
      uint32_t n = 0;
      ASSERT_EQ(fg_objects(rig.ws, objects, FG_MAX_OBJECTS, &n, nullptr), FG_OK);
      const int32_t k = object_of_box(objects, n, rig.scene, b);
      ASSERT_GE(k, 0);
      EXPECT_EQ(objects[k].is_target, 1u);
    }
  }
  // Cleared: the rule's target again, the same grasp as at first.
  ASSERT_EQ(fg_clear_target(rig.ws), FG_OK);
  fg_grasp got;
  ASSERT_EQ(fg_plan(rig.ws, &got), FG_OK);
  EXPECT_TRUE(same_bits(got.position, by_rule.position));
  EXPECT_TRUE(same_bits(got.closing, by_rule.closing));
}

TEST(FirmwareApiObjects, TargetsOutsideEmptyOrMalformedAreAnsweredWithTheirStatus) {
  ObjectsRig rig;
  ASSERT_TRUE(rig.plan());
  fg_workspace* ws = rig.ws;
  fg_grasp g;
  // Outside the workspace crop box (x in [-0.1, 1.1]): refused by fg_plan, named.
  const float far_point[3] = {2.f, 0.f, 0.05f};
  ASSERT_EQ(fg_set_target_point(ws, far_point), FG_OK);
  EXPECT_EQ(fg_plan(ws, &g), FG_ERR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(fg_last_message(ws)).find("target point"), std::string::npos) << fg_last_message(ws);
  EXPECT_NE(std::string(fg_last_message(ws)).find("outside"), std::string::npos) << fg_last_message(ws);
  const float far_lo[3] = {2.f, 2.f, 0.f}, far_hi[3] = {2.5f, 2.5f, 0.2f};
  ASSERT_EQ(fg_set_target_box(ws, far_lo, far_hi), FG_OK);
  EXPECT_EQ(fg_plan(ws, &g), FG_ERR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(fg_last_message(ws)).find("target box"), std::string::npos) << fg_last_message(ws);
  // A refused plan lists no objects, and plan_object has nothing to plan on.
  fg_object objects[FG_MAX_OBJECTS];
  uint32_t n = 9;
  ASSERT_EQ(fg_objects(ws, objects, FG_MAX_OBJECTS, &n, nullptr), FG_OK);
  EXPECT_EQ(n, 0u);
  EXPECT_EQ(fg_plan_object(ws, 0, &g), FG_ERR_INVALID_SEQUENCE);
  // A box in the air over the table: no object inside it.
  const float air_lo[3] = {0.2f, -0.3f, 0.4f}, air_hi[3] = {0.3f, -0.2f, 0.5f};
  ASSERT_EQ(fg_set_target_box(ws, air_lo, air_hi), FG_OK);
  EXPECT_EQ(fg_plan(ws, &g), FG_NO_GRASP);
  EXPECT_EQ(g.reason, FG_REASON_NO_OBJECT);
  ASSERT_EQ(fg_objects(ws, objects, FG_MAX_OBJECTS, &n, nullptr), FG_OK);
  EXPECT_EQ(n, 3u) << "the objects are listed though none is in the box";
  for (uint32_t k = 0; k < n; ++k) EXPECT_EQ(objects[k].is_target, 0u);
  // Malformed targets are refused, and the one before stays (the box in the air).
  const float nan_point[3] = {0.5f, NAN, 0.05f};
  EXPECT_EQ(fg_set_target_point(ws, nan_point), FG_ERR_NON_FINITE);
  EXPECT_NE(std::string(fg_last_message(ws)).find("not finite"), std::string::npos) << fg_last_message(ws);
  const float inf_hi[3] = {INFINITY, 0.f, 0.f};
  EXPECT_EQ(fg_set_target_box(ws, air_lo, inf_hi), FG_ERR_NON_FINITE);
  EXPECT_EQ(fg_set_target_box(ws, air_hi, air_lo), FG_ERR_INVALID_ARGUMENT);  // minimum above maximum
  EXPECT_NE(std::string(fg_last_message(ws)).find("minimum"), std::string::npos) << fg_last_message(ws);
  EXPECT_EQ(fg_plan(ws, &g), FG_NO_GRASP);
  EXPECT_EQ(g.reason, FG_REASON_NO_OBJECT);
  // Null pointers.
  uint32_t count = 7, dropped = 7;
  EXPECT_EQ(fg_set_target_point(ws, nullptr), FG_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(fg_set_target_box(ws, nullptr, air_hi), FG_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(fg_set_target_box(ws, air_lo, nullptr), FG_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(fg_objects(ws, nullptr, FG_MAX_OBJECTS, &count, &dropped), FG_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(count, 0u);
  EXPECT_EQ(dropped, 0u);
  EXPECT_EQ(fg_objects(ws, objects, FG_MAX_OBJECTS, nullptr, &dropped), FG_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(fg_objects(ws, objects, 0, &count, &dropped), FG_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(fg_plan_object(ws, 0, nullptr), FG_ERR_INVALID_ARGUMENT);
  fg_grasp ranked[2];
  EXPECT_EQ(fg_plan_object_ranked(ws, 0, nullptr, 2, &count), FG_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(fg_plan_object_ranked(ws, 0, ranked, 0, &count), FG_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(fg_plan_object_ranked(ws, 0, ranked, 2, nullptr), FG_ERR_INVALID_ARGUMENT);
  // Not a workspace.
  EXPECT_EQ(fg_set_target_point(nullptr, far_point), FG_ERR_NOT_A_WORKSPACE);
  EXPECT_EQ(fg_set_target_box(nullptr, air_lo, air_hi), FG_ERR_NOT_A_WORKSPACE);
  EXPECT_EQ(fg_clear_target(nullptr), FG_ERR_NOT_A_WORKSPACE);
  EXPECT_EQ(fg_objects(nullptr, objects, FG_MAX_OBJECTS, &count, nullptr), FG_ERR_NOT_A_WORKSPACE);
  EXPECT_EQ(fg_plan_object(nullptr, 0, &g), FG_ERR_NOT_A_WORKSPACE);
  EXPECT_EQ(fg_plan_object_ranked(nullptr, 0, ranked, 2, &count), FG_ERR_NOT_A_WORKSPACE);
}

TEST(FirmwareApiObjects, PlanObjectNeedsAPlanAndAnIndexInTheList) {
  ObjectsRig rig;
  ASSERT_TRUE(rig.plan());
  fg_workspace* ws = rig.ws;
  fg_grasp g;
  fg_object objects[FG_MAX_OBJECTS];
  uint32_t n = 0, count = 5;
  ASSERT_EQ(fg_objects(ws, objects, FG_MAX_OBJECTS, &n, nullptr), FG_OK);
  ASSERT_EQ(n, 3u);
  EXPECT_EQ(fg_plan_object(ws, n, &g), FG_ERR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(fg_last_message(ws)).find("index"), std::string::npos) << fg_last_message(ws);
  EXPECT_EQ(fg_plan_object(ws, UINT32_MAX, &g), FG_ERR_INVALID_ARGUMENT);
  fg_grasp ranked[2];
  EXPECT_EQ(fg_plan_object_ranked(ws, n, ranked, 2, &count), FG_ERR_INVALID_ARGUMENT);
  EXPECT_EQ(count, 0u);
  // After fg_reset, before fg_plan: nothing listed, nothing to plan on.
  ASSERT_EQ(fg_reset(ws), FG_OK);
  ASSERT_EQ(fg_objects(ws, objects, FG_MAX_OBJECTS, &n, nullptr), FG_OK);
  EXPECT_EQ(n, 0u);
  EXPECT_EQ(fg_plan_object(ws, 0, &g), FG_ERR_INVALID_SEQUENCE);
  EXPECT_NE(std::string(fg_last_message(ws)).find("plan()"), std::string::npos) << fg_last_message(ws);
  EXPECT_EQ(fg_plan_object_ranked(ws, 0, ranked, 2, &count), FG_ERR_INVALID_SEQUENCE);
  // A fresh workspace too.
  auto mem = std::make_unique<Memory>();
  fg_config cfg;
  ASSERT_EQ(fg_config_default(&cfg), FG_OK);
  fg_workspace* fresh = nullptr;
  ASSERT_EQ(fg_init(mem->bytes, sizeof mem->bytes, &cfg, &fresh), FG_OK);
  EXPECT_EQ(fg_plan_object(fresh, 0, &g), FG_ERR_INVALID_SEQUENCE);
}

}  // namespace
