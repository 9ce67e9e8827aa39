// Planner: configuration, pose validation and ingest of sensor data into the shared
// voxel grid (algorithm.md A.1-A.4).
#include <cmath>
#include <cstring>

#include "fg/core/planner.hpp"
#include "fg/platform/platform.hpp"

namespace fg {

Status Planner::configure(const PlannerConfig& cfg, const char** field) {
  const Status s = validate(cfg, field);
  if (s != Status::ok) {
    message_ = "invalid planner configuration";
    return s;
  }
  cfg_ = cfg;
  reset();
  return Status::ok;
}

void Planner::reset() {
  for (uint32_t i = 0; i < kMaxSensors; ++i) {
    role_added_[i] = false;
    sensor_origin_[i] = Vec3::Zero();
  }
  counts_ = PointCounts{};
  ingest_us_ = 0;
  overflow_ = false;
  crop_min_ = Vec3(cfg_.workspace_centre_x_m - cfg_.crop_half_x_m,
                   cfg_.workspace_centre_y_m - cfg_.crop_half_y_m, cfg_.crop_min_z_m);
  crop_max_ = Vec3(cfg_.workspace_centre_x_m + cfg_.crop_half_x_m,
                   cfg_.workspace_centre_y_m + cfg_.crop_half_y_m, cfg_.crop_max_z_m);
  // 2.5 cells of margin below the crop box: every accepted point has a key with room
  // for the +-2 cell neighbour offsets of the clustering (voxel_grid.hpp).
  grid_.reset(crop_min_ - Vec3::Constant(2.5f * cfg_.voxel_leaf_m), cfg_.voxel_leaf_m);
  object_.clear();
  plane_found_ = false;
  n_views_ = 0;
  n_candidates_ = 0;
  chosen_view_ = -1;
  message_ = "";
}

Status Planner::check_pose(const Pose& p) {
  if (!p.R.allFinite() || !p.t.allFinite()) {
    message_ = "sensor pose has a NaN or Inf value";
    return Status::non_finite;
  }
  const Mat3 e = p.R.transpose() * p.R - Mat3::Identity();
  if (e.cwiseAbs().maxCoeff() > 1e-3f) {
    message_ = "sensor pose rotation is not orthonormal";
    return Status::invalid_pose;
  }
  if (p.R.determinant() < 0.f) {
    message_ = "sensor pose rotation is a reflection (determinant -1)";
    return Status::invalid_pose;
  }
  if (p.t.cwiseAbs().maxCoeff() > 100.f) {
    message_ = "sensor pose position is more than 100 m from the robot";
    return Status::invalid_pose;
  }
  return Status::ok;
}

Status Planner::ingest_begin(SensorRole role, const Pose& world_T_sensor) {
  const uint32_t r = static_cast<uint32_t>(role);
  if (r >= kMaxSensors) {
    message_ = "unknown sensor role";
    return Status::invalid_sensor;
  }
  if (role_added_[r]) {
    message_ = "this sensor role was already added since reset()";
    return Status::invalid_sensor;
  }
  if (grid_.finalized()) {
    message_ = "sensor data added after plan(): call reset() before the next capture";
    return Status::invalid_sequence;
  }
  const Status s = check_pose(world_T_sensor);
  if (s != Status::ok) return s;
  role_added_[r] = true;
  sensor_origin_[r] = world_T_sensor.t;
  sensor_pose_[r] = world_T_sensor;
  for (uint32_t i = 0; i < kSightBins * kSightBins; ++i) sight_mm_[r][i] = 0xFFFFu;
  return Status::ok;
}

namespace {
// Bits of a 4-bit lane mask.
constexpr uint8_t kPopcount4[16] = {0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4};

// Every other point with a finite depth in front of the sensor feeds the direction bins
// (a bin spans several pixels, and the division is a large part of a point's cost):
// kSightLanes[p][m] are the lanes of a group of four, with valid-depth lanes m, whose
// running count of valid points is odd when p valid points came before (mod 2).
struct SightLanes {
  uint8_t lanes[2][16];
  constexpr SightLanes() : lanes{} {
    for (uint32_t p = 0; p < 2; ++p)
      for (uint32_t m = 0; m < 16; ++m) {
        uint32_t count = p, sel = 0;
        for (uint32_t k = 0; k < 4; ++k)
          if ((m >> k) & 1u) {
            ++count;
            if (count & 1u) sel |= 1u << k;
          }
        lanes[p][m] = static_cast<uint8_t>(sel);
      }
  }
};
constexpr SightLanes kSightLanes{};

// The first and the last set lane of a 4-bit mask with at most two set lanes (the
// same lane twice when one is set): the bins are updated twice per group without a
// loop, whose trip count (0, 1 or 2) the branch predictor cannot know.
struct TwoLanes {
  uint8_t first[16], last[16];
  constexpr TwoLanes() : first{}, last{} {
    for (uint32_t m = 1; m < 16; ++m) {
      uint32_t f = 0, l = 0;
      while (((m >> f) & 1u) == 0u) ++f;
      for (uint32_t k = 0; k < 4; ++k)
        if ((m >> k) & 1u) l = k;
      first[m] = static_cast<uint8_t>(f);
      last[m] = static_cast<uint8_t>(l);
    }
  }
};
constexpr TwoLanes kTwoLanes{};

inline V4f splat(float v) { return V4f{v, v, v, v}; }

// The filter-transform-insert step shared by every kind of input (the hot loop). Points
// arrive in blocks of up to kBatch as x, y and z arrays and are staged four at a time,
// one lane per point: the range and crop tests, the transform to cell units and the
// key are the scalar formulas lane by lane (the same numbers), and the accepted points
// are compacted, in their order, into the pending list that then reaches the grid.
// The rigid transform and the voxel scaling are folded into one affine map from the
// sensor frame to grid cell units, and the crop box is a box in cell units.
struct Ingest {
  V4f r[3][3];        // cell_j = ((r[j][0] * x + r[j][1] * y) + r[j][2] * z) + c[j]
  V4f c[3], lo[3], hi[3];
  V4f leaf, zmin, zmax;
  uint16_t* sight;    // kSightBins^2 nearest returns of this sensor
  uint32_t offered = 0, nonfinite = 0, kept = 0;
  uint32_t parity = 0;  // valid-depth points so far, mod 2
  // A block's accepted points wait here before they reach the grid: the arithmetic of
  // a block runs without waiting on memory, then its grid look-ups and sums issue back
  // to back. 64 points per block (about 1.3 KiB of stack) on the host; small builds
  // keep the stack small.
  static constexpr uint32_t kBatch = kMaxVoxels >= 65536u ? 64u : 16u;
  V4f pend_o[kBatch];         // offsets from the cell corner (m), lane 3 = 1 (the count)
  uint32_t pend_key[kBatch];
  uint8_t pend_lane[kBatch];  // the point's place in its block
  uint32_t n_pend = 0;

