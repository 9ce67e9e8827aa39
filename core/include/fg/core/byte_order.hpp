// Byte order. The core reads byte arrays a word at a time (flags eight per load, the
// ingest's lane places eight per store), and files are little-endian whatever the
// host: these helpers keep both right on big-endian targets (scripts/cross.sh builds
// and tests one, 32-bit MIPS), at no cost on little-endian ones.
#pragma once
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace fg {

constexpr bool kLittleEndian = __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__;
static_assert(kLittleEndian || __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__, "a mixed byte order");

//! The word whose byte b, counted from the least significant, is byte b in memory of
//! the native word v: v itself on little-endian targets, v byte-reversed elsewhere. Its
//! own inverse.
inline uint64_t le_order64(uint64_t v) { return kLittleEndian ? v : __builtin_bswap64(v); }
inline uint32_t le_order(uint32_t v) { return kLittleEndian ? v : __builtin_bswap32(v); }
inline uint16_t le_order(uint16_t v) { return kLittleEndian ? v : __builtin_bswap16(v); }
inline uint64_t le_order(uint64_t v) { return le_order64(v); }
inline uint8_t le_order(uint8_t v) { return v; }

//! The unsigned integer as wide as T (1, 2, 4 or 8 bytes).
template <class T>
using SameSizeUint = std::conditional_t<
    sizeof(T) == 1, uint8_t,
    std::conditional_t<sizeof(T) == 2, uint16_t, std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>>>;

//! A value of T (an integer or floating type of 1, 2, 4 or 8 bytes) stored little-endian at p.
template <class T>
inline T load_le(const uint8_t* p) {
  static_assert(sizeof(T) == 1 || sizeof(T) == 2 || sizeof(T) == 4 || sizeof(T) == 8, "1, 2, 4 or 8 bytes");
  SameSizeUint<T> u;
  std::memcpy(&u, p, sizeof u);
  u = le_order(u);
  T v;
  std::memcpy(&v, &u, sizeof v);
  return v;
}

//! Stores v little-endian at p (the inverse of load_le).
template <class T>
inline void store_le(T v, uint8_t* p) {
  static_assert(sizeof(T) == 1 || sizeof(T) == 2 || sizeof(T) == 4 || sizeof(T) == 8, "1, 2, 4 or 8 bytes");
  SameSizeUint<T> u;
  std::memcpy(&u, &v, sizeof u);
  u = le_order(u);
  std::memcpy(p, &u, sizeof u);
}

}  // namespace fg
