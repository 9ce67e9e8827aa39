// The ingest's hot loop (algorithm.md A.1-A.4), shared by every kind of input: points
// arrive in blocks of up to kBatch as x, y and z arrays; each is range-filtered,
// transformed to grid cell units, crop-tested and queued, then the block's kept
// points reach the voxel grid in their order. The lanes of a vector step are points:
// four on every target (SSE2 on x86-64, NEON on aarch64, scalar code on Cortex-M),
// eight where the x86-64 CPU has AVX2. Every lane computes the scalar formulas, so
// every width gives the same grid, bit for bit.
#pragma once
#include <cstdint>

#include "fg/core/limits.hpp"
#include "fg/core/pinhole.hpp"
#include "fg/core/pipeline/registration.hpp"
#include "fg/core/pipeline/units.hpp"
#include "fg/core/vec4.hpp"
#include "fg/core/voxel_grid.hpp"

namespace fg {
namespace ingest {

struct State {
  // cell_j = ((r[j][0] * x + r[j][1] * y) + r[j][2] * z) + c[j]: the rigid transform
  // and the voxel scaling folded into one affine map from the sensor frame to cells.
  float r[3][3], c[3];
  float lo[3], hi[3];  // the crop box in cell units
  float leaf, zmin, zmax;
  float depth_mm = 1000.f;    // millimetres per unit of depth (the sight map's)
  uint16_t* sight = nullptr;  // kSightBins^2 nearest returns of this sensor
  uint32_t offered = 0, nonfinite = 0, kept = 0;
  uint32_t parity = 0;  // valid-depth points so far, mod 2 (the direction bins' share)
  uint32_t lanes = 4;   // the vector width (lanes(requested), once per cloud)
  // A cloud read twice for the registration (Planner, A.4b): the first pass only
  // gathers depth moments (kMomentBins^2, zeroed before), the second is the ingest.
  bool moments_only = false;
  DepthMoments* moments = nullptr;
  uint32_t moment_count = 0;     // points with a depth met by the first pass
  uint32_t moment_in_range = 0;  // of those it binned, those within the range filter's depths
  // A block's kept points wait here before they reach the grid: the arithmetic of a
  // block runs without waiting on memory, then its grid look-ups and sums issue back
  // to back. 64 points per block (about 1.3 KiB) on the host; small builds keep the
  // stack small.
  static constexpr uint32_t kBatch = kMaxVoxels >= 65536u ? 64u : 16u;
  V4f pend_o[kBatch];  // offsets from the cell corner (m), lane 3 = 1 (the count)
  uint32_t pend_key[kBatch];
  uint8_t pend_lane[kBatch];  // the point's place in its block
  uint32_t n_pend = 0;
  // The units check's sample (units.hpp), taken while the sensor has kept no point: the
  // depth of one refused point in front of the sensor per group of lanes, from every
  // 2^k-th such group, k growing as the sample fills, so that it spans the whole cloud.
  float depth_sample[kUnitSamples];
  uint32_t n_depth_sample = 0;
  uint32_t depth_groups = 0;       // groups offered to the sample
  uint32_t depth_stride_mask = 0;  // 2^k - 1
};

//! Offers one refused depth to the units check's sample (State::depth_sample).
inline void sample_depth(State& s, float z) {
  if ((s.depth_groups++ & s.depth_stride_mask) != 0u) return;
  if (s.n_depth_sample == kUnitSamples) {  // full: keep every other, take half as many
    for (uint32_t i = 0, j = 0; i < kUnitSamples / 2; ++i, j += 2) s.depth_sample[i] = s.depth_sample[j];
    s.n_depth_sample = kUnitSamples / 2;
    s.depth_stride_mask = 2u * s.depth_stride_mask + 1u;
    if (((s.depth_groups - 1u) & s.depth_stride_mask) != 0u) return;
  }
  s.depth_sample[s.n_depth_sample++] = z;
}

//! Stages and adds n <= State::kBatch points; false when the grid is full. Then
//! offered, nonfinite and kept count exactly the points read up to the refused one.
[[nodiscard]] bool add_block(State& s, VoxelGrid& grid, const float* x, const float* y, const float* z, uint32_t n);

//! Adds one point (sensor frame, the cloud's units, a depth in front) to State::moments.
void add_moment(State& s, float x, float y, float z);
//! The first pass over `count` points at base[k] + i * stride_bytes (x, y, z): adds every
//! fourth with a depth in front, counting on from the calls before.
void add_moments(State& s, const uint8_t* const base[3], uint32_t count, uint32_t stride_bytes);
//! The same over a depth image's pixels (millimetres, 0: no return), row by row: the
//! points of its organized cloud, with or without those without a return.
void add_moments_depth(State& s, const uint16_t* depth_mm, uint16_t width, uint16_t height, const PinholeIntrinsics& k);

//! The vector width add_block uses (4 or 8) for the width a caller asks for: 4 forces
//! the four-lane path of every target, anything else (0 by convention) picks the widest
//! this CPU runs. The caller keeps its choice (Planner::set_ingest_lanes) and passes it
//! here once per cloud, into State::lanes.
uint32_t lanes(uint32_t requested);

}  // namespace ingest
}  // namespace fg
