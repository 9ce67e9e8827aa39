// hal/sim scene generation and export: determinism, the placement and camera rules of every
// kind, the second object, and the scene folder round trip (scene.json, PCDs, truth.json).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "fg/core/constants.hpp"
#include "io/pcd.hpp"
#include "io/scene.hpp"
#include "sim/grasp_judge.hpp"
#include "sim/scene_export.hpp"
#include "sim/scene_gen.hpp"

using namespace fg::sim;

namespace {

using fg::kPi;

std::string temp_dir(const std::string& name) {
  const auto d = std::filesystem::temp_directory_path() / ("fg_test_sim_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  return d.string();
}

}  // namespace

TEST(SimScene, SameSeedSameImages) {
  for (ObjectKind k : {ObjectKind::bottle, ObjectKind::bat_standing}) {
    SceneOptions opt;
    opt.second_object_rate = 1.0;
    const GeneratedScene a = make_scene(k, 77, opt);
    const GeneratedScene b = make_scene(k, 77, opt);
    const SceneImages ia = render_scene(a), ib = render_scene(b);
    EXPECT_EQ(ia.head.mm, ib.head.mm);
    EXPECT_EQ(ia.hand.mm, ib.hand.mm);
    EXPECT_EQ(truth_to_json(a), truth_to_json(b));
    const GeneratedScene c = make_scene(k, 78, opt);
    EXPECT_NE(truth_to_json(a), truth_to_json(c));
    EXPECT_NE(render_scene(c).head.mm, ia.head.mm);
  }
  // The same seed with another kind is another scene.
  EXPECT_NE(make_scene(ObjectKind::can, 5).head.world_T_sensor.t, make_scene(ObjectKind::box, 5).head.world_T_sensor.t);
}

TEST(SimScene, EveryKindFollowsThePlacementRules) {
  for (ObjectKind k : all_kinds()) {
    for (uint64_t seed = 0; seed < 15; ++seed) {
      SceneOptions opt;
      opt.second_object_rate = 0.5;
      const GeneratedScene s = make_scene(k, seed, opt);
      SCOPED_TRACE(std::string(kind_name(k)) + " seed " + std::to_string(seed));
      ASSERT_GE(s.world.objects.size(), 1u);
      ASSERT_EQ(s.target, 0);
      const Object& t = s.world.objects[0];
      EXPECT_EQ(t.kind, kind_name(k));
      const Aabb box = t.aabb();
      EXPECT_NEAR(box.lo.z(), 0.0, 1e-9);  // standing on the table
      const V3 c = box.centre();
      EXPECT_GE(c.x(), 0.4 - 1e-9);
      EXPECT_LE(c.x(), 0.6 + 1e-9);
      EXPECT_GE(c.y(), -0.15 - 1e-9);
      EXPECT_LE(c.y(), 0.15 + 1e-9);
      EXPECT_NEAR((s.truth.target_centre - c).norm(), 0.0, 1e-12);
      const bool expect_fit = !(k == ObjectKind::wide_box || k == ObjectKind::big_sphere);
      EXPECT_EQ(s.truth.target_fits, expect_fit) << s.truth.target_min_width;
      // Head camera.
      const V3 head = s.head.world_T_sensor.t;
      EXPECT_LE(std::abs(head.x()), 0.05 + 1e-9);
      EXPECT_LE(std::abs(head.y()), 0.1 + 1e-9);
      EXPECT_GE(head.z(), 0.75 - 1e-9);
      EXPECT_LE(head.z(), 0.9 + 1e-9);
      EXPECT_NEAR(s.head.world_T_sensor.R.col(2).dot((c - head).normalized()), 1.0, 1e-9);
      // Hand camera: distance, elevation, azimuth offset from the head.
      const V3 hv = s.hand.world_T_sensor.t - c;
      EXPECT_GE(hv.norm(), 0.35 - 1e-9);
      EXPECT_LE(hv.norm(), 0.55 + 1e-9);
      const double el = std::asin(hv.z() / hv.norm()) * 180 / kPi;
      EXPECT_GE(el, 25 - 1e-6);
      EXPECT_LE(el, 60 + 1e-6);
      const double az_hand = std::atan2(hv.y(), hv.x()), az_head = std::atan2(head.y() - c.y(), head.x() - c.x());
      double daz = std::abs(std::remainder(az_hand - az_head, 2 * kPi)) * 180 / kPi;
      EXPECT_GE(daz, 40 - 1e-6);
      EXPECT_LE(daz, 120 + 1e-6);
      EXPECT_NEAR(s.hand.world_T_sensor.R.col(2).dot(-hv.normalized()), 1.0, 1e-9);
      // Objects never overlap the table top.
      for (const Object& o : s.world.objects) EXPECT_GE(o.aabb().lo.z(), -1e-9);
      if (s.world.objects.size() > 1) {
        const Object& o2 = s.world.objects[1];
        const V3 c2 = o2.aabb().centre();
        const double d = std::hypot(c2.x() - c.x(), c2.y() - c.y());
        EXPECT_GE(d, 0.15 - 1e-9);
        EXPECT_LE(d, 0.25 + 1e-9);
        // Never touching: sample the second object's surface against the target's SDF.
        for (const Part& p : o2.parts) {
          for (int i = 0; i < 200; ++i) {
            const double th = 2 * kPi * i / 200;
            const V3 q = p.world_T_shape.t +
                         0.5 * p.width_along(V3(std::cos(th), std::sin(th), 0)) * V3(std::cos(th), std::sin(th), 0);
            EXPECT_GT(t.sdf(q), 0.02);
          }
        }
        EXPECT_GT(std::hypot(c2.x() - 0.5, c2.y()), std::hypot(c.x() - 0.5, c.y()));
      }
    }
  }
}

TEST(SimScene, SecondObjectRateIsRespected) {
  int with = 0;
  for (uint64_t seed = 0; seed < 100; ++seed) with += make_scene(ObjectKind::can, seed).world.objects.size() > 1;
  EXPECT_GT(with, 15);
  EXPECT_LT(with, 45);
  SceneOptions none;
  none.second_object_rate = 0.0;
  for (uint64_t seed = 0; seed < 20; ++seed)
    EXPECT_EQ(make_scene(ObjectKind::can, seed, none).world.objects.size(), 1u);
}

TEST(SimScene, TheTargetIsSeenByBothCameras) {
  for (ObjectKind k : all_kinds()) {
    const GeneratedScene s = make_scene(k, 3);
    std::vector<int> hit;
    render_true_depth(s.world, s.head, nullptr, &hit);
    const int head_px = static_cast<int>(std::count(hit.begin(), hit.end(), 0));
    render_true_depth(s.world, s.hand, nullptr, &hit);
    const int hand_px = static_cast<int>(std::count(hit.begin(), hit.end(), 0));
    EXPECT_GT(head_px, 300) << kind_name(k);
    EXPECT_GT(hand_px, 1500) << kind_name(k);
  }
}

TEST(SimScene, ExportAndReadBack) {
  SceneOptions opt;
  opt.second_object_rate = 1.0;
  const GeneratedScene s = make_scene(ObjectKind::spray_bottle, 12, opt);
  const std::string dir = temp_dir("export");
  const SceneImages images = render_scene(s);
  const fg::host::ReadResult w = export_scene(s, images, dir);
  ASSERT_TRUE(w.ok) << w.error;

  // truth.json
  GeneratedScene back;
  const fg::host::ReadResult r = read_truth(dir + "/truth.json", back);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(back.kind, s.kind);
  EXPECT_EQ(back.seed, s.seed);
  EXPECT_EQ(back.target, s.target);
  ASSERT_EQ(back.world.objects.size(), s.world.objects.size());
  for (size_t i = 0; i < s.world.objects.size(); ++i) {
    const Object &a = s.world.objects[i], &b = back.world.objects[i];
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.kind, b.kind);
    ASSERT_EQ(a.parts.size(), b.parts.size());
    for (size_t j = 0; j < a.parts.size(); ++j) {
      EXPECT_EQ(a.parts[j].name, b.parts[j].name);
      EXPECT_EQ(a.parts[j].shape, b.parts[j].shape);
      EXPECT_EQ(a.parts[j].graspable, b.parts[j].graspable);
      EXPECT_EQ(a.parts[j].size, b.parts[j].size);
      EXPECT_EQ(a.parts[j].world_T_shape.R, b.parts[j].world_T_shape.R);
      EXPECT_EQ(a.parts[j].world_T_shape.t, b.parts[j].world_T_shape.t);
    }
  }
  EXPECT_EQ(back.world.table.height, s.world.table.height);
  EXPECT_EQ(back.world.table.x_max, s.world.table.x_max);
  EXPECT_EQ(back.truth.target_fits, s.truth.target_fits);
  EXPECT_EQ(back.truth.target_min_width, s.truth.target_min_width);
  EXPECT_EQ(back.gripper.max_opening_m, s.gripper.max_opening_m);
  EXPECT_EQ(back.gripper.palm_width_m, s.gripper.palm_width_m);
  EXPECT_EQ(back.head.world_T_sensor.R, s.head.world_T_sensor.R);
  EXPECT_EQ(back.hand.world_T_sensor.t, s.hand.world_T_sensor.t);
  EXPECT_EQ(back.hand_noise_seed, s.hand_noise_seed);
  // The world read back renders the same images.
  EXPECT_EQ(render_scene(back).head.mm, images.head.mm);

