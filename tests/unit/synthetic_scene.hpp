// Synthetic world-frame scenes shared by the planner tests: a table top at z = 0 and
// boxes standing on it, sampled with a seeded jitter (the draw order is part of each
// test's scene); and an upright can's wall as a camera in front of it sees it,
// noise-free.
#pragma once
#include <cmath>
#include <random>
#include <vector>

#include "fg/core/constants.hpp"
#include "fg/core/types.hpp"

namespace fg::test {

using fg::kPi;

// A point from double coordinates (the constructed scenes are laid out in double).
inline fg::Vec3 v3(double x, double y, double z) {
  return fg::Vec3(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
}

// The pose (world_T_sensor) of a sensor at `eye` looking at `target`, in the optical
// frame: z forward, x right and horizontal, y down (x along world x when looking
// straight down).
inline fg::Pose look_at(const fg::Vec3& eye, const fg::Vec3& target) {
  const fg::Vec3 z = (target - eye).normalized();
  fg::Vec3 x = z.cross(fg::Vec3::UnitZ());
  if (x.norm() < 1e-6f) x = fg::Vec3::UnitX();
  x.normalize();
  fg::Pose p;
  p.R.col(0) = x;
  p.R.col(1) = z.cross(x);
  p.R.col(2) = z;
  p.t = eye;
  return p;
}

// A 0.8 x 0.8 table top centred at (0.5, 0) at z = 0, sampled every `step` with a
// small jitter, leaving out the footprint [x0, x1] x [y0, y1] (hidden under an object).
inline void add_table(std::vector<fg::Vec3>& pts, std::mt19937& rng, float step, float x0 = 1, float x1 = 0,
                      float y0 = 1, float y1 = 0) {
  std::uniform_real_distribution<float> j(-0.3f * step, 0.3f * step);
  for (float x = 0.1f + 0.5f * step; x < 0.9f; x += step)
    for (float y = -0.4f + 0.5f * step; y < 0.4f; y += step) {
      const float px = x + j(rng), py = y + j(rng);
      if (px >= x0 && px <= x1 && py >= y0 && py <= y1) continue;
      pts.push_back(fg::Vec3(px, py, 0.f));
    }
}

// The five visible faces of an axis-aligned box standing on z = 0 (sizes sx, sy, sz),
// centred at (cx, cy), sampled every `step`.
inline void add_box(std::vector<fg::Vec3>& pts, std::mt19937& rng, float cx, float cy, float sx, float sy, float sz,
                    float step) {
  std::uniform_real_distribution<float> u(0.f, 1.f);
  auto face = [&](const fg::Vec3& o, const fg::Vec3& a, const fg::Vec3& b) {
    const int na = static_cast<int>(std::ceil(a.norm() / step)), nb = static_cast<int>(std::ceil(b.norm() / step));
    for (int i = 0; i < na; ++i)
      for (int k = 0; k < nb; ++k)
        pts.push_back(o + a * ((static_cast<float>(i) + u(rng)) / static_cast<float>(na)) +
                      b * ((static_cast<float>(k) + u(rng)) / static_cast<float>(nb)));
  };
  const fg::Vec3 lo(cx - 0.5f * sx, cy - 0.5f * sy, 0.f);
  const fg::Vec3 X(sx, 0, 0), Y(0, sy, 0), Z(0, 0, sz);
  face(lo + Z, X, Y);  // top
  face(lo, X, Z);      // y = min
  face(lo + Y, X, Z);  // y = max
  face(lo, Y, Z);      // x = min
  face(lo + X, Y, Z);  // x = max
}

// The wall of an upright can (radius r, height h, centre (cx, cy)) within `half` (rad)
// of -x, the part a camera in front of it sees before its rays graze the rest: arcs one
// `step` apart, rows one `step` apart from z = 0 to h, noise-free (double precision).
inline void add_can_wall_facing_minus_x(std::vector<fg::Vec3>& pts, double cx, double cy, double r, double h,
                                        double half, double step) {
  const int nz = static_cast<int>(std::lround(h / step));
  const int na = static_cast<int>(std::lround(2.0 * half * r / step));
  for (int k = 0; k <= na; ++k) {
    const double a = kPi - half + 2.0 * half * k / na;
    for (int j = 0; j <= nz; ++j)
      pts.push_back(fg::Vec3(static_cast<float>(cx + r * std::cos(a)), static_cast<float>(cy + r * std::sin(a)),
                             static_cast<float>(h * j / nz)));
  }
}

}  // namespace fg::test
