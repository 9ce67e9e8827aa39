// Host-only PCD v0.7 reader and writer (the project's own, hardened).
//
// Hardening rules: every size is checked before it is used, every product is
// overflow-checked, nothing is allocated before the data is known to be big enough
// for it (binary: exact size; binary_compressed: the declared sizes must agree with
// the header and with what the LZF bytes can possibly hold; ascii: a lower bound of
// bytes per row), and the output cloud is only touched when the whole file parsed.
#include "pcd.hpp"

#include <array>
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
#include <utility>
#include <vector>

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

using text::cat;
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

using Tokens = std::vector<std::string_view>;

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

//! Walks the file line by line: the header, then the rows of DATA ascii (whose line
//! numbers in messages continue the header's).
struct LineCursor {
  const uint8_t* data = nullptr;
  size_t size = 0;
  size_t pos = 0;      //!< first byte of the next line
  size_t line_no = 0;  //!< 1-based number of the line last returned

  bool at_end() const { return pos >= size; }

  //! The next line, trimmed; pos moves past its line break.
  std::string_view next() {
    const void* nl = std::memchr(data + pos, '\n', size - pos);
    const size_t line_end = nl ? static_cast<size_t>(static_cast<const uint8_t*>(nl) - data) : size;
    const std::string_view line(reinterpret_cast<const char*>(data) + pos, line_end - pos);
    pos = nl ? line_end + 1 : size;
    ++line_no;
    return trim(line);
  }
};

// ---- header ---------------------------------------------------------------------------

//! The header lines as declared, before they are checked against each other. The
//! token views point into the file's bytes.
struct PcdHeader {
  Tokens fields_tok, size_tok, type_tok, count_tok;
  bool have_version = false, have_fields = false, have_size = false, have_type = false, have_count = false,
       have_width = false, have_height = false, have_points = false, have_viewpoint = false, have_data = false;
  uint64_t width = 0, height = 1, points = 0;
  std::array<double, 7> viewpoint{{0, 0, 0, 1, 0, 0, 0}};
  DataKind kind = DataKind::ascii;
};

//! One header line: its text, its tokens (at least one) and " (header line N)" for
//! messages.
struct HeaderLine {
  std::string_view text;
  const Tokens& tok;
  std::string where;

  Tokens values() const { return Tokens(tok.begin() + 1, tok.end()); }
};

//! Marks a header key as seen; true when it had been seen already (a duplicate line).
bool seen_before(bool& seen) {
  if (seen) return true;
  seen = true;
  return false;
}

[[nodiscard]] ReadResult version_line(const HeaderLine& l, const std::string& name, PcdHeader& h) {
  if (seen_before(h.have_version)) return fail(name, cat("duplicate VERSION line", l.where));
  if (l.tok.size() != 2 || (l.tok[1] != ".7" && l.tok[1] != "0.7")) {
    return fail(name, cat("unsupported VERSION '", printable(l.text.substr(7)), "' (expected 0.7 or .7)", l.where));
  }
  return {};
}

//! FIELDS (or COLUMNS), SIZE, TYPE or COUNT: one entry per field, matched up once the
//! whole header is read.
[[nodiscard]] ReadResult list_line(const HeaderLine& l, std::string_view key, bool& seen, Tokens& values,
                                   const std::string& name) {
  if (seen_before(seen)) return fail(name, cat("duplicate ", key, " line", l.where));
  values = l.values();
  return {};
}

//! WIDTH, HEIGHT or POINTS: one non-negative integer (WIDTH and HEIGHT within 32 bits).
[[nodiscard]] ReadResult count_line(const HeaderLine& l, std::string_view key, bool& seen, uint64_t& v,
                                    const std::string& name) {
  if (seen_before(seen)) return fail(name, cat("duplicate ", key, " line", l.where));
  if (l.tok.size() != 2) return fail(name, cat(key, " needs exactly one value", l.where));
  if (!parse_u64(l.tok[1], v, LeadingPlus::reject)) {
    return fail(name, cat(key, " value '", printable(l.tok[1]),
                          "' is not a non-negative integer (non-numeric or out of range)", l.where));
  }
  if (key != "POINTS" && v > std::numeric_limits<uint32_t>::max()) {
    return fail(name, cat(key, " ", std::to_string(v), " is too large", l.where));
  }
  return {};
}

