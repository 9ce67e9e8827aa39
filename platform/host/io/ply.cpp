// Host-only PLY reader and writer (the project's own, hardened): vertex x y z.
//
// Every element of the file is walked (not only `vertex`), so a truncated face list
// after the vertices is reported too. Before allocating the vertex array, the number
// of vertices is checked against the bytes left (binary: the minimum bytes per vertex;
// ascii: the minimum characters per vertex). Loops over elements with list properties
// consume at least one byte or token per item, so they end with the data.
#include "ply.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <new>
#include <optional>
#include <string_view>

#include "fg/core/byte_order.hpp"
#include "pcd.hpp"
#include "text_parse.hpp"

namespace fg::host {

namespace {

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

enum class Scalar { i8, u8, i16, u16, i32, u32, f32, f64 };

std::optional<Scalar> parse_scalar(std::string_view t) {
  if (t == "char" || t == "int8") return Scalar::i8;
  if (t == "uchar" || t == "uint8") return Scalar::u8;
  if (t == "short" || t == "int16") return Scalar::i16;
  if (t == "ushort" || t == "uint16") return Scalar::u16;
  if (t == "int" || t == "int32") return Scalar::i32;
  if (t == "uint" || t == "uint32") return Scalar::u32;
  if (t == "float" || t == "float32") return Scalar::f32;
  if (t == "double" || t == "float64") return Scalar::f64;
  return std::nullopt;
}

uint32_t scalar_size(Scalar s) {
  switch (s) {
    case Scalar::i8:
    case Scalar::u8:
      return 1;
    case Scalar::i16:
    case Scalar::u16:
      return 2;
    case Scalar::i32:
    case Scalar::u32:
    case Scalar::f32:
      return 4;
    case Scalar::f64:
      return 8;
  }
  return 1;
}

// binary_little_endian on every host.
double read_scalar(const uint8_t* p, Scalar s) {
  switch (s) {
    case Scalar::i8:
      return load_le<int8_t>(p);
    case Scalar::u8:
      return load_le<uint8_t>(p);
    case Scalar::i16:
      return load_le<int16_t>(p);
    case Scalar::u16:
      return load_le<uint16_t>(p);
    case Scalar::i32:
      return load_le<int32_t>(p);
    case Scalar::u32:
      return load_le<uint32_t>(p);
    case Scalar::f32:
      return static_cast<double>(load_le<float>(p));
    case Scalar::f64:
      return load_le<double>(p);
  }
  return 0;
}

//! A list count as an unsigned integer; false for a negative count.
[[nodiscard]] bool read_count(const uint8_t* p, Scalar s, uint64_t& n) {
  int64_t v = 0;
  switch (s) {
    case Scalar::i8: {
      // A two's complement byte: with its high bit set, the count is negative.
      const uint8_t b = load_le<uint8_t>(p);
      if (b & 0x80u) return false;
      v = b;
      break;
    }
    case Scalar::u8:
      v = load_le<uint8_t>(p);
      break;
    case Scalar::i16:
      v = load_le<int16_t>(p);
      break;
    case Scalar::u16:
      v = load_le<uint16_t>(p);
      break;
    case Scalar::i32:
      v = load_le<int32_t>(p);
      break;
    case Scalar::u32:
      v = load_le<uint32_t>(p);
      break;
    default:
      return false;  // float counts are rejected in the header
  }
  if (v < 0) return false;
  n = static_cast<uint64_t>(v);
  return true;
}

struct Prop {
  std::string name;
  Scalar type = Scalar::f32;
  bool is_list = false;
  Scalar count_type = Scalar::u8;
  int slot = -1;  //!< 0/1/2 for x/y/z of the vertex element
};

struct Element {
  std::string name;
  uint64_t count = 0;
  std::vector<Prop> props;
};

enum class Format { ascii, binary_le };

using Tokens = std::vector<std::string_view>;

//! Walks the file: header lines, then the data (binary bytes or ascii tokens).
struct ByteCursor {
  const uint8_t* data = nullptr;
  size_t size = 0;
  size_t pos = 0;      //!< the next byte to read
  size_t line_no = 0;  //!< 1-based number of the header line last read

  size_t left() const { return size - pos; }

  //! The next line as it is (not trimmed); false at the end of the file.
  [[nodiscard]] bool next_line(std::string_view& line) {
    if (pos >= size) return false;
    const void* nl = std::memchr(data + pos, '\n', size - pos);
    const size_t end = nl ? static_cast<size_t>(static_cast<const uint8_t*>(nl) - data) : size;
    line = std::string_view(reinterpret_cast<const char*>(data) + pos, end - pos);
    pos = nl ? end + 1 : size;
    ++line_no;
    return true;
  }

