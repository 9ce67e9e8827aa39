// Host-only: a point cloud as read from a file (PCD or PLY). Host code may allocate.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "big_buffer.hpp"

namespace fg::host {

struct PointCloud {
  BigBuffer<float> xyz;  //!< 3 floats per point, x y z; NaN kept for missing pixels
  uint32_t width = 0;    //!< organized: image width; unorganized: point count
  uint32_t height = 1;   //!< organized: image height; unorganized: 1
  bool organized() const { return height > 1; }
  size_t size() const { return planar() ? planar_points : xyz.size() / 3; }
  //! Instead of xyz, when the reader was allowed to (ReadLimits::planar) and the file is
  //! binary_compressed with 4-byte float x, y and z: the decompressed block itself, a
  //! structure of arrays whose x, y and z arrays start planar_offset[0..2] bytes in. No
  //! copy into x y z triples (the planner takes both layouts).
  BigBuffer<uint8_t> planar_block;
  size_t planar_offset[3] = {0, 0, 0};
  uint64_t planar_points = 0;
  bool planar() const { return !planar_block.empty(); }
  const float* planar_array(int k) const {
    return reinterpret_cast<const float*>(planar_block.data() + planar_offset[k]);
  }
  //! Per-point integer labels when the file has a `label` field (e.g. mOSD ground
  //! truth), else empty. Readers fill it; the planner ignores it.
  std::vector<uint32_t> labels;
  //! PCD VIEWPOINT tx ty tz qw qx qy qz (identity when the file has none)
  std::array<double, 7> viewpoint{{0, 0, 0, 1, 0, 0, 0}};
};

//! Limits a reader enforces before it allocates anything.
struct ReadLimits {
  uint64_t max_points = 10'000'000;      //!< more declared points -> error
  uint64_t max_file_bytes = 1ull << 31;  //!< larger files -> error
  //! The caller takes a structure of arrays (PointCloud::planar_block) where the file
  //! holds one; otherwise xyz is filled.
  bool planar = false;
};

//! The outcome of a read: ok, or an error message naming the file and the problem.
struct ReadResult {
  bool ok = true;
  std::string error;
  [[nodiscard]] static ReadResult failure(std::string msg) { return ReadResult{false, std::move(msg)}; }
};

//! Reads a whole file in binary mode into `out`. Errors (naming `path`): cannot open,
//! a directory, a read error, or more than `max_bytes` bytes (checked before reading
//! regular files; other files are read in chunks and stop at the limit).
[[nodiscard]] ReadResult read_file_bytes(const std::string& path, BigBuffer<uint8_t>& out,
                                         uint64_t max_bytes = ReadLimits{}.max_file_bytes);

}  // namespace fg::host
