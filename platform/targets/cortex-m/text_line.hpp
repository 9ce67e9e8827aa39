// A fixed-size text line for the image's report: strings, integers and fixed-point
// floats, written without printf (newlib's printf family may allocate).
#pragma once
#include <cstdint>

namespace fg::cortex_m {

class TextLine {
 public:
  TextLine& operator<<(const char* s) {
    while (s != nullptr && *s != '\0') put(*s++);
    return *this;
  }
  TextLine& operator<<(uint64_t v) {
    char digits[20];
    uint32_t n = 0;
    do {
      digits[n++] = static_cast<char>('0' + v % 10u);
      v /= 10u;
    } while (v != 0);
    while (n > 0) put(digits[--n]);
    return *this;
  }
  TextLine& operator<<(uint32_t v) { return *this << static_cast<uint64_t>(v); }
  TextLine& operator<<(int32_t v) {
    if (v < 0) put('-');
    return *this << static_cast<uint64_t>(v < 0 ? -static_cast<int64_t>(v) : v);
  }

  //! v with `decimals` digits after the point (at most 6), rounded; "nan", "inf" and
  //! "big" (|v| >= 1e9) where fixed point does not fit.
  TextLine& fixed(float v, uint32_t decimals = 4) {
    if (v != v) return *this << "nan";
    if (v < 0.f) {
      put('-');
      v = -v;
    }
    if (v > 3.4e38f) return *this << "inf";
    if (v >= 1e9f) return *this << "big";
    if (decimals > 6) decimals = 6;
    uint64_t scale = 1;
    for (uint32_t i = 0; i < decimals; ++i) scale *= 10u;
    const auto scaled = static_cast<uint64_t>(static_cast<double>(v) * static_cast<double>(scale) + 0.5);
    *this << scaled / scale;
    if (decimals > 0) {
      put('.');
      uint64_t frac = scaled % scale;
      for (uint64_t d = scale / 10u; d > 0; d /= 10u) {
        put(static_cast<char>('0' + frac / d));
        frac %= d;
      }
    }
    return *this;
  }

  const char* c_str() const { return buf_; }

 private:
  void put(char c) {
    if (len_ + 1 < sizeof(buf_)) {
      buf_[len_++] = c;
      buf_[len_] = '\0';
    }
  }
  char buf_[160] = {};
  uint32_t len_ = 0;
};

}  // namespace fg::cortex_m
