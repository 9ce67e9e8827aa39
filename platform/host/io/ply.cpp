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

ReadResult parse_ply_impl(const uint8_t* data, size_t size, const std::string& name, PointCloud& out,
                          const ReadLimits& limits) {
  if (size == 0) return fail(name, "empty file (no PLY header)");
  if (size > limits.max_file_bytes) {
    return fail(name, "file of " + std::to_string(size) + " bytes is larger than the limit of " +
                          std::to_string(limits.max_file_bytes) + " bytes");
  }
  // ---- header -------------------------------------------------------------------------
  size_t pos = 0;
  size_t line_no = 0;
  auto next_line = [&](std::string_view& line) {
    if (pos >= size) return false;
    const void* nl = std::memchr(data + pos, '\n', size - pos);
    const size_t end = nl ? static_cast<size_t>(static_cast<const uint8_t*>(nl) - data) : size;
    line = std::string_view(reinterpret_cast<const char*>(data) + pos, end - pos);
    pos = nl ? end + 1 : size;
    ++line_no;
    return true;
  };
  std::string_view line;
  next_line(line);
  if (trim(line) != "ply") return fail(name, "not a PLY file (the first line is not 'ply')");

  std::optional<Format> format;
  std::vector<Element> elems;
  std::vector<std::string_view> tok;
  bool ended = false;
  while (!ended && next_line(line)) {
    const std::string where = " (header line " + std::to_string(line_no) + ")";
    split_ws(line, tok);
    if (tok.empty()) continue;
    const std::string_view key = tok[0];
    if (key == "comment" || key == "obj_info") continue;
    if (key == "end_header") {
      if (tok.size() != 1) return fail(name, "malformed end_header line" + where);
      ended = true;
    } else if (key == "format") {
      if (format) return fail(name, "duplicate format line" + where);
      if (tok.size() != 3) return fail(name, "malformed format line" + where);
      if (tok[1] == "binary_big_endian") {
        return fail(name,
                    "format binary_big_endian is not supported (big-endian PLY; use ascii or "
                    "binary_little_endian)");
      }
      if (tok[1] == "ascii") {
        format = Format::ascii;
      } else if (tok[1] == "binary_little_endian") {
        format = Format::binary_le;
      } else {
        return fail(name, "unknown PLY format '" + printable(tok[1]) + "'" + where);
      }
      if (tok[2] != "1.0" && tok[2] != "1") {
        return fail(name, "unsupported PLY version '" + printable(tok[2]) + "' (expected 1.0)" + where);
      }
    } else if (key == "element") {
      if (tok.size() != 3) return fail(name, "malformed element line (expected: element NAME COUNT)" + where);
      Element e;
      e.name = std::string(tok[1]);
      if (!parse_u64(tok[2], e.count, LeadingPlus::accept)) {
        return fail(name, "element '" + printable(tok[1]) + "' count '" + printable(tok[2]) +
                              "' is not a non-negative integer (non-numeric)" + where);
      }
      for (const Element& o : elems) {
        if (o.name == e.name) return fail(name, "duplicate element '" + printable(e.name) + "'" + where);
      }
      elems.push_back(std::move(e));
    } else if (key == "property") {
      if (elems.empty()) return fail(name, "property line before any element line" + where);
      Prop p;
      if (tok.size() >= 2 && tok[1] == "list") {
        if (tok.size() != 5) {
          return fail(name, "malformed list property (expected: property list COUNTTYPE TYPE NAME)" + where);
        }
        const auto ct = parse_scalar(tok[2]);
        const auto it = parse_scalar(tok[3]);
        if (!ct || !it) return fail(name, "unknown property type in list property" + where);
        if (*ct == Scalar::f32 || *ct == Scalar::f64) {
          return fail(name, "list count type must be an integer type, not '" + printable(tok[2]) + "'" + where);
        }
        p.is_list = true;
        p.count_type = *ct;
        p.type = *it;
        p.name = std::string(tok[4]);
      } else {
        if (tok.size() != 3) return fail(name, "malformed property line (expected: property TYPE NAME)" + where);
        const auto t = parse_scalar(tok[1]);
        if (!t) return fail(name, "unknown property type '" + printable(tok[1]) + "'" + where);
        p.type = *t;
        p.name = std::string(tok[2]);
      }
      Element& e = elems.back();
      for (const Prop& o : e.props) {
        if (o.name == p.name) {
          return fail(name,
                      "duplicate property '" + printable(p.name) + "' in element '" + printable(e.name) + "'" + where);
        }
      }
      e.props.push_back(std::move(p));
    } else {
      return fail(name,
                  "unknown header line '" + printable(trim(line)) + "'" + where + " (garbled or truncated header)");
    }
  }
  if (!ended) return fail(name, "truncated header: no end_header line");
  if (!format) return fail(name, "header has no format line");

  // ---- the vertex element -------------------------------------------------------------
  Element* vertex = nullptr;
  for (Element& e : elems) {
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

  PointCloud cloud;
  cloud.width = static_cast<uint32_t>(vertex->count);
  cloud.height = 1;

  // ---- data ---------------------------------------------------------------------------
  if (*format == Format::binary_le) {
    for (const Element& e : elems) {
      if (e.props.empty() || e.count == 0) continue;
      const bool is_vertex = &e == vertex;
      bool has_list = false;
      uint64_t fixed = 0, min_size = 0;
      for (const Prop& p : e.props) {
        if (p.is_list) {
          has_list = true;
          min_size += scalar_size(p.count_type);
        } else {
          fixed += scalar_size(p.type);
          min_size += scalar_size(p.type);
        }
      }
      const uint64_t left = size - pos;
      uint64_t need = 0;
      if (!mul_ok(e.count, min_size, need) || need > left) {
        return fail(name, "element '" + printable(e.name) + "' declares " + std::to_string(e.count) +
                              " items of at least " + std::to_string(min_size) + " bytes but only " +
                              std::to_string(left) + " bytes are left (data too short / truncated)");
      }
      if (is_vertex) cloud.xyz.resize(e.count * 3);
      if (!has_list) {
        if (is_vertex) {
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
          const uint8_t* base = data + pos;
          float* dst = cloud.xyz.data();
          for (uint64_t i = 0; i < e.count; ++i, base += fixed, dst += 3) {
            for (int k = 0; k < 3; ++k) dst[k] = to_float(read_scalar(base + off[k], typ[k]));
          }
        }
        pos += static_cast<size_t>(need);
        continue;
      }
      for (uint64_t i = 0; i < e.count; ++i) {
        for (const Prop& p : e.props) {
          const auto truncated = [&]() {
            return fail(name, "element '" + printable(e.name) + "' item " + std::to_string(i) + " of " +
                                  std::to_string(e.count) +
                                  " runs past the end of the data (data too short / truncated)");
          };
          if (!p.is_list) {
            const uint32_t sz = scalar_size(p.type);
            if (size - pos < sz) return truncated();
            if (p.slot >= 0)
              cloud.xyz[i * 3 + static_cast<uint64_t>(p.slot)] = to_float(read_scalar(data + pos, p.type));
            pos += sz;
            continue;
          }
          const uint32_t csz = scalar_size(p.count_type);
          if (size - pos < csz) return truncated();
          uint64_t n = 0;
          if (!read_count(data + pos, p.count_type, n)) {
            return fail(name, "element '" + printable(e.name) + "' item " + std::to_string(i) + ": list '" +
                                  printable(p.name) + "' has a negative count");
          }
          pos += csz;
          uint64_t bytes = 0;
          if (!mul_ok(n, scalar_size(p.type), bytes) || bytes > size - pos) return truncated();
          pos += static_cast<size_t>(bytes);
        }
      }
    }
  } else {
    auto next_token = [&](std::string_view& t) {
      while (pos < size && is_space(static_cast<char>(data[pos]))) ++pos;
      if (pos >= size) return false;
      const size_t start = pos;
      while (pos < size && !is_space(static_cast<char>(data[pos]))) ++pos;
      t = std::string_view(reinterpret_cast<const char*>(data) + start, pos - start);
      return true;
    };
    std::string_view t;
    for (const Element& e : elems) {
      if (e.props.empty() || e.count == 0) continue;
      const bool is_vertex = &e == vertex;
      if (is_vertex) {
        // each vertex holds at least one token (of at least one byte) per property
        uint64_t need = 0;
        const uint64_t left = size - pos;
        if (!mul_ok(e.count, e.props.size(), need) || need > left) {
          return fail(name, "element 'vertex' declares " + std::to_string(e.count) + " vertices but only " +
                                std::to_string(left) + " bytes of ascii data are left (data too short / truncated)");
        }
        cloud.xyz.resize(e.count * 3);
      }
      for (uint64_t i = 0; i < e.count; ++i) {
        for (const Prop& p : e.props) {
          const auto truncated = [&]() {
            return fail(name, "ascii data ends in element '" + printable(e.name) + "' item " + std::to_string(i) +
                                  " of " + std::to_string(e.count) + " (data too short / truncated)");
          };
          if (!next_token(t)) return truncated();
          if (!p.is_list) {
            double v = 0;
            float fv = 0;
            if (!(p.slot >= 0 ? parse_real(t, fv) : parse_real(t, v))) {
              return fail(name, "element '" + printable(e.name) + "' item " + std::to_string(i) + ": value '" +
                                    printable(t) + "' of property '" + printable(p.name) + "' is not a number");
            }
            if (p.slot >= 0) cloud.xyz[i * 3 + static_cast<uint64_t>(p.slot)] = fv;
            continue;
          }
          uint64_t n = 0;
          if (!parse_u64(t, n, LeadingPlus::accept)) {
            return fail(name, "element '" + printable(e.name) + "' item " + std::to_string(i) + ": list count '" +
                                  printable(t) + "' of '" + printable(p.name) + "' is not a non-negative integer");
          }
          for (uint64_t k = 0; k < n; ++k) {
            if (!next_token(t)) return truncated();
            double v = 0;
            float fv = 0;
            if (!(p.slot >= 0 ? parse_real(t, fv) : parse_real(t, v))) {
              return fail(name, "element '" + printable(e.name) + "' item " + std::to_string(i) + ": list value '" +
                                    printable(t) + "' is not a number");
            }
          }
        }
      }
    }
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
