#include "pcd_stream.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "fg/core/byte_order.hpp"
#include "text_parse.hpp"

namespace fg::host {

namespace {
// A PCD header is a dozen short lines; one this long is read by the whole-file reader.
constexpr size_t kHeaderBytes = size_t{16} << 10;

//! Reads up to n bytes at `offset`, retrying interrupted and partial reads; the bytes
//! read (fewer at the end of the file), or -1 on an error.
int64_t read_at(int fd, uint8_t* out, size_t n, uint64_t offset) {
  size_t got = 0;
  while (got < n) {  // bounded: each pass reads at least one byte or ends
    const ssize_t r = ::pread(fd, out + got, n - got, static_cast<off_t>(offset + got));
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) return -1;
    if (r == 0) break;
    got += static_cast<size_t>(r);
  }
  return static_cast<int64_t>(got);
}
}  // namespace

PcdStream::~PcdStream() { close_file(); }

void PcdStream::close_file() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

bool PcdStream::open(const std::string& path, const ReadLimits& limits) {
  close_file();
  if constexpr (!kLittleEndian) return false;  // the floats would need their bytes swapped
  path_ = path;
  error_.clear();
  next_point_ = 0;
  // Non-blocking: opening a FIFO must not wait for a writer (it is refused below).
  fd_ = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) return false;
  struct stat st {};
  if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode) || static_cast<uint64_t>(st.st_size) > limits.max_file_bytes) {
    close_file();
    return false;
  }
  const uint64_t file_bytes = static_cast<uint64_t>(st.st_size);
  std::vector<uint8_t> head(kHeaderBytes < file_bytes ? kHeaderBytes : static_cast<size_t>(file_bytes));
  const int64_t got = read_at(fd_, head.data(), head.size(), 0);
  bool binary_floats = false;
  if (got != static_cast<int64_t>(head.size()) ||
      !parse_pcd_header(head.data(), head.size(), path, limits, binary_floats, layout_).ok || !binary_floats) {
    close_file();
    return false;
  }
  // Whole points per chunk; the points the header declares must all be in the file
  // (the whole-file reader names a short one).
  const uint64_t data_bytes = layout_.points * layout_.point_size;  // checked by the header's parse
  if (layout_.point_size > kChunkBytes || layout_.data_offset > file_bytes ||
      file_bytes - layout_.data_offset < data_bytes) {
    close_file();
    return false;
  }
  buffer_.resize(kChunkBytes);
  return true;
}

bool PcdStream::next(PointPiece& piece) {
  piece = PointPiece{};
  if (fd_ < 0) {
    error_ = text::cat(path_, ": not open for streaming");
    return false;
  }
  if (next_point_ >= layout_.points) return true;  // the end: no more points
  const uint64_t per_chunk = kChunkBytes / layout_.point_size;
  const uint64_t left = layout_.points - next_point_;
  const uint64_t n = left < per_chunk ? left : per_chunk;
  const size_t bytes = static_cast<size_t>(n * layout_.point_size);
  const uint64_t at = layout_.data_offset + next_point_ * layout_.point_size;
  const int64_t got = read_at(fd_, buffer_.data(), bytes, at);
  if (got < 0) {
    error_ = text::cat(path_, ": read error: ", std::strerror(errno));
    return false;
  }
  if (static_cast<size_t>(got) < bytes) {
    error_ = text::cat(path_, ": the file shrank while it was read: DATA binary ends ",
                       std::to_string(at + static_cast<uint64_t>(got) - layout_.data_offset), " bytes in, but ",
                       std::to_string(layout_.points), " points need ",
                       std::to_string(layout_.points * layout_.point_size), " (truncated)");
    return false;
  }
  next_point_ += n;
  piece.x = buffer_.data() + layout_.offset[0];
  piece.y = buffer_.data() + layout_.offset[1];
  piece.z = buffer_.data() + layout_.offset[2];
  piece.stride = static_cast<uint32_t>(layout_.point_size);
  piece.count = static_cast<uint32_t>(n);
  return true;
}

}  // namespace fg::host
