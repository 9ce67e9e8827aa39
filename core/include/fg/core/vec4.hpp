// Four floats (or ints) handled as one value: GCC's vector extensions, SSE on x86-64,
// NEON on aarch64, plain scalar code on targets without a vector unit (Cortex-M7).
// Each lane is ordinary IEEE arithmetic in the order of the scalar formula, so every
// target computes the same numbers (the aarch64 plan stays bit-identical to the host's).
#pragma once
#include <cstdint>
#if defined(__SSE2__)
#include <emmintrin.h>
#elif defined(__aarch64__)
#include <arm_neon.h>
#endif

namespace fg {

typedef float V4f __attribute__((vector_size(16)));
typedef int32_t V4i __attribute__((vector_size(16)));

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

}  // namespace fg