  // Stages lanes `live` of four points, the block's points lane0..lane0+3.
  void stage4(V4f x, V4f y, V4f z, uint32_t live, uint32_t lane0) {
    // Direction bins: the nearest return per bin (the min is order-free).
    const uint32_t valid = lane_mask((z > 0.f) & (z <= 3.0e38f)) & live;
    uint32_t sel = kSightLanes.lanes[parity][valid];
    parity ^= kPopcount4[valid] & 1u;
    if (sel != 0u) {
      constexpr float half = 0.5f * static_cast<float>(kSightBins);
      const V4f inv = 1.f / z;
      const V4f bu = (x * inv + 1.f) * half, bv = (y * inv + 1.f) * half;
      const V4i in_bins = (bu >= 0.f) & (bv >= 0.f) & (bu < 2.f * half) & (bv < 2.f * half);
      sel &= lane_mask(in_bins);
      const V4f mm = z * 1000.f;
      const V4i below = mm < 65534.f;
      const V4f capped = select_or_zero(below, mm) + select_or_zero(~below, splat(65534.f));
      const V4i d = __builtin_convertvector(capped, V4i);
      // Out-of-bin lanes become 0 before the conversion (their values may be NaN).
      const V4i bin = __builtin_convertvector(select_or_zero(in_bins, bv), V4i) * static_cast<int32_t>(kSightBins) +
                      __builtin_convertvector(select_or_zero(in_bins, bu), V4i);
      if (sel != 0u) {
        // Alternate valid lanes: at most two of the four (the min is idempotent).
        const uint32_t k0 = kTwoLanes.first[sel], k1 = kTwoLanes.last[sel];
        uint16_t& cur0 = sight[static_cast<uint32_t>(bin[k0])];
        const uint32_t d0 = static_cast<uint32_t>(d[k0]);
        cur0 = static_cast<uint16_t>(d0 < cur0 ? d0 : cur0);
        uint16_t& cur1 = sight[static_cast<uint32_t>(bin[k1])];
        const uint32_t d1 = static_cast<uint32_t>(d[k1]);
        cur1 = static_cast<uint16_t>(d1 < cur1 ? d1 : cur1);
      }
    }
    const V4f fx = ((r[0][0] * x + r[0][1] * y) + r[0][2] * z) + c[0];
    const V4f fy = ((r[1][0] * x + r[1][1] * y) + r[1][2] * z) + c[1];
    const V4f fz = ((r[2][0] * x + r[2][1] * y) + r[2][2] * z) + c[2];
    const V4i in_box = (z >= zmin) & (z <= zmax) & (fx >= lo[0]) & (fx <= hi[0]) & (fy >= lo[1]) &
                       (fy <= hi[1]) & (fz >= lo[2]) & (fz <= hi[2]);
    const uint32_t accepted = lane_mask(in_box) & live;
    if (accepted != live) {
      // NaN and Inf points always end here (every comparison with NaN fails, and each
      // cell coordinate of a point with an Inf coordinate is Inf or NaN), so only here
      // is finiteness tested: x * 0 is 0 for finite x, else NaN.
      nonfinite += kPopcount4[~lane_mask((x * 0.f + y * 0.f + z * 0.f) == 0.f) & live];
      if (accepted == 0u) return;
    }
    // In the crop box, so at least 2 cells inside the key range (reset()); refused
    // lanes become 0 before the conversion.
    const V4i ix = __builtin_convertvector(select_or_zero(in_box, fx), V4i);
    const V4i iy = __builtin_convertvector(select_or_zero(in_box, fy), V4i);
    const V4i iz = __builtin_convertvector(select_or_zero(in_box, fz), V4i);
    const V4f ox = (fx - __builtin_convertvector(ix, V4f)) * leaf;
    const V4f oy = (fy - __builtin_convertvector(iy, V4f)) * leaf;
    const V4f oz = (fz - __builtin_convertvector(iz, V4f)) * leaf;
    typedef uint32_t V4u __attribute__((vector_size(16)));
    const V4u key = reinterpret_cast<V4u>(ix) | (reinterpret_cast<V4u>(iy) << 11) |
                    (reinterpret_cast<V4u>(iz) << 22);  // VoxelGrid::pack
    // Four (x, y, z, 1) offsets out of the lanes, then a compaction without branches:
    // every lane is written at the next free place, which advances for accepted lanes.
    const V4f one = splat(1.f);
    const V4f xy01 = __builtin_shufflevector(ox, oy, 0, 4, 1, 5), xy23 = __builtin_shufflevector(ox, oy, 2, 6, 3, 7);
    const V4f z101 = __builtin_shufflevector(oz, one, 0, 4, 1, 5), z123 = __builtin_shufflevector(oz, one, 2, 6, 3, 7);
    const V4f o[4] = {__builtin_shufflevector(xy01, z101, 0, 1, 4, 5), __builtin_shufflevector(xy01, z101, 2, 3, 6, 7),
                      __builtin_shufflevector(xy23, z123, 0, 1, 4, 5), __builtin_shufflevector(xy23, z123, 2, 3, 6, 7)};
    uint32_t n = n_pend;
    if (accepted == 0xFu) {  // the rule: four points kept, stored as they are
      for (uint32_t k = 0; k < 4; ++k) pend_o[n + k] = o[k];
      std::memcpy(&pend_key[n], &key, sizeof key);
      for (uint32_t k = 0; k < 4; ++k) pend_lane[n + k] = static_cast<uint8_t>(lane0 + k);
      n_pend = n + 4u;
      return;
    }
    for (uint32_t k = 0; k < 4; ++k) {
      pend_o[n] = o[k];
      pend_key[n] = key[k];
      pend_lane[n] = static_cast<uint8_t>(lane0 + k);
      n += (accepted >> k) & 1u;
    }
    n_pend = n;
  }

