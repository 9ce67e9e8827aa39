// Host-only PCD v0.7 reader and writer (the project's own, hardened).
//
// Hardening rules: every size is checked before it is used, every product is
// overflow-checked, nothing is allocated before the data is known to be big enough
// for it (binary: exact size; binary_compressed: the declared sizes must agree with
// the header and with what the LZF bytes can possibly hold; ascii: a lower bound of
// bytes per row), and the output cloud is only touched when the whole file parsed.
#include "pcd.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <new>
#include <string_view>
#include <system_error>

#include "fg/core/byte_order.hpp"
#include "lzf.hpp"
#include "text_parse.hpp"

// Binary PCD data is little-endian (as PCL writes it on the machines it runs on), read
// and written so on every host.

namespace fg::host {

namespace {
// An integer label field of 1, 2 or 4 bytes (little endian), as unsigned.
uint32_t read_label(const uint8_t* p, uint32_t size) {
  uint32_t v = 0;
  for (uint32_t k = 0; k < size && k < 4; ++k) v |= uint32_t{p[k]} << (8 * k);
  return v;
}

using text::fail;
using text::is_space;
using text::LeadingPlus;
using text::mul_ok;
using text::parse_real;
using text::parse_u64;
using text::printable;
using text::split_ws;
using text::to_float;
using text::trim;

struct Field {
  std::string name;
  uint32_t size = 0;
  char type = 'F';
  uint64_t count = 1;
  uint64_t offset = 0;  //!< byte offset inside one point (binary)
};

enum class DataKind { ascii, binary, binary_compressed };

std::string dims(uint64_t width, uint64_t height, uint64_t points) {
  if (height > 1) return std::to_string(width) + "x" + std::to_string(height);
  return std::to_string(points);
}

float read_coord(const uint8_t* p, uint32_t size) {
  if (size == 4) return load_le<float>(p);
  return to_float(load_le<double>(p));
}

ReadResult parse_pcd_impl(const uint8_t* data, size_t size, const std::string& name, PointCloud& out,
                          const ReadLimits& limits) {
  if (size == 0) return fail(name, "empty file (no PCD header)");
  if (size > limits.max_file_bytes) {
    return fail(name, "file of " + std::to_string(size) + " bytes is larger than the limit of " +
                          std::to_string(limits.max_file_bytes) + " bytes");
  }

  // ---- header -------------------------------------------------------------------------
  std::vector<std::string_view> fields_tok, size_tok, type_tok, count_tok, tok;
  bool have_version = false, have_fields = false, have_size = false, have_type = false, have_count = false,
       have_width = false, have_height = false, have_points = false, have_viewpoint = false, have_data = false;
  uint64_t width = 0, height = 1, points = 0;
  std::array<double, 7> viewpoint{{0, 0, 0, 1, 0, 0, 0}};
  DataKind kind = DataKind::ascii;
  size_t pos = 0;
  size_t line_no = 0;
  while (pos < size && !have_data) {
    const void* nl = std::memchr(data + pos, '\n', size - pos);
    const size_t line_end = nl ? static_cast<size_t>(static_cast<const uint8_t*>(nl) - data) : size;
    std::string_view line(reinterpret_cast<const char*>(data) + pos, line_end - pos);
    pos = nl ? line_end + 1 : size;
    ++line_no;
    line = trim(line);
    if (line.empty() || line.front() == '#') continue;
    split_ws(line, tok);
    const std::string_view key = tok[0];
    const std::string where = " (header line " + std::to_string(line_no) + ")";
    auto dup = [&](bool& seen) {
      if (seen) return true;
      seen = true;
      return false;
    };
    auto values = [&]() { return std::vector<std::string_view>(tok.begin() + 1, tok.end()); };
    if (key == "VERSION") {
      if (dup(have_version)) return fail(name, "duplicate VERSION line" + where);
      if (tok.size() != 2 || (tok[1] != ".7" && tok[1] != "0.7")) {
        return fail(name, "unsupported VERSION '" + printable(line.substr(7)) + "' (expected 0.7 or .7)" + where);
      }
    } else if (key == "FIELDS" || key == "COLUMNS") {
      if (dup(have_fields)) return fail(name, "duplicate FIELDS line" + where);
      fields_tok = values();
      if (fields_tok.empty()) return fail(name, "FIELDS line names no fields" + where);
    } else if (key == "SIZE") {
      if (dup(have_size)) return fail(name, "duplicate SIZE line" + where);
      size_tok = values();
    } else if (key == "TYPE") {
      if (dup(have_type)) return fail(name, "duplicate TYPE line" + where);
      type_tok = values();
    } else if (key == "COUNT") {
      if (dup(have_count)) return fail(name, "duplicate COUNT line" + where);
      count_tok = values();
    } else if (key == "WIDTH" || key == "HEIGHT" || key == "POINTS") {
      bool& seen = key == "WIDTH" ? have_width : key == "HEIGHT" ? have_height : have_points;
      uint64_t& v = key == "WIDTH" ? width : key == "HEIGHT" ? height : points;
      const std::string k(key);
      if (dup(seen)) return fail(name, "duplicate " + k + " line" + where);
      if (tok.size() != 2) return fail(name, k + " needs exactly one value" + where);
      if (!parse_u64(tok[1], v, LeadingPlus::reject)) {
        return fail(name, k + " value '" + printable(tok[1]) +
                              "' is not a non-negative integer (non-numeric or out of range)" + where);
      }
      if (k != "POINTS" && v > std::numeric_limits<uint32_t>::max()) {
        return fail(name, k + " " + std::to_string(v) + " is too large" + where);
      }
    } else if (key == "VIEWPOINT") {
      if (dup(have_viewpoint)) return fail(name, "duplicate VIEWPOINT line" + where);
      if (tok.size() != 8) {
        return fail(name,
                    "VIEWPOINT needs 7 values (tx ty tz qw qx qy qz), got " + std::to_string(tok.size() - 1) + where);
      }
      for (size_t i = 0; i < 7; ++i) {
        if (!parse_real(tok[i + 1], viewpoint[i])) {
          return fail(name, "VIEWPOINT value '" + printable(tok[i + 1]) + "' is not a number" + where);
        }
        if (!std::isfinite(viewpoint[i])) {
          return fail(name, "VIEWPOINT value '" + printable(tok[i + 1]) + "' is not finite" + where);
        }
      }
      const double qn = std::sqrt(viewpoint[3] * viewpoint[3] + viewpoint[4] * viewpoint[4] +
                                  viewpoint[5] * viewpoint[5] + viewpoint[6] * viewpoint[6]);
      if (!(qn > 1e-9)) return fail(name, "VIEWPOINT quaternion is zero" + where);
    } else if (key == "DATA") {
      if (tok.size() != 2) return fail(name, "DATA needs exactly one value" + where);
      if (tok[1] == "ascii") {
        kind = DataKind::ascii;
      } else if (tok[1] == "binary") {
        kind = DataKind::binary;
      } else if (tok[1] == "binary_compressed") {
        kind = DataKind::binary_compressed;
      } else {
        return fail(name, "unknown DATA kind '" + printable(tok[1]) +
                              "' (expected ascii, binary or binary_compressed)" + where);
      }
      have_data = true;
    } else {
      return fail(name, "unknown header line '" + printable(line) + "'" + where +
                            " (not a PCD v0.7 header, or a truncated/garbled one)");
    }
  }
  if (!have_data) return fail(name, "truncated header: no DATA line");
  const size_t data_offset = pos;

  // ---- fields -------------------------------------------------------------------------
  if (!have_fields) return fail(name, "header has no FIELDS line");
  const size_t nf = fields_tok.size();
  if (!have_size) return fail(name, "header has no SIZE line");
  if (!have_type) return fail(name, "header has no TYPE line");
  auto count_mismatch = [&](const char* what, size_t n) {
    return fail(name, std::string(what) + " has " + std::to_string(n) + " entries but FIELDS has " +
                          std::to_string(nf) + " (count mismatch)");
  };
  if (size_tok.size() != nf) return count_mismatch("SIZE", size_tok.size());
  if (type_tok.size() != nf) return count_mismatch("TYPE", type_tok.size());
  if (have_count && count_tok.size() != nf) return count_mismatch("COUNT", count_tok.size());

  std::vector<Field> fields(nf);
  uint64_t point_size = 0;   // bytes per point
  uint64_t total_count = 0;  // values per point (ascii)
  int ix = -1, iy = -1, iz = -1;
  int il = -1;  // optional integer `label` field (ground truth of labelled captures)
  for (size_t f = 0; f < nf; ++f) {
    Field& fd = fields[f];
    fd.name = std::string(fields_tok[f]);
    const std::string fq = "field '" + printable(fd.name) + "'";
    uint64_t sz = 0;
    if (!parse_u64(size_tok[f], sz, LeadingPlus::reject) || (sz != 1 && sz != 2 && sz != 4 && sz != 8)) {
      return fail(name, "SIZE '" + printable(size_tok[f]) + "' of " + fq + " is not 1, 2, 4 or 8");
    }
    fd.size = static_cast<uint32_t>(sz);
    const std::string_view t = type_tok[f];
    if (t.size() != 1 || std::string_view("IUFiuf").find(t[0]) == std::string_view::npos) {
      return fail(name, "TYPE '" + printable(t) + "' of " + fq + " is not I, U or F");
    }
    fd.type = static_cast<char>(std::toupper(static_cast<unsigned char>(t[0])));
    if (fd.type == 'F' && fd.size != 4 && fd.size != 8) {
      return fail(name, fq + " is TYPE F with SIZE " + std::to_string(fd.size) + " (expected 4 or 8)");
    }
    if (have_count) {
      if (!parse_u64(count_tok[f], fd.count, LeadingPlus::reject) || fd.count == 0) {
        return fail(name, "COUNT '" + printable(count_tok[f]) + "' of " + fq + " is not a positive integer");
      }
    }
    uint64_t bytes = 0;
    if (!mul_ok(fd.size, fd.count, bytes) || point_size + bytes < point_size || total_count + fd.count < total_count) {
      return fail(name, "COUNT of " + fq + " is too large");
    }
    fd.offset = point_size;
    point_size += bytes;
    total_count += fd.count;
    if (fd.name != "_") {
      for (size_t g = 0; g < f; ++g) {
        if (fields[g].name == fd.name) return fail(name, "duplicate " + fq + " in FIELDS");
      }
    }
    if (fd.name == "label" && fd.count == 1 && (fd.type == 'U' || fd.type == 'I') && fd.size <= 4)
      il = static_cast<int>(f);
    if (fd.name == "x") ix = static_cast<int>(f);
    if (fd.name == "y") iy = static_cast<int>(f);
    if (fd.name == "z") iz = static_cast<int>(f);
  }
  for (const auto& [idx, axis] : {std::pair<int, const char*>{ix, "x"}, {iy, "y"}, {iz, "z"}}) {
    if (idx < 0) {
      std::string list;
      for (const auto& s : fields_tok) list += (list.empty() ? "" : " ") + printable(s);
      return fail(name, std::string("missing field '") + axis + "' (FIELDS " + list + ")");
    }
    const Field& fd = fields[static_cast<size_t>(idx)];
    if (fd.type != 'F' || fd.count != 1) {
      return fail(name, std::string("field '") + axis + "' must be TYPE F, SIZE 4 or 8, COUNT 1 (got " + fd.type + " " +
                            std::to_string(fd.size) + " " + std::to_string(fd.count) + ")");
    }
  }

  // ---- dimensions ---------------------------------------------------------------------
  if (!have_width && !have_points) return fail(name, "header has neither WIDTH nor POINTS");
  if (!have_width) {
    if (have_height && height != 1) return fail(name, "header has HEIGHT but no WIDTH");
    if (points > std::numeric_limits<uint32_t>::max()) {
      return fail(name, "POINTS " + std::to_string(points) + " is too large");
    }
    width = points;
    height = 1;
  }
  uint64_t wh = 0;
  if (!mul_ok(width, height, wh)) return fail(name, "WIDTH x HEIGHT overflows");
  if (!have_points) points = wh;
  if (wh != points) {
    return fail(name, "WIDTH x HEIGHT = " + std::to_string(width) + "x" + std::to_string(height) + " = " +
                          std::to_string(wh) + " does not match POINTS " + std::to_string(points) +
                          " (inconsistent point count)");
  }
  if (points > limits.max_points) {
    return fail(name, "declares " + std::to_string(points) + " points, more than the limit of " +
                          std::to_string(limits.max_points) + " (too many points)");
  }
  uint64_t data_bytes = 0;
  if (!mul_ok(points, point_size, data_bytes)) {
    return fail(name, "points x point size overflows (too many points or fields too large)");
  }
  const uint64_t remaining = size - data_offset;
  const std::string npts = dims(width, height, points) + " points";

  const Field& fx = fields[static_cast<size_t>(ix)];
  const Field& fy = fields[static_cast<size_t>(iy)];
  const Field& fz = fields[static_cast<size_t>(iz)];
  PointCloud cloud;
  cloud.width = static_cast<uint32_t>(width);
  cloud.height = static_cast<uint32_t>(height);
  cloud.viewpoint = viewpoint;

  // ---- data ---------------------------------------------------------------------------
  if (kind == DataKind::binary) {
    if (remaining < data_bytes) {
      return fail(name, "DATA binary holds " + std::to_string(remaining) + " bytes but " + npts + " need " +
                            std::to_string(data_bytes) + " (file too short / truncated)");
    }
    cloud.xyz.resize(points * 3);
    const uint8_t* base = data + data_offset;
    float* o = cloud.xyz.data();
    for (uint64_t i = 0; i < points; ++i, base += point_size, o += 3) {
      o[0] = read_coord(base + fx.offset, fx.size);
      o[1] = read_coord(base + fy.offset, fy.size);
      o[2] = read_coord(base + fz.offset, fz.size);
    }
    if (il >= 0) {
      const Field& fl = fields[static_cast<size_t>(il)];
      cloud.labels.resize(points);
      for (uint64_t i = 0; i < points; ++i)
        cloud.labels[i] = read_label(data + data_offset + i * point_size + fl.offset, fl.size);
    }
  } else if (kind == DataKind::binary_compressed) {
    if (remaining < 8) {
      return fail(name, "DATA binary_compressed holds " + std::to_string(remaining) +
                            " bytes, too few for the 8-byte compressed/uncompressed size header "
                            "(file truncated)");
    }
    const uint32_t csize = load_le<uint32_t>(data + data_offset);
    const uint32_t usize = load_le<uint32_t>(data + data_offset + 4);
    if (csize > remaining - 8) {
      return fail(name, "compressed size " + std::to_string(csize) + " is larger than the " +
                            std::to_string(remaining - 8) + " bytes left in the file (truncated)");
    }
    if (usize != data_bytes) {
      return fail(name, "uncompressed size " + std::to_string(usize) + " does not match the " +
                            std::to_string(data_bytes) + " bytes that " + npts + " of " + std::to_string(point_size) +
                            " bytes need (size mismatch)");
    }
    if (usize > lzf::max_decompressed_size(csize)) {
      return fail(name, "uncompressed size " + std::to_string(usize) + " (" + npts + ") cannot come from " +
                            std::to_string(csize) + " compressed bytes (size mismatch / corrupt)");
    }
    BigBuffer<uint8_t> buf(usize > 0 ? usize : 1);
    std::string err;
    if (!lzf::decompress(data + data_offset + 8, csize, buf.data(), usize, err)) {
      return fail(name, "DATA binary_compressed: " + err);
    }
    // Structure of arrays: the block of field f starts at points * (offset of f in a point).
    const size_t block[3] = {static_cast<size_t>(points * fx.offset), static_cast<size_t>(points * fy.offset),
                             static_cast<size_t>(points * fz.offset)};
    const uint8_t* bx = buf.data() + block[0];
    const uint8_t* by = buf.data() + block[1];
    const uint8_t* bz = buf.data() + block[2];
    if (il >= 0) {
      const Field& fl = fields[static_cast<size_t>(il)];
      const uint8_t* bl = buf.data() + points * fl.offset;
      cloud.labels.resize(points);
      for (uint64_t i = 0; i < points; ++i) cloud.labels[i] = read_label(bl + i * fl.size, fl.size);
    }
    if (limits.planar && points > 0 && fx.size == 4 && fy.size == 4 && fz.size == 4) {
      // x, y and z are float arrays in the block already: hand the block over (in the
      // host's byte order).
      if constexpr (!kLittleEndian) {
        for (int k = 0; k < 3; ++k) {
          uint8_t* b = buf.data() + block[k];
          for (uint64_t i = 0; i < points; ++i, b += 4) {
            uint32_t u;
            std::memcpy(&u, b, 4);
            u = le_order(u);
            std::memcpy(b, &u, 4);
          }
        }
      }
      for (int k = 0; k < 3; ++k) cloud.planar_offset[k] = block[k];
      cloud.planar_points = points;
      cloud.planar_block = std::move(buf);
    } else {
      cloud.xyz.resize(points * 3);
      float* o = cloud.xyz.data();
      for (uint64_t i = 0; i < points; ++i, o += 3) {
        o[0] = read_coord(bx + i * fx.size, fx.size);
        o[1] = read_coord(by + i * fy.size, fy.size);
        o[2] = read_coord(bz + i * fz.size, fz.size);
      }
    }
  } else {
    // ascii: every value takes at least one byte, so V values per point bound the points
    // (and the allocation) by the bytes present.
    uint64_t min_bytes = 0;
    if (!mul_ok(points, total_count, min_bytes) || remaining < min_bytes) {
      return fail(name, "DATA ascii holds " + std::to_string(remaining) + " bytes, too few for " + npts + " of " +
                            std::to_string(total_count) + " values each (file too short / truncated)");
    }
    cloud.xyz.resize(points * 3);
    std::vector<int> slot(nf, -1);
    slot[static_cast<size_t>(ix)] = 0;
    slot[static_cast<size_t>(iy)] = 1;
    slot[static_cast<size_t>(iz)] = 2;
    uint64_t row = 0;
    while (row < points) {
      if (pos >= size) {
        return fail(name, "DATA ascii has " + std::to_string(row) + " rows but " + npts +
                              " are declared (too few rows / truncated)");
      }
      const void* nl = std::memchr(data + pos, '\n', size - pos);
      const size_t line_end = nl ? static_cast<size_t>(static_cast<const uint8_t*>(nl) - data) : size;
      std::string_view line(reinterpret_cast<const char*>(data) + pos, line_end - pos);
      pos = nl ? line_end + 1 : size;
      ++line_no;
      line = trim(line);
      if (line.empty()) continue;
      split_ws(line, tok);
      if (tok.size() != total_count) {
        return fail(name, "ascii row " + std::to_string(row + 1) + " (line " + std::to_string(line_no) + ") has " +
                              std::to_string(tok.size()) + " values, expected " + std::to_string(total_count) +
                              (tok.size() < total_count ? " (too few values)" : " (too many values)"));
      }
      size_t k = 0;
      for (size_t f = 0; f < nf; ++f) {
        for (uint64_t c = 0; c < fields[f].count; ++c, ++k) {
          double v = 0;
          float fv = 0;
          const bool num = slot[f] >= 0 ? parse_real(tok[k], fv) : parse_real(tok[k], v);
          if (!num) {
            return fail(name, "ascii row " + std::to_string(row + 1) + " (line " + std::to_string(line_no) +
                                  "): value '" + printable(tok[k]) + "' of field '" + printable(fields[f].name) +
                                  "' is not a number");
          }
          if (slot[f] >= 0) cloud.xyz[row * 3 + static_cast<size_t>(slot[f])] = fv;
        }
      }
      ++row;
    }
    for (size_t i = pos; i < size; ++i) {
      const char c = static_cast<char>(data[i]);
      if (!is_space(c) && c != '\0') {
        return fail(name, "DATA ascii has more rows than the " + std::to_string(points) +
                              " declared by POINTS (extra data after the last point)");
      }
    }
  }
  out = std::move(cloud);
  return {};
}

void append_double(std::string& s, double v) {
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  s.append(buf, res.ptr);
}

void append_float(std::string& s, float v) {
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  s.append(buf, res.ptr);
}

}  // namespace

ReadResult read_file_bytes(const std::string& path, BigBuffer<uint8_t>& out, uint64_t max_bytes) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st)) return fail(path, "cannot open file (does not exist or is not readable)");
  if (fs::is_directory(st)) return fail(path, "is a directory, not a file");
  // Devices, FIFOs and sockets are refused: one may never end (/dev/zero) or block
  // until a writer appears, and "never hangs" is part of the contract.
  if (!fs::is_regular_file(st)) return fail(path, "is not a regular file (a device, FIFO or socket)");
  uintmax_t expected = 0;
  {
    expected = fs::file_size(path, ec);
    if (ec) expected = 0;
    if (expected > max_bytes) {
      return fail(path, "file of " + std::to_string(expected) + " bytes is larger than the limit of " +
                            std::to_string(max_bytes) + " bytes");
    }
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) return fail(path, "cannot open file for reading");
  BigBuffer<uint8_t> bytes;
  constexpr size_t kChunk = size_t{1} << 20;
  try {
    // The size the file system reported in one read, then chunks while more arrives
    // (a file that grows while it is read still stops at max_bytes).
    bytes.reserve(static_cast<size_t>(expected) + kChunk);
    size_t want = static_cast<size_t>(expected) + 1;  // +1: end of file seen in the first read
    for (;;) {
      const size_t old = bytes.size();
      bytes.resize(old + want);
      in.read(reinterpret_cast<char*>(bytes.data() + old), static_cast<std::streamsize>(want));
      const size_t got = static_cast<size_t>(in.gcount());
      bytes.resize(old + got);
      if (bytes.size() > max_bytes) {
        return fail(path, "file is larger than the limit of " + std::to_string(max_bytes) + " bytes");
      }
      if (got < want) break;
      want = kChunk;
    }
  } catch (const std::bad_alloc&) {
    return fail(path, "out of memory while reading the file");
  }
  if (in.bad()) return fail(path, "read error");
  out = std::move(bytes);
  return {};
}

