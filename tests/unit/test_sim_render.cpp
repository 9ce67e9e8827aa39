// hal/sim depth rendering: analytic plane depth, noise statistics and quantization, the
// pinhole silhouette size, the validity limits, the cloud conversion, the structured-light
// effects (edge band, projector shadows, dark and steep surfaces), and the render time.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>

#include "sim/depth_render.hpp"
#include "sim/scene_gen.hpp"

using namespace fg::sim;

namespace {

World big_table_world() {
  World w;
  w.table.x_min = -3;
  w.table.x_max = 4;
  w.table.y_min = -4;
  w.table.y_max = 4;
  return w;
}

Camera down_camera(double height) {
  Camera c;
  c.world_T_sensor = look_at(V3(0.5, 0, height), V3(0.5, 0, 0), V3(1, 0, 0));
  return c;
}

}  // namespace

TEST(SimRender, PlaneFacingTheCameraHasItsDistance) {
  const World w = big_table_world();
  const Camera cam = down_camera(1.0);
  const DepthImage img = render_depth(w, cam, NoiseModel::none(), 1);
  ASSERT_EQ(img.width, 640);
  ASSERT_EQ(img.height, 480);
  for (uint16_t v : img.mm) ASSERT_EQ(v, 1000);
}

TEST(SimRender, TiltedPlaneMatchesAnalyticDepth) {
  const World w = big_table_world();
  Camera cam;
  cam.world_T_sensor = look_at(V3(-0.3, 0.1, 0.9), V3(0.6, -0.1, 0.0));
  const DepthImage img = render_depth(w, cam, NoiseModel::none(), 1);
  // The plane z = 0 in the sensor frame: n_s . p = c_s.
  const M3& R = cam.world_T_sensor.R;
  const V3 n_s = R.transpose() * V3(0, 0, 1);
  const double c_s = -cam.world_T_sensor.t.z();  // n . (R p + t) = 0
  int valid = 0;
  for (int v = 0; v < img.height; v += 3) {
    for (int u = 0; u < img.width; u += 3) {
      const V3 ray((u - cam.K.cx) / cam.K.fx, (v - cam.K.cy) / cam.K.fy, 1.0);
      const double z = c_s / n_s.dot(ray);
      const double cosi = std::abs(n_s.dot(ray.normalized()));
      const bool expect_valid = z > 0.35 && z < 3.5 && cosi > std::cos(78.0 * M_PI / 180.0) + 1e-6;
      const uint16_t mm = img.at(u, v);
      if (expect_valid) {
        ASSERT_NE(mm, 0) << u << "," << v;
        EXPECT_NEAR(mm * 1e-3, z, 0.5e-3 + 1e-9) << u << "," << v;
        ++valid;
      } else if (cosi < std::cos(78.0 * M_PI / 180.0) - 1e-3 || z > 3.5 + 1e-3 || z < 0) {
        EXPECT_EQ(mm, 0) << u << "," << v;
      }
    }
  }
  EXPECT_GT(valid, 20000);
}

TEST(SimRender, GrazingAndOutOfRangePixelsAreMissing) {
  const World w = big_table_world();
  // Nearly horizontal view: far pixels exceed 78 degrees incidence or 3.5 m.
  Camera cam;
  cam.world_T_sensor = look_at(V3(-2.5, 0, 0.3), V3(0, 0, 0));
  const DepthImage img = render_depth(w, cam, NoiseModel::none(), 1);
  // The row through the image centre looks at the plane at 0.3/|p| ~ 6.8 deg grazing angle:
  // the incidence is ~83 deg, so no return there.
  EXPECT_EQ(img.at(320, 240), 0);
  // Too close.
  const DepthImage close = render_depth(w, down_camera(0.3), NoiseModel::none(), 1);
  for (uint16_t v : close.mm) ASSERT_EQ(v, 0);
}

TEST(SimRender, NoiseStatisticsFollowTheModel) {
  const World w = big_table_world();
  const Camera cam = down_camera(1.0);
  NoiseModel n = NoiseModel::none();
  n.gaussian = true;
  const DepthImage img = render_depth(w, cam, n, 7);
  double sum = 0, sum2 = 0;
  for (uint16_t v : img.mm) {
    const double e = v * 1e-3 - 1.0;
    sum += e;
    sum2 += e * e;
  }
  const double cnt = static_cast<double>(img.mm.size());
  const double mean = sum / cnt;
  const double sd = std::sqrt(sum2 / cnt - mean * mean);
  const double sigma = depth_sigma(n, 1.0);
  EXPECT_NEAR(sigma, 1.2e-3 + 1.9e-3 * 0.36, 1e-12);
  const double expected = std::sqrt(sigma * sigma + 1e-6 / 12.0);  // + millimetre rounding
  EXPECT_NEAR(sd, expected, 0.03 * expected);
  EXPECT_NEAR(mean, 0.0, 0.05e-3);
  // Different seeds, different noise; the same seed, the same image.
  EXPECT_NE(render_depth(w, cam, n, 8).mm, img.mm);
  EXPECT_EQ(render_depth(w, cam, n, 7).mm, img.mm);
}

