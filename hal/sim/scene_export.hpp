// Host-only simulation: writes a generated scene as a scene folder
//   scene.json  the manifest of spec/scene-and-cli.md (sensors head and hand, gripper)
//   head.pcd, hand.pcd  organized 640x480 clouds in each sensor's optical frame (NaN = missing)
//   truth.json  the true world (objects, parts, poses, sizes), target, table, gripper,
//               cameras and ground-truth facts, readable back with read_truth.
#pragma once
#include <string>

#include "io/pcd.hpp"
#include "io/point_cloud.hpp"
#include "sim/scene_gen.hpp"

namespace fg::sim {

struct ExportOptions {
  fg::host::PcdEncoding encoding = fg::host::PcdEncoding::binary;
};

//! Renders both cameras and writes the folder (created if missing).
[[nodiscard]] fg::host::ReadResult export_scene(const GeneratedScene& scene, const std::string& dir,
                                                const ExportOptions& options = {});
//! Same with images rendered beforehand.
[[nodiscard]] fg::host::ReadResult export_scene(const GeneratedScene& scene, const SceneImages& images,
                                                const std::string& dir, const ExportOptions& options = {});

std::string truth_to_json(const GeneratedScene& scene);
[[nodiscard]] fg::host::ReadResult parse_truth(const std::string& text, const std::string& name, GeneratedScene& out);
[[nodiscard]] fg::host::ReadResult write_truth(const std::string& path, const GeneratedScene& scene);
[[nodiscard]] fg::host::ReadResult read_truth(const std::string& path, GeneratedScene& out);

}  // namespace fg::sim
