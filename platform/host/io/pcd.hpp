// Host-only PCD v0.7 reader and writer (the project's own, hardened).
#pragma once
#include <cstdint>
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

//! Where a DATA binary file's x, y and z lie, for a reader that takes its points in
//! place (pcd_stream.hpp): 4-byte little-endian floats at these offsets in each point.
struct PcdBinaryFloats {
  uint64_t data_offset = 0;        //!< the first point's byte in the file (the header's length)
  uint64_t points = 0;             //!< as WIDTH x HEIGHT and POINTS declare them
  uint64_t point_size = 0;         //!< bytes per point
  uint64_t offset[3] = {0, 0, 0};  //!< of x, y and z in a point
};

//! Parses the header at the start of `data` (a file's first `size` bytes). ok with
//! `binary_floats` true when the file is DATA binary with 4-byte float x, y and z (and
//! `out` says where); ok with false for any other valid header; an error naming the
//! problem for a header that is not valid within these bytes.
[[nodiscard]] ReadResult parse_pcd_header(const uint8_t* data, size_t size, const std::string& name,
                                          const ReadLimits& limits, bool& binary_floats, PcdBinaryFloats& out);

enum class PcdEncoding { ascii, binary, binary_compressed };

//! Writes x y z (float) with the cloud's width/height and viewpoint.
[[nodiscard]] ReadResult write_pcd(const std::string& path, const PointCloud& cloud,
                                   PcdEncoding encoding = PcdEncoding::binary);

}  // namespace fg::host
