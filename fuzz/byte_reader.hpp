// Decodes a fuzz input as little-endian fields; bytes past the end read as 0, so every
// input decodes (shared by the fuzz targets that build structured calls from bytes).
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace fg_fuzz {

class ByteReader {
 public:
  ByteReader(const uint8_t* data, size_t size) : p_(data), n_(size) {}
  bool done() const { return i_ >= n_; }
  uint8_t u8() { return i_ < n_ ? p_[i_++] : 0; }
  uint16_t u16() {
    const uint16_t lo = u8();
    return static_cast<uint16_t>(lo | (u8() << 8));
  }
  uint32_t u32() {
    uint32_t v = 0;
    for (int k = 0; k < 4; ++k) v |= static_cast<uint32_t>(u8()) << (8 * k);
    return v;
  }
  float f32() {
    const uint32_t b = u32();
    float f;
    std::memcpy(&f, &b, 4);
    return f;
  }
  //! Up to `want` bytes of the rest of the input.
  size_t take(size_t want, const uint8_t*& out) {
    const size_t left = i_ < n_ ? n_ - i_ : 0;
    const size_t k = want < left ? want : left;
    out = p_ + i_;
    i_ += k;
    return k;
  }

 private:
  const uint8_t* p_;
  size_t n_;
  size_t i_ = 0;
};

}  // namespace fg_fuzz
