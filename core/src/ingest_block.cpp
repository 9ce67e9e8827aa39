// The ingest's vector step at each width (ingest_block.hpp): ingest_lanes.inc compiled
// for four lanes everywhere and for eight on x86-64 CPUs with AVX2, chosen at run time.
#include "ingest_block.hpp"

#include <cstring>

#include "fg/core/byte_order.hpp"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define FG_INGEST_AVX2 1
#include <immintrin.h>
#else
#define FG_INGEST_AVX2 0
#endif

namespace fg {
namespace ingest {
namespace {

// The lane tables of a width W.
template <uint32_t W>
struct LaneTables {
  uint8_t popcount[1u << W];  // set lanes of a mask
  // sight[p][m]: the lanes of a group with valid-depth lanes m whose running count of
  // valid points is odd when p valid points came before (mod 2): every other point
  // with a finite depth feeds the direction bins.
  uint8_t sight[2][1u << W];
  // pick[m][j]: the j-th set lane of a mask with at most W / 2 set lanes (alternate
  // lanes), the last one repeated.
  uint8_t pick[1u << W][W / 2];
  constexpr LaneTables() : popcount{}, sight{}, pick{} {
    for (uint32_t m = 0; m < (1u << W); ++m) {
      uint32_t count = 0;
      uint8_t last = 0;
      for (uint32_t k = 0; k < W; ++k)
        if ((m >> k) & 1u) {
          if (count < W / 2) pick[m][count] = static_cast<uint8_t>(k);
          last = static_cast<uint8_t>(k);
          ++count;
        }
      popcount[m] = static_cast<uint8_t>(count);
      for (uint32_t j = count; j < W / 2; ++j) pick[m][j] = last;
      for (uint32_t p = 0; p < 2; ++p) {
        uint32_t run = p, sel = 0;
        for (uint32_t k = 0; k < W; ++k)
          if ((m >> k) & 1u) {
            ++run;
            if (run & 1u) sel |= 1u << k;
          }
        sight[p][m] = static_cast<uint8_t>(sel);
      }
    }
  }
};

}  // namespace

// Four lanes: GCC's vector extensions (vec4.hpp).
namespace lanes4 {
namespace {
typedef V4f VF;
typedef V4i VI;
typedef uint32_t VU __attribute__((vector_size(16)));
constexpr uint32_t kLanes = 4;
constexpr LaneTables<kLanes> kTables{};
inline uint32_t mask_of(VI m) { return lane_mask(m); }
// Four (x, y, z, 1) offsets out of the lanes: a 4 x 4 transpose.
inline void offsets_of(VF ox, VF oy, VF oz, V4f* out) {
  const VF one = {1.f, 1.f, 1.f, 1.f};
  const VF xy01 = __builtin_shufflevector(ox, oy, 0, 4, 1, 5), xy23 = __builtin_shufflevector(ox, oy, 2, 6, 3, 7);
  const VF z101 = __builtin_shufflevector(oz, one, 0, 4, 1, 5), z123 = __builtin_shufflevector(oz, one, 2, 6, 3, 7);
  out[0] = __builtin_shufflevector(xy01, z101, 0, 1, 4, 5);
  out[1] = __builtin_shufflevector(xy01, z101, 2, 3, 6, 7);
  out[2] = __builtin_shufflevector(xy23, z123, 0, 1, 4, 5);
  out[3] = __builtin_shufflevector(xy23, z123, 2, 3, 6, 7);
}
#define FG_LANES_TARGET
#include "ingest_lanes.inc"
#undef FG_LANES_TARGET
}  // namespace
}  // namespace lanes4

#if FG_INGEST_AVX2
// Eight lanes in the 256-bit registers of AVX2 (only AVX2: no FMA, whose fused
// multiply-adds would round differently from the four-lane path).
namespace lanes8 {
namespace {
typedef float VF __attribute__((vector_size(32)));
typedef int32_t VI __attribute__((vector_size(32)));
typedef uint32_t VU __attribute__((vector_size(32)));
constexpr uint32_t kLanes = 8;
constexpr LaneTables<kLanes> kTables{};
#define FG_LANES_TARGET __attribute__((target("avx2")))
FG_LANES_TARGET inline uint32_t mask_of(VI m) {
  return static_cast<uint32_t>(_mm256_movemask_ps(reinterpret_cast<__m256>(m)));
}
// Eight (x, y, z, 1) offsets out of the lanes: a 4 x 4 transpose in each 128-bit half.
FG_LANES_TARGET inline void offsets_of(VF ox, VF oy, VF oz, V4f* out) {
  const VF one = {1.f, 1.f, 1.f, 1.f, 1.f, 1.f, 1.f, 1.f};
  const VF xy_a = __builtin_shufflevector(ox, oy, 0, 8, 1, 9, 4, 12, 5, 13);
  const VF xy_b = __builtin_shufflevector(ox, oy, 2, 10, 3, 11, 6, 14, 7, 15);
  const VF z1_a = __builtin_shufflevector(oz, one, 0, 8, 1, 9, 4, 12, 5, 13);
  const VF z1_b = __builtin_shufflevector(oz, one, 2, 10, 3, 11, 6, 14, 7, 15);
  const VF p[4] = {__builtin_shufflevector(xy_a, z1_a, 0, 1, 8, 9, 4, 5, 12, 13),     // points 0 and 4
                   __builtin_shufflevector(xy_a, z1_a, 2, 3, 10, 11, 6, 7, 14, 15),   // 1 and 5
                   __builtin_shufflevector(xy_b, z1_b, 0, 1, 8, 9, 4, 5, 12, 13),     // 2 and 6
                   __builtin_shufflevector(xy_b, z1_b, 2, 3, 10, 11, 6, 7, 14, 15)};  // 3 and 7
  for (int j = 0; j < 4; ++j) {
    out[j] = __builtin_shufflevector(p[j], p[j], 0, 1, 2, 3);
    out[j + 4] = __builtin_shufflevector(p[j], p[j], 4, 5, 6, 7);
  }
}
#include "ingest_lanes.inc"
#undef FG_LANES_TARGET
}  // namespace
}  // namespace lanes8
#endif

// The registration's first pass (State::moments): the depths, in metres, of every
// fourth point with a depth in front of the sensor (counted across the calls, so the
// same points whatever pieces a cloud comes in, and whether or not its points without
// a return are given), per bin of half the sight map's resolution; nothing else. Only
// the depth of the others is read. Apart from the ingest's loop, which it would slow
// down.
void add_moment(State& s, float x, float y, float z) {
  if (z >= s.zmin && z <= s.zmax) ++s.moment_in_range;
  constexpr float half = 0.5f * static_cast<float>(kSightBins);
  const float inv = 1.f / z;
  const float bu = (x * inv + 1.f) * half, bv = (y * inv + 1.f) * half;
  if (!(bu >= 0.f && bv >= 0.f && bu < 2.f * half && bv < 2.f * half)) return;
  const uint32_t bin = (static_cast<uint32_t>(bv) / 2u) * (kSightBins / 2u) + static_cast<uint32_t>(bu) / 2u;
  const float zm = z * (s.depth_mm * 0.001f);
  DepthMoments& mo = s.moments[bin];
  mo.sum += zm;
  mo.sq += zm * zm;
  mo.n += 1.f;
}

namespace {
// Every fourth of the points i in [0, count) that have a depth (by their running count,
// State::moment_count) goes to take(i); the others cost a test of their depth only.
// The range filter's depths are counted among those taken (moment_in_range): a cloud
// with none there is not registered.
template <class HasDepth, class Take>
inline void every_fourth_with_depth(State& s, uint32_t count, HasDepth has_depth, Take take) {
  uint32_t n = s.moment_count;
  for (uint32_t i = 0; i < count; ++i) {
    if (!has_depth(i)) continue;
    if ((n++ & 3u) == 0u) take(i);
  }
  s.moment_count = n;
}
}  // namespace

void add_moments(State& s, const uint8_t* const base[3], uint32_t count, uint32_t stride_bytes) {
  const auto z_at = [&](uint32_t i) {
    float z;
    std::memcpy(&z, base[2] + static_cast<size_t>(i) * stride_bytes, sizeof z);
    return z;
  };
  every_fourth_with_depth(
      s, count,
      [&](uint32_t i) {
        const float z = z_at(i);
        return z > 0.f && z <= 3.0e38f;  // NaN fails too
      },
      [&](uint32_t i) {
        const size_t off = static_cast<size_t>(i) * stride_bytes;
        float x, y;
        std::memcpy(&x, base[0] + off, sizeof x);
        std::memcpy(&y, base[1] + off, sizeof y);
        add_moment(s, x, y, z_at(i));
      });
}

void add_moments_depth(State& s, const uint16_t* depth_mm, uint16_t width, uint16_t height,
                       const PinholeIntrinsics& k) {
  const float ifx = 1.f / k.fx, ify = 1.f / k.fy;
  for (uint32_t v = 0; v < height; ++v) {
    const uint16_t* row = depth_mm + static_cast<size_t>(v) * width;
    const float yf = (static_cast<float>(v) - k.cy) * ify;
    every_fourth_with_depth(
        s, width, [&](uint32_t u) { return row[u] != 0u; },
        [&](uint32_t u) {
          const float z = static_cast<float>(row[u]) * 0.001f;
          add_moment(s, (static_cast<float>(u) - k.cx) * ifx * z, yf * z, z);
        });
  }
}

bool add_block(State& s, VoxelGrid& grid, const float* x, const float* y, const float* z, uint32_t n) {
#if FG_INGEST_AVX2
  if (s.lanes == 8u) return lanes8::add_block(s, grid, x, y, z, n);
#endif
  return lanes4::add_block(s, grid, x, y, z, n);
}

uint32_t lanes([[maybe_unused]] uint32_t requested) {  // only x86-64 has a choice
#if FG_INGEST_AVX2
  if (requested == 4u) return 4u;
  __builtin_cpu_init();  // idempotent; needed before constructors have run
  if (__builtin_cpu_supports("avx2")) return 8u;
#endif
  return 4u;
}

}  // namespace ingest
}  // namespace fg