//! VIEWPOINT tx ty tz qw qx qy qz: finite numbers, a quaternion that is not zero.
[[nodiscard]] ReadResult viewpoint_line(const HeaderLine& l, const std::string& name, PcdHeader& h) {
  if (seen_before(h.have_viewpoint)) return fail(name, cat("duplicate VIEWPOINT line", l.where));
  if (l.tok.size() != 8) {
    return fail(
        name, cat("VIEWPOINT needs 7 values (tx ty tz qw qx qy qz), got ", std::to_string(l.tok.size() - 1), l.where));
  }
  std::array<double, 7>& viewpoint = h.viewpoint;
  for (size_t i = 0; i < 7; ++i) {
    if (!parse_real(l.tok[i + 1], viewpoint[i])) {
      return fail(name, cat("VIEWPOINT value '", printable(l.tok[i + 1]), "' is not a number", l.where));
    }
    if (!std::isfinite(viewpoint[i])) {
      return fail(name, cat("VIEWPOINT value '", printable(l.tok[i + 1]), "' is not finite", l.where));
    }
  }
  const double qn = std::sqrt(viewpoint[3] * viewpoint[3] + viewpoint[4] * viewpoint[4] + viewpoint[5] * viewpoint[5] +
                              viewpoint[6] * viewpoint[6]);
  if (!(qn > 1e-9)) return fail(name, cat("VIEWPOINT quaternion is zero", l.where));
  return {};
}

//! DATA ascii, binary or binary_compressed: the last header line.
[[nodiscard]] ReadResult data_line(const HeaderLine& l, const std::string& name, PcdHeader& h) {
  if (l.tok.size() != 2) return fail(name, cat("DATA needs exactly one value", l.where));
  if (l.tok[1] == "ascii") {
    h.kind = DataKind::ascii;
  } else if (l.tok[1] == "binary") {
    h.kind = DataKind::binary;
  } else if (l.tok[1] == "binary_compressed") {
    h.kind = DataKind::binary_compressed;
  } else {
    return fail(name, cat("unknown DATA kind '", printable(l.tok[1]), "' (expected ascii, binary or binary_compressed)",
                          l.where));
  }
  h.have_data = true;
  return {};
}

//! One header line by its key (the line's first token).
[[nodiscard]] ReadResult header_line(const HeaderLine& l, const std::string& name, PcdHeader& h) {
  const std::string_view key = l.tok[0];
  if (key == "VERSION") return version_line(l, name, h);
  if (key == "FIELDS" || key == "COLUMNS") {
    if (ReadResult r = list_line(l, "FIELDS", h.have_fields, h.fields_tok, name); !r.ok) return r;
    if (h.fields_tok.empty()) return fail(name, cat("FIELDS line names no fields", l.where));
    return {};
  }
  if (key == "SIZE") return list_line(l, key, h.have_size, h.size_tok, name);
  if (key == "TYPE") return list_line(l, key, h.have_type, h.type_tok, name);
  if (key == "COUNT") return list_line(l, key, h.have_count, h.count_tok, name);
  if (key == "WIDTH") return count_line(l, key, h.have_width, h.width, name);
  if (key == "HEIGHT") return count_line(l, key, h.have_height, h.height, name);
  if (key == "POINTS") return count_line(l, key, h.have_points, h.points, name);
  if (key == "VIEWPOINT") return viewpoint_line(l, name, h);
  if (key == "DATA") return data_line(l, name, h);
  return fail(name, cat("unknown header line '", printable(l.text), "'", l.where,
                        " (not a PCD v0.7 header, or a truncated/garbled one)"));
}