  //! The next white-space separated token of ascii data; false at the end of the file.
  [[nodiscard]] bool next_token(std::string_view& t) {
    while (pos < size && is_space(static_cast<char>(data[pos]))) ++pos;
    if (pos >= size) return false;
    const size_t start = pos;
    while (pos < size && !is_space(static_cast<char>(data[pos]))) ++pos;
    t = std::string_view(reinterpret_cast<const char*>(data) + start, pos - start);
    return true;
  }
};

// ---- header ---------------------------------------------------------------------------

//! What the header declares: the format and the elements, in file order.
struct PlyHeader {
  std::optional<Format> format;
  std::vector<Element> elems;
};

//! One header line: its text, its tokens (at least one) and " (header line N)" for
//! messages.
struct HeaderLine {
  std::string_view text;
  const Tokens& tok;
  std::string where;
};

//! format ascii|binary_little_endian 1.0
[[nodiscard]] ReadResult format_line(const HeaderLine& l, const std::string& name, PlyHeader& h) {
  if (h.format) return fail(name, cat("duplicate format line", l.where));
  if (l.tok.size() != 3) return fail(name, cat("malformed format line", l.where));
  if (l.tok[1] == "binary_big_endian") {
    return fail(name,
                "format binary_big_endian is not supported (big-endian PLY; use ascii or "
                "binary_little_endian)");
  }
  if (l.tok[1] == "ascii") {
    h.format = Format::ascii;
  } else if (l.tok[1] == "binary_little_endian") {
    h.format = Format::binary_le;
  } else {
    return fail(name, cat("unknown PLY format '", printable(l.tok[1]), "'", l.where));
  }
  if (l.tok[2] != "1.0" && l.tok[2] != "1") {
    return fail(name, cat("unsupported PLY version '", printable(l.tok[2]), "' (expected 1.0)", l.where));
  }
  return {};
}

//! element NAME COUNT (names unique).
[[nodiscard]] ReadResult element_line(const HeaderLine& l, const std::string& name, PlyHeader& h) {
  if (l.tok.size() != 3) return fail(name, cat("malformed element line (expected: element NAME COUNT)", l.where));
  Element e;
  e.name = std::string(l.tok[1]);
  if (!parse_u64(l.tok[2], e.count, LeadingPlus::accept)) {
    return fail(name, cat("element '", printable(l.tok[1]), "' count '", printable(l.tok[2]),
                          "' is not a non-negative integer (non-numeric)", l.where));
  }
  for (const Element& o : h.elems) {
    if (o.name == e.name) return fail(name, cat("duplicate element '", printable(e.name), "'", l.where));
  }
  h.elems.push_back(std::move(e));
  return {};
}

//! The type and name of `property list COUNTTYPE TYPE NAME` or `property TYPE NAME`.
[[nodiscard]] ReadResult property_decl(const HeaderLine& l, const std::string& name, Prop& p) {
  const Tokens& tok = l.tok;
  if (tok.size() >= 2 && tok[1] == "list") {
    if (tok.size() != 5) {
      return fail(name, cat("malformed list property (expected: property list COUNTTYPE TYPE NAME)", l.where));
    }
    const auto ct = parse_scalar(tok[2]);
    const auto it = parse_scalar(tok[3]);
    if (!ct || !it) return fail(name, cat("unknown property type in list property", l.where));
    if (*ct == Scalar::f32 || *ct == Scalar::f64) {
      return fail(name, cat("list count type must be an integer type, not '", printable(tok[2]), "'", l.where));
    }
    p.is_list = true;
    p.count_type = *ct;
    p.type = *it;
    p.name = std::string(tok[4]);
    return {};
  }
  if (tok.size() != 3) return fail(name, cat("malformed property line (expected: property TYPE NAME)", l.where));
  const auto t = parse_scalar(tok[1]);
  if (!t) return fail(name, cat("unknown property type '", printable(tok[1]), "'", l.where));
  p.type = *t;
  p.name = std::string(tok[2]);
  return {};
}

//! A property of the last element (names unique within it).
[[nodiscard]] ReadResult property_line(const HeaderLine& l, const std::string& name, PlyHeader& h) {
  if (h.elems.empty()) return fail(name, cat("property line before any element line", l.where));
  Prop p;
  if (ReadResult r = property_decl(l, name, p); !r.ok) return r;
  Element& e = h.elems.back();
  for (const Prop& o : e.props) {
    if (o.name == p.name) {
      return fail(name,
                  cat("duplicate property '", printable(p.name), "' in element '", printable(e.name), "'", l.where));
    }
  }
  e.props.push_back(std::move(p));
  return {};
}

//! One header line by its key (the line's first token); `ended` at end_header.
[[nodiscard]] ReadResult header_line(const HeaderLine& l, const std::string& name, PlyHeader& h, bool& ended) {
  const std::string_view key = l.tok[0];
  if (key == "comment" || key == "obj_info") return {};
  if (key == "end_header") {
    if (l.tok.size() != 1) return fail(name, cat("malformed end_header line", l.where));
    ended = true;
    return {};
  }
  if (key == "format") return format_line(l, name, h);
  if (key == "element") return element_line(l, name, h);
  if (key == "property") return property_line(l, name, h);
  return fail(name,
              cat("unknown header line '", printable(trim(l.text)), "'", l.where, " (garbled or truncated header)"));
}

//! Reads the header from its `ply` line to end_header; the cursor then stands at the
//! first byte of the data.
[[nodiscard]] ReadResult read_header(ByteCursor& c, const std::string& name, PlyHeader& h) {
  std::string_view line;
  if (!c.next_line(line) || trim(line) != "ply") return fail(name, "not a PLY file (the first line is not 'ply')");
  Tokens tok;
  bool ended = false;
  while (!ended && c.next_line(line)) {
    split_ws(line, tok);
    if (tok.empty()) continue;
    const HeaderLine l{line, tok, cat(" (header line ", std::to_string(c.line_no), ")")};
    if (ReadResult r = header_line(l, name, h, ended); !r.ok) return r;
  }
  if (!ended) return fail(name, "truncated header: no end_header line");
  if (!h.format) return fail(name, "header has no format line");
  return {};
}

//! The `vertex` element, with its scalar properties x, y, z marked as slots 0, 1, 2, and
//! a vertex count within the limits.
[[nodiscard]] ReadResult find_vertex(PlyHeader& h, const ReadLimits& limits, const std::string& name,
                                     const Element*& found_vertex) {
  Element* vertex = nullptr;
  for (Element& e : h.elems) {
    if (e.name == "vertex") vertex = &e;
  }
  if (!vertex) return fail(name, "has no 'vertex' element");
  for (int axis = 0; axis < 3; ++axis) {
    const char* an = axis == 0 ? "x" : axis == 1 ? "y" : "z";
    Prop* found = nullptr;
    for (Prop& p : vertex->props) {
      if (p.name == an) found = &p;
    }
    if (!found) return fail(name, std::string("vertex element has no property '") + an + "' (missing field)");
    if (found->is_list) return fail(name, std::string("vertex property '") + an + "' is a list, not a scalar");
    found->slot = axis;
  }
  if (vertex->count > limits.max_points) {
    return fail(name, "declares " + std::to_string(vertex->count) + " vertices, more than the limit of " +
                          std::to_string(limits.max_points) + " (too many points)");
  }
  if (vertex->count > std::numeric_limits<uint32_t>::max()) {
    return fail(name, "declares too many vertices (" + std::to_string(vertex->count) + ")");
  }
  found_vertex = vertex;
  return {};
}

// ---- binary_little_endian data --------------------------------------------------------

//! The bytes of one item of an element: those of its scalar properties (`fixed`), and
//! the fewest an item can take (`min_size`: a list takes at least its count).
struct ItemBytes {
  bool has_list = false;
  uint64_t fixed = 0;
  uint64_t min_size = 0;
};

ItemBytes item_bytes(const Element& e) {
  ItemBytes b;
  for (const Prop& p : e.props) {
    if (p.is_list) {
      b.has_list = true;
      b.min_size += scalar_size(p.count_type);
    } else {
      b.fixed += scalar_size(p.type);
      b.min_size += scalar_size(p.type);
    }
  }
  return b;
}

//! Vertices without list properties: x, y and z at the same offsets in every item of
//! `item_size` bytes, from `base` on.
void read_fixed_vertices(const Element& e, const uint8_t* base, uint64_t item_size, PointCloud& cloud) {
  uint64_t off[3] = {0, 0, 0};
  Scalar typ[3] = {Scalar::f32, Scalar::f32, Scalar::f32};
  uint64_t o = 0;
  for (const Prop& p : e.props) {
    if (p.slot >= 0) {
      off[p.slot] = o;
      typ[p.slot] = p.type;
    }
    o += scalar_size(p.type);
  }
  float* dst = cloud.xyz.data();
  for (uint64_t i = 0; i < e.count; ++i, base += item_size, dst += 3) {
    for (int k = 0; k < 3; ++k) dst[k] = to_float(read_scalar(base + off[k], typ[k]));
  }
}

[[nodiscard]] ReadResult item_past_end(const Element& e, uint64_t i, const std::string& name) {
  return fail(name, "element '" + printable(e.name) + "' item " + std::to_string(i) + " of " + std::to_string(e.count) +
                        " runs past the end of the data (data too short / truncated)");
}

//! Property p of item i of an element with list properties: a scalar (x, y or z into
//! the cloud), or a list skipped over.
[[nodiscard]] ReadResult binary_property(const Element& e, uint64_t i, const Prop& p, ByteCursor& c,
                                         const std::string& name, PointCloud& cloud) {
  if (!p.is_list) {
    const uint32_t sz = scalar_size(p.type);
    if (c.left() < sz) return item_past_end(e, i, name);
    if (p.slot >= 0) cloud.xyz[i * 3 + static_cast<uint64_t>(p.slot)] = to_float(read_scalar(c.data + c.pos, p.type));
    c.pos += sz;
    return {};
  }
  const uint32_t csz = scalar_size(p.count_type);
  if (c.left() < csz) return item_past_end(e, i, name);
  uint64_t n = 0;
  if (!read_count(c.data + c.pos, p.count_type, n)) {
    return fail(name, "element '" + printable(e.name) + "' item " + std::to_string(i) + ": list '" + printable(p.name) +
                          "' has a negative count");
  }
  c.pos += csz;
  uint64_t bytes = 0;
  if (!mul_ok(n, scalar_size(p.type), bytes) || bytes > c.left()) return item_past_end(e, i, name);
  c.pos += static_cast<size_t>(bytes);
  return {};
}

//! All items of one element. Its count is first checked against the bytes left.
[[nodiscard]] ReadResult binary_element(const Element& e, bool is_vertex, ByteCursor& c, const std::string& name,
                                        PointCloud& cloud) {
  const ItemBytes item = item_bytes(e);
  const uint64_t left = c.left();
  uint64_t need = 0;
  if (!mul_ok(e.count, item.min_size, need) || need > left) {
    return fail(name, "element '" + printable(e.name) + "' declares " + std::to_string(e.count) +
                          " items of at least " + std::to_string(item.min_size) + " bytes but only " +
                          std::to_string(left) + " bytes are left (data too short / truncated)");
  }
  if (is_vertex) cloud.xyz.resize(e.count * 3);
  if (!item.has_list) {
    // Items of one size: the element is exactly `need` bytes.
    if (is_vertex) read_fixed_vertices(e, c.data + c.pos, item.fixed, cloud);
    c.pos += static_cast<size_t>(need);
    return {};
  }
  for (uint64_t i = 0; i < e.count; ++i) {
    for (const Prop& p : e.props) {
      if (ReadResult r = binary_property(e, i, p, c, name, cloud); !r.ok) return r;
    }
  }
  return {};
}

// ---- ascii data -----------------------------------------------------------------------

[[nodiscard]] ReadResult ascii_data_ends(const Element& e, uint64_t i, const std::string& name) {
  return fail(name, "ascii data ends in element '" + printable(e.name) + "' item " + std::to_string(i) + " of " +
                        std::to_string(e.count) + " (data too short / truncated)");
}

//! Property p of item i: a number (x, y or z into the cloud), or a list count and that
//! many numbers.
[[nodiscard]] ReadResult ascii_property(const Element& e, uint64_t i, const Prop& p, ByteCursor& c,
                                        const std::string& name, PointCloud& cloud) {
  std::string_view t;
  if (!c.next_token(t)) return ascii_data_ends(e, i, name);
  if (!p.is_list) {
    double v = 0;
    float fv = 0;
    if (!(p.slot >= 0 ? parse_real(t, fv) : parse_real(t, v))) {
      return fail(name, "element '" + printable(e.name) + "' item " + std::to_string(i) + ": value '" + printable(t) +
                            "' of property '" + printable(p.name) + "' is not a number");
    }
    if (p.slot >= 0) cloud.xyz[i * 3 + static_cast<uint64_t>(p.slot)] = fv;
    return {};
  }
  uint64_t n = 0;
  if (!parse_u64(t, n, LeadingPlus::accept)) {
    return fail(name, "element '" + printable(e.name) + "' item " + std::to_string(i) + ": list count '" +
                          printable(t) + "' of '" + printable(p.name) + "' is not a non-negative integer");
  }
  for (uint64_t k = 0; k < n; ++k) {
    if (!c.next_token(t)) return ascii_data_ends(e, i, name);
    double v = 0;
    float fv = 0;
    if (!(p.slot >= 0 ? parse_real(t, fv) : parse_real(t, v))) {
      return fail(name, "element '" + printable(e.name) + "' item " + std::to_string(i) + ": list value '" +
                            printable(t) + "' is not a number");
    }
  }
  return {};
}

//! All items of one element, token by token.
[[nodiscard]] ReadResult ascii_element(const Element& e, bool is_vertex, ByteCursor& c, const std::string& name,
                                       PointCloud& cloud) {
  if (is_vertex) {
    // each vertex holds at least one token (of at least one byte) per property
    uint64_t need = 0;
    const uint64_t left = c.left();
    if (!mul_ok(e.count, e.props.size(), need) || need > left) {
      return fail(name, "element 'vertex' declares " + std::to_string(e.count) + " vertices but only " +
                            std::to_string(left) + " bytes of ascii data are left (data too short / truncated)");
    }
    cloud.xyz.resize(e.count * 3);
  }
  for (uint64_t i = 0; i < e.count; ++i) {
    for (const Prop& p : e.props) {
      if (ReadResult r = ascii_property(e, i, p, c, name, cloud); !r.ok) return r;
    }
  }
  return {};
}

//! Header, the vertex element, then every element of the data in its format. `out` is
//! only touched when the whole file parsed.
[[nodiscard]] ReadResult parse_ply_impl(const uint8_t* data, size_t size, const std::string& name, PointCloud& out,
                                        const ReadLimits& limits) {
  if (ReadResult r = text::file_size_ok(size, limits.max_file_bytes, name, "PLY"); !r.ok) return r;
  ByteCursor c{data, size};
  PlyHeader header;
  if (ReadResult r = read_header(c, name, header); !r.ok) return r;
  const Element* vertex = nullptr;
  if (ReadResult r = find_vertex(header, limits, name, vertex); !r.ok) return r;

  PointCloud cloud;
  cloud.width = static_cast<uint32_t>(vertex->count);
  cloud.height = 1;
  // Every element is walked, not only the vertices, so that a truncated element after
  // them is an error too.
  const bool binary = *header.format == Format::binary_le;
  for (const Element& e : header.elems) {
    if (e.props.empty() || e.count == 0) continue;
    const bool is_vertex = &e == vertex;
    ReadResult r = binary ? binary_element(e, is_vertex, c, name, cloud) : ascii_element(e, is_vertex, c, name, cloud);
    if (!r.ok) return r;
  }
  out = std::move(cloud);
  return {};
}

}  // namespace

ReadResult parse_ply(const uint8_t* data, size_t size, const std::string& name, PointCloud& out,
                     const ReadLimits& limits) {
  return text::guarded_parse(data, size, name, [&] { return parse_ply_impl(data, size, name, out, limits); });
}

ReadResult read_ply(const std::string& path, PointCloud& out, const ReadLimits& limits) {
  BigBuffer<uint8_t> bytes;
  if (ReadResult r = read_file_bytes(path, bytes, limits.max_file_bytes); !r.ok) return r;
  return parse_ply(bytes.data(), bytes.size(), path, out, limits);
}

ReadResult write_ply(const std::string& path, const PointCloud& cloud, bool binary) {
  if (cloud.xyz.size() % 3 != 0) {
    return fail(path, "cannot write: xyz holds " + std::to_string(cloud.xyz.size()) + " floats, not a multiple of 3");
  }
  const size_t n = cloud.size();
  std::string s = std::string("ply\nformat ") + (binary ? "binary_little_endian" : "ascii") +
                  " 1.0\ncomment written by forcegrasp\nelement vertex " + std::to_string(n) +
                  "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  if (binary) {
    uint8_t le[4];
    for (const float v : cloud.xyz) {
      store_le(v, le);
      s.append(reinterpret_cast<const char*>(le), 4);
    }
  } else {
    char buf[64];
    for (size_t i = 0; i < n; ++i) {
      for (size_t k = 0; k < 3; ++k) {
        if (k) s += ' ';
        const auto res = std::to_chars(buf, buf + sizeof buf, cloud.xyz[i * 3 + k]);
        s.append(buf, res.ptr);
      }
      s += '\n';
    }
  }
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) return fail(path, "cannot open file for writing");
  f.write(s.data(), static_cast<std::streamsize>(s.size()));
  f.close();
  if (!f) return fail(path, "write error");
  return {};
}

ReadResult read_cloud(const std::string& path, PointCloud& out, const ReadLimits& limits) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".pcd") return read_pcd(path, out, limits);
  if (ext == ".ply") return read_ply(path, out, limits);
  return fail(path, "unknown cloud file extension '" + printable(ext) + "' (expected .pcd or .ply)");
}

}  // namespace fg::host
