// The C API compiled as C++, checked against the C++ Planner it wraps (the oracle):
// on the shipped two-sensor example and the real captures, fg_plan's answer equals
// Planner::plan's bit for bit; configurations round-trip; the workspace budget holds.
#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "fg/core/planner.hpp"
#include "forcegrasp/forcegrasp.h"
#include "io/pcd.hpp"
#include "io/ply.hpp"
#include "io/scene.hpp"

namespace {

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
  EXPECT_EQ(std::memcmp(planar_got.position, got.position, sizeof got.position), 0);
  EXPECT_EQ(std::memcmp(planar_got.closing, got.closing, sizeof got.closing), 0);
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
  EXPECT_EQ(std::memcmp(ranked[0].position, got.position, sizeof got.position), 0);
  EXPECT_EQ(std::memcmp(ranked[0].closing, got.closing, sizeof got.closing), 0);
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

}  // namespace
