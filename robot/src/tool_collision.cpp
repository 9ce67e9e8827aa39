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

// The grasp frame: x closing, y across, z approach (orthonormal in double), as the
// columns of R; false for a query without one (non-finite, or closing along the
// approach) or a tool without pieces.
bool grasp_frame(const ToolGeometry& tool, const GraspQuery& q, Eigen::Matrix3d& R) {
  if (!finite(q.position) || !finite(q.approach) || !finite(q.closing) || !finite(q.pregrasp) ||
      !(q.approach.norm() > 0.5f) || !(q.closing.norm() > 0.5f) || !(tool.piece_height_m > 0.f))
    return false;
  const V3d z = q.approach.cast<double>().normalized();
  V3d x = q.closing.cast<double>() - z * z.dot(q.closing.cast<double>());
  if (!(x.norm() > 0.5)) return false;  // closing (nearly) along the approach
  x.normalize();
  R.col(0) = x;
  R.col(1) = z.cross(x);
  R.col(2) = z;
  return true;
}

// The tool in the grasp frame, swept back to the pre-grasp by `back`, shrunk by the
// tolerance (boxes), and the same boxes in world (world_box): the fingers, the palm and
// the body behind it, when there is one. Returns how many boxes.
uint32_t swept_tool(const ToolGeometry& tool, float back, const V3d& origin, const Eigen::Matrix3d& R,
                    LocalBox boxes[4], BoxShape world_box[4]) {
  const GripperGeometry& g = tool.gripper;
  const float ho = 0.5f * g.max_opening_m, t = g.finger_thickness_m, hfd = 0.5f * g.finger_depth_m;
  const float palm_back = -hfd - g.palm_depth_m;
  boxes[0] = {{-ho - t, -0.5f * g.finger_width_m, -hfd - back}, {-ho, 0.5f * g.finger_width_m, hfd}, 0};
  boxes[1] = {{ho, -0.5f * g.finger_width_m, -hfd - back}, {ho + t, 0.5f * g.finger_width_m, hfd}, 0};
  boxes[2] = {{-ho - t, -0.5f * g.palm_width_m, palm_back - back}, {ho + t, 0.5f * g.palm_width_m, -hfd}, 1};
  boxes[3] = {{-tool.body_half_width_m, -tool.body_half_width_m, -tool.tcp_offset_m - back},
              {tool.body_half_width_m, tool.body_half_width_m, palm_back},
              1};
  const uint32_t n_boxes = tool.tcp_offset_m > -palm_back ? 4u : 3u;  // no body if the palm is the flange
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
  return n_boxes;
}

// The support plane: a slab whose top lies plane_clearance above it, under the tool.
// True when a box meets it; each GJK test counted in gjk_calls.
bool tool_hits_plane(const ToolGeometry& tool, const GraspQuery& q, const V3d& origin, const BoxShape* world_box,
                     uint32_t n_boxes, uint32_t& gjk_calls) {
  if (q.support == nullptr || !q.support->n.allFinite() || !std::isfinite(q.support->d)) return false;
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
    ++gjk_calls;
    if (intersect(&world_box[b], box_support, &slab, box_support, tool.max_iterations)) return true;
  }
  return false;
}

constexpr uint32_t kMaxSlabs = ToolCollision::kMaxSlabs;
constexpr uint32_t kBands = ToolCollision::kBands;
constexpr uint32_t kMaxPieces = ToolCollision::kMaxPieces;

// How the object points within the tool's reach are cut into convex pieces: slabs
// along the approach, bands across it (y_band: the fingers', the body's).
struct PieceCut {
  Eigen::Matrix3f Rt;  // world to grasp frame
  Vec3 pos;
  float z_min, z_max, slab_h, x_reach;
  uint32_t n_slabs;
  float y_band[kBands];

  // The point in the grasp frame and its slab, or false when it is out of reach in x
  // or z; the band test (y) is per band.
  bool locate(const Vec3& p, Vec3& local, uint32_t& slab) const {
    local = Rt * (p - pos);
    if (!(std::fabs(local.x()) <= x_reach && local.z() >= z_min && local.z() < z_max)) return false;
    slab = std::min(n_slabs - 1, static_cast<uint32_t>((local.z() - z_min) / slab_h));
    return true;
  }
};

PieceCut piece_cut(const ToolGeometry& tool, const GraspQuery& q, const Eigen::Matrix3d& R, float back) {
  const GripperGeometry& g = tool.gripper;
  const float ho = 0.5f * g.max_opening_m, t = g.finger_thickness_m, hfd = 0.5f * g.finger_depth_m;
  PieceCut cut;
  cut.z_min = -tool.tcp_offset_m - back - 0.01f;
  cut.z_max = hfd + 0.01f;
  cut.slab_h = tool.piece_height_m;
  cut.n_slabs = static_cast<uint32_t>(std::ceil((cut.z_max - cut.z_min) / cut.slab_h));
  if (cut.n_slabs > kMaxSlabs) {
    cut.n_slabs = kMaxSlabs;
    cut.slab_h = (cut.z_max - cut.z_min) / static_cast<float>(kMaxSlabs);
  }
  cut.x_reach = ho + t + 0.01f;
  cut.y_band[0] = 0.5f * g.finger_width_m + 0.005f;
  cut.y_band[1] = std::max(0.5f * g.palm_width_m, tool.body_half_width_m) + 0.005f;
  cut.Rt = R.transpose().cast<float>();
  cut.pos = q.position;
  return cut;
}

