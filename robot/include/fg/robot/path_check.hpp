// The tool along the joint path the arm executes (the free move from where the arm
// stands to the start of the approach line, then the approach waypoints), sampled in
// joint space, against the support plane and every scene point that is not the plane
// (the target and the other objects). A joint-space move leaves the straight line
// between its end poses: on the way it may sweep the open gripper through the table or
// another object, which the checks of the approach line alone do not see.
// Embedded side: no heap, no libccd (box corners against a plane, points in boxes);
// every loop bounded by the sample bound and the point count, and a plan's checks
// together by a work budget (PathBudget) so the whole select stage has a fixed bound.
#pragma once
#include <Eigen/Core>
#include <cstdint>

#include "fg/core/grasp_check.hpp"
#include "fg/core/limits.hpp"
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
  //! Work budget of one plan's path checks together (PathBudget): tool poses sampled,
  //! and scene points tested against a sampled tool. A plan that spends it checks no
  //! further path (those candidates are turned down, PathHit::budget), so the worst
  //! case of the select stage is fixed whatever the scene. The largest use seen in
  //! `forcegrasp sim` (4 x 380 trials) was 7,232 samples and 300,931 point tests in
  //! one plan; typical plans use about 240 and 5,000.
  uint32_t plan_samples = 16384;
  uint32_t plan_point_tests = 1u << 22;
};

enum class PathHit : uint8_t {
  none = 0,
  support_plane = 1,
  scene = 2,
  invalid = 3,
  budget = 4,  //!< the work budget ran out before the path was cleared (not checked further)
};
const char* to_string(PathHit h);

//! What is left of a plan's path-check work (PathCheckConfig::plan_samples / plan_point_tests).
struct PathBudget {
  uint32_t samples = 0;
  uint32_t point_tests = 0;
  static PathBudget of(const PathCheckConfig& cfg) { return PathBudget{cfg.plan_samples, cfg.plan_point_tests}; }
};

//! Where prepare_path_scene files the kept scene points: their indices sorted by
//! vertical column (kPathColumnM square columns in x and y, kPathColumns per axis,
//! wrapping round, so any extent fits: far points only share a column), so a tool pose
//! scans only the columns under its bounding box, not the whole scene.
//! (Small builds: 16 columns of 8 cm, 1 KiB of starts; the host: 32 of 4 cm, 4 KiB.
//! Either way one wrap spans 1.28 m, about a workspace.)
constexpr uint32_t kPathColumns = kMaxObjectPoints >= 4096 ? 32 : 16;
constexpr double kPathColumnM = 1.28 / kPathColumns;
struct PathSceneScratch {
  uint32_t idx[kMaxObjectPoints];
  uint32_t column_start[kPathColumns * kPathColumns + 1];
};

//! The scene as the samples test it: the support plane, the bounds of the kept scene
//! points and, when they fit the scratch, their indices by column (gathered once per
//! plan). Refers to the query's arrays and the scratch.
struct PathScene {
  const uint32_t* idx = nullptr;           //!< the kept points' indices, by column, when gathered
  const uint32_t* column_start = nullptr;  //!< column c holds idx[column_start[c] .. column_start[c + 1])
  uint32_t n_idx = 0;
  bool has_plane = false;
  Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  double d = 0.0;
  bool has_points = false;
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();  //!< the kept points' bounds
};

//! Two passes over q.scene_points (O(n_scene_points)); `scratch` (optional) receives
//! the kept points' indices by column. Without it, or when more points are kept than
//! kMaxObjectPoints, every sample scans all of them: same result, slower.
PathScene prepare_path_scene(const GraspQuery& q, PathSceneScratch* scratch);

//! The tool (ToolGeometry: open fingers, palm, body; tcp_offset from MotionConfig) at
//! samples of the joint-space straight line from q_from to q_to (q_from itself
//! excluded, q_to included), against q.support (when not null) and q.scene_points
//! (kept ones). `at` receives the fraction of the segment of the first hit. A tool
//! that is in contact at q_from is not judged until the first sample where it is clear
//! (the arm is leaving a contact it is already in: calibration offsets, or resting).
[[nodiscard]] PathHit joint_segment_hit(const MotionConfig& motion, const ToolGeometry& tool,
                                        const PathCheckConfig& cfg, const double q_from[6], const double q_to[6],
                                        const GraspQuery& q, double* at = nullptr);

//! The whole executed path of a grasp motion: q_now -> m.pregrasp -> m.approach[0..]
//! (the free move, from q_now, as joint_segment_hit; the approach steps from their start)
//! against `scene` (prepare_path_scene of q). `segment` receives the index of the
//! segment of the first hit (0: the free move). `budget` (optional) is charged one
//! sample per tool pose and one point test per scene point scanned; when a sample or
//! its scan would overdraw it, the answer is PathHit::budget.
[[nodiscard]] PathHit grasp_path_hit(const MotionConfig& motion, const ToolGeometry& tool, const PathCheckConfig& cfg,
                                     const double q_now[6], const GraspMotion& m, const PathScene& scene,
                                     const GraspQuery& q, int* segment = nullptr, PathBudget* budget = nullptr);

}  // namespace fg::robot
