// Geometry of a parallel gripper, as the planner and its checks see it.
// Frame of a grasp: origin at `position` (the pad centres' midpoint), +z = approach,
// +x = closing (from the left finger to the right one), +y = z cross x.
#pragma once

namespace fg {

struct GripperGeometry {
  float max_opening_m = 0.085f;       //!< largest distance between the pad faces
  float min_opening_m = 0.005f;       //!< smallest graspable width (below: sensor noise)
  float finger_width_m = 0.022f;      //!< pad extent across the closing plane (grasp y)
  float finger_depth_m = 0.040f;      //!< pad extent along the approach (grasp z)
  float finger_thickness_m = 0.010f;  //!< finger extent along the closing direction
  float palm_depth_m = 0.040f;        //!< palm box extent along the approach, behind the pads
  float palm_width_m = 0.050f;        //!< palm box extent across the closing plane
  // The palm spans the open fingers along the closing direction:
  // max_opening_m + 2 * finger_thickness_m.
};

}  // namespace fg
