// Host-only: a DATA binary PCD file's points handed to the planner in place, chunk by
// chunk through one buffer of bounded size: no copy of the whole file and no
// intermediate cloud, so memory does not grow with the file.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "fg/core/planner.hpp"
#include "pcd.hpp"

namespace fg::host {

class PcdStream final : public PointSource {
 public:
  //! The chunk buffer's size: a few hundred kilobytes stay in the core's L2 cache while
  //! the ingest reads them.
  static constexpr size_t kChunkBytes = size_t{256} << 10;

  PcdStream() = default;
  PcdStream(const PcdStream&) = delete;
  PcdStream& operator=(const PcdStream&) = delete;
  ~PcdStream();

  //! Opens `path` for streaming. True when it is a regular file of DATA binary with
  //! 4-byte float x, y and z, long enough for the points its header declares, on a
  //! little-endian host. False for anything else, valid or not: read_cloud() then reads
  //! the whole file and names any problem, as it always has.
  [[nodiscard]] bool open(const std::string& path, const ReadLimits& limits = {});

  //! The next chunk of whole points (PointSource). False when the file shrank while it
  //! was read or a read failed: error() names the file and the problem.
  [[nodiscard]] bool next(PointPiece& piece) override;

  //! From the first point again (PointSource): the planner reads a hand cloud twice.
  bool can_rewind() const override { return fd_ >= 0; }
  [[nodiscard]] bool rewind() override {
    next_point_ = 0;
    return fd_ >= 0;
  }

  const std::string& error() const { return error_; }
  uint64_t points() const { return layout_.points; }

 private:
  void close_file();
  int fd_ = -1;
  std::string path_, error_;
  PcdBinaryFloats layout_;
  uint64_t next_point_ = 0;  // the first point of the next chunk
  std::vector<uint8_t> buffer_;
};

}  // namespace fg::host