TEST(SimRender, DisparityQuantizationLevels) {
  const World w = big_table_world();
  Camera cam;
  cam.world_T_sensor = look_at(V3(-0.2, 0, 1.2), V3(0.7, 0, 0));
  NoiseModel n;  // full model
  n.edge_dropout = 0.0;
  const DepthImage img = render_depth(w, cam, n, 3);
  std::set<uint16_t> values(img.mm.begin(), img.mm.end());
  values.erase(0);
  ASSERT_GT(values.size(), 20u);
  for (uint16_t v : values) {
    // v must be a rounded disparity level 1 / (k * level).
    const double level = std::round(1.0 / (v * 1e-3 * n.quant_k));
    EXPECT_NEAR(1.0 / (level * n.quant_k), v * 1e-3, 0.5e-3 + 1e-9) << v;
  }
  // At 2 m the step is 2.85e-3 * 4 = 11.4 mm: neighbouring values there are ~11 mm apart.
  auto it = values.lower_bound(2000);
  ASSERT_NE(it, values.end());
  const uint16_t a = *it;
  ASSERT_NE(++it, values.end());
  EXPECT_NEAR(*it - a, 2.85e-3 * (a * 1e-3) * (a * 1e-3) * 1000, 1.5);
}

TEST(SimRender, BoxSilhouetteHasThePinholeSize) {
  World w = big_table_world();
  Object box;
  box.name = "box";
  box.parts.push_back(Part::box("b", V3(0.05, 0.03, 0.05), Rigid::translation(V3(0.5, 0, 0.05))));
  w.objects.push_back(box);
  const Camera cam = down_camera(1.0);  // image u = world -y, image v = world -x
  const DepthImage img = render_depth(w, cam, NoiseModel::none(), 1);
  int count_u = 0, count_v = 0, area = 0;
  for (int u = 0; u < 640; ++u) count_u += img.at(u, 240) == 900 ? 1 : 0;
  for (int v = 0; v < 480; ++v) count_v += img.at(320, v) == 900 ? 1 : 0;
  for (uint16_t v : img.mm) area += v == 900 ? 1 : 0;
  const double wu = 0.06 * 525.0 / 0.9, wv = 0.10 * 525.0 / 0.9;
  EXPECT_NEAR(count_u, wu, 1.0);
  EXPECT_NEAR(count_v, wv, 1.0);
  EXPECT_NEAR(area, wu * wv, wu + wv);
}

TEST(SimRender, CloudConversionInvertsTheProjection) {
  World w = big_table_world();
  w.objects.push_back(make_object(ObjectKind::can, 5));
  Camera cam;
  cam.world_T_sensor = look_at(V3(-0.1, 0.3, 0.7), V3(0.0, 0.0, 0.05));
  const DepthImage img = render_depth(w, cam, NoiseModel(), 11);
  const fg::host::PointCloud cloud = depth_to_cloud(img, cam.K);
  ASSERT_EQ(cloud.width, 640u);
  ASSERT_EQ(cloud.height, 480u);
  ASSERT_EQ(cloud.size(), 640u * 480u);
  int missing = 0;
  for (int v = 0; v < 480; v += 7) {
    for (int u = 0; u < 640; u += 5) {
      const size_t i = static_cast<size_t>(v) * 640 + u;
      const float* p = &cloud.xyz[3 * i];
      if (img.mm[i] == 0) {
        EXPECT_TRUE(std::isnan(p[0]) && std::isnan(p[1]) && std::isnan(p[2]));
        ++missing;
        continue;
      }
      EXPECT_NEAR(p[2], img.mm[i] * 1e-3, 1e-6);
      EXPECT_NEAR(cam.K.fx * p[0] / p[2] + cam.K.cx, u, 1e-3);
      EXPECT_NEAR(cam.K.fy * p[1] / p[2] + cam.K.cy, v, 1e-3);
    }
  }
  EXPECT_GT(missing, 0);  // the can's silhouette edges drop some pixels
}