ReadResult parse_pcd(const uint8_t* data, size_t size, const std::string& name, PointCloud& out,
                     const ReadLimits& limits) {
  return text::guarded_parse(data, size, name, [&] { return parse_pcd_impl(data, size, name, out, limits); });
}

ReadResult read_pcd(const std::string& path, PointCloud& out, const ReadLimits& limits) {
  BigBuffer<uint8_t> bytes;
  if (ReadResult r = read_file_bytes(path, bytes, limits.max_file_bytes); !r.ok) return r;
  return parse_pcd(bytes.data(), bytes.size(), path, out, limits);
}

ReadResult write_pcd(const std::string& path, const PointCloud& cloud, PcdEncoding encoding) {
  if (cloud.xyz.size() % 3 != 0) {
    return fail(path, "cannot write: xyz holds " + std::to_string(cloud.xyz.size()) + " floats, not a multiple of 3");
  }
  const uint64_t n = cloud.size();
  if (uint64_t{cloud.width} * cloud.height != n) {
    return fail(path, "cannot write: width x height = " + std::to_string(cloud.width) + "x" +
                          std::to_string(cloud.height) + " does not match the " + std::to_string(n) +
                          " points of the cloud");
  }
  if (encoding == PcdEncoding::binary_compressed && n * 12 > std::numeric_limits<uint32_t>::max()) {
    return fail(path, "cannot write: too many points for binary_compressed (32-bit sizes)");
  }
  std::string h =
      "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\n"
      "TYPE F F F\nCOUNT 1 1 1\nWIDTH " +
      std::to_string(cloud.width) + "\nHEIGHT " + std::to_string(cloud.height) + "\nVIEWPOINT";
  for (double v : cloud.viewpoint) {
    h += ' ';
    append_double(h, v);
  }
  h += "\nPOINTS " + std::to_string(n) + "\nDATA ";
  h += encoding == PcdEncoding::ascii    ? "ascii\n"
       : encoding == PcdEncoding::binary ? "binary\n"
                                         : "binary_compressed\n";

  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) return fail(path, "cannot open file for writing");
  f.write(h.data(), static_cast<std::streamsize>(h.size()));
  if (encoding == PcdEncoding::ascii) {
    std::string body;
    body.reserve(static_cast<size_t>(n) * 36);
    for (uint64_t i = 0; i < n; ++i) {
      for (int k = 0; k < 3; ++k) {
        if (k) body += ' ';
        append_float(body, cloud.xyz[i * 3 + static_cast<uint64_t>(k)]);
      }
      body += '\n';
    }
    f.write(body.data(), static_cast<std::streamsize>(body.size()));
  } else if (encoding == PcdEncoding::binary) {
    std::vector<uint8_t> le(cloud.xyz.size() * 4);  // little-endian floats, point by point
    for (size_t i = 0; i < cloud.xyz.size(); ++i) store_le(cloud.xyz[i], &le[i * 4]);
    f.write(reinterpret_cast<const char*>(le.data()), static_cast<std::streamsize>(le.size()));
  } else {
    // Structure of arrays (all x, all y, all z), little-endian floats.
    std::vector<uint8_t> soa(cloud.xyz.size() * 4);
    for (uint64_t i = 0; i < n; ++i) {
      for (uint64_t k = 0; k < 3; ++k) store_le(cloud.xyz[i * 3 + k], &soa[(k * n + i) * 4]);
    }
    const std::vector<uint8_t> packed = lzf::compress(soa.data(), soa.size());
    if (packed.size() > std::numeric_limits<uint32_t>::max()) {
      return fail(path, "cannot write: compressed data exceeds 4 GiB");
    }
    uint8_t sizes[8];
    store_le(static_cast<uint32_t>(packed.size()), sizes);
    store_le(static_cast<uint32_t>(soa.size()), sizes + 4);
    f.write(reinterpret_cast<const char*>(sizes), sizeof sizes);
    f.write(reinterpret_cast<const char*>(packed.data()), static_cast<std::streamsize>(packed.size()));
  }
  f.close();
  if (!f) return fail(path, "write error");
  return {};
}

}  // namespace fg::host