  // scene.json: the contract's manifest.
  fg::host::Scene scene;
  const fg::host::ReadResult rs = fg::host::read_scene(dir + "/scene.json", scene);
  ASSERT_TRUE(rs.ok) << rs.error;
  ASSERT_EQ(scene.sensors.size(), 2u);
  EXPECT_EQ(scene.sensors[0].name, "head");
  EXPECT_EQ(scene.sensors[1].name, "hand");
  EXPECT_DOUBLE_EQ(scene.gripper.max_opening, 0.085);
  EXPECT_DOUBLE_EQ(scene.gripper.finger_width, 0.022);
  EXPECT_DOUBLE_EQ(scene.gripper.finger_depth, 0.040);
  ASSERT_TRUE(scene.sensors[1].pose.has_value());
  for (int i = 0; i < 3; ++i) {
    EXPECT_DOUBLE_EQ(scene.sensors[1].pose->position[static_cast<size_t>(i)], s.hand.world_T_sensor.t[i]);
    for (int j = 0; j < 3; ++j)
      EXPECT_DOUBLE_EQ(scene.sensors[1].pose->rotation[static_cast<size_t>(i)][static_cast<size_t>(j)],
                       s.hand.world_T_sensor.R(i, j));
  }

  // The clouds: organized 640x480 in the optical frame, NaN for missing pixels.
  for (int k = 0; k < 2; ++k) {
    fg::host::PointCloud cloud;
    const fg::host::ReadResult rp = fg::host::read_pcd(scene.sensors[static_cast<size_t>(k)].cloud_path, cloud);
    ASSERT_TRUE(rp.ok) << rp.error;
    EXPECT_EQ(cloud.width, 640u);
    EXPECT_EQ(cloud.height, 480u);
    const DepthImage& img = k == 0 ? images.head : images.hand;
    const fg::host::PointCloud expect = depth_to_cloud(img, s.head.K);
    ASSERT_EQ(cloud.xyz.size(), expect.xyz.size());
    size_t same = 0;
    for (size_t i = 0; i < cloud.xyz.size(); ++i)
      same += (cloud.xyz[i] == expect.xyz[i]) || (std::isnan(cloud.xyz[i]) && std::isnan(expect.xyz[i]));
    EXPECT_EQ(same, cloud.xyz.size());
    // Transformed to world, the points lie on the true surfaces (within the noise).
    const Rigid& T = k == 0 ? s.head.world_T_sensor : s.hand.world_T_sensor;
    int checked = 0;
    for (size_t i = 0; i < cloud.size(); i += 97) {
      if (std::isnan(cloud.xyz[3 * i])) continue;
      const V3 p = T.apply(V3(cloud.xyz[3 * i], cloud.xyz[3 * i + 1], cloud.xyz[3 * i + 2]));
      double d = std::abs(p.z() - s.world.table.height);
      for (const Object& o : s.world.objects) d = std::min(d, std::abs(o.sdf(p)));
      EXPECT_LT(d, 0.015);
      ++checked;
    }
    EXPECT_GT(checked, 1000);
  }
  std::filesystem::remove_all(dir);
}

