// Fuzz target: fg::host::parse_pcd on the bytes (ascii, binary, binary_compressed/LZF),
// with the default ReadLimits of read_pcd. Findings: crashes, sanitizer reports, leaks,
// hangs, and breaches of the reader's contract (fuzz_check.hpp).
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_check.hpp"
#include "io/pcd.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string name = "fuzz.pcd";
  fg::host::PointCloud cloud = fg_fuzz::sentinel_cloud();
  const fg::host::ReadResult r = fg::host::parse_pcd(data, size, name, cloud);
  fg_fuzz::check_cloud_read(r, cloud, name);
  return 0;
}
