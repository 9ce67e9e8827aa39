// validate(PlannerConfig): the defaults pass; every field set out of its range (NaN,
// Inf, negative, huge, zero where zero is meaningless) gives invalid_config and names
// that very field; in-range edge values pass; Planner::configure reports the same.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "fg/core/config.hpp"
#include "fg/core/limits.hpp"
#include "fg/core/planner.hpp"

namespace {

using fg::PlannerConfig;
using fg::Status;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

TEST(Config, DefaultsValidate) {
  PlannerConfig c;
  const char* field = "untouched";
  EXPECT_EQ(fg::validate(c, &field), Status::ok);
  EXPECT_EQ(field, nullptr);
  EXPECT_EQ(fg::validate(c, nullptr), Status::ok);
}

TEST(Config, DocumentedDefaults) {
  // algorithm.md: range 0.3-1.5 m, leaf 5 mm, RANSAC 1 cm, 20 deg, 5 deg steps, 2 mm
  // scan lines, 4 mm discontinuity, beta_max 0.2 rad.
  PlannerConfig c;
  EXPECT_FLOAT_EQ(c.range_min_m, 0.3f);
  EXPECT_FLOAT_EQ(c.range_max_m, 1.5f);
  EXPECT_FLOAT_EQ(c.voxel_leaf_m, 0.005f);
  EXPECT_FLOAT_EQ(c.plane_distance_m, 0.01f);
  EXPECT_NEAR(c.plane_max_tilt_rad, 20.0 * 3.14159265358979 / 180.0, 1e-6);
  EXPECT_NEAR(c.dtheta_rad, 5.0 * 3.14159265358979 / 180.0, 1e-6);
  EXPECT_FLOAT_EQ(c.scan_delta_m, 0.002f);
  EXPECT_FLOAT_EQ(c.dx_threshold_m, 0.004f);
  EXPECT_FLOAT_EQ(c.beta_max_rad, 0.2f);
  EXPECT_LE(c.ransac_iterations, fg::kRansacMaxIters);
}

struct FloatField {
  const char* name;
  std::function<float&(PlannerConfig&)> ref;
  std::vector<float> bad;
  std::vector<float> good;  // in range, with the other fields at their defaults
};

struct UintField {
  const char* name;
  std::function<uint32_t&(PlannerConfig&)> ref;
  std::vector<uint32_t> bad;
  std::vector<uint32_t> good;
};

#define FF(field) [](PlannerConfig& c) -> float& { return c.field; }
#define UF(field) [](PlannerConfig& c) -> uint32_t& { return c.field; }

const float kHuge = 1e30f;

std::vector<FloatField> float_fields() {
  return {
      {"gripper.max_opening",
       FF(gripper.max_opening_m),
       {kNaN, kInf, -kInf, -0.085f, 0.f, 0.001f, 0.6f, kHuge},
       {0.02f, 0.2f}},
      {"gripper.min_opening", FF(gripper.min_opening_m), {kNaN, kInf, -0.01f, 0.09f, kHuge}, {0.f, 0.03f}},
      {"gripper.finger_width",
       FF(gripper.finger_width_m),
       {kNaN, kInf, -0.02f, 0.f, 0.001f, 0.3f, kHuge},
       {0.01f, 0.05f}},
      {"gripper.finger_depth", FF(gripper.finger_depth_m), {kNaN, kInf, -0.04f, 0.f, 0.4f, kHuge}, {0.01f, 0.1f}},
      {"gripper.finger_thickness", FF(gripper.finger_thickness_m), {kNaN, kInf, -0.01f, 0.2f, kHuge}, {0.f, 0.02f}},
      {"gripper.palm_depth", FF(gripper.palm_depth_m), {kNaN, kInf, -0.04f, 0.6f, kHuge}, {0.f, 0.1f}},
      {"gripper.palm_width", FF(gripper.palm_width_m), {kNaN, kInf, -0.05f, 0.6f, kHuge}, {0.f, 0.1f}},
      {"range_min", FF(range_min_m), {kNaN, kInf, -0.3f, -kInf, 25.f, kHuge}, {0.f, 0.5f}},
      {"range_max", FF(range_max_m), {kNaN, kInf, -1.5f, 0.f, 0.3f, 25.f, kHuge}, {0.5f, 3.f}},
      {"voxel_leaf", FF(voxel_leaf_m), {kNaN, kInf, -0.005f, 0.f, 0.0001f, 0.1f, kHuge}, {0.003f, 0.01f}},
      {"crop_half_x", FF(crop_half_x_m), {kNaN, kInf, -0.6f, 0.f, 6.f, kHuge}, {0.1f, 1.f}},
      {"crop_half_y", FF(crop_half_y_m), {kNaN, kInf, -0.6f, 0.f, 6.f, kHuge}, {0.1f, 1.f}},
      {"crop_shrink_min", FF(crop_shrink_min_m), {kNaN, kInf, -0.45f, 0.f, 0.005f, kHuge}, {0.1f, 0.6f, 2.f}},
      {"crop_min_z", FF(crop_min_z_m), {kNaN, -kInf, -kHuge, -200.f}, {-0.2f, 0.5f}},
      {"crop_max_z", FF(crop_max_z_m), {kNaN, kInf, -0.6f, -0.5f, 5.f, kHuge}, {0.f, 2.f}},
      {"plane_distance", FF(plane_distance_m), {kNaN, kInf, -0.01f, 0.f, 0.2f, kHuge}, {0.001f, 0.05f}},
      {"plane_max_tilt", FF(plane_max_tilt_rad), {kNaN, kInf, -0.35f, 1.6f, 3.2f, kHuge}, {0.f, 1.f}},
      {"object_min_height", FF(object_min_height_m), {kNaN, kInf, -0.006f, 0.3f, kHuge}, {0.f, 0.02f}},
      {"workspace_centre_x", FF(workspace_centre_x_m), {kNaN, kInf, -kInf, -200.f, kHuge}, {-0.5f, 1.f}},
      {"workspace_centre_y", FF(workspace_centre_y_m), {kNaN, kInf, -kInf, 200.f, -kHuge}, {-0.5f, 1.f}},
      {"dtheta", FF(dtheta_rad), {kNaN, kInf, -0.087f, 0.f, 0.001f, 2.f, kHuge}, {0.01f, 0.5f}},
      {"single_sensor_arc", FF(single_sensor_arc_rad), {kNaN, kInf, -1.f, 3.2f, kHuge}, {0.f, 3.f}},
      {"vertical_snap", FF(vertical_snap_rad), {kNaN, kInf, -0.26f, 1.6f, kHuge}, {0.f, 1.f}},
      {"vertical_snap_round", FF(vertical_snap_round_rad), {kNaN, kInf, -0.52f, 1.6f, kHuge}, {0.f, 1.f}},
      {"axis_ratio_min", FF(axis_ratio_min), {kNaN, kInf, -1.3f, 0.f, 0.5f, 200.f, kHuge}, {1.f, 10.f}},
      {"approach_view_max", FF(approach_view_max_rad), {kNaN, kInf, -0.1f, 3.2f, kHuge}, {0.f, 1.f, 3.14f}},
      {"scan_delta", FF(scan_delta_m), {kNaN, kInf, -0.002f, 0.f, 0.0001f, 0.1f, kHuge}, {0.001f, 0.01f}},
      {"dx_threshold", FF(dx_threshold_m), {kNaN, kInf, -0.004f, 0.f, 0.2f, kHuge}, {0.001f, 0.05f}},
      {"width_margin", FF(width_margin_m), {kNaN, kInf, -0.004f, 0.05f, kHuge}, {0.f, 0.01f}},
      {"hull_cell", FF(hull_cell_m), {kNaN, kInf, -0.0025f, 0.f, 0.0001f, 0.1f, kHuge}, {0.001f, 0.01f}},
      {"centre_weight", FF(centre_weight), {kNaN, kInf, -0.5f, 200.f, kHuge}, {0.f, 1e-6f, 10.f}},
      {"beta_max", FF(beta_max_rad), {kNaN, kInf, -0.2f, 1.6f, kHuge}, {0.f, 1.f}},
      {"contact_band", FF(contact_band_m), {kNaN, kInf, -0.004f, 0.f, 0.1f, kHuge}, {0.001f, 0.01f}},
      {"reach_width_ratio", FF(reach_width_ratio), {kNaN, kInf, -0.6f, 1.5f, kHuge}, {0.f, 1.f}},
      {"friction_mu", FF(friction_mu), {kNaN, kInf, -0.5f, 20.f, kHuge}, {0.f, 1.f}},
      {"table_clearance", FF(table_clearance_m), {kNaN, kInf, -1.f, -0.06f, 0.2f, kHuge}, {-0.01f, 0.f, 0.05f}},
      {"collision_tolerance", FF(collision_tolerance_m), {kNaN, kInf, -0.001f, 0.03f, kHuge}, {0.f, 0.01f}},
      {"pregrasp_clearance", FF(pregrasp_clearance_m), {kNaN, kInf, -0.02f, 0.6f, kHuge}, {0.f, 0.1f}},
      {"palm_clearance", FF(palm_clearance_m), {kNaN, kInf, -0.005f, 0.2f, kHuge}, {0.f, 0.05f}},
  };
}

std::vector<UintField> uint_fields() {
  const uint32_t big = 0xFFFFFFFFu;
  return {
      {"ransac_iterations", UF(ransac_iterations), {0u, fg::kRansacMaxIters + 1, big}, {1u, fg::kRansacMaxIters}},
      {"cluster_cells", UF(cluster_cells), {0u, 3u, big}, {1u, 2u}},
      {"min_object_points", UF(min_object_points), {0u, 2u, fg::kMaxObjectPoints + 1, big}, {3u, 100u}},
      {"hull_closing_cells", UF(hull_closing_cells), {9u, 100u, big}, {0u, 8u}},
      {"candidates_per_view", UF(candidates_per_view), {0u, 17u, big}, {1u, 16u}},
  };
}

std::string str(const char* s) { return s == nullptr ? std::string("(null)") : std::string(s); }

TEST(Config, EachFloatFieldOutOfRangeNamesThatField) {
  for (const FloatField& f : float_fields()) {
    for (float v : f.bad) {
      PlannerConfig c;
      f.ref(c) = v;
      const char* field = nullptr;
      EXPECT_EQ(fg::validate(c, &field), Status::invalid_config) << f.name << " = " << v;
      EXPECT_EQ(str(field), f.name) << f.name << " = " << v;
    }
    for (float v : f.good) {
      PlannerConfig c;
      f.ref(c) = v;
      const char* field = "untouched";
      EXPECT_EQ(fg::validate(c, &field), Status::ok) << f.name << " = " << v << " (field " << str(field) << ")";
    }
  }
}

TEST(Config, EachUintFieldOutOfRangeNamesThatField) {
  for (const UintField& f : uint_fields()) {
    for (uint32_t v : f.bad) {
      PlannerConfig c;
      f.ref(c) = v;
      const char* field = nullptr;
      EXPECT_EQ(fg::validate(c, &field), Status::invalid_config) << f.name << " = " << v;
      EXPECT_EQ(str(field), f.name) << f.name << " = " << v;
    }
    for (uint32_t v : f.good) {
      PlannerConfig c;
      f.ref(c) = v;
      EXPECT_EQ(fg::validate(c, nullptr), Status::ok) << f.name << " = " << v;
    }
  }
}

TEST(Config, EnumOutOfRangeNamesTargetRule) {
  PlannerConfig c;
  c.target_rule = static_cast<fg::TargetRule>(7);
  const char* field = nullptr;
  EXPECT_EQ(fg::validate(c, &field), Status::invalid_config);
  EXPECT_EQ(str(field), "target_rule");
  c.target_rule = fg::TargetRule::largest;
  EXPECT_EQ(fg::validate(c, &field), Status::ok);
}

TEST(Config, AnyFieldCanBeTheSeed) {
  PlannerConfig c;
  for (uint32_t s : {0u, 1u, 0xFFFFFFFFu}) {
    c.ransac_seed = s;
    EXPECT_EQ(fg::validate(c, nullptr), Status::ok);
  }
}

TEST(Config, RelationsBetweenFields) {
  {
    // min_opening above max_opening.
    PlannerConfig c;
    c.gripper.max_opening_m = 0.05f;
    c.gripper.min_opening_m = 0.06f;
    const char* field = nullptr;
    EXPECT_EQ(fg::validate(c, &field), Status::invalid_config);
    EXPECT_EQ(str(field), "gripper.min_opening");
  }
  {
    // range_max not above range_min.
    PlannerConfig c;
    c.range_min_m = 1.0f;
    c.range_max_m = 1.0f;
    const char* field = nullptr;
    EXPECT_EQ(fg::validate(c, &field), Status::invalid_config);
    EXPECT_EQ(str(field), "range_max");
  }
  {
    // crop_max_z not above crop_min_z.
    PlannerConfig c;
    c.crop_min_z_m = 0.5f;
    c.crop_max_z_m = 0.4f;
    const char* field = nullptr;
    EXPECT_EQ(fg::validate(c, &field), Status::invalid_config);
    EXPECT_EQ(str(field), "crop_max_z");
  }
  {
    // The crop box must fit the voxel key: 2 * 3 m / 5 mm = 1200 cells is fine in x
    // (11 bits); 4 m / 5 mm = 800 in z is fine, 6 m / 5 mm = 1200 is not (10 bits).
    PlannerConfig c;
    c.crop_half_x_m = 3.f;
    EXPECT_EQ(fg::validate(c, nullptr), Status::ok);
    c.crop_half_x_m = 6.f;
    const char* field = nullptr;
    EXPECT_EQ(fg::validate(c, &field), Status::invalid_config);
    EXPECT_EQ(str(field), "crop_half_x");
    PlannerConfig z;
    z.crop_min_z_m = -2.f;
    z.crop_max_z_m = 2.f;
    EXPECT_EQ(fg::validate(z, nullptr), Status::ok);
    z.crop_max_z_m = 4.f;
    EXPECT_EQ(fg::validate(z, &field), Status::invalid_config);
    EXPECT_EQ(str(field), "crop_max_z");
  }
  {
    // width_margin at most half the opening.
    PlannerConfig c;
    c.gripper.max_opening_m = 0.02f;
    c.width_margin_m = 0.011f;
    const char* field = nullptr;
    EXPECT_EQ(fg::validate(c, &field), Status::invalid_config);
    EXPECT_EQ(str(field), "width_margin");
  }
}

TEST(Config, PlannerConfigureReportsTheFieldAndKeepsTheOldConfig) {
  auto planner = std::make_unique<fg::Planner>();
  PlannerConfig good;
  good.voxel_leaf_m = 0.004f;
  ASSERT_EQ(planner->configure(good), Status::ok);
  PlannerConfig bad;
  bad.dx_threshold_m = kNaN;
  const char* field = nullptr;
  EXPECT_EQ(planner->configure(bad, &field), Status::invalid_config);
  EXPECT_EQ(str(field), "dx_threshold");
  EXPECT_STRNE(planner->last_message(), "");
  EXPECT_FLOAT_EQ(planner->config().voxel_leaf_m, 0.004f);
  EXPECT_EQ(planner->configure(bad), Status::invalid_config);  // a null field pointer is fine
}

}  // namespace