// The checker's piece memory: the points' indices by piece, each piece's range of
// them, and its box in the grasp frame.
struct PieceTable {
  uint16_t* index;
  uint32_t* begin;  // kMaxPieces + 1
  float (*lo)[3];
  float (*hi)[3];
};

// Files the first n object points into their pieces (by band and slab; a point may lie
// in both bands), in index order: a counting sort. Returns how many pieces hold a point.
uint32_t fill_pieces(const GraspQuery& q, uint32_t n, const PieceCut& cut, const PieceTable& t) {
  uint32_t count[kMaxPieces + 1] = {};
  for (uint32_t i = 0; i < n; ++i) {
    Vec3 l;
    uint32_t s;
    if (!cut.locate(q.object_points[i], l, s)) continue;
    for (uint32_t band = 0; band < kBands; ++band)
      if (std::fabs(l.y()) <= cut.y_band[band]) ++count[band * kMaxSlabs + s];
  }
  t.begin[0] = 0;
  for (uint32_t p = 0; p < kMaxPieces; ++p) {
    t.begin[p + 1] = t.begin[p] + count[p];
    count[p] = t.begin[p];  // now the fill cursor
    for (int k = 0; k < 3; ++k) {
      t.lo[p][k] = 1e30f;
      t.hi[p][k] = -1e30f;
    }
  }
  for (uint32_t i = 0; i < n; ++i) {
    Vec3 l;
    uint32_t s;
    if (!cut.locate(q.object_points[i], l, s)) continue;
    for (uint32_t band = 0; band < kBands; ++band) {
      if (!(std::fabs(l.y()) <= cut.y_band[band])) continue;
      const uint32_t p = band * kMaxSlabs + s;
      t.index[count[p]++] = static_cast<uint16_t>(i);
      for (int k = 0; k < 3; ++k) {
        t.lo[p][k] = std::min(t.lo[p][k], l[k]);
        t.hi[p][k] = std::max(t.hi[p][k], l[k]);
      }
    }
  }
  uint32_t n_pieces = 0;
  for (uint32_t p = 0; p < kMaxPieces; ++p) n_pieces += t.begin[p + 1] > t.begin[p] ? 1u : 0u;
  return n_pieces;
}

// Each box against the pieces of its band whose boxes in the grasp frame overlap it.
// True when one meets it; each GJK test counted in gjk_calls.
bool tool_hits_pieces(const ToolGeometry& tool, const GraspQuery& q, const LocalBox* boxes, const BoxShape* world_box,
                      uint32_t n_boxes, uint32_t n_slabs, const PieceTable& t, uint32_t& gjk_calls) {
  for (uint32_t b = 0; b < n_boxes; ++b) {
    const LocalBox& box = boxes[b];
    for (uint32_t s = 0; s < n_slabs; ++s) {
      const uint32_t p = box.band * kMaxSlabs + s;
      if (t.begin[p + 1] == t.begin[p]) continue;
      bool apart = false;  // the boxes in the grasp frame do not overlap: no hit
      for (int k = 0; k < 3; ++k) apart = apart || t.lo[p][k] > box.hi[k] || t.hi[p][k] < box.lo[k];
      if (apart) continue;
      const PieceShape piece{q.object_points, t.index + t.begin[p], t.begin[p + 1] - t.begin[p]};
      ++gjk_calls;
      if (intersect(&world_box[b], box_support, &piece, piece_support, tool.max_iterations)) return true;
    }
  }
  return false;
}

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
  Eigen::Matrix3d R;
  if (!grasp_frame(tool, q, R)) return ToolHit::invalid;
  const V3d origin = q.position.cast<double>();
  const float back = std::max(0.f, (q.position - q.pregrasp).dot(q.approach.normalized()));
  LocalBox boxes[4];
  BoxShape world_box[4];
  const uint32_t n_boxes = swept_tool(tool, back, origin, R, boxes, world_box);
  if (tool_hits_plane(tool, q, origin, world_box, n_boxes, gjk_calls_)) return ToolHit::support_plane;
  if (q.object_points == nullptr || q.n_object_points == 0) return ToolHit::none;

  // Convex pieces: the object points within the tool's reach, by band and slab.
  const PieceCut cut = piece_cut(tool, q, R, back);
  const PieceTable table{index_, begin_, lo_, hi_};
  n_pieces_ = fill_pieces(q, std::min(q.n_object_points, kMaxObjectPoints), cut, table);
  if (tool_hits_pieces(tool, q, boxes, world_box, n_boxes, cut.n_slabs, table, gjk_calls_)) return ToolHit::object;
  return ToolHit::none;
}

}  // namespace fg::robot
