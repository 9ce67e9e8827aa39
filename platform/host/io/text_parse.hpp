// Internal to the host file readers (pcd.cpp, ply.cpp, scene.cpp): small text and number helpers
// for header lines and ascii data. Not a public API; nothing outside io/ includes it.
#pragma once

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <limits>
#include <new>
#include <string>
#include <string_view>
#include <system_error>
#include <type_traits>
#include <vector>

#include "point_cloud.hpp"

namespace fg::host::text {

[[nodiscard]] inline ReadResult fail(const std::string& name, const std::string& msg) {
  return ReadResult::failure(name + ": " + msg);
}

//! The parts (strings, string views, C strings, characters) joined into one string,
//! without the temporary strings of a chain of `+`.
template <typename... Parts>
std::string cat(const Parts&... parts) {
  static_assert(((std::is_convertible_v<const Parts&, std::string_view> || std::is_same_v<Parts, char>)&&...),
                "cat joins strings and characters (numbers go through std::to_string)");
  std::string s;
  ((s += parts), ...);
  return s;
}

//! Blanks and line breaks: ' ', \t, \r, \n, \v, \f.
inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

inline std::string_view trim(std::string_view s) {
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

//! The white-space separated tokens of `s` into `out` (cleared first).
inline void split_ws(std::string_view s, std::vector<std::string_view>& out) {
  out.clear();
  size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && is_space(s[i])) ++i;
    const size_t start = i;
    while (i < s.size() && !is_space(s[i])) ++i;
    if (i > start) out.push_back(s.substr(start, i - start));
  }
}

//! For messages: at most 40 characters, non-printable bytes shown as '?'.
inline std::string printable(std::string_view s) {
  std::string r;
  const size_t n = std::min<size_t>(s.size(), 40);
  for (size_t i = 0; i < n; ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    r.push_back(c >= 0x20 && c < 0x7f ? static_cast<char>(c) : '?');
  }
  if (s.size() > n) r += "...";
  return r;
}

//! Whether parse_u64 takes "+12" as 12 (PLY) or refuses it (PCD).
enum class LeadingPlus { reject, accept };

//! A whole token as a decimal unsigned integer (no sign other than an allowed '+').
[[nodiscard]] inline bool parse_u64(std::string_view s, uint64_t& v, LeadingPlus plus) {
  if (plus == LeadingPlus::accept && !s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return false;
  const auto res = std::from_chars(s.data(), s.data() + s.size(), v);
  return res.ec == std::errc() && res.ptr == s.data() + s.size();
}

//! A whole token as a number: decimal or exponent form, optional sign, nan / inf.
//! Values beyond the type's range become +-inf (or a denormal / 0), like strtod.
template <typename T>
[[nodiscard]] bool parse_real(std::string_view s, T& v) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return false;
  const auto res = std::from_chars(s.data(), s.data() + s.size(), v);
  if (res.ptr != s.data() + s.size()) return false;
  if (res.ec == std::errc::result_out_of_range) {
    const std::string tmp(s);
    char* end = nullptr;
    if constexpr (std::is_same_v<T, float>) {
      v = std::strtof(tmp.c_str(), &end);
    } else {
      v = std::strtod(tmp.c_str(), &end);
    }
    return end == tmp.c_str() + tmp.size();
  }
  return res.ec == std::errc();
}

//! double -> float without undefined behaviour for values beyond float's range.
inline float to_float(double d) {
  constexpr double kMax = static_cast<double>(std::numeric_limits<float>::max());
  if (d > kMax) return std::numeric_limits<float>::infinity();
  if (d < -kMax) return -std::numeric_limits<float>::infinity();
  return static_cast<float>(d);  // NaN and in-range values
}

//! r = a * b; false when the product overflows.
[[nodiscard]] inline bool mul_ok(uint64_t a, uint64_t b, uint64_t& r) { return !__builtin_mul_overflow(a, b, &r); }

//! A file's bytes, before its parse: not empty (a `format` header is needed) and within
//! the reader's limit.
[[nodiscard]] inline ReadResult file_size_ok(size_t size, uint64_t max_bytes, const std::string& name,
                                             const char* format) {
  if (size == 0) return fail(name, cat("empty file (no ", format, " header)"));
  if (size > max_bytes) {
    return fail(name, "file of " + std::to_string(size) + " bytes is larger than the limit of " +
                          std::to_string(max_bytes) + " bytes");
  }
  return {};
}

//! Runs a reader's parse on bytes in memory: a null buffer, an allocation failure or any
//! other exception becomes an error naming `name`, never an escape.
template <typename Parse>
[[nodiscard]] ReadResult guarded_parse(const uint8_t* data, size_t size, const std::string& name, Parse&& parse) {
  if (data == nullptr && size != 0) return fail(name, "no data");
  try {
    return parse();
  } catch (const std::bad_alloc&) {
    return fail(name, "out of memory while reading the cloud");
  } catch (const std::exception& e) {
    return fail(name, std::string("unexpected error: ") + e.what());
  }
}

}  // namespace fg::host::text
