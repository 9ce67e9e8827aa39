// The tool along the executed joint path against the support plane and the scene
// points (path_check.hpp).
#include "fg/robot/path_check.hpp"

#include <algorithm>
#include <cmath>

namespace fg::robot {
namespace {

using V3d = Eigen::Vector3d;

struct ToolBox {
  V3d lo, hi;           // in the grasp frame (origin at the pads' centre, z approach)
  double point_shrink;  // against the scene points
  double plane_shrink;  // against the support plane
};

// Open fingers, palm and the body behind it, as ToolCollision has them.
uint32_t tool_boxes(const ToolGeometry& tool, const PathCheckConfig& cfg, ToolBox out[4]) {
  const GripperGeometry& g = tool.gripper;
  const double ho = 0.5 * g.max_opening_m, t = g.finger_thickness_m, hfd = 0.5 * g.finger_depth_m;
  const double hfw = 0.5 * g.finger_width_m, hpw = 0.5 * g.palm_width_m, bw = tool.body_half_width_m;
  const double palm_back = -hfd - g.palm_depth_m;
  const double pt = cfg.point_tolerance_m;
  out[0] = {V3d(-ho - t, -hfw, -hfd), V3d(-ho, hfw, hfd), pt, 0.0};
  out[1] = {V3d(ho, -hfw, -hfd), V3d(ho + t, hfw, hfd), pt, 0.0};
  out[2] = {V3d(-ho - t, -hpw, palm_back), V3d(ho + t, hpw, -hfd), pt, 0.0};
  if (!(tool.tcp_offset_m > -palm_back)) return 3u;  // the palm is the flange: no body
  out[3] = {V3d(-bw, -bw, -static_cast<double>(tool.tcp_offset_m)), V3d(bw, bw, palm_back), tool.tolerance_m,
            tool.tolerance_m};
  return 4u;
}

struct Scene {
  const uint32_t* idx = nullptr;  // the kept points' indices, when gathered
  uint32_t n_idx = 0;
  bool has_plane = false;
  V3d n = V3d::UnitZ();
  double d = 0.0;
  bool has_points = false;
  V3d lo, hi;  // the kept points' bounds
};

bool kept(const GraspQuery& q, uint32_t i) {
  return (q.scene_keep == nullptr || q.scene_keep[i] != 0) && q.scene_points[i].allFinite();
}

Scene make_scene(const GraspQuery& q, uint32_t* scratch, uint32_t capacity) {
  Scene s;
  if (q.support != nullptr && q.support->n.allFinite() && std::isfinite(q.support->d) &&
      q.support->n.norm() > 0.5f) {
    s.has_plane = true;
    const double len = q.support->n.cast<double>().norm();
    s.n = q.support->n.cast<double>() / len;
    s.d = static_cast<double>(q.support->d) / len;
  }
  if (q.scene_points != nullptr) {
    s.lo = V3d::Constant(1e30);
    s.hi = V3d::Constant(-1e30);
    uint32_t n_kept = 0;
    for (uint32_t i = 0; i < q.n_scene_points; ++i) {
      if (!kept(q, i)) continue;
      const V3d p = q.scene_points[i].cast<double>();
      s.lo = s.lo.cwiseMin(p);
      s.hi = s.hi.cwiseMax(p);
      s.has_points = true;
      if (scratch != nullptr && n_kept < capacity) scratch[n_kept] = i;
      ++n_kept;
    }
    if (scratch != nullptr && n_kept <= capacity) {
      s.idx = scratch;
      s.n_idx = n_kept;
    }
  }
  return s;
}

// The tool at joints qs against the scene.
PathHit pose_hit(const MotionConfig& motion, const PathCheckConfig& cfg,
                 const ToolBox* boxes, uint32_t n_boxes, const Scene& scene, const GraspQuery& q,
                 const double qs[6]) {
  PoseD base_T_tool0;
  if (!ur5_forward_d(motion.robot, qs, base_T_tool0)) return PathHit::invalid;
  const PoseD w = compose(to_d(motion.world_T_base), base_T_tool0);
  const Eigen::Matrix3d& R = w.R;
  const V3d origin = w.t + R.col(2) * static_cast<double>(motion.tcp_offset_m);
  V3d lo = V3d::Constant(1e30), hi = V3d::Constant(-1e30);
  for (uint32_t b = 0; b < n_boxes; ++b) {
    const ToolBox& box = boxes[b];
    double h_min = 1e30;
    for (int k = 0; k < 8; ++k) {
      const V3d c((k & 1) ? box.hi.x() : box.lo.x(), (k & 2) ? box.hi.y() : box.lo.y(),
                  (k & 4) ? box.hi.z() : box.lo.z());
      const V3d p = origin + R * c;
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
      if (scene.has_plane) h_min = std::min(h_min, scene.n.dot(p) + scene.d);
    }
    // The lowest corner of the box shrunk by plane_shrink along each of its axes.
    if (scene.has_plane) {
      const double shrink = box.plane_shrink * (R.transpose() * scene.n).cwiseAbs().sum();
      const double clearance = box.plane_shrink > 0.0 ? 0.0 : static_cast<double>(cfg.plane_clearance_m);
      if (h_min + shrink < clearance) return PathHit::support_plane;
    }
  }
  if (!scene.has_points) return PathHit::none;
  if ((lo.array() > scene.hi.array()).any() || (hi.array() < scene.lo.array()).any()) return PathHit::none;
  const Eigen::Matrix3d Rt = R.transpose();
  const uint32_t n = scene.idx != nullptr ? scene.n_idx : q.n_scene_points;
  for (uint32_t k = 0; k < n; ++k) {
    const uint32_t i = scene.idx != nullptr ? scene.idx[k] : k;
    if (scene.idx == nullptr && !kept(q, i)) continue;
    const V3d p = q.scene_points[i].cast<double>();
    if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any()) continue;
    const V3d l = Rt * (p - origin);
    for (uint32_t b = 0; b < n_boxes; ++b) {
      const ToolBox& box = boxes[b];
      const double s = box.point_shrink;
      if (l.x() > box.lo.x() + s && l.x() < box.hi.x() - s && l.y() > box.lo.y() + s && l.y() < box.hi.y() - s &&
          l.z() > box.lo.z() + s && l.z() < box.hi.z() - s)
        return PathHit::scene;
    }
  }
  return PathHit::none;
}

PathHit segment_hit(const MotionConfig& motion, const PathCheckConfig& cfg,
                    const ToolBox* boxes, uint32_t n_boxes, const Scene& scene, const GraspQuery& q,
                    const double q_from[6], const double q_to[6], double* at, bool leaving_contact) {
  double span = 0.0;
  for (int j = 0; j < 6; ++j) {
    if (!std::isfinite(q_from[j]) || !std::isfinite(q_to[j])) return PathHit::invalid;
    span = std::max(span, std::fabs(q_to[j] - q_from[j]));
  }
  const double step = cfg.step_rad > 1e-6 ? cfg.step_rad : 1e-6;
  const double want = std::ceil(span / step);
  const uint32_t bound = std::max<uint32_t>(cfg.max_samples, 1u);
  const uint32_t n = want < 1.0 ? 1u : (want > static_cast<double>(bound) ? bound : static_cast<uint32_t>(want));
  // A tool that starts in contact (the arm's joints put it on the plane or among the
  // points: a calibration offset, or it rests there) is not judged until it is clear.
  bool in_contact = leaving_contact && pose_hit(motion, cfg, boxes, n_boxes, scene, q, q_from) != PathHit::none;
  for (uint32_t k = 1; k <= n; ++k) {
    const double f = static_cast<double>(k) / static_cast<double>(n);
    double qs[6];
    for (int j = 0; j < 6; ++j) qs[j] = k == n ? q_to[j] : q_from[j] + (q_to[j] - q_from[j]) * f;
    const PathHit h = pose_hit(motion, cfg, boxes, n_boxes, scene, q, qs);
    if (in_contact) {
      in_contact = h != PathHit::none;
      continue;
    }
    if (h != PathHit::none) {
      if (at != nullptr) *at = f;
      return h;
    }
  }
  return PathHit::none;
}

}  // namespace

