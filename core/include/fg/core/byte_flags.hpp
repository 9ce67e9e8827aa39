// Byte flags read eight at a time. Planning marks voxels with one byte each (kept off
// the support plane, in the object, ...); most of a typical scene's voxels are the
// plane's, so loops over the few flagged ones skip eight unflagged bytes per load.
#pragma once
#include <cstdint>
#include <cstring>

#include "fg/core/byte_order.hpp"

namespace fg {

//! Byte b of the result is 1 when byte b of v is not 0, else 0.
inline uint64_t nonzero_ones8(uint64_t v) {
  return ((((v & 0x7F7F7F7F7F7F7F7Fu) + 0x7F7F7F7F7F7F7F7Fu) | v) >> 7) & 0x0101010101010101u;
}

//! Bit b set when byte b of v is not 0.
inline uint32_t nonzero_bits8(uint64_t v) {
  return static_cast<uint32_t>((nonzero_ones8(v) * 0x0102040810204080u) >> 56);  // byte b's bit to bit b
}

//! Bit b set when byte b of p[0..7] is not 0.
inline uint32_t nonzero_bytes8(const uint8_t* p) {
  uint64_t v;
  std::memcpy(&v, p, sizeof v);
  return nonzero_bits8(le_order64(v));  // byte b of the word is p[b]
}

//! Calls f(i) for every i < n with flags[i] != 0, in increasing order (flags null:
//! every i < n).
template <class F>
inline void for_each_flagged(const uint8_t* flags, uint32_t n, F&& f) {
  uint32_t i = 0;
  if (flags == nullptr) {
    for (; i < n; ++i) f(i);
    return;
  }
  for (; i + 8 <= n; i += 8) {
    uint64_t v;
    std::memcpy(&v, flags + i, sizeof v);
    if (v == 0) continue;  // the common case: one load and test for eight
    for (uint32_t m = nonzero_bits8(le_order64(v)); m != 0; m &= m - 1) f(i + static_cast<uint32_t>(__builtin_ctz(m)));
  }
  for (; i < n; ++i)
    if (flags[i] != 0) f(i);
}

}  // namespace fg
