// Fuzz target: fg::host::parse_pcd on the bytes (ascii, binary, binary_compressed/LZF),
// with the default ReadLimits of read_pcd and again with ReadLimits::planar, and the
// same bytes as a file streamed by fg::host::PcdStream (the reader `forcegrasp plan`
// takes DATA binary files with). Findings: crashes, sanitizer reports, leaks, hangs,
// and breaches of the readers' contracts (fuzz_check.hpp): a stream must only open a
// file the whole-file reader reads, and hand over its points, bit for bit.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "fuzz_check.hpp"
#include "io/pcd.hpp"
#include "io/pcd_stream.hpp"

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace {

//! Streams the bytes as a file (an in-memory one) and checks the pieces against the
//! whole-file reader's cloud.
void check_stream(const uint8_t* data, size_t size, const fg::host::ReadResult& whole,
                  const fg::host::PointCloud& cloud) {
#if defined(__linux__)
  const int fd = memfd_create("fuzz.pcd", MFD_CLOEXEC);
  if (fd < 0) return;
  size_t put = 0;
  while (put < size) {
    const ssize_t w = ::write(fd, data + put, size - put);
    if (w <= 0) break;
    put += static_cast<size_t>(w);
  }
  fg::host::PcdStream stream;
  const bool opened = put == size && stream.open("/proc/self/fd/" + std::to_string(fd));
  ::close(fd);  // the stream holds its own descriptor
  if (!opened) return;
  FG_FUZZ_CHECK(whole.ok, "the stream opened a file the whole-file reader refuses");
  FG_FUZZ_CHECK(stream.points() == cloud.size(), "the stream declares another point count");
  size_t i = 0;
  for (;;) {  // bounded: every piece holds at least one point until the end
    fg::PointPiece piece;
    FG_FUZZ_CHECK(stream.next(piece), "the stream failed on an unchanged file");
    if (piece.count == 0) break;
    FG_FUZZ_CHECK(piece.count <= cloud.size() - i, "the stream hands over more points than the file holds");
    for (uint32_t j = 0; j < piece.count; ++j, ++i) {
      const uint8_t* at[3] = {piece.x, piece.y, piece.z};
      for (int k = 0; k < 3; ++k)
        FG_FUZZ_CHECK(std::memcmp(at[k] + static_cast<size_t>(j) * piece.stride,
                                  &cloud.xyz[i * 3 + static_cast<size_t>(k)], sizeof(float)) == 0,
                      "the stream hands over other coordinates");
    }
  }
  FG_FUZZ_CHECK(i == cloud.size(), "the stream ends early");
#else
  (void)data, (void)size, (void)whole, (void)cloud;
#endif
}

}  // namespace

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
  check_stream(data, size, r, cloud);
  return 0;
}