//! Reads the header up to and including its DATA line (blank lines and # comments
//! skipped); the cursor then stands at the first byte of the data.
[[nodiscard]] ReadResult read_header(LineCursor& lines, const std::string& name, PcdHeader& h) {
  Tokens tok;
  while (!lines.at_end() && !h.have_data) {
    const std::string_view line = lines.next();
    if (line.empty() || line.front() == '#') continue;
    split_ws(line, tok);
    const HeaderLine l{line, tok, cat(" (header line ", std::to_string(lines.line_no), ")")};
    if (ReadResult r = header_line(l, name, h); !r.ok) return r;
  }
  if (!h.have_data) return fail(name, "truncated header: no DATA line");
  return {};
}

// ---- fields ---------------------------------------------------------------------------

//! The fields of a point: their places in it, and which of them are x, y, z and the label.
struct PcdLayout {
  std::vector<Field> fields;
  uint64_t point_size = 0;   //!< bytes per point
  uint64_t total_count = 0;  //!< values per point (ascii)
  int ix = -1, iy = -1, iz = -1;
  int il = -1;  //!< optional integer `label` field (ground truth of labelled captures)

  const Field& at(int i) const { return fields[static_cast<size_t>(i)]; }
};

//! FIELDS, SIZE and TYPE are there, and SIZE, TYPE and COUNT have one entry per field.
[[nodiscard]] ReadResult check_field_lists(const PcdHeader& h, const std::string& name) {
  if (!h.have_fields) return fail(name, "header has no FIELDS line");
  const size_t nf = h.fields_tok.size();
  if (!h.have_size) return fail(name, "header has no SIZE line");
  if (!h.have_type) return fail(name, "header has no TYPE line");
  auto count_mismatch = [&](const char* what, size_t n) {
    return fail(name, std::string(what) + " has " + std::to_string(n) + " entries but FIELDS has " +
                          std::to_string(nf) + " (count mismatch)");
  };
  if (h.size_tok.size() != nf) return count_mismatch("SIZE", h.size_tok.size());
  if (h.type_tok.size() != nf) return count_mismatch("TYPE", h.type_tok.size());
  if (h.have_count && h.count_tok.size() != nf) return count_mismatch("COUNT", h.count_tok.size());
  return {};
}

//! Field f from its SIZE, TYPE and COUNT entries, placed after the fields before it.
[[nodiscard]] ReadResult add_field(const PcdHeader& h, size_t f, const std::string& name, PcdLayout& lay) {
  Field& fd = lay.fields[f];
  fd.name = std::string(h.fields_tok[f]);
  const std::string fq = "field '" + printable(fd.name) + "'";
  uint64_t sz = 0;
  if (!parse_u64(h.size_tok[f], sz, LeadingPlus::reject) || (sz != 1 && sz != 2 && sz != 4 && sz != 8)) {
    return fail(name, "SIZE '" + printable(h.size_tok[f]) + "' of " + fq + " is not 1, 2, 4 or 8");
  }
  fd.size = static_cast<uint32_t>(sz);
  const std::string_view t = h.type_tok[f];
  if (t.size() != 1 || std::string_view("IUFiuf").find(t[0]) == std::string_view::npos) {
    return fail(name, "TYPE '" + printable(t) + "' of " + fq + " is not I, U or F");
  }
  fd.type = static_cast<char>(std::toupper(static_cast<unsigned char>(t[0])));
  if (fd.type == 'F' && fd.size != 4 && fd.size != 8) {
    return fail(name, fq + " is TYPE F with SIZE " + std::to_string(fd.size) + " (expected 4 or 8)");
  }
  if (h.have_count) {
    if (!parse_u64(h.count_tok[f], fd.count, LeadingPlus::reject) || fd.count == 0) {
      return fail(name, "COUNT '" + printable(h.count_tok[f]) + "' of " + fq + " is not a positive integer");
    }
  }
  uint64_t bytes = 0;
  if (!mul_ok(fd.size, fd.count, bytes) || lay.point_size + bytes < lay.point_size ||
      lay.total_count + fd.count < lay.total_count) {
    return fail(name, "COUNT of " + fq + " is too large");
  }
  fd.offset = lay.point_size;
  lay.point_size += bytes;
  lay.total_count += fd.count;
  if (fd.name != "_") {  // "_" is PCL's padding: it may repeat
    for (size_t g = 0; g < f; ++g) {
      if (lay.fields[g].name == fd.name) return fail(name, "duplicate " + fq + " in FIELDS");
    }
  }
  if (fd.name == "label" && fd.count == 1 && (fd.type == 'U' || fd.type == 'I') && fd.size <= 4)
    lay.il = static_cast<int>(f);
  if (fd.name == "x") lay.ix = static_cast<int>(f);
  if (fd.name == "y") lay.iy = static_cast<int>(f);
  if (fd.name == "z") lay.iz = static_cast<int>(f);
  return {};
}