TEST(SimRender, EdgeDropoutsHitDepthEdgesOnly) {
  World w = big_table_world();
  Object box;
  box.parts.push_back(Part::box("b", V3(0.05, 0.05, 0.1), Rigid::translation(V3(0.5, 0, 0.1))));
  w.objects.push_back(box);
  NoiseModel n = NoiseModel::none();
  n.edge_dropout = 0.5;
  const DepthImage clean = render_depth(w, down_camera(1.0), NoiseModel::none(), 1);
  const DepthImage img = render_depth(w, down_camera(1.0), n, 1);
  int dropped = 0;
  for (int v = 1; v < 479; ++v)
    for (int u = 1; u < 639; ++u) {
      if (clean.at(u, v) == 0 || img.at(u, v) != 0) continue;
      ++dropped;
      bool edge = false;
      for (int k = -1; k <= 1; ++k)
        edge = edge || clean.at(u + k, v) != clean.at(u, v) || clean.at(u, v + k) != clean.at(u, v);
      EXPECT_TRUE(edge) << u << "," << v;
    }
  EXPECT_GT(dropped, 100);
  EXPECT_LT(dropped, 400);
}

TEST(SimRender, EdgeDropoutsReachTheBand) {
  World w = big_table_world();
  Object box;
  box.parts.push_back(Part::box("b", V3(0.05, 0.05, 0.1), Rigid::translation(V3(0.5, 0, 0.1))));
  w.objects.push_back(box);
  NoiseModel n = NoiseModel::none();
  n.edge_dropout = 0.5;
  n.edge_band_px = 2;
  const DepthImage clean = render_depth(w, down_camera(1.0), NoiseModel::none(), 1);
  const DepthImage img = render_depth(w, down_camera(1.0), n, 1);
  int dropped = 0, second_pixel = 0;
  for (int v = 2; v < 478; ++v)
    for (int u = 2; u < 638; ++u) {
      if (clean.at(u, v) == 0 || img.at(u, v) != 0) continue;
      ++dropped;
      const auto edge_at = [&](int r) {
        return clean.at(u - r, v) != clean.at(u, v) || clean.at(u + r, v) != clean.at(u, v) ||
               clean.at(u, v - r) != clean.at(u, v) || clean.at(u, v + r) != clean.at(u, v);
      };
      EXPECT_TRUE(edge_at(1) || edge_at(2)) << u << "," << v;
      second_pixel += !edge_at(1) ? 1 : 0;
    }
  EXPECT_GT(second_pixel, 100);  // the band's second pixel drops too
  EXPECT_LT(dropped, 1000);
}

TEST(SimRender, ProjectorShadowsFallBesideNearerSurfaces) {
  // A 0.2 m box under a camera 1 m up: the projector, 7.5 cm along the optical x axis,
  // cannot light a band of table f b (1/z_near - 1/z_far) = 525 x 0.075 x (1/0.8 - 1) ~ 10
  // pixels wide on the box's side away from it, as long as the box's top edge looks
  // (0.1 m at 0.8 m: 66 pixels).
  World w = big_table_world();
  Object box;
  box.parts.push_back(Part::box("b", V3(0.05, 0.05, 0.1), Rigid::translation(V3(0.5, 0, 0.1))));
  w.objects.push_back(box);
  const Camera cam = down_camera(1.0);
  NoiseModel n = NoiseModel::none();
  n.projector_shadow = true;
  const DepthImage clean = render_depth(w, cam, NoiseModel::none(), 1);
  const DepthImage img = render_depth(w, cam, n, 1);
  int shadow = 0, box_left = 640;
  for (int v = 0; v < 480; ++v)
    for (int u = 0; u < 640; ++u)
      if (clean.at(u, v) == 800) box_left = std::min(box_left, u);
  for (int v = 0; v < 480; ++v)
    for (int u = 0; u < 640; ++u) {
      if (clean.at(u, v) == img.at(u, v)) continue;
      ++shadow;
      EXPECT_EQ(img.at(u, v), 0);
      EXPECT_EQ(clean.at(u, v), 1000) << "only the table is shadowed";
      EXPECT_LT(u, box_left) << "on the side away from the projector";
      EXPECT_GE(u, box_left - 11);
    }
  EXPECT_GT(shadow, 9 * 64);
  EXPECT_LT(shadow, 11 * 68);
}

