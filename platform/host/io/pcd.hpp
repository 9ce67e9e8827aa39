// Host-only PCD v0.7 reader and writer (the project's own, hardened).
#pragma once
#include <string>

#include "point_cloud.hpp"

namespace fg::host {

//! Reads x, y, z of a PCD file (VERSION .7/0.7; DATA ascii, binary, binary_compressed
//! with LZF; any field order and extra fields of any TYPE/SIZE/COUNT; organized or
//! not; NaN points kept; VIEWPOINT optional). Never crashes on malformed input: every
//! problem is an error naming the file and what is wrong.
[[nodiscard]] ReadResult read_pcd(const std::string& path, PointCloud& out, const ReadLimits& limits = {});

//! Same, from bytes in memory (`name` is used in messages). For fuzzing and tests.
[[nodiscard]] ReadResult parse_pcd(const uint8_t* data, size_t size, const std::string& name, PointCloud& out,
                                   const ReadLimits& limits = {});

enum class PcdEncoding { ascii, binary, binary_compressed };

//! Writes x y z (float) with the cloud's width/height and viewpoint.
[[nodiscard]] ReadResult write_pcd(const std::string& path, const PointCloud& cloud,
                                   PcdEncoding encoding = PcdEncoding::binary);

}  // namespace fg::host