TEST(SimScene, ReadTruthRejectsBadFiles) {
  GeneratedScene out;
  EXPECT_FALSE(parse_truth("{", "x", out).ok);
  EXPECT_FALSE(parse_truth("{\"format\": \"other\"}", "x", out).ok);
  EXPECT_FALSE(parse_truth("{\"format\": \"forcegrasp-sim-truth\"}", "x", out).ok);
  std::string good = truth_to_json(make_scene(ObjectKind::can, 1));
  EXPECT_TRUE(parse_truth(good, "x", out).ok);
  const std::string bad = std::string(good).replace(good.find("\"target\": 0"), 11, "\"target\": 5");
  EXPECT_FALSE(parse_truth(bad, "x", out).ok);
  EXPECT_FALSE(read_truth("/nonexistent/truth.json", out).ok);
}

TEST(SimScene, AGoodGraspExistsOnFittingTargets) {
  // Sanity of generator + judge together: a top-down grasp across the narrow direction of
  // an upright box, at its top, passes on every seed.
  for (uint64_t seed = 0; seed < 10; ++seed) {
    const GeneratedScene s = make_scene(ObjectKind::box, seed);
    const Object& t = s.world.objects[0];
    const Part& body = t.parts[0];
    const V3 narrow = body.world_T_shape.R.col(0);
    const double top = t.aabb().hi.z();
    Grasp g;
    g.position = V3(body.world_T_shape.t.x(), body.world_T_shape.t.y(), top + 0.015).cast<float>();
    g.approach = fg::Vec3(0, 0, -1);
    g.closing = narrow.cast<float>();
    g.width = static_cast<float>(2 * body.size.x());
    const JudgeResult r = judge_grasp(s.world, s.target, g, s.gripper);
    EXPECT_TRUE(r.success) << "seed " << seed << ": " << r.reason;
  }
}
