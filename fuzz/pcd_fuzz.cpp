// Fuzz target: fg::host::parse_pcd on the bytes (ascii, binary, binary_compressed/LZF),
// with the default ReadLimits of read_pcd and again with ReadLimits::planar. Findings:
// crashes, sanitizer reports, leaks, hangs, and breaches of the reader's contract
// (fuzz_check.hpp).
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "fuzz_check.hpp"
#include "io/pcd.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string name = "fuzz.pcd";
  fg::host::PointCloud cloud = fg_fuzz::sentinel_cloud();
  const fg::host::ReadResult r = fg::host::parse_pcd(data, size, name, cloud);
  fg_fuzz::check_cloud_read(r, cloud, name);
  // The planar read (what `forcegrasp plan` asks for): the same outcome and the same
  // coordinates, bit for bit.
  fg::host::ReadLimits planar_limits;
  planar_limits.planar = true;
  fg::host::PointCloud planar = fg_fuzz::sentinel_cloud();
  const fg::host::ReadResult rp = fg::host::parse_pcd(data, size, name, planar, planar_limits);
  fg_fuzz::check_cloud_read(rp, planar, name);
  FG_FUZZ_CHECK(rp.ok == r.ok && rp.error == r.error, "the planar read ends differently");
  if (r.ok && planar.planar()) {
    FG_FUZZ_CHECK(planar.size() == cloud.size(), "the planar read has another point count");
    for (size_t i = 0; i < cloud.size(); ++i)
      for (int k = 0; k < 3; ++k)
        FG_FUZZ_CHECK(
            std::memcmp(planar.planar_array(k) + i, &cloud.xyz[i * 3 + static_cast<size_t>(k)], sizeof(float)) == 0,
            "the planar read has other coordinates");
  }
  return 0;
}
