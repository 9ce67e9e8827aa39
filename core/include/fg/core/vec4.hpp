// Four floats (or ints) handled as one value: GCC's vector extensions, SSE on x86-64,
// NEON on aarch64, plain scalar code on targets without a vector unit (Cortex-M7).
// Each lane is ordinary IEEE arithmetic in the order of the scalar formula, so every
// target computes the same numbers (the aarch64 plan stays bit-identical to the host's).
#pragma once
#include <cstdint>
#include <cstring>
#if defined(__SSE2__)
#include <emmintrin.h>
#elif defined(__aarch64__)
#include <arm_neon.h>
#endif

namespace fg {

typedef float V4f __attribute__((vector_size(16)));
typedef int32_t V4i __attribute__((vector_size(16)));
typedef uint32_t V4u __attribute__((vector_size(16)));

//! True when every lane of a comparison result is set.
inline bool all_lanes(V4i m) {
#if defined(__SSE2__)
  return _mm_movemask_ps(_mm_castsi128_ps(reinterpret_cast<__m128i>(m))) == 0xF;
#elif defined(__aarch64__)
  return vminvq_u32(vreinterpretq_u32_s32(m)) != 0u;
#else
  return (m[0] & m[1] & m[2] & m[3]) != 0;
#endif
}

//! Bit k set when lane k of a comparison result is set (lanes are 0 or -1).
inline uint32_t lane_mask(V4i m) {
#if defined(__SSE2__)
  return static_cast<uint32_t>(_mm_movemask_ps(_mm_castsi128_ps(reinterpret_cast<__m128i>(m))));
#elif defined(__aarch64__)
  const uint32x4_t bits = {1u, 2u, 4u, 8u};
  return vaddvq_u32(vandq_u32(vreinterpretq_u32_s32(m), bits));
#else
  return static_cast<uint32_t>((m[0] & 1) | (m[1] & 2) | (m[2] & 4) | (m[3] & 8));
#endif
}

//! Four floats from any address.
inline V4f load4(const void* p) {
  V4f v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

//! Four packed xyz triples (the 48 bytes a, b, c: x0 y0 z0 x1 | y1 z1 x2 y2 | z2 x3 y3
//! z3) as x, y and z lanes. Each shuffle takes two lanes of either operand (one shufps
//! on SSE); the bits move unchanged (NaN payloads too).
inline void deinterleave_xyz(V4f a, V4f b, V4f c, V4f& x, V4f& y, V4f& z) {
  const V4f xy23 = __builtin_shufflevector(b, c, 2, 3, 5, 6);  // x2 y2 x3 y3
  const V4f yz01 = __builtin_shufflevector(a, b, 1, 2, 4, 5);  // y0 z0 y1 z1
  x = __builtin_shufflevector(a, xy23, 0, 3, 4, 6);
  y = __builtin_shufflevector(yz01, xy23, 0, 2, 5, 7);
  z = __builtin_shufflevector(yz01, c, 1, 3, 4, 7);
}

//! The inverse of deinterleave_xyz: x, y and z lanes as four packed triples a, b, c.
inline void interleave_xyz(V4f x, V4f y, V4f z, V4f& a, V4f& b, V4f& c) {
  a = __builtin_shufflevector(__builtin_shufflevector(x, y, 0, 4, 1, 5), z, 0, 1, 4, 2);  // x0 y0 z0 x1
  b = __builtin_shufflevector(__builtin_shufflevector(y, z, 1, 5, 2, 6), x, 0, 1, 6, 2);  // y1 z1 x2 y2
  c = __builtin_shufflevector(z, __builtin_shufflevector(x, y, 3, 7, 3, 7), 2, 4, 5, 3);  // z2 x3 y3 z3
}

}  // namespace fg