//! x, y and z are there, each one float value.
[[nodiscard]] ReadResult check_xyz(const PcdHeader& h, const PcdLayout& lay, const std::string& name) {
  for (const auto& [idx, axis] : {std::pair<int, const char*>{lay.ix, "x"}, {lay.iy, "y"}, {lay.iz, "z"}}) {
    if (idx < 0) {
      std::string list;
      for (const auto& s : h.fields_tok) {
        if (!list.empty()) list += ' ';
        list += printable(s);
      }
      return fail(name, std::string("missing field '") + axis + "' (FIELDS " + list + ")");
    }
    const Field& fd = lay.at(idx);
    if (fd.type != 'F' || fd.count != 1) {
      return fail(name, std::string("field '") + axis + "' must be TYPE F, SIZE 4 or 8, COUNT 1 (got " + fd.type + " " +
                            std::to_string(fd.size) + " " + std::to_string(fd.count) + ")");
    }
  }
  return {};
}

//! The fields of FIELDS, SIZE, TYPE and COUNT laid out in a point.
[[nodiscard]] ReadResult lay_out_fields(const PcdHeader& h, const std::string& name, PcdLayout& lay) {
  if (ReadResult r = check_field_lists(h, name); !r.ok) return r;
  lay.fields.resize(h.fields_tok.size());
  for (size_t f = 0; f < lay.fields.size(); ++f) {
    if (ReadResult r = add_field(h, f, name, lay); !r.ok) return r;
  }
  return check_xyz(h, lay, name);
}

// ---- dimensions -----------------------------------------------------------------------

//! The cloud's size as WIDTH, HEIGHT and POINTS declare it.
struct PcdShape {
  uint64_t width = 0, height = 1, points = 0;
  uint64_t data_bytes = 0;  //!< points x bytes per point (binary data)
  std::string npts;         //!< "N points" or "WxH points", for messages
};

//! WIDTH x HEIGHT and POINTS agree (one may stand for the other) and are within the limits.
[[nodiscard]] ReadResult check_dimensions(const PcdHeader& h, uint64_t point_size, const ReadLimits& limits,
                                          const std::string& name, PcdShape& shape) {
  uint64_t width = h.width, height = h.height, points = h.points;
  if (!h.have_width && !h.have_points) return fail(name, "header has neither WIDTH nor POINTS");
  if (!h.have_width) {
    if (h.have_height && height != 1) return fail(name, "header has HEIGHT but no WIDTH");
    if (points > std::numeric_limits<uint32_t>::max()) {
      return fail(name, "POINTS " + std::to_string(points) + " is too large");
    }
    width = points;
    height = 1;
  }
  uint64_t wh = 0;
  if (!mul_ok(width, height, wh)) return fail(name, "WIDTH x HEIGHT overflows");
  if (!h.have_points) points = wh;
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
  shape.width = width;
  shape.height = height;
  shape.points = points;
  shape.data_bytes = data_bytes;
  shape.npts = dims(width, height, points) + " points";
  return {};
}

// ---- data -----------------------------------------------------------------------------

//! The bytes after the header.
struct DataBytes {
  const uint8_t* begin = nullptr;
  uint64_t size = 0;
};

