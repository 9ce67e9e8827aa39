#include "sim/depth_render.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "fg/core/constants.hpp"
#include "sim/sim_rng.hpp"

namespace fg::sim {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

double depth_sigma(const NoiseModel& noise, double z) {
  const double dz = z - noise.sigma_z0;
  return noise.sigma_a + noise.sigma_b * dz * dz;
}

std::vector<double> render_true_depth(const World& world, const Camera& cam, std::vector<double>* cos_incidence,
                                      std::vector<int>* hit_object) {
  const Intrinsics& K = cam.K;
  const size_t n = static_cast<size_t>(std::max(0, K.width)) * static_cast<size_t>(std::max(0, K.height));
  std::vector<double> depth(n, kNaN);
  if (cos_incidence) cos_incidence->assign(n, 0.0);
  if (hit_object) hit_object->assign(n, kHitNothing);
  const Raycaster caster(world);
  const M3& R = cam.world_T_sensor.R;
  const V3& eye = cam.world_T_sensor.t;
  for (int v = 0; v < K.height; ++v) {
    const double ys = (v - K.cy) / K.fy;
    for (int u = 0; u < K.width; ++u) {
      const double xs = (u - K.cx) / K.fx;
      // Direction with unit optical z: the ray parameter is the z depth.
      const V3 d = R * V3(xs, ys, 1.0);
      RayHit hit;
      if (!caster.cast(eye, d, 1e-6, 1e3, hit)) continue;
      const size_t i = static_cast<size_t>(v) * K.width + u;
      depth[i] = hit.t;
      if (cos_incidence) (*cos_incidence)[i] = hit.inside ? 0.0 : std::abs(d.dot(hit.normal)) / d.norm();
      if (hit_object) (*hit_object)[i] = hit.object;
    }
  }
  return depth;
}

DepthImage render_depth(const World& world, const Camera& cam, const NoiseModel& noise, uint64_t seed) {
  std::vector<double> cosi;
  std::vector<int> hit_object;
  const bool by_surface = noise.dark_dropout;
  const std::vector<double> z = render_true_depth(world, cam, &cosi, by_surface ? &hit_object : nullptr);
  const int W = cam.K.width, H = cam.K.height;
  const double cos_limit = std::cos(noise.max_incidence_deg * kPi / 180.0);

  // Validity from geometry alone.
  std::vector<uint8_t> valid(z.size(), 0);
  for (size_t i = 0; i < z.size(); ++i)
    valid[i] = std::isfinite(z[i]) && cosi[i] >= cos_limit && z[i] >= noise.z_min && z[i] <= noise.z_max;

  if (noise.projector_shadow) {
    // Geometry too: the segment from the projector to the surface point must be free.
    const Raycaster caster(world);
    const M3& R = cam.world_T_sensor.R;
    const V3& eye = cam.world_T_sensor.t;
    const V3 projector = eye + R * V3(noise.projector_baseline, 0.0, 0.0);
    for (int v = 0; v < H; ++v) {
      for (int u = 0; u < W; ++u) {
        const size_t i = static_cast<size_t>(v) * W + u;
        if (!valid[i]) continue;
        const V3 p = eye + z[i] * (R * V3((u - cam.K.cx) / cam.K.fx, (v - cam.K.cy) / cam.K.fy, 1.0));
        const V3 d = p - projector;
        const double len = d.norm();
        // Stop 2 mm short of the point so that its own surface does not count.
        RayHit hit;
        if (len > 2e-3 && caster.cast(projector, d, 1e-6, 1.0 - 2e-3 / len, hit)) valid[i] = 0;
      }
    }
  }

  const double steep_span = noise.max_incidence_deg - noise.steep_from_deg;
  DepthImage img;
  img.width = W;
  img.height = H;
  img.mm.assign(z.size(), 0);
  Rng rng(seed);
  for (int v = 0; v < H; ++v) {
    for (int u = 0; u < W; ++u) {
      const size_t i = static_cast<size_t>(v) * W + u;
      if (!valid[i]) continue;
      double zz = z[i];
      if (noise.edge_dropout > 0.0) {
        bool edge = false;
        const int du[4] = {-1, 1, 0, 0}, dv[4] = {0, 0, -1, 1};
        for (int r = 1; r <= std::max(1, noise.edge_band_px) && !edge; ++r) {
          for (int k = 0; k < 4 && !edge; ++k) {
            const int uu = u + r * du[k], vv = v + r * dv[k];
            if (uu < 0 || vv < 0 || uu >= W || vv >= H) continue;
            const size_t j = static_cast<size_t>(vv) * W + uu;
            edge = !std::isfinite(z[j]) || std::abs(z[j] - zz) > noise.edge_jump;
          }
        }
        if (edge && rng.uniform() < noise.edge_dropout) continue;
      }
      if (noise.dark_dropout || noise.steep_dropout) {
        double keep = 1.0;
        if (noise.dark_dropout) {
          const int o = hit_object[i];
          const double albedo = o >= 0           ? world.objects[static_cast<size_t>(o)].albedo
                                : o == kHitTable ? world.table.albedo
                                                 : 1.0;
          const double ret = albedo * cosi[i] / (zz * zz);
          const double drop = (noise.return_full - ret) / (noise.return_full - noise.return_none);
          keep *= 1.0 - std::clamp(drop, 0.0, 1.0);
        }
        if (noise.steep_dropout && steep_span > 0.0) {
          const double incidence_deg = std::acos(std::clamp(cosi[i], 0.0, 1.0)) * 180.0 / kPi;
          keep *= 1.0 - std::clamp((incidence_deg - noise.steep_from_deg) / steep_span, 0.0, 1.0);
        }
        if (rng.uniform() >= keep) continue;
      }
      if (noise.gaussian) zz += depth_sigma(noise, zz) * rng.normal();
      if (noise.quantize && noise.quant_k > 0.0 && zz > 0.0) {
        const double level = std::round((1.0 / zz) / noise.quant_k);
        if (level <= 0.0) continue;
        zz = 1.0 / (level * noise.quant_k);
      }
      if (!(zz >= noise.z_min && zz <= noise.z_max)) continue;
      const double mm = std::round(zz * 1000.0);
      img.mm[i] = static_cast<uint16_t>(std::clamp(mm, 1.0, 65535.0));
    }
  }
  return img;
}

fg::host::PointCloud depth_to_cloud(const DepthImage& depth, const Intrinsics& K) {
  fg::host::PointCloud cloud;
  cloud.width = static_cast<uint32_t>(depth.width);
  cloud.height = static_cast<uint32_t>(depth.height);
  cloud.xyz.assign(static_cast<size_t>(depth.width) * depth.height * 3, std::numeric_limits<float>::quiet_NaN());
  for (int v = 0; v < depth.height; ++v) {
    for (int u = 0; u < depth.width; ++u) {
      const size_t i = static_cast<size_t>(v) * depth.width + u;
      const uint16_t mm = depth.mm[i];
      if (mm == 0) continue;
      const double zz = mm * 1e-3;
      cloud.xyz[3 * i + 0] = static_cast<float>((u - K.cx) * zz / K.fx);
      cloud.xyz[3 * i + 1] = static_cast<float>((v - K.cy) * zz / K.fy);
      cloud.xyz[3 * i + 2] = static_cast<float>(zz);
    }
  }
  return cloud;
}

}  // namespace fg::sim
