// The tool along the executed joint path against the support plane and the scene
// points (path_check.hpp).
#include "fg/robot/path_check.hpp"

#include <algorithm>
#include <cmath>

#include "fg/core/byte_flags.hpp"

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

// The column of a point (PathSceneScratch): the unwrapped cell along one axis, then
// wrapped round. Cells far outside any workspace saturate (coordinates were finite).
int64_t cell_of(double v) {
  const double c = std::floor(v / kPathColumnM);
  return c < -1e9 ? -1000000000 : (c > 1e9 ? 1000000000 : static_cast<int64_t>(c));
}
uint32_t wrap(int64_t c) {
  const int64_t m = static_cast<int64_t>(kPathColumns);
  return static_cast<uint32_t>(((c % m) + m) % m);
}
uint32_t column_of(double x, double y) { return wrap(cell_of(y)) * kPathColumns + wrap(cell_of(x)); }

bool kept(const GraspQuery& q, uint32_t i) {
  return (q.scene_keep == nullptr || q.scene_keep[i] != 0) && q.scene_points[i].allFinite();
}

// f(i) for every kept point, in index order: the flags are read eight at a time (a
// scene's voxels are mostly the plane's, not flagged), then finiteness as kept() tests it.
template <class F>
void for_each_kept(const GraspQuery& q, F&& f) {
  for_each_flagged(q.scene_keep, q.n_scene_points, [&](uint32_t i) {
    if (q.scene_points[i].allFinite()) f(i);
  });
}

