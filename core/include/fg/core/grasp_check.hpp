// A check the layers above the core add to the planner's own (algorithm.md F): the
// robot layer's inverse kinematics and convex collision checks of the whole tool.
// The planner asks it about each ranked candidate that passed the core's checks, in
// ranking order, and moves on to the next candidate when it says no. No heap: the
// implementation keeps whatever it needs (joint solutions, scratch) in itself.
#pragma once
#include <cstdint>

#include "fg/core/plane.hpp"
#include "fg/core/types.hpp"

namespace fg {

enum class GraspVerdict : uint8_t {
  pass = 0,
  collision = 1,    //!< some part of the tool or arm meets the support plane or the object
  unreachable = 2,  //!< no joint solution within the limits at the pre-grasp or the grasp
};

//! One candidate as the check sees it, all in `world`.
struct GraspQuery {
  Vec3 position;              //!< the pads' centre at the grasp
  Vec3 approach;              //!< unit, palm towards the object (grasp +z)
  Vec3 closing;               //!< unit, left finger towards the right one (grasp +x)
  Vec3 pregrasp;              //!< position backed off along -approach
  float width;                //!< object width between the contacts
  const Plane* support;       //!< the support plane, or null when none was found
  const Vec3* object_points;  //!< the target's points (the planner's memory; valid
  uint32_t n_object_points;   //!< during the call only)
  //! Everything in the scene that is not the support plane (the target and the other
  //! objects): scene_points[i] for every i < n_scene_points whose scene_keep[i] is not
  //! 0 (scene_keep null: all of them). The planner's voxel centroids; valid during the
  //! call only. Null / 0 when not given.
  const Vec3* scene_points = nullptr;
  const uint8_t* scene_keep = nullptr;
  uint32_t n_scene_points = 0;
};

class GraspCheck {
 public:
  [[nodiscard]] GraspVerdict check(const GraspQuery& q) { return do_check(q); }
  //! The planner calls this once at the start of each plan(), before any check():
  //! the scene of this plan, and a fresh per-plan work budget where the check keeps one.
  void begin_plan() { do_begin_plan(); }

 protected:
  GraspCheck() = default;
  GraspCheck(const GraspCheck&) = default;
  GraspCheck& operator=(const GraspCheck&) = default;
  ~GraspCheck() = default;  // not owned through this interface

 private:
  [[nodiscard]] virtual GraspVerdict do_check(const GraspQuery& q) = 0;
  virtual void do_begin_plan() {}
};

}  // namespace fg
