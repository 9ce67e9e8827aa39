// Host-only PLY reader (the project's own, hardened): vertex x y z.
#pragma once
#include <string>

#include "point_cloud.hpp"

namespace fg::host {

//! Reads the x, y, z properties of the `vertex` element of a PLY file (format ascii 1.0
//! or binary_little_endian 1.0; any property order and types; other elements, e.g.
//! faces with list properties, are skipped). Result is unorganized.
[[nodiscard]] ReadResult read_ply(const std::string& path, PointCloud& out, const ReadLimits& limits = {});

[[nodiscard]] ReadResult parse_ply(const uint8_t* data, size_t size, const std::string& name, PointCloud& out,
                                   const ReadLimits& limits = {});

//! Writes an ascii or binary_little_endian PLY with float x y z vertices (for tests).
[[nodiscard]] ReadResult write_ply(const std::string& path, const PointCloud& cloud, bool binary);

//! Reads a cloud by file extension (.pcd / .ply, case-insensitive).
[[nodiscard]] ReadResult read_cloud(const std::string& path, PointCloud& out, const ReadLimits& limits = {});

}  // namespace fg::host
