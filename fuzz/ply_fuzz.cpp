// Fuzz target: fg::host::parse_ply on the bytes (ascii and binary_little_endian, any
// elements and list properties), with the default ReadLimits of read_ply. Findings:
// crashes, sanitizer reports, leaks, hangs, and breaches of the reader's contract
// (fuzz_check.hpp).
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_check.hpp"
#include "io/ply.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string name = "fuzz.ply";
  fg::host::PointCloud cloud = fg_fuzz::sentinel_cloud();
  const fg::host::ReadResult r = fg::host::parse_ply(data, size, name, cloud);
  fg_fuzz::check_cloud_read(r, cloud, name);
  FG_FUZZ_CHECK(!r.ok || cloud.height == 1, "a PLY cloud is unorganized (height 1)");
  return 0;
}