  // Stages and adds n <= kBatch points; false when the grid is full. Then offered,
  // nonfinite and kept count exactly the points read up to the refused one.
  bool add_block(VoxelGrid& grid, const float* x, const float* y, const float* z, uint32_t n) {
    const uint32_t offered0 = offered, nonfinite0 = nonfinite;
    n_pend = 0;
    uint32_t i = 0;
    for (; i + 4u <= n; i += 4u) {
      V4f vx, vy, vz;
      std::memcpy(&vx, x + i, sizeof vx);
      std::memcpy(&vy, y + i, sizeof vy);
      std::memcpy(&vz, z + i, sizeof vz);
      stage4(vx, vy, vz, 0xFu, i);
    }
    if (i < n) {
      V4f vx{}, vy{}, vz{};
      for (uint32_t k = 0; i + k < n; ++k) {
        vx[k] = x[i + k];
        vy[k] = y[i + k];
        vz[k] = z[i + k];
      }
      stage4(vx, vy, vz, (1u << (n - i)) - 1u, i);
    }
    offered += n;
    for (uint32_t k = 0; k < n_pend; ++k) {
      if (!grid.add_to_cell(pend_key[k], pend_o[k])) {
        // The refused point is read (counted), not kept; the points after it are not.
        const uint32_t last = pend_lane[k];
        offered = offered0 + last + 1u;
        nonfinite = nonfinite0;
        for (uint32_t j = 0; j < last; ++j)
          if (!(x[j] * 0.f + y[j] * 0.f + z[j] * 0.f == 0.f)) ++nonfinite;
        kept += k;
        return false;
      }
    }
    kept += n_pend;
    return true;
  }
};

// Points gathered into x, y and z blocks (strided arrays and depth images).
struct Block {
  float x[Ingest::kBatch], y[Ingest::kBatch], z[Ingest::kBatch];
  uint32_t n = 0;
};

Ingest make_ingest(const Pose& p, const PlannerConfig& cfg, const VoxelGrid& grid,
                   const Vec3& crop_lo, const Vec3& crop_hi, uint16_t* sight) {
  Ingest in;
  const float inv = 1.f / grid.leaf();
  for (int j = 0; j < 3; ++j)
    for (int k = 0; k < 3; ++k) in.r[j][k] = splat(p.R(j, k) * inv);
  const Vec3 c = (p.t - grid.origin()) * inv, lo = (crop_lo - grid.origin()) * inv,
             hi = (crop_hi - grid.origin()) * inv;
  for (int j = 0; j < 3; ++j) {
    in.c[j] = splat(c[j]);
    in.lo[j] = splat(lo[j]);
    in.hi[j] = splat(hi[j]);
  }
  in.leaf = splat(grid.leaf());
  in.zmin = splat(cfg.range_min_m);
  in.zmax = splat(cfg.range_max_m);
  in.sight = sight;
  return in;
}
}  // namespace

// The bookkeeping both kinds of input end with.
Status Planner::end_ingest(uint32_t offered, uint32_t finite, uint32_t kept, uint64_t t0, Status st) {
  counts_.input += offered;
  counts_.finite += finite;
  counts_.after_filter += kept;
  ingest_us_ += static_cast<uint32_t>(platform::monotonic_us() - t0);
  if (st != Status::ok) {
    overflow_ = true;
    message_ = "more occupied voxels than the build's FG_MAX_VOXELS (or a cloud that crowds the voxel hash); shrink the crop box or enlarge the voxel leaf";
  }
  return st;
}

Status Planner::add_points(SensorRole role, const float* xyz, uint32_t count,
                           uint32_t stride_bytes, const Pose& world_T_sensor) {
  if (xyz == nullptr && count > 0) {
    message_ = "point array is null";
    return Status::invalid_argument;
  }
  if (stride_bytes < 3 * sizeof(float)) {
    message_ = "point stride is smaller than three floats";
    return Status::invalid_argument;
  }
  // No offset from a null array (count 0): it is not read.
  const uint8_t* p = reinterpret_cast<const uint8_t*>(xyz);
  const uint8_t* const base[3] = {p, p ? p + sizeof(float) : p, p ? p + 2 * sizeof(float) : p};
  return add_coordinates(role, base, count, stride_bytes, world_T_sensor);
}

Status Planner::add_points_planar(SensorRole role, const float* x, const float* y, const float* z,
                                  uint32_t count, const Pose& world_T_sensor) {
  if ((x == nullptr || y == nullptr || z == nullptr) && count > 0) {
    message_ = "a coordinate array is null";
    return Status::invalid_argument;
  }
  const uint8_t* const base[3] = {reinterpret_cast<const uint8_t*>(x), reinterpret_cast<const uint8_t*>(y),
                                  reinterpret_cast<const uint8_t*>(z)};
  return add_coordinates(role, base, count, sizeof(float), world_T_sensor);
}

Status Planner::add_coordinates(SensorRole role, const uint8_t* const base[3], uint32_t count,
                                uint32_t stride_bytes, const Pose& world_T_sensor) {
  const Status s = ingest_begin(role, world_T_sensor);
  if (s != Status::ok) return s;
  const uint64_t t0 = platform::monotonic_us();
  Ingest in = make_ingest(world_T_sensor, cfg_, grid_, crop_min_, crop_max_,
                          sight_mm_[static_cast<uint32_t>(role)]);
  Status st = Status::ok;
  const uint8_t *bx = base[0], *by = base[1], *bz = base[2];
  if (stride_bytes == sizeof(float)) {
    // x, y and z arrays: the blocks are read in place.
    const float *x = reinterpret_cast<const float*>(bx), *y = reinterpret_cast<const float*>(by),
                *z = reinterpret_cast<const float*>(bz);
    for (uint32_t i = 0; i < count; i += Ingest::kBatch) {
      const uint32_t n = count - i < Ingest::kBatch ? count - i : Ingest::kBatch;
      if (!in.add_block(grid_, x + i, y + i, z + i, n)) {
        st = Status::capacity_exceeded;
        break;
      }
    }
  } else {
    Block blk;
    for (uint32_t i = 0; i < count; i += Ingest::kBatch) {
      const uint32_t n = count - i < Ingest::kBatch ? count - i : Ingest::kBatch;
      for (uint32_t k = 0; k < n; ++k) {
        // Any alignment; three scalar loads.
        const size_t off = static_cast<size_t>(i + k) * stride_bytes;
        std::memcpy(&blk.x[k], bx + off, sizeof(float));
        std::memcpy(&blk.y[k], by + off, sizeof(float));
        std::memcpy(&blk.z[k], bz + off, sizeof(float));
      }
      if (!in.add_block(grid_, blk.x, blk.y, blk.z, n)) {
        st = Status::capacity_exceeded;
        break;
      }
    }
  }
  return end_ingest(count, in.offered - in.nonfinite, in.kept, t0, st);
}

Status Planner::add_depth_image(SensorRole role, const uint16_t* depth_mm, uint16_t width,
                                uint16_t height, const PinholeIntrinsics& k,
                                const Pose& world_T_sensor) {
  if (depth_mm == nullptr || width == 0 || height == 0) {
    message_ = "depth image is null or empty";
    return Status::invalid_argument;
  }
  if (!(std::isfinite(k.fx) && std::isfinite(k.fy) && std::isfinite(k.cx) && std::isfinite(k.cy))) {
    message_ = "depth intrinsics have a NaN or Inf value";
    return Status::non_finite;
  }
  if (!(k.fx > 1.f && k.fy > 1.f && k.fx < 1e5f && k.fy < 1e5f) ||
      std::fabs(k.cx) > 1e5f || std::fabs(k.cy) > 1e5f) {
    message_ = "depth intrinsics are out of range (focal length must be 1..1e5 px)";
    return Status::invalid_argument;
  }
  const Status s = ingest_begin(role, world_T_sensor);
  if (s != Status::ok) return s;
  const uint64_t t0 = platform::monotonic_us();
  Ingest in = make_ingest(world_T_sensor, cfg_, grid_, crop_min_, crop_max_,
                          sight_mm_[static_cast<uint32_t>(role)]);
  Status st = Status::ok;
  const float ifx = 1.f / k.fx, ify = 1.f / k.fy;
  Block blk;
  for (uint32_t v = 0; v < height && st == Status::ok; ++v) {
    const float yf = (static_cast<float>(v) - k.cy) * ify;
    const uint16_t* row = depth_mm + static_cast<size_t>(v) * width;
    for (uint32_t u = 0; u < width; ++u) {
      if (row[u] == 0) continue;  // no return: not a point
      const float z = static_cast<float>(row[u]) * 0.001f;
      blk.x[blk.n] = (static_cast<float>(u) - k.cx) * ifx * z;
      blk.y[blk.n] = yf * z;
      blk.z[blk.n] = z;
      if (++blk.n == Ingest::kBatch) {
        blk.n = 0;
        if (!in.add_block(grid_, blk.x, blk.y, blk.z, Ingest::kBatch)) {
          st = Status::capacity_exceeded;
          break;
        }
      }
    }
  }
  if (st == Status::ok && !in.add_block(grid_, blk.x, blk.y, blk.z, blk.n)) st = Status::capacity_exceeded;
  return end_ingest(static_cast<uint32_t>(width) * height, in.offered - in.nonfinite, in.kept, t0, st);
}

}  // namespace fg
