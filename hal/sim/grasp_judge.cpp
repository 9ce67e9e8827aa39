#include "sim/grasp_judge.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "fg/core/constants.hpp"

namespace fg::sim {

namespace {

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

// A box in the gripper frame.
struct GBox {
  V3 c;
  V3 h;
  const char* name;
};

// Adaptive test of a gripper box against one object: subdivides until every cell is either
// clear (sdf(centre) - radius >= -tol, valid because the SDFs are 1-Lipschitz), below the
// resolution, or holds a point deeper than tol inside the object.
[[nodiscard]] bool box_hits_object(const Rigid& G, const GBox& box, const Object& obj, double tol, double& depth) {
  struct Cell {
    V3 c, h;
  };
  std::vector<Cell> stack;
  stack.push_back({box.c, box.h});
  const double min_half = 0.25e-3;
  size_t guard = 0;
  while (!stack.empty() && guard < 2'000'000) {
    ++guard;
    const Cell cell = stack.back();
    stack.pop_back();
    const double d = obj.sdf(G.apply(cell.c));
    const double r = cell.h.norm();
    if (d - r >= -tol) continue;
    if (d < -tol) {
      depth = -d;
      return true;
    }
    int axis;
    const double hmax = cell.h.maxCoeff(&axis);
    if (hmax < min_half) continue;
    Cell a = cell, b = cell;
    a.h[axis] *= 0.5;
    b.h[axis] *= 0.5;
    a.c[axis] -= a.h[axis];
    b.c[axis] += b.h[axis];
    stack.push_back(a);
    stack.push_back(b);
  }
  return false;
}

// (a): the open gripper in frame G against the table and every object (the target
// first); "" when clear, else the reason.
[[nodiscard]] std::string open_pose_hit(const World& world, int target, const Rigid& G,
                                        const fg::GripperGeometry& gripper, double tolerance, float& depth_out) {
  const double m = gripper.max_opening_m;
  const double th = gripper.finger_thickness_m;
  const double fw = gripper.finger_width_m;
  const double fd = gripper.finger_depth_m;
  const double pd = gripper.palm_depth_m;
  const double pw = gripper.palm_width_m;
  const GBox boxes[3] = {
      {V3(-(0.5 * m + 0.5 * th), 0, 0), V3(0.5 * th, 0.5 * fw, 0.5 * fd), "left_finger"},
      {V3(+(0.5 * m + 0.5 * th), 0, 0), V3(0.5 * th, 0.5 * fw, 0.5 * fd), "right_finger"},
      {V3(0, 0, -0.5 * fd - 0.5 * pd), V3(0.5 * m + th, 0.5 * pw, 0.5 * pd), "palm"},
  };
  if (world.has_table) {
    for (const GBox& b : boxes) {
      double zmin = std::numeric_limits<double>::infinity();
      for (int k = 0; k < 8; ++k) {
        const V3 corner =
            b.c + V3((k & 1) ? b.h.x() : -b.h.x(), (k & 2) ? b.h.y() : -b.h.y(), (k & 4) ? b.h.z() : -b.h.z());
        zmin = std::min(zmin, G.apply(corner).z());
      }
      const double depth = world.table.height - zmin;
      if (depth > tolerance) {
        depth_out = static_cast<float>(depth);
        return std::string("collision_open_pose:table ") + b.name + fmt(" %.3f", depth);
      }
    }
  }
  // Target first, then the other objects.
  std::vector<int> order{target};
  for (int i = 0; i < static_cast<int>(world.objects.size()); ++i)
    if (i != target) order.push_back(i);
  for (int oi : order) {
    const Object& obj = world.objects[static_cast<size_t>(oi)];
    const Aabb ob = obj.aabb();
    for (const GBox& b : boxes) {
      // Early out: the box's world AABB against the object's.
      Aabb bb;
      for (int k = 0; k < 8; ++k)
        bb.extend(G.apply(
            b.c + V3((k & 1) ? b.h.x() : -b.h.x(), (k & 2) ? b.h.y() : -b.h.y(), (k & 4) ? b.h.z() : -b.h.z())));
      if ((bb.lo.array() > ob.hi.array()).any() || (bb.hi.array() < ob.lo.array()).any()) continue;
      double depth = 0.0;
      if (box_hits_object(G, b, obj, tolerance, depth)) {
        depth_out = static_cast<float>(depth);
        const std::string what = oi == target ? std::string("target") : obj.name;
        return "collision_open_pose:" + what + " " + b.name + fmt(" %.3f", depth);
      }
    }
  }
  return std::string();
}

bool finite(const fg::Vec3& v) { return v.allFinite(); }

// Friction angle of a contact at p (on the surface of obj) pushed along `force`: the angle
// between the force and the inward normal of the faces meeting at p. The normals are the SDF
// gradients at points just inside the surface around p: there they are the normals of the
// nearby faces (at an edge, of both faces, never the bisector the gradient has on the edge
// itself; points on the SDF's creases are skipped). The best face counts: a flat pad on a face beside an edge holds by
// that face, while an edge whose faces are all steep to the closing line (a box's diagonal) fails.
double contact_angle(const Object& obj, const V3& p, const V3& force) {
  constexpr double rho = 0.5e-3;  // sampling radius around the contact
  constexpr double h = 2e-5;      // gradient step
  double best = kPi;
  bool any = false;
  // Directions on a Fibonacci sphere: irregular, so they avoid the symmetry planes of edges.
  constexpr int kSamples = 64;
  for (int k = 0; k < kSamples; ++k) {
    const double cz = 1.0 - (2.0 * k + 1.0) / kSamples;
    const double sz = std::sqrt(std::max(0.0, 1.0 - cz * cz));
    const double phi = 2.399963229728653 * k + 0.3;
    const V3 q = p + rho * V3(sz * std::cos(phi), sz * std::sin(phi), cz);
    const double f0 = obj.sdf(q);
    if (f0 > -0.1 * rho) continue;
    // One-sided differences must agree: a point on a crease of the SDF (the medial plane
    // of an edge, where the gradient is a meaningless mix of two faces) is skipped.
    V3 gp, gm;
    for (int i = 0; i < 3; ++i) {
      gp[i] = (obj.sdf(q + h * V3::Unit(i)) - f0) / h;
      gm[i] = (f0 - obj.sdf(q - h * V3::Unit(i))) / h;
    }
    if (gp.norm() < 0.05 || gm.norm() < 0.05 || gp.normalized().dot(gm.normalized()) < 0.999) continue;
    const V3 n = (gp + gm).normalized();
    any = true;
    best = std::min(best, std::acos(std::clamp(-n.dot(force), -1.0, 1.0)));
  }
  if (!any) {
    const V3 n = obj.normal(p);
    if (n.squaredNorm() > 0.0) best = std::acos(std::clamp(-n.dot(force), -1.0, 1.0));
  }
  return best;
}

// The grasp frame G (x closing, y = z x x, z approach, origin at the grasp's position):
// "" when the grasp's frame is valid, else the reason.
[[nodiscard]] std::string grasp_frame(const Grasp& grasp, double max_frame_skew, Rigid& G) {
  if (!finite(grasp.position) || !finite(grasp.approach) || !finite(grasp.closing) || !std::isfinite(grasp.width))
    return "invalid_grasp non-finite";
  V3 z = to_v3(grasp.approach);
  V3 x = to_v3(grasp.closing);
  if (z.norm() < 1e-6 || x.norm() < 1e-6) return "invalid_grasp zero_vector";
  z.normalize();
  x.normalize();
  if (std::abs(x.dot(z)) > max_frame_skew) return "invalid_grasp closing_not_orthogonal " + fmt("%.3f", x.dot(z));
  x = (x - x.dot(z) * z).normalized();
  const V3 y = z.cross(x);
  G.R.col(0) = x;
  G.R.col(1) = y;
  G.R.col(2) = z;
  G.t = to_v3(grasp.position);
  return std::string();
}

// Where one pad first touches as it closes.
struct PadContact {
  bool touched = false;
  double t = 0.0;  // travel from the open pad face to the target
  V3 p = V3::Zero();
  double other_t = std::numeric_limits<double>::infinity();  // travel to another object
  std::string other;
  double angle = kPi;  // friction angle at the contact
};

// What the closing rays of both pads share.
struct PadRays {
  const World& world;
  int target;
  const Rigid& G;
  const Raycaster& caster;  // the objects only
  double m, fw, fd;         // max opening, finger width and depth
  int ny, nz;               // rays across and along the pad
};

// (b) for one pad (side 0 left, 1 right): rays from the open pad face inwards.
PadContact close_pad(const PadRays& c, int side) {
  const Rigid& G = c.G;
  const double sx = side == 0 ? -1.0 : 1.0;  // pad face at sx * m/2, moving towards -sx
  const V3 dir_world = G.R * V3(-sx, 0, 0);
  PadContact pc;
  struct RayT {
    double t;
    double r2;
    V3 p;
  };
  std::vector<RayT> target_hits;
  for (int iy = 0; iy < c.ny; ++iy) {
    const double yy = -0.5 * c.fw + c.fw * iy / (c.ny - 1);
    for (int iz = 0; iz < c.nz; ++iz) {
      const double zz = -0.5 * c.fd + c.fd * iz / (c.nz - 1);
      const V3 o = G.apply(V3(sx * 0.5 * c.m, yy, zz));
      RayHit hit;
      if (!c.caster.cast(o, dir_world, 0.0, c.m, hit)) continue;
      if (hit.object == c.target) {
        target_hits.push_back({hit.t, yy * yy + zz * zz, o + hit.t * dir_world});
      } else if (hit.t < pc.other_t) {
        pc.other_t = hit.t;
        pc.other = c.world.objects[static_cast<size_t>(hit.object)].name;
      }
    }
  }
  if (target_hits.empty()) return pc;
  double tmin = std::numeric_limits<double>::infinity();
  for (const RayT& r : target_hits) tmin = std::min(tmin, r.t);
  // The pad touches where the rays meet the target first (within 0.2 mm: a flat face
  // touches along many rays). Its friction angle is the best over that contact patch
  // (ties: nearest the pad centre).
  const Object& tobj = c.world.objects[static_cast<size_t>(c.target)];
  const V3 force = -sx * G.R.col(0);  // the pad pushes the object along this
  const RayT* best = nullptr;
  double best_angle = kPi;
  for (const RayT& r : target_hits) {
    if (r.t > tmin + 2e-4) continue;
    const double a = contact_angle(tobj, r.p, force);
    if (!best || a < best_angle - 1e-9 || (a <= best_angle + 1e-9 && r.r2 < best->r2)) {
      best = &r;
      best_angle = std::min(best_angle, a);
    }
  }
  pc.touched = true;
  pc.t = tmin;
  pc.p = best->p;
  pc.angle = best_angle;
  return pc;
}

// (b)'s verdict: "" when each pad first touches the target, else the reason.
[[nodiscard]] std::string closing_failure(const PadContact (&pads)[2]) {
  for (int side = 0; side < 2; ++side) {
    const PadContact& pc = pads[side];
    const char* sname = side == 0 ? "left" : "right";
    if (pc.other_t < (pc.touched ? pc.t : std::numeric_limits<double>::infinity()))
      return std::string("collision_closing:") + pc.other + " " + sname;
  }
  if (!pads[0].touched) return "miss_left";
  if (!pads[1].touched) return "miss_right";
  return std::string();
}

// (c): "" when both contacts are inside the friction cone of mu, else the reason.
[[nodiscard]] std::string friction_failure(const PadContact (&pads)[2], double mu) {
  const double cone = std::atan(mu);
  for (int side = 0; side < 2; ++side) {
    const double angle = pads[side].angle;
    if (angle > cone + 1e-6)
      return std::string(side == 0 ? "friction_left " : "friction_right ") + fmt("%.1fdeg", angle * 180.0 / kPi);
  }
  return std::string();
}

}  // namespace

JudgeResult judge_grasp(const World& world, int target, const Grasp& grasp, const fg::GripperGeometry& gripper,
                        double mu) {
  JudgeOptions o;
  o.mu = mu;
  return judge_grasp(world, target, grasp, gripper, o);
}

JudgeResult judge_grasp(const World& world, int target, const Grasp& grasp, const fg::GripperGeometry& gripper,
                        const JudgeOptions& opt) {
  JudgeResult res;
  if (target < 0 || static_cast<size_t>(target) >= world.objects.size()) {
    res.reason = "invalid_target";
    return res;
  }
  // ---- The grasp frame.
  Rigid G;
  res.reason = grasp_frame(grasp, opt.max_frame_skew, G);
  if (!res.reason.empty()) return res;
  const double m = gripper.max_opening_m;
  if (grasp.width < 0.0f) {
    res.reason = "invalid_grasp negative_width";
    return res;
  }
  if (grasp.width > m + 1e-4) {
    res.reason = "width_exceeds_opening " + fmt("%.3f", grasp.width);
    return res;
  }

  // ---- (a) collisions at the open pose.
  float depth = 0.f;
  res.reason = open_pose_hit(world, target, G, gripper, opt.collision_tolerance, depth);
  if (!res.reason.empty()) {
    res.max_penetration = depth;
    return res;
  }

  // ---- (b) closing: rays from each open pad face inwards. The table is left out: both
  // pads are above it (checked above), so the segment between them is too.
  World objects_only = world;
  objects_only.has_table = false;
  const Raycaster caster(objects_only);
  const PadRays rays{world,
                     target,
                     G,
                     caster,
                     m,
                     gripper.finger_width_m,
                     gripper.finger_depth_m,
                     std::max(2, opt.rays_across),
                     std::max(2, opt.rays_along)};
  const PadContact pads[2] = {close_pad(rays, 0), close_pad(rays, 1)};
  res.reason = closing_failure(pads);
  if (!res.reason.empty()) return res;
  const double xl = -0.5 * m + pads[0].t;
  const double xr = 0.5 * m - pads[1].t;
  res.true_width = static_cast<float>(xr - xl);
  res.contact_left = to_vec3(pads[0].p);
  res.contact_right = to_vec3(pads[1].p);
  if (xr - xl < gripper.min_opening_m) {
    res.reason = "too_narrow " + fmt("%.3f", xr - xl);
    return res;
  }

  // ---- (c) friction cones at the first contacts.
  res.angle_left = static_cast<float>(pads[0].angle);
  res.angle_right = static_cast<float>(pads[1].angle);
  res.reason = friction_failure(pads, opt.mu);
  if (!res.reason.empty()) return res;

  // ---- (d) reported width.
  const double werr = std::abs(static_cast<double>(grasp.width) - (xr - xl));
  if (werr > opt.width_tolerance) {
    res.reason = "width_error " + fmt("%.3f", werr);
    return res;
  }
  res.success = true;
  res.reason = "success";
  return res;
}

std::string open_pose_collision(const World& world, int target, const Grasp& grasp, const fg::GripperGeometry& gripper,
                                double tolerance) {
  V3 z = to_v3(grasp.approach), x = to_v3(grasp.closing);
  if (!finite(grasp.position) || !(z.norm() > 1e-6) || !(x.norm() > 1e-6)) return "invalid_grasp";
  z.normalize();
  x = x - x.dot(z) * z;
  if (!(x.norm() > 1e-6)) return "invalid_grasp";
  x.normalize();
  Rigid G;
  G.R.col(0) = x;
  G.R.col(1) = z.cross(x);
  G.R.col(2) = z;
  G.t = to_v3(grasp.position);
  float depth = 0.f;
  return open_pose_hit(world, target, G, gripper, tolerance, depth);
}

FitReport target_fit(const Object& object, const fg::GripperGeometry& gripper, double margin) {
  std::vector<V3> dirs;
  for (int k = 0; k < 360; ++k) {
    const double a = kPi * k / 360.0;
    dirs.emplace_back(std::cos(a), std::sin(a), 0.0);
  }
  // Exact minima of boxes and cylinders lie along their axes' horizontal projections or
  // perpendicular to them.
  for (const Part& p : object.parts) {
    for (int i = 0; i < 3; ++i) {
      V3 a = p.world_T_shape.R.col(i);
      a.z() = 0.0;
      if (a.norm() < 1e-6) continue;
      a.normalize();
      dirs.push_back(a);
      dirs.emplace_back(-a.y(), a.x(), 0.0);
    }
  }
  FitReport rep;
  rep.min_width = std::numeric_limits<double>::infinity();
  for (const V3& u : dirs) {
    const double w = object.width_along(u);
    if (w < rep.min_width) {
      rep.min_width = w;
      rep.part = -1;
      rep.direction = u;
    }
    for (size_t i = 0; i < object.parts.size(); ++i) {
      if (!object.parts[i].graspable) continue;
      const double wp = object.parts[i].width_along(u);
      if (wp < rep.min_width) {
        rep.min_width = wp;
        rep.part = static_cast<int>(i);
        rep.direction = u;
      }
    }
  }
  rep.fits = rep.min_width <= gripper.max_opening_m - margin;
  return rep;
}

}  // namespace fg::sim
