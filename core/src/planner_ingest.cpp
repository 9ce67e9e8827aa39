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
// The filter-transform-insert step shared by both kinds of input (hot loop). The
// rigid transform and the voxel scaling are folded into one affine map from the
// sensor frame to grid cell units, and the crop box is a box in cell units.
struct Ingest {
  V4f col[3], c;      // cell = col[0] * x + col[1] * y + col[2] * z + c (lane 3: 0)
  V4f lo, hi;         // crop box in cell units (lane 3: -1 and 1, so it passes)
  V4f leaf;           // the voxel leaf in every lane
  float zmin, zmax;
  uint16_t* sight;    // kSightBins^2 nearest returns of this sensor
  uint32_t offered = 0, nonfinite = 0, kept = 0;
  uint32_t parity = 0;
  // Accepted points wait in a small batch before they reach the grid: the arithmetic
  // of a batch runs without waiting on memory, then its grid look-ups and sums issue
  // back to back. Each entry keeps the counters as they were at its point, so a full
  // grid reports exactly the points read up to the one refused.
  // 64 (2 KiB of stack) measured best on the host (16: +2%, 256: same); small builds
  // keep the stack small.
  static constexpr uint32_t kBatch = kMaxVoxels >= 65536u ? 64u : 16u;
  struct Pending {
    V4f o;
    uint32_t key, offered, nonfinite;
  };
  Pending pend[kBatch];
  uint32_t n_pend = 0;

  // Adds the batch to the grid; false when the grid is full.
  bool flush(VoxelGrid& grid) {
    const uint32_t n = n_pend;
    n_pend = 0;
    for (uint32_t k = 0; k < n; ++k) {
      if (!grid.add_to_cell(pend[k].key, pend[k].o)) {
        offered = pend[k].offered;
        nonfinite = pend[k].nonfinite;
        kept += k;
        return false;
      }
    }
    kept += n;
    return true;
  }

  // A point the range or the crop box refused: NaN and Inf points always end here
  // (every comparison with NaN fails, and an Inf coordinate makes the cell NaN or
  // Inf), so only here is finiteness tested. x * 0 is 0 for finite x, else NaN.
  void refuse(float x, float y, float z) {
    if (!(x * 0.f + y * 0.f + z * 0.f == 0.f)) ++nonfinite;
  }

  // Returns false when the grid is full.
  bool add(VoxelGrid& grid, float x, float y, float z) {
    stage(x, y, z);
    return n_pend < kBatch || flush(grid);
  }

  // Filters, transforms and queues one point (and feeds the direction bins).
  void stage(float x, float y, float z) {
    ++offered;
    // Every other point with a finite depth in front of the sensor feeds the direction
    // bins (a NaN or Inf x or y fails the bin test): a bin spans several pixels, and
    // the division is a large part of the per-point cost.
    if (z > 0.f && z <= 3.0e38f && (++parity & 1u) != 0u) {
      // Nearest return per direction bin, updated without a branch: a bin spans a few
      // points of a row, so whether the next point changes bin is unpredictable.
      constexpr float half = 0.5f * static_cast<float>(kSightBins);
      const float inv = 1.f / z;
      const float bu = (x * inv + 1.f) * half, bv = (y * inv + 1.f) * half;
      if (bu >= 0.f && bv >= 0.f && bu < 2.f * half && bv < 2.f * half) {
        const float mm = z * 1000.f;
        const uint32_t d = mm < 65534.f ? static_cast<uint32_t>(mm) : 65534u;
        const uint32_t bin = static_cast<uint32_t>(bv) * kSightBins + static_cast<uint32_t>(bu);
        const uint32_t cur = sight[bin];
        sight[bin] = static_cast<uint16_t>(d < cur ? d : cur);
      }
    }
    if (!(z >= zmin && z <= zmax)) {
      refuse(x, y, z);
      return;
    }
    const V4f f = col[0] * x + col[1] * y + col[2] * z + c;
    if (!all_lanes((f >= lo) & (f <= hi))) {
      refuse(x, y, z);
      return;
    }
    // In the crop box, so at least 2 cells inside the key range (reset()).
    const V4i i = __builtin_convertvector(f, V4i);
    // Lane 3 of f and i is 0 (finite point): o[3] = 1, the point's count.
    const V4f o = (f - __builtin_convertvector(i, V4f)) * leaf + V4f{0.f, 0.f, 0.f, 1.f};
    const uint32_t key = VoxelGrid::pack(static_cast<uint32_t>(i[0]), static_cast<uint32_t>(i[1]),
                                         static_cast<uint32_t>(i[2]));
    pend[n_pend++] = Pending{o, key, offered, nonfinite};
  }
};

Ingest make_ingest(const Pose& p, const PlannerConfig& cfg, const VoxelGrid& grid,
                   const Vec3& crop_lo, const Vec3& crop_hi, uint16_t* sight) {
  Ingest in;
  const float inv = 1.f / grid.leaf();
  for (int j = 0; j < 3; ++j) in.col[j] = V4f{p.R(0, j) * inv, p.R(1, j) * inv, p.R(2, j) * inv, 0.f};
  const Vec3 c = (p.t - grid.origin()) * inv, lo = (crop_lo - grid.origin()) * inv,
             hi = (crop_hi - grid.origin()) * inv;
  in.c = V4f{c.x(), c.y(), c.z(), 0.f};
  in.lo = V4f{lo.x(), lo.y(), lo.z(), -1.f};
  in.hi = V4f{hi.x(), hi.y(), hi.z(), 1.f};
  const float leaf = grid.leaf();
  in.leaf = V4f{leaf, leaf, leaf, leaf};
  in.zmin = cfg.range_min_m;
  in.zmax = cfg.range_max_m;
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
  for (uint32_t i = 0; i < count; ++i) {
    // Any alignment; three scalar loads (a copy through a float[3] went via the stack).
    const size_t off = static_cast<size_t>(i) * stride_bytes;
    float x, y, z;
    std::memcpy(&x, bx + off, sizeof x);
    std::memcpy(&y, by + off, sizeof y);
    std::memcpy(&z, bz + off, sizeof z);
    if (!in.add(grid_, x, y, z)) {
      st = Status::capacity_exceeded;
      break;
    }
  }
  if (st == Status::ok && !in.flush(grid_)) st = Status::capacity_exceeded;
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
  bool full = false;
  for (uint32_t v = 0; v < height && !full; ++v) {
    const float yf = (static_cast<float>(v) - k.cy) * ify;
    const uint16_t* row = depth_mm + static_cast<size_t>(v) * width;
    for (uint32_t u = 0; u < width; ++u) {
      if (row[u] == 0) continue;
      const float z = static_cast<float>(row[u]) * 0.001f;
      const float x = (static_cast<float>(u) - k.cx) * ifx * z;
      if (!in.add(grid_, x, yf * z, z)) {
        st = Status::capacity_exceeded;
        full = true;
        break;
      }
    }
  }
  if (st == Status::ok && !in.flush(grid_)) st = Status::capacity_exceeded;
  return end_ingest(static_cast<uint32_t>(width) * height, in.offered - in.nonfinite, in.kept, t0, st);
}

}  // namespace fg