// The tool at joints qs against the scene.
// `budget` (optional) pays one sample, and the points scanned: a pose it cannot pay
// for in full is not tested (PathHit::budget), so the answer never depends on where in
// a scan the budget ran out.
[[nodiscard]] PathHit pose_hit(const MotionConfig& motion, const PathCheckConfig& cfg, const ToolBox* boxes,
                               uint32_t n_boxes, const PathScene& scene, const GraspQuery& q, const double qs[6],
                               PathBudget* budget) {
  if (budget != nullptr) {
    if (budget->samples == 0) return PathHit::budget;
    --budget->samples;
  }
  PoseD base_T_tool0;
  if (!ur5_forward_d(motion.robot, qs, base_T_tool0)) return PathHit::invalid;
  const PoseD w = compose(to_d(motion.world_T_base), base_T_tool0);
  const Eigen::Matrix3d& R = w.R;
  const V3d origin = w.t + R.col(2) * static_cast<double>(motion.tcp_offset_m);
  V3d lo = V3d::Constant(1e30), hi = V3d::Constant(-1e30);  // the whole tool's bounds
  V3d box_lo[4], box_hi[4];                                 // each box's
  for (uint32_t b = 0; b < n_boxes; ++b) {
    const ToolBox& box = boxes[b];
    double h_min = 1e30;
    box_lo[b] = V3d::Constant(1e30);
    box_hi[b] = V3d::Constant(-1e30);
    for (int k = 0; k < 8; ++k) {
      const V3d c((k & 1) ? box.hi.x() : box.lo.x(), (k & 2) ? box.hi.y() : box.lo.y(),
                  (k & 4) ? box.hi.z() : box.lo.z());
      const V3d p = origin + R * c;
      box_lo[b] = box_lo[b].cwiseMin(p);
      box_hi[b] = box_hi[b].cwiseMax(p);
      if (scene.has_plane) h_min = std::min(h_min, scene.n.dot(p) + scene.d);
    }
    lo = lo.cwiseMin(box_lo[b]);
    hi = hi.cwiseMax(box_hi[b]);
    // The lowest corner of the box shrunk by plane_shrink along each of its axes.
    if (scene.has_plane) {
      const double shrink = box.plane_shrink * (R.transpose() * scene.n).cwiseAbs().sum();
      const double clearance = box.plane_shrink > 0.0 ? 0.0 : static_cast<double>(cfg.plane_clearance_m);
      if (h_min + shrink < clearance) return PathHit::support_plane;
    }
  }
  if (!scene.has_points) return PathHit::none;
  const auto disjoint = [&scene](const V3d& l, const V3d& h) {
    return (l.array() > scene.hi.array()).any() || (h.array() < scene.lo.array()).any();
  };
  if (disjoint(lo, hi)) return PathHit::none;
  const Eigen::Matrix3d Rt = R.transpose();
  // Point i inside box b (shrunk by its tolerance)?
  const auto inside = [&](uint32_t b, uint32_t i) {
    const V3d p = q.scene_points[i].cast<double>();
    if ((p.array() < box_lo[b].array()).any() || (p.array() > box_hi[b].array()).any()) return false;
    const V3d l = Rt * (p - origin);
    const ToolBox& box = boxes[b];
    const double sh = box.point_shrink;
    return l.x() > box.lo.x() + sh && l.x() < box.hi.x() - sh && l.y() > box.lo.y() + sh && l.y() < box.hi.y() - sh &&
           l.z() > box.lo.z() + sh && l.z() < box.hi.z() - sh;
  };
  if (scene.idx == nullptr) {  // not gathered: every point of the scene, against every box
    if (budget != nullptr) {
      if (budget->point_tests < q.n_scene_points) return PathHit::budget;
      budget->point_tests -= q.n_scene_points;
    }
    for (uint32_t i = 0; i < q.n_scene_points; ++i) {
      if (!kept(q, i)) continue;
      for (uint32_t b = 0; b < n_boxes; ++b)
        if (inside(b, i)) return PathHit::scene;
    }
    return PathHit::none;
  }
  // Per box, the columns under its bounds clipped to the points' bounds (each column at
  // most once per box): the points to scan are counted first, so the budget is
  // charged before any is tested.
  struct Columns {
    int64_t x0 = 0, y0 = 0, nx = 0, ny = 0;
  } cols[4];
  uint32_t n_scan = 0;
  const uint32_t* cs = scene.column_start;
  for (uint32_t b = 0; b < n_boxes; ++b) {
    if (disjoint(box_lo[b], box_hi[b])) continue;
    const V3d clo = box_lo[b].cwiseMax(scene.lo), chi = box_hi[b].cwiseMin(scene.hi);
    Columns& c = cols[b];
    c.x0 = cell_of(clo.x());
    c.y0 = cell_of(clo.y());
    c.nx = std::min<int64_t>(cell_of(chi.x()) - c.x0 + 1, kPathColumns);
    c.ny = std::min<int64_t>(cell_of(chi.y()) - c.y0 + 1, kPathColumns);
    for (int64_t dy = 0; dy < c.ny; ++dy)
      for (int64_t dx = 0; dx < c.nx; ++dx) {
        const uint32_t col = wrap(c.y0 + dy) * kPathColumns + wrap(c.x0 + dx);
        n_scan += cs[col + 1] - cs[col];
      }
  }
  if (budget != nullptr) {
    if (budget->point_tests < n_scan) return PathHit::budget;
    budget->point_tests -= n_scan;
  }
  for (uint32_t b = 0; b < n_boxes; ++b) {
    const Columns& c = cols[b];
    for (int64_t dy = 0; dy < c.ny; ++dy)
      for (int64_t dx = 0; dx < c.nx; ++dx) {
        const uint32_t col = wrap(c.y0 + dy) * kPathColumns + wrap(c.x0 + dx);
        for (uint32_t k = cs[col]; k < cs[col + 1]; ++k)
          if (inside(b, scene.idx[k])) return PathHit::scene;
      }
  }
  return PathHit::none;
}

