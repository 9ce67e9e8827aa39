// Host-only: SVG pictures of the planner's stages for `forcegrasp plan --pictures DIR`.
#pragma once
#include <string>
#include <vector>

#include "fg/core/planner.hpp"

namespace fg::host {

//! Writes object_top.svg, object_side.svg (object cloud, grasp and gripper),
//! silhouette.svg (chosen viewpoint: silhouette, contour, scan lines, kept lines,
//! fitted sides) and balance.svg (beta and dz over the viewpoints) into dir. The
//! ranked alternates (`--top`) are drawn in the object pictures too, numbered from 1
//! in rank order, each as its closing line between the contacts.
[[nodiscard]] bool write_pictures(Planner& planner, const PlanResult& result, const std::string& dir,
                                  std::string& error, const std::vector<Grasp>& alternates = {});

}  // namespace fg::host
