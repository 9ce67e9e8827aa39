// The tool along the joint path the arm executes (the free move from where the arm
// stands to the start of the approach line, then the approach waypoints), sampled in
// joint space, against the support plane and every scene point that is not the plane
// (the target and the other objects). A joint-space move leaves the straight line
// between its end poses: on the way it may sweep the open gripper through the table or
// another object, which the checks of the approach line alone do not see.
// Embedded side: no heap, no libccd (box corners against a plane, points in boxes);
// every loop bounded by the sample bound and the point count.
#pragma once
#include <cstdint>

#include "fg/core/grasp_check.hpp"
#include "fg/robot/grasp_motion.hpp"
#include "fg/robot/tool_collision.hpp"

namespace fg::robot {

struct PathCheckConfig {
  //! Every corner of the open fingers and the palm stays this far above the support
  //! plane (the body behind the palm: its box shrunk by ToolGeometry::tolerance_m,
  //! above the plane).
  float plane_clearance_m = 0.002f;
  //! Fingers and palm shrunk by this against the scene points (the core's collision
  //! tolerance); the body by ToolGeometry::tolerance_m.
  float point_tolerance_m = 0.001f;
  //! Largest change of any joint between two samples (rad): 0.01 rad of the shoulder
  //! moves the tool at most about 9 mm at the UR5's full reach.
  double step_rad = 0.01;
  //! Samples per joint-space segment at most (the step grows on longer moves).
  uint32_t max_samples = 512;
};

enum class PathHit : uint8_t { none = 0, support_plane = 1, scene = 2, invalid = 3 };
const char* to_string(PathHit h);

//! The tool (ToolGeometry: open fingers, palm, body; tcp_offset from MotionConfig) at
//! samples of the joint-space straight line from q_from to q_to (q_from itself
//! excluded, q_to included), against q.support (when not null) and q.scene_points
//! (kept ones). `at` receives the fraction of the segment of the first hit. A tool
//! that is in contact at q_from is not judged until the first sample where it is clear
//! (the arm is leaving a contact it is already in: calibration offsets, or resting).
PathHit joint_segment_hit(const MotionConfig& motion, const ToolGeometry& tool, const PathCheckConfig& cfg,
                          const double q_from[6], const double q_to[6], const GraspQuery& q, double* at = nullptr);

//! The whole executed path of a grasp motion: q_now -> m.pregrasp -> m.approach[0..]
//! (the free move, from q_now, as joint_segment_hit; the approach steps from their start).
//! `segment` receives the index of the segment of the first hit (0: the free move).
//! `scratch` (optional, `capacity` entries): the indices of the kept scene points are
//! gathered there once, so the samples do not scan the plane's points (when more
//! points are kept than fit, every sample scans all of them: same result, slower).
PathHit grasp_path_hit(const MotionConfig& motion, const ToolGeometry& tool, const PathCheckConfig& cfg,
                       const double q_now[6], const GraspMotion& m, const GraspQuery& q, int* segment = nullptr,
                       uint32_t* scratch = nullptr, uint32_t capacity = 0);

}  // namespace fg::robot
