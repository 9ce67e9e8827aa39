// Shared by the reader fuzz targets: a check that aborts (a finding) when a documented
// property of a reader's result does not hold. Nothing here is a sanitizer: these are
// the readers' own contracts (platform/host/io/*.hpp and the comments of pcd.cpp/ply.cpp).
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string>

#include "io/point_cloud.hpp"

#define FG_FUZZ_CHECK(cond, what)                                                                                 \
  do {                                                                                                            \
    if (!(cond)) {                                                                                                \
      std::fprintf(stderr, "\n==fg-fuzz== FINDING at %s:%d: %s (failed: %s)\n", __FILE__, __LINE__, what, #cond); \
      std::abort();                                                                                               \
    }                                                                                                             \
  } while (0)

namespace fg_fuzz {

//! A cloud that no reader produces: it must come back untouched from a failed read.
inline fg::host::PointCloud sentinel_cloud() {
  fg::host::PointCloud c;
  c.width = 0xC0FFEEu;
  c.height = 7;
  c.xyz.assign(3, -1.f);
  return c;
}

//! The contracts of parse_pcd / parse_ply: an error names the file ("NAME: what");
//! the output is only touched when the whole file parsed; a parsed cloud has
//! width x height points of 3 floats, and labels are empty or one per point.
inline void check_cloud_read(const fg::host::ReadResult& r, const fg::host::PointCloud& c, const std::string& name) {
  if (!r.ok) {
    FG_FUZZ_CHECK(r.error.rfind(name + ": ", 0) == 0, "error message does not start with the file name");
    FG_FUZZ_CHECK(r.error.size() > name.size() + 2, "empty error message");
    FG_FUZZ_CHECK(c.width == 0xC0FFEEu && c.height == 7 && c.xyz.size() == 3 && c.labels.empty(),
                  "a failed read modified the output cloud");
    return;
  }
  FG_FUZZ_CHECK(r.error.empty(), "a successful read carries an error message");
  FG_FUZZ_CHECK(c.xyz.size() % 3 == 0, "xyz is not a multiple of 3 floats");
  FG_FUZZ_CHECK(!c.planar() || c.xyz.empty(), "a planar cloud also holds triples");
  for (int k = 0; k < 3 && c.planar(); ++k)
    FG_FUZZ_CHECK(c.planar_offset[k] <= c.planar_block.size() &&
                      c.planar_points <= (c.planar_block.size() - c.planar_offset[k]) / sizeof(float),
                  "a planar coordinate array runs past its block");
  FG_FUZZ_CHECK(c.size() == static_cast<size_t>(c.width) * c.height, "point count differs from width x height");
  FG_FUZZ_CHECK(c.labels.empty() || c.labels.size() == c.size(), "labels are neither empty nor one per point");
}

}  // namespace fg_fuzz