//! DATA binary: one point after another, each point_size bytes.
[[nodiscard]] ReadResult read_binary(DataBytes bytes, const PcdLayout& lay, const PcdShape& shape,
                                     const std::string& name, PointCloud& cloud) {
  if (bytes.size < shape.data_bytes) {
    return fail(name, "DATA binary holds " + std::to_string(bytes.size) + " bytes but " + shape.npts + " need " +
                          std::to_string(shape.data_bytes) + " (file too short / truncated)");
  }
  const uint64_t points = shape.points;
  const Field& fx = lay.at(lay.ix);
  const Field& fy = lay.at(lay.iy);
  const Field& fz = lay.at(lay.iz);
  cloud.xyz.resize(points * 3);
  const uint8_t* base = bytes.begin;
  float* o = cloud.xyz.data();
  for (uint64_t i = 0; i < points; ++i, base += lay.point_size, o += 3) {
    o[0] = read_coord(base + fx.offset, fx.size);
    o[1] = read_coord(base + fy.offset, fy.size);
    o[2] = read_coord(base + fz.offset, fz.size);
  }
  if (lay.il >= 0) {
    const Field& fl = lay.at(lay.il);
    cloud.labels.resize(points);
    for (uint64_t i = 0; i < points; ++i)
      cloud.labels[i] = read_label(bytes.begin + i * lay.point_size + fl.offset, fl.size);
  }
  return {};
}

//! DATA binary_compressed: checks the compressed and uncompressed sizes of its 8-byte
//! head against the file and the header, then decompresses the LZF block into `buf`.
[[nodiscard]] ReadResult decompress_block(DataBytes bytes, const PcdLayout& lay, const PcdShape& shape,
                                          const std::string& name, BigBuffer<uint8_t>& buf) {
  const uint64_t remaining = bytes.size;
  if (remaining < 8) {
    return fail(name, "DATA binary_compressed holds " + std::to_string(remaining) +
                          " bytes, too few for the 8-byte compressed/uncompressed size header "
                          "(file truncated)");
  }
  const uint32_t csize = load_le<uint32_t>(bytes.begin);
  const uint32_t usize = load_le<uint32_t>(bytes.begin + 4);
  if (csize > remaining - 8) {
    return fail(name, "compressed size " + std::to_string(csize) + " is larger than the " +
                          std::to_string(remaining - 8) + " bytes left in the file (truncated)");
  }
  if (usize != shape.data_bytes) {
    return fail(name, "uncompressed size " + std::to_string(usize) + " does not match the " +
                          std::to_string(shape.data_bytes) + " bytes that " + shape.npts + " of " +
                          std::to_string(lay.point_size) + " bytes need (size mismatch)");
  }
  if (usize > lzf::max_decompressed_size(csize)) {
    return fail(name, "uncompressed size " + std::to_string(usize) + " (" + shape.npts + ") cannot come from " +
                          std::to_string(csize) + " compressed bytes (size mismatch / corrupt)");
  }
  buf.resize(usize > 0 ? usize : 1);
  std::string err;
  if (!lzf::decompress(bytes.begin + 8, csize, buf.data(), usize, err)) {
    return fail(name, "DATA binary_compressed: " + err);
  }
  return {};
}

//! Makes the decompressed block the cloud's planar block: its x, y and z arrays are 4-byte
//! floats already, and only need the host's byte order.
void hand_over_block(BigBuffer<uint8_t>& buf, const std::array<size_t, 3>& block, uint64_t points, PointCloud& cloud) {
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
}

