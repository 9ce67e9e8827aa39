// The whole tool against the scene, with libccd's non-allocating GJK
// (ccdGJKIntersect, max_iterations set): the open fingers, the palm and the body
// behind it (gripper base, coupling, flange) swept from the pre-grasp to the grasp,
// against the support plane (a slab under it) and the target's convex pieces (its
// points near the tool, cut into slabs along the approach; one hull per slab and per
// band: a narrow band for the fingers, a wide one for the palm and the body, so the
// hull of a wide slab does not swallow the space beside a finger).
// Embedded side (no heap); needs libccd (host and aarch64 builds, not cortex-m).
#pragma once
#include <cstdint>

#include "fg/core/grasp_check.hpp"
#include "fg/core/gripper.hpp"
#include "fg/core/limits.hpp"

namespace fg::robot {

struct ToolGeometry {
  GripperGeometry gripper;
  float tcp_offset_m = 0.15f;        //!< flange to the pads' centre (the body's length)
  float body_half_width_m = 0.032f;  //!< body behind the palm: square, flange-sized
  float plane_clearance_m = 0.0f;    //!< every part at least this far above the plane
  float tolerance_m = 0.002f;        //!< boxes shrunk by this (sensor noise on the hull)
  float piece_height_m = 0.02f;      //!< slab thickness of the convex pieces
  uint32_t max_iterations = 64;      //!< libccd GJK iterations per pair
};

enum class ToolHit : uint8_t { none = 0, support_plane = 1, object = 2, invalid = 3 };
const char* to_string(ToolHit h);

//! An oriented box (centre, axes as columns, half extents) against the convex hull of
//! points[idx[0..n)] (idx null: points[0..n)), by libccd's GJK. n must be >= 1.
[[nodiscard]] bool box_intersects_point_hull(const Vec3& centre, const Mat3& axes, const Vec3& half, const Vec3* points,
                                             const uint16_t* idx, uint32_t n, uint32_t max_iterations);

//! Scratch and results of the check: keep one (it is large on the host).
class ToolCollision {
 public:
  static constexpr uint32_t kMaxSlabs = 24;
  static constexpr uint32_t kBands = 2;  // fingers, body
  static constexpr uint32_t kMaxPieces = kMaxSlabs * kBands;

  //! First hit of the tool swept from q.pregrasp to q.position, or none.
  [[nodiscard]] ToolHit check(const ToolGeometry& tool, const GraspQuery& q);
  //! Pairs tested by GJK in the last check (for reports and timing).
  uint32_t gjk_calls() const { return gjk_calls_; }
  uint32_t pieces() const { return n_pieces_; }

 private:
  static_assert(kMaxObjectPoints <= 65535u, "piece indices are 16 bit");
  uint16_t index_[kBands * kMaxObjectPoints];
  uint32_t begin_[kMaxPieces + 1];
  float lo_[kMaxPieces][3], hi_[kMaxPieces][3];  // each piece's box in the grasp frame
  uint32_t n_pieces_ = 0;
  uint32_t gjk_calls_ = 0;
};

}  // namespace fg::robot