TEST(SimRender, DarkSurfacesLoseReturns) {
  // Two boxes' tops 1 m from the camera: albedo 0.05 returns 0.05 cos(i) / 1^2, dropped with
  // probability (0.08 - 0.05) / (0.08 - 0.01) = 0.43; white returns all, the table too.
  World w = big_table_world();
  w.table.height = -0.3;
  for (int k = 0; k < 2; ++k) {
    Object box;
    box.parts.push_back(Part::box("b", V3(0.08, 0.08, 0.15), Rigid::translation(V3(0.5, k ? 0.1 : -0.1, -0.15))));
    box.albedo = k ? 1.0 : 0.05;
    w.objects.push_back(box);
  }
  const Camera cam = down_camera(1.0);
  NoiseModel n = NoiseModel::none();
  n.dark_dropout = true;
  const DepthImage img = render_depth(w, cam, n, 5);
  std::vector<int> hit;
  std::vector<double> cosi;
  render_true_depth(w, cam, &cosi, &hit);
  int seen[3] = {0, 0, 0}, kept[3] = {0, 0, 0};
  for (size_t i = 0; i < hit.size(); ++i) {
    const int which = hit[i] == 0 ? 0 : hit[i] == 1 ? 1 : 2;
    // The tops only: the boxes' sides, seen almost edge-on, return little whatever their albedo.
    if (hit[i] == kHitNothing || (which < 2 && cosi[i] < 0.9)) continue;
    ++seen[which];
    kept[which] += img.mm[i] != 0 ? 1 : 0;
  }
  ASSERT_GT(seen[0], 5000);
  EXPECT_NEAR(1.0 - static_cast<double>(kept[0]) / seen[0], 0.43, 0.03);
  EXPECT_EQ(kept[1], seen[1]);
  EXPECT_EQ(kept[2], seen[2]);  // the table at 1.3 m: 1 / 1.69 still returns enough
}

TEST(SimRender, SteepSurfacesThinOutBeforeTheLimit) {
  const World w = big_table_world();
  Camera cam;
  cam.world_T_sensor = look_at(V3(-0.3, 0, 0.7), V3(1.2, 0, 0));
  NoiseModel n = NoiseModel::none();
  n.steep_dropout = true;
  const DepthImage img = render_depth(w, cam, n, 9);
  std::vector<double> cosi;
  render_true_depth(w, cam, &cosi, nullptr);
  // Kept share by incidence: all below 60 deg, then 1 - (i - 60) / 18.
  int seen[3] = {0, 0, 0}, kept[3] = {0, 0, 0};
  for (size_t i = 0; i < cosi.size(); ++i) {
    const double inc = std::acos(std::clamp(cosi[i], 0.0, 1.0)) * 180.0 / M_PI;
    const int bin = inc < 58 ? 0 : (inc > 63 && inc < 65) ? 1 : (inc > 71 && inc < 73) ? 2 : -1;
    if (bin < 0 || !(img.mm[i] != 0 || cosi[i] > 0)) continue;
    ++seen[bin];
    kept[bin] += img.mm[i] != 0 ? 1 : 0;
  }
  ASSERT_GT(seen[0], 1000);
  ASSERT_GT(seen[1], 1000);
  ASSERT_GT(seen[2], 1000);
  EXPECT_EQ(kept[0], seen[0]);
  EXPECT_NEAR(static_cast<double>(kept[1]) / seen[1], 1.0 - 4.0 / 18.0, 0.04);
  EXPECT_NEAR(static_cast<double>(kept[2]) / seen[2], 1.0 - 12.0 / 18.0, 0.04);
}

TEST(SimRender, RendersTableAndTwoObjects) {
  // Speed is the benchmarks' business; the time is printed for information only
  // (about 25 ms per 640x480 image in Release on the development machine).
  SceneOptions opt;
  opt.second_object_rate = 1.0;
  const GeneratedScene s = make_scene(ObjectKind::bottle, 3, opt);
  ASSERT_EQ(s.world.objects.size(), 2u);
  const auto t0 = std::chrono::steady_clock::now();
  const DepthImage img = render_depth(s.world, s.head, s.noise, 1);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::printf("render 640x480 (table + 2 objects): %.1f ms\n", ms);
  int valid = 0;
  for (uint16_t v : img.mm) valid += v != 0 ? 1 : 0;
  EXPECT_GT(valid, 100000);
  // Both objects are visible from the head camera.
  std::vector<int> hit;
  render_true_depth(s.world, s.head, nullptr, &hit);
  EXPECT_GT(std::count(hit.begin(), hit.end(), 0), 200);
  EXPECT_GT(std::count(hit.begin(), hit.end(), 1), 50);
}
