// The tool against the support plane and the target's convex pieces with libccd's
// GJK (tool_collision.hpp). libccd is built in double (Debian: CCD_DOUBLE).
#include "fg/robot/tool_collision.hpp"

#include <ccd/ccd.h>

#include <algorithm>
#include <cmath>

namespace fg::robot {
namespace {

using V3d = Eigen::Vector3d;

// An oriented box in world: centre, axes (columns), half extents.
struct BoxShape {
  V3d c;
  Eigen::Matrix3d R;
  V3d h;
};

// The hull of some object points, given by their indices (null: the first n).
struct PieceShape {
  const Vec3* pts;
  const uint16_t* idx;
  uint32_t n;
  const Vec3& at(uint32_t i) const { return pts[idx != nullptr ? idx[i] : i]; }
};

V3d from_ccd(const ccd_vec3_t* v) { return V3d(v->v[0], v->v[1], v->v[2]); }
void to_ccd(const V3d& p, ccd_vec3_t* v) {
  v->v[0] = p.x();
  v->v[1] = p.y();
  v->v[2] = p.z();
}

void box_support(const void* obj, const ccd_vec3_t* dir, ccd_vec3_t* out) {
  const BoxShape& b = *static_cast<const BoxShape*>(obj);
  const V3d l = b.R.transpose() * from_ccd(dir);
  const V3d corner(l.x() >= 0.0 ? b.h.x() : -b.h.x(), l.y() >= 0.0 ? b.h.y() : -b.h.y(),
                   l.z() >= 0.0 ? b.h.z() : -b.h.z());
  to_ccd(b.c + b.R * corner, out);
}

// O(n) per call: pieces are small (a slab of the points near the tool).
void piece_support(const void* obj, const ccd_vec3_t* dir, ccd_vec3_t* out) {
  const PieceShape& s = *static_cast<const PieceShape*>(obj);
  const V3d d = from_ccd(dir);
  V3d best = s.at(0).cast<double>();
  double best_dot = d.dot(best);
  for (uint32_t i = 1; i < s.n; ++i) {
    const V3d p = s.at(i).cast<double>();
    const double v = d.dot(p);
    if (v > best_dot) {
      best_dot = v;
      best = p;
    }
  }
  to_ccd(best, out);
}

bool intersect(const void* a, ccd_support_fn sa, const void* b, ccd_support_fn sb, uint32_t max_iterations) {
  ccd_t ccd;
  CCD_INIT(&ccd);
  ccd.support1 = sa;
  ccd.support2 = sb;
  ccd.max_iterations = max_iterations;  // CCD_INIT leaves it unlimited
  return ccdGJKIntersect(a, b, &ccd) != 0;
}

struct LocalBox {
  float lo[3], hi[3];
  uint32_t band;
};

bool finite(const Vec3& v) { return v.allFinite(); }

}  // namespace

bool box_intersects_point_hull(const Vec3& centre, const Mat3& axes, const Vec3& half, const Vec3* points,
                               const uint16_t* idx, uint32_t n, uint32_t max_iterations) {
  if (points == nullptr || n == 0) return false;
  const BoxShape box{centre.cast<double>(), axes.cast<double>(), half.cast<double>()};
  const PieceShape piece{points, idx, n};
  return intersect(&box, box_support, &piece, piece_support, max_iterations);
}

const char* to_string(ToolHit h) {
  switch (h) {
    case ToolHit::none:
      return "none";
    case ToolHit::support_plane:
      return "support_plane";
    case ToolHit::object:
      return "object";
    case ToolHit::invalid:
      return "invalid";
  }
  return "unknown";
}

ToolHit ToolCollision::check(const ToolGeometry& tool, const GraspQuery& q) {
  gjk_calls_ = 0;
  n_pieces_ = 0;
  const GripperGeometry& g = tool.gripper;
  if (!finite(q.position) || !finite(q.approach) || !finite(q.closing) || !finite(q.pregrasp) ||
      !(q.approach.norm() > 0.5f) || !(q.closing.norm() > 0.5f) || !(tool.piece_height_m > 0.f))
    return ToolHit::invalid;
  // The grasp frame: x closing, y across, z approach (orthonormal in double).
  const V3d z = q.approach.cast<double>().normalized();
  V3d x = q.closing.cast<double>() - z * z.dot(q.closing.cast<double>());
  if (!(x.norm() > 0.5)) return ToolHit::invalid;  // closing (nearly) along the approach
  x.normalize();
  Eigen::Matrix3d R;
  R.col(0) = x;
  R.col(1) = z.cross(x);
  R.col(2) = z;
  const V3d origin = q.position.cast<double>();
  const float back = std::max(0.f, (q.position - q.pregrasp).dot(q.approach.normalized()));

  // The tool in the grasp frame, swept back to the pre-grasp, shrunk by the tolerance.
  const float ho = 0.5f * g.max_opening_m, t = g.finger_thickness_m, hfd = 0.5f * g.finger_depth_m;
  const float palm_back = -hfd - g.palm_depth_m;
  LocalBox boxes[4] = {
      {{-ho - t, -0.5f * g.finger_width_m, -hfd - back}, {-ho, 0.5f * g.finger_width_m, hfd}, 0},
      {{ho, -0.5f * g.finger_width_m, -hfd - back}, {ho + t, 0.5f * g.finger_width_m, hfd}, 0},
      {{-ho - t, -0.5f * g.palm_width_m, palm_back - back}, {ho + t, 0.5f * g.palm_width_m, -hfd}, 1},
      {{-tool.body_half_width_m, -tool.body_half_width_m, -tool.tcp_offset_m - back},
       {tool.body_half_width_m, tool.body_half_width_m, palm_back},
       1},
  };
  const uint32_t n_boxes = tool.tcp_offset_m > -palm_back ? 4u : 3u;  // no body if the palm is the flange
  BoxShape world_box[4];
  for (uint32_t b = 0; b < n_boxes; ++b) {
    V3d lo, hi;
    for (int k = 0; k < 3; ++k) {
      lo[k] = boxes[b].lo[k] + tool.tolerance_m;
      hi[k] = boxes[b].hi[k] - tool.tolerance_m;
      boxes[b].lo[k] = static_cast<float>(lo[k]);
      boxes[b].hi[k] = static_cast<float>(hi[k]);
    }
    world_box[b] = BoxShape{origin + R * (0.5 * (lo + hi)), R, (0.5 * (hi - lo)).cwiseMax(0.0)};
  }

  // The support plane: a slab whose top lies plane_clearance above it, under the tool.
  if (q.support != nullptr && q.support->n.allFinite() && std::isfinite(q.support->d)) {
    const V3d n = q.support->n.cast<double>().normalized();
    const double h_tool = n.dot(origin) + static_cast<double>(q.support->d);  // height of the grasp centre
    Eigen::Matrix3d P;
    const V3d a = std::fabs(n.x()) < 0.9 ? V3d::UnitX() : V3d::UnitY();
    P.col(0) = (a - n * n.dot(a)).normalized();
    P.col(1) = n.cross(P.col(0));
    P.col(2) = n;
    constexpr double kHalfThickness = 0.5, kHalfSize = 2.0;
    const V3d top = origin - n * (h_tool - static_cast<double>(tool.plane_clearance_m));
    const BoxShape slab{top - n * kHalfThickness, P, V3d(kHalfSize, kHalfSize, kHalfThickness)};
    for (uint32_t b = 0; b < n_boxes; ++b) {
      ++gjk_calls_;
      if (intersect(&world_box[b], box_support, &slab, box_support, tool.max_iterations)) return ToolHit::support_plane;
    }
  }
  if (q.object_points == nullptr || q.n_object_points == 0) return ToolHit::none;

  // Convex pieces: the object points within the tool's reach, by band and slab.
  const uint32_t n = std::min(q.n_object_points, kMaxObjectPoints);
  const float z_min = -tool.tcp_offset_m - back - 0.01f, z_max = hfd + 0.01f;
  float slab_h = tool.piece_height_m;
  uint32_t n_slabs = static_cast<uint32_t>(std::ceil((z_max - z_min) / slab_h));
  if (n_slabs > kMaxSlabs) {
    n_slabs = kMaxSlabs;
    slab_h = (z_max - z_min) / static_cast<float>(kMaxSlabs);
  }
  const float x_reach = ho + t + 0.01f;
  const float y_band[kBands] = {0.5f * g.finger_width_m + 0.005f,
                                std::max(0.5f * g.palm_width_m, tool.body_half_width_m) + 0.005f};
  const Eigen::Matrix3f Rt = R.transpose().cast<float>();
  const Vec3 pos = q.position;
  // The point in the grasp frame and its slab, or false when it is out of reach in x
  // or z; the band test (y) is per band.
  const auto locate = [&](const Vec3& p, Vec3& local, uint32_t& slab) {
    local = Rt * (p - pos);
    if (!(std::fabs(local.x()) <= x_reach && local.z() >= z_min && local.z() < z_max)) return false;
    slab = std::min(n_slabs - 1, static_cast<uint32_t>((local.z() - z_min) / slab_h));
    return true;
  };
  uint32_t count[kMaxPieces + 1] = {};
  for (uint32_t i = 0; i < n; ++i) {
    Vec3 l;
    uint32_t s;
    if (!locate(q.object_points[i], l, s)) continue;
    for (uint32_t band = 0; band < kBands; ++band)
      if (std::fabs(l.y()) <= y_band[band]) ++count[band * kMaxSlabs + s];
  }
  begin_[0] = 0;
  for (uint32_t p = 0; p < kMaxPieces; ++p) {
    begin_[p + 1] = begin_[p] + count[p];
    count[p] = begin_[p];  // now the fill cursor
    for (int k = 0; k < 3; ++k) {
      lo_[p][k] = 1e30f;
      hi_[p][k] = -1e30f;
    }
  }
  for (uint32_t i = 0; i < n; ++i) {
    Vec3 l;
    uint32_t s;
    if (!locate(q.object_points[i], l, s)) continue;
    for (uint32_t band = 0; band < kBands; ++band) {
      if (!(std::fabs(l.y()) <= y_band[band])) continue;
      const uint32_t p = band * kMaxSlabs + s;
      index_[count[p]++] = static_cast<uint16_t>(i);
      for (int k = 0; k < 3; ++k) {
        lo_[p][k] = std::min(lo_[p][k], l[k]);
        hi_[p][k] = std::max(hi_[p][k], l[k]);
      }
    }
  }
  for (uint32_t p = 0; p < kMaxPieces; ++p) n_pieces_ += begin_[p + 1] > begin_[p] ? 1u : 0u;

  for (uint32_t b = 0; b < n_boxes; ++b) {
    const LocalBox& box = boxes[b];
    for (uint32_t s = 0; s < n_slabs; ++s) {
      const uint32_t p = box.band * kMaxSlabs + s;
      if (begin_[p + 1] == begin_[p]) continue;
      bool apart = false;  // the boxes in the grasp frame do not overlap: no hit
      for (int k = 0; k < 3; ++k) apart = apart || lo_[p][k] > box.hi[k] || hi_[p][k] < box.lo[k];
      if (apart) continue;
      const PieceShape piece{q.object_points, index_ + begin_[p], begin_[p + 1] - begin_[p]};
      ++gjk_calls_;
      if (intersect(&world_box[b], box_support, &piece, piece_support, tool.max_iterations)) return ToolHit::object;
    }
  }
  return ToolHit::none;
}

}  // namespace fg::robot