[[nodiscard]] PathHit segment_hit(const MotionConfig& motion, const PathCheckConfig& cfg, const ToolBox* boxes,
                                  uint32_t n_boxes, const PathScene& scene, const GraspQuery& q, const double q_from[6],
                                  const double q_to[6], double* at, bool leaving_contact, PathBudget* budget) {
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
  PathHit h0 = PathHit::none;
  if (leaving_contact) h0 = pose_hit(motion, cfg, boxes, n_boxes, scene, q, q_from, budget);
  if (h0 == PathHit::budget || h0 == PathHit::invalid) return h0;
  bool in_contact = h0 != PathHit::none;
  for (uint32_t k = 1; k <= n; ++k) {
    const double f = static_cast<double>(k) / static_cast<double>(n);
    double qs[6];
    for (int j = 0; j < 6; ++j) qs[j] = k == n ? q_to[j] : q_from[j] + (q_to[j] - q_from[j]) * f;
    const PathHit h = pose_hit(motion, cfg, boxes, n_boxes, scene, q, qs, budget);
    if (h == PathHit::budget) return h;
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
    case PathHit::none:
      return "none";
    case PathHit::support_plane:
      return "support_plane";
    case PathHit::scene:
      return "scene";
    case PathHit::invalid:
      return "invalid";
    case PathHit::budget:
      return "budget";
  }
  return "unknown";
}

PathScene prepare_path_scene(const GraspQuery& q, PathSceneScratch* scratch) {
  PathScene s;
  if (q.support != nullptr && q.support->n.allFinite() && std::isfinite(q.support->d) && q.support->n.norm() > 0.5f) {
    s.has_plane = true;
    const double len = q.support->n.cast<double>().norm();
    s.n = q.support->n.cast<double>() / len;
    s.d = static_cast<double>(q.support->d) / len;
  }
  if (q.scene_points == nullptr) return s;
  s.lo = V3d::Constant(1e30);
  s.hi = V3d::Constant(-1e30);
  uint32_t n_kept = 0;
  uint32_t* count = scratch != nullptr ? scratch->column_start : nullptr;
  if (count != nullptr) std::fill(count, count + static_cast<size_t>(kPathColumns) * kPathColumns + 1, 0u);
  for_each_kept(q, [&](uint32_t i) {
    const V3d p = q.scene_points[i].cast<double>();
    s.lo = s.lo.cwiseMin(p);
    s.hi = s.hi.cwiseMax(p);
    ++n_kept;
    if (count != nullptr) ++count[column_of(p.x(), p.y()) + 1];
  });
  s.has_points = n_kept > 0;
  if (count == nullptr || n_kept > kMaxObjectPoints) return s;
  // Counting sort in place: count[c + 1] becomes the end of column c, each index is
  // put just below its column's end, which leaves count[c + 1] at the column's start;
  // one shift down makes count[c] the start of column c.
  constexpr uint32_t kCells = kPathColumns * kPathColumns;
  for (uint32_t c = 0; c < kCells; ++c) count[c + 1] += count[c];
  for_each_kept(q, [&](uint32_t i) {
    const V3d p = q.scene_points[i].cast<double>();
    scratch->idx[--count[column_of(p.x(), p.y()) + 1]] = i;
  });
  for (uint32_t c = 0; c < kCells; ++c) count[c] = count[c + 1];
  count[kCells] = n_kept;
  s.idx = scratch->idx;
  s.column_start = scratch->column_start;
  s.n_idx = n_kept;
  return s;
}

PathHit joint_segment_hit(const MotionConfig& motion, const ToolGeometry& tool, const PathCheckConfig& cfg,
                          const double q_from[6], const double q_to[6], const GraspQuery& q, double* at) {
  ToolBox boxes[4];
  const uint32_t nb = tool_boxes(tool, cfg, boxes);
  const PathScene scene = prepare_path_scene(q, nullptr);
  return segment_hit(motion, cfg, boxes, nb, scene, q, q_from, q_to, at, true, nullptr);
}

PathHit grasp_path_hit(const MotionConfig& motion, const ToolGeometry& tool, const PathCheckConfig& cfg,
                       const double q_now[6], const GraspMotion& m, const PathScene& scene, const GraspQuery& q,
                       int* segment, PathBudget* budget) {
  ToolBox boxes[4];
  const uint32_t nb = tool_boxes(tool, cfg, boxes);
  const double* from = q_now;
  const double* to = m.pregrasp;
  for (int s = 0; s <= GraspMotion::kApproachSteps; ++s) {
    const PathHit h = segment_hit(motion, cfg, boxes, nb, scene, q, from, to, nullptr, s == 0, budget);
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