//! DATA binary_compressed: a structure of arrays (all values of the first field, then of
//! the second, ...), LZF-compressed.
[[nodiscard]] ReadResult read_compressed(DataBytes bytes, const PcdLayout& lay, const PcdShape& shape, bool planar,
                                         const std::string& name, PointCloud& cloud) {
  BigBuffer<uint8_t> buf;
  if (ReadResult r = decompress_block(bytes, lay, shape, name, buf); !r.ok) return r;
  const uint64_t points = shape.points;
  const Field& fx = lay.at(lay.ix);
  const Field& fy = lay.at(lay.iy);
  const Field& fz = lay.at(lay.iz);
  // Structure of arrays: the block of field f starts at points * (offset of f in a point).
  const std::array<size_t, 3> block = {static_cast<size_t>(points * fx.offset), static_cast<size_t>(points * fy.offset),
                                       static_cast<size_t>(points * fz.offset)};
  if (lay.il >= 0) {
    const Field& fl = lay.at(lay.il);
    const uint8_t* bl = buf.data() + points * fl.offset;
    cloud.labels.resize(points);
    for (uint64_t i = 0; i < points; ++i) cloud.labels[i] = read_label(bl + i * fl.size, fl.size);
  }
  if (planar && points > 0 && fx.size == 4 && fy.size == 4 && fz.size == 4) {
    hand_over_block(buf, block, points, cloud);
    return {};
  }
  const uint8_t* bx = buf.data() + block[0];
  const uint8_t* by = buf.data() + block[1];
  const uint8_t* bz = buf.data() + block[2];
  cloud.xyz.resize(points * 3);
  float* o = cloud.xyz.data();
  for (uint64_t i = 0; i < points; ++i, o += 3) {
    o[0] = read_coord(bx + i * fx.size, fx.size);
    o[1] = read_coord(by + i * fy.size, fy.size);
    o[2] = read_coord(bz + i * fz.size, fz.size);
  }
  return {};
}

//! One row of DATA ascii (`row` counted from 0): a number for every value of every
//! field; x, y and z go to the cloud. `slot` is 0, 1, 2 for the fields x, y, z, else -1.
[[nodiscard]] ReadResult ascii_row(const Tokens& tok, uint64_t row, size_t line_no, const PcdLayout& lay,
                                   const std::vector<int>& slot, const std::string& name, PointCloud& cloud) {
  if (tok.size() != lay.total_count) {
    return fail(name, "ascii row " + std::to_string(row + 1) + " (line " + std::to_string(line_no) + ") has " +
                          std::to_string(tok.size()) + " values, expected " + std::to_string(lay.total_count) +
                          (tok.size() < lay.total_count ? " (too few values)" : " (too many values)"));
  }
  size_t k = 0;
  for (size_t f = 0; f < lay.fields.size(); ++f) {
    for (uint64_t c = 0; c < lay.fields[f].count; ++c, ++k) {
      double v = 0;
      float fv = 0;
      const bool num = slot[f] >= 0 ? parse_real(tok[k], fv) : parse_real(tok[k], v);
      if (!num) {
        return fail(name, "ascii row " + std::to_string(row + 1) + " (line " + std::to_string(line_no) + "): value '" +
                              printable(tok[k]) + "' of field '" + printable(lay.fields[f].name) + "' is not a number");
      }
      if (slot[f] >= 0) cloud.xyz[row * 3 + static_cast<size_t>(slot[f])] = fv;
    }
  }
  return {};
}

