// Host only: reads a UR arm's URDF (ur_description layout) through urdfdom into the
// plain DH parameter struct the embedded side uses (fg::robot::Ur5Params). urdfdom
// allocates and throws; nothing here reaches firmware, which gets the numbers.
#pragma once
#include <string>

#include "fg/robot/ur5.hpp"

namespace fg::host {

//! Fills `out` from the URDF at `path`: d1, a2, a3, d4, d5, d6 from the joint origins
//! of shoulder_pan .. wrist_3 and the wrist_3 -> tool0 joint; the twists and the base
//! turn are those of the layout, which is checked (joint axes, origin rotations, zero
//! offsets where the layout has none, to 1e-6). A calibrated URDF in the same layout
//! gives its own lengths. False with `error` naming the file and the problem.
[[nodiscard]] bool read_ur5_urdf(const std::string& path, robot::Ur5Params& out, std::string& error);

}  // namespace fg::host