const char* to_string(PathHit h) {
  switch (h) {
    case PathHit::none: return "none";
    case PathHit::support_plane: return "support_plane";
    case PathHit::scene: return "scene";
    case PathHit::invalid: return "invalid";
  }
  return "unknown";
}

PathHit joint_segment_hit(const MotionConfig& motion, const ToolGeometry& tool, const PathCheckConfig& cfg,
                          const double q_from[6], const double q_to[6], const GraspQuery& q, double* at) {
  ToolBox boxes[4];
  const uint32_t nb = tool_boxes(tool, cfg, boxes);
  const Scene scene = make_scene(q, nullptr, 0);
  return segment_hit(motion, cfg, boxes, nb, scene, q, q_from, q_to, at, true);
}

PathHit grasp_path_hit(const MotionConfig& motion, const ToolGeometry& tool, const PathCheckConfig& cfg,
                       const double q_now[6], const GraspMotion& m, const GraspQuery& q, int* segment,
                       uint32_t* scratch, uint32_t capacity) {
  ToolBox boxes[4];
  const uint32_t nb = tool_boxes(tool, cfg, boxes);
  const Scene scene = make_scene(q, scratch, capacity);
  const double* from = q_now;
  const double* to = m.pregrasp;
  for (int s = 0; s <= GraspMotion::kApproachSteps; ++s) {
    const PathHit h = segment_hit(motion, cfg, boxes, nb, scene, q, from, to, nullptr, s == 0);
    if (h != PathHit::none) {
      if (segment != nullptr) *segment = s;
      return h;
    }
    if (s == GraspMotion::kApproachSteps) break;
    from = to;
    to = m.approach[s];
  }
  return PathHit::none;
}

}  // namespace fg::robot