//! DATA ascii: one line per point (blank lines skipped), then nothing but blanks or NUL
//! bytes.
[[nodiscard]] ReadResult read_ascii(LineCursor& lines, const PcdLayout& lay, const PcdShape& shape,
                                    const std::string& name, PointCloud& cloud) {
  const uint64_t points = shape.points;
  const uint64_t remaining = lines.size - lines.pos;
  // Every value takes at least one byte, so V values per point bound the points (and
  // the allocation) by the bytes present.
  uint64_t min_bytes = 0;
  if (!mul_ok(points, lay.total_count, min_bytes) || remaining < min_bytes) {
    return fail(name, "DATA ascii holds " + std::to_string(remaining) + " bytes, too few for " + shape.npts + " of " +
                          std::to_string(lay.total_count) + " values each (file too short / truncated)");
  }
  cloud.xyz.resize(points * 3);
  std::vector<int> slot(lay.fields.size(), -1);
  slot[static_cast<size_t>(lay.ix)] = 0;
  slot[static_cast<size_t>(lay.iy)] = 1;
  slot[static_cast<size_t>(lay.iz)] = 2;
  Tokens tok;
  uint64_t row = 0;
  while (row < points) {
    if (lines.at_end()) {
      return fail(name, "DATA ascii has " + std::to_string(row) + " rows but " + shape.npts +
                            " are declared (too few rows / truncated)");
    }
    const std::string_view line = lines.next();
    if (line.empty()) continue;
    split_ws(line, tok);
    if (ReadResult r = ascii_row(tok, row, lines.line_no, lay, slot, name, cloud); !r.ok) return r;
    ++row;
  }
  for (size_t i = lines.pos; i < lines.size; ++i) {
    const char c = static_cast<char>(lines.data[i]);
    if (!is_space(c) && c != '\0') {
      return fail(name, "DATA ascii has more rows than the " + std::to_string(points) +
                            " declared by POINTS (extra data after the last point)");
    }
  }
  return {};
}

//! Header, field layout, dimensions, then the data section of its kind. `out` is only
//! touched when the whole file parsed.
//! Everything the header declares, checked: the header lines, the fields' layout in a
//! point and the cloud's size; `lines` then stands at the first byte of the data.
[[nodiscard]] ReadResult parse_header_block(LineCursor& lines, const std::string& name, const ReadLimits& limits,
                                            PcdHeader& header, PcdLayout& layout, PcdShape& shape) {
  if (ReadResult r = read_header(lines, name, header); !r.ok) return r;
  if (ReadResult r = lay_out_fields(header, name, layout); !r.ok) return r;
  return check_dimensions(header, layout.point_size, limits, name, shape);
}

[[nodiscard]] ReadResult parse_pcd_impl(const uint8_t* data, size_t size, const std::string& name, PointCloud& out,
                                        const ReadLimits& limits) {
  if (ReadResult r = text::file_size_ok(size, limits.max_file_bytes, name, "PCD"); !r.ok) return r;
  LineCursor lines{data, size};
  PcdHeader header;
  PcdLayout layout;
  PcdShape shape;
  if (ReadResult r = parse_header_block(lines, name, limits, header, layout, shape); !r.ok) return r;

  PointCloud cloud;
  cloud.width = static_cast<uint32_t>(shape.width);
  cloud.height = static_cast<uint32_t>(shape.height);
  cloud.viewpoint = header.viewpoint;
  const DataBytes bytes{data + lines.pos, size - lines.pos};
  ReadResult r;
  switch (header.kind) {
    case DataKind::binary:
      r = read_binary(bytes, layout, shape, name, cloud);
      break;
    case DataKind::binary_compressed:
      r = read_compressed(bytes, layout, shape, limits.planar, name, cloud);
      break;
    case DataKind::ascii:
      r = read_ascii(lines, layout, shape, name, cloud);
      break;
  }
  if (!r.ok) return r;
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

ReadResult parse_pcd_header(const uint8_t* data, size_t size, const std::string& name, const ReadLimits& limits,
                            bool& binary_floats, PcdBinaryFloats& out) {
  binary_floats = false;
  return text::guarded_parse(data, size, name, [&]() -> ReadResult {
    LineCursor lines{data, size};
    PcdHeader header;
    PcdLayout layout;
    PcdShape shape;
    if (ReadResult r = parse_header_block(lines, name, limits, header, layout, shape); !r.ok) return r;
    const Field& fx = layout.at(layout.ix);
    const Field& fy = layout.at(layout.iy);
    const Field& fz = layout.at(layout.iz);
    if (header.kind != DataKind::binary || fx.size != 4 || fy.size != 4 || fz.size != 4) return {};
    binary_floats = true;
    out.data_offset = lines.pos;
    out.points = shape.points;
    out.point_size = layout.point_size;
    out.offset[0] = fx.offset;
    out.offset[1] = fy.offset;
    out.offset[2] = fz.offset;
    return {};
  });
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
