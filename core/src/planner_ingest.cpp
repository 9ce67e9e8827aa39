// Planner: configuration, pose validation and ingest of sensor data into the shared
// voxel grid (algorithm.md A.1-A.4).
#include <cmath>
#include <cstring>

#include "fg/core/planner.hpp"
#include "fg/platform/platform.hpp"
#include "ingest_block.hpp"

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

void Planner::configured_crop(Vec3& lo, Vec3& hi) const {
  lo = Vec3(cfg_.workspace_centre_x_m - cfg_.crop_half_x_m, cfg_.workspace_centre_y_m - cfg_.crop_half_y_m,
            cfg_.crop_min_z_m);
  hi = Vec3(cfg_.workspace_centre_x_m + cfg_.crop_half_x_m, cfg_.workspace_centre_y_m + cfg_.crop_half_y_m,
            cfg_.crop_max_z_m);
}

// A.4c with the head's table off level: the grid and the crop box as reset() leaves
// them, the head no longer added (its sight map unused), its kept points uncounted.
void Planner::leave_out_head() {
  sensors_.added[static_cast<uint32_t>(SensorRole::head)] = false;
  counts_.after_filter = 0;
  reset_grid();
}

void Planner::reset_grid() {
  Vec3 crop_min, crop_max;
  configured_crop(crop_min, crop_max);
  // 2.5 cells of margin below the crop box: every accepted point has a key with room
  // for the +-2 cell neighbour offsets of the clustering (voxel_grid.hpp).
  grid_.reset(crop_min - Vec3::Constant(2.5f * cfg_.voxel_leaf_m), cfg_.voxel_leaf_m);
  const float inv = 1.f / grid_.leaf();
  const Vec3 lo = (crop_min - grid_.origin()) * inv, hi = (crop_max - grid_.origin()) * inv;
  for (int j = 0; j < 3; ++j) {
    crop_lo_cells_[j] = lo[j];
    crop_hi_cells_[j] = hi[j];
  }
  crop_used_ = CropUsed{crop_min.x(), crop_min.y(), crop_max.x(), crop_max.y(), 0u, 0u};
}

void Planner::reset() {
  sensors_.clear();
  counts_ = PointCounts{};
  ingest_us_ = 0;
  overflow_ = false;
  reset_grid();
  object_.clear();
  objects_ready_ = false;
  support_ = SupportPlane{};
  views_.n = 0;
  candidates_.n = 0;
  chosen_view_ = -1;
  chosen_candidate_ = kMaxCandidates;
  n_alternates_ = 0;
  registration_ = RegistrationResult{};
  look_ = LookAdvice{};
  message_ = "";
}

Status validate_pose(const Pose& p, const char** message) {
  const char* why = "";
  Status s = Status::ok;
  if (!p.R.allFinite() || !p.t.allFinite()) {
    why = "sensor pose has a NaN or Inf value";
    s = Status::non_finite;
  } else if ((p.R.transpose() * p.R - Mat3::Identity()).cwiseAbs().maxCoeff() > 1e-3f) {
    why = "sensor pose rotation is not orthonormal";
    s = Status::invalid_pose;
  } else if (p.R.determinant() < 0.f) {
    why = "sensor pose rotation is a reflection (determinant -1)";
    s = Status::invalid_pose;
  } else if (p.t.cwiseAbs().maxCoeff() > 100.f) {
    why = "sensor pose position is more than 100 m from the robot";
    s = Status::invalid_pose;
  }
  if (message != nullptr) *message = why;
  return s;
}

Status Planner::check_pose(const Pose& p) {
  const char* why = "";
  const Status s = validate_pose(p, &why);
  if (s != Status::ok) message_ = why;
  return s;
}

namespace {
// Points gathered into x, y and z blocks (strided arrays and depth images).
struct Block {
  float x[ingest::State::kBatch], y[ingest::State::kBatch], z[ingest::State::kBatch];
  uint32_t n = 0;
};

// Points k < n of a strided block into x, y and z arrays. Packed xyz triples (stride
// 12) and points padded to 16 bytes (PCL's PointXYZ), the common layouts, go four at a
// time through shuffles, which move the bits unchanged (NaN payloads too); `whole` is
// how many of the block's points may be read with all `stride` bytes (a cloud's last
// padded point may end at its z).
void gather(Block& blk, const uint8_t* const b[3], uint32_t stride, uint32_t n, uint32_t whole) {
  uint32_t k = 0;
  if (b[1] == b[0] + 4 && b[2] == b[0] + 8) {
    if (stride == 12) {
      for (; k + 4 <= n; k += 4) {
        const uint8_t* p = b[0] + static_cast<size_t>(k) * 12;
        V4f x, y, z;
        deinterleave_xyz(load4(p), load4(p + 16), load4(p + 32), x, y, z);
        std::memcpy(&blk.x[k], &x, sizeof x);
        std::memcpy(&blk.y[k], &y, sizeof y);
        std::memcpy(&blk.z[k], &z, sizeof z);
      }
    } else if (stride == 16) {
      for (; k + 4 <= whole; k += 4) {
        const uint8_t* p = b[0] + static_cast<size_t>(k) * 16;
        const V4f p0 = load4(p), p1 = load4(p + 16), p2 = load4(p + 32), p3 = load4(p + 48);
        const V4f xy01 = __builtin_shufflevector(p0, p1, 0, 4, 1, 5),
                  xy23 = __builtin_shufflevector(p2, p3, 0, 4, 1, 5);
        const V4f z01 = __builtin_shufflevector(p0, p1, 2, 6, 2, 6), z23 = __builtin_shufflevector(p2, p3, 2, 6, 2, 6);
        const V4f x = __builtin_shufflevector(xy01, xy23, 0, 1, 4, 5);
        const V4f y = __builtin_shufflevector(xy01, xy23, 2, 3, 6, 7);
        const V4f z = __builtin_shufflevector(z01, z23, 0, 1, 4, 5);
        std::memcpy(&blk.x[k], &x, sizeof x);
        std::memcpy(&blk.y[k], &y, sizeof y);
        std::memcpy(&blk.z[k], &z, sizeof z);
      }
    }
  }
  for (; k < n; ++k) {
    // Any stride and alignment; three scalar loads.
    const size_t off = static_cast<size_t>(k) * stride;
    std::memcpy(&blk.x[k], b[0] + off, sizeof(float));
    std::memcpy(&blk.y[k], b[1] + off, sizeof(float));
    std::memcpy(&blk.z[k], b[2] + off, sizeof(float));
  }
}

// `metres_per_unit` scales the points on their way in: folded into the transform, the
// range filter's bounds and the sight map's millimetres (exact at 1).
void make_ingest(ingest::State& in, const Pose& p, const PlannerConfig& cfg, const VoxelGrid& grid,
                 const float crop_lo[3], const float crop_hi[3], uint16_t* sight, uint32_t requested_lanes,
                 float metres_per_unit) {
  const float inv = 1.f / grid.leaf();
  for (int j = 0; j < 3; ++j)
    for (int k = 0; k < 3; ++k) in.r[j][k] = p.R(j, k) * inv * metres_per_unit;
  const Vec3 c = (p.t - grid.origin()) * inv;
  for (int j = 0; j < 3; ++j) {
    in.c[j] = c[j];
    in.lo[j] = crop_lo[j];
    in.hi[j] = crop_hi[j];
  }
  in.leaf = grid.leaf();
  in.zmin = cfg.range_min_m / metres_per_unit;
  in.zmax = cfg.range_max_m / metres_per_unit;
  in.depth_mm = 1000.f * metres_per_unit;
  in.sight = sight;
  in.lanes = ingest::lanes(requested_lanes);
}
}  // namespace

Status Planner::ingest_begin(SensorRole role, const Pose& world_T_sensor, ingest::State& in, bool in_sensor_units) {
  const uint32_t r = static_cast<uint32_t>(role);
  if (r >= kMaxSensors) {
    message_ = "unknown sensor role";
    return Status::invalid_sensor;
  }
  if (sensors_.added[r]) {
    message_ = "this sensor role was already added since reset()";
    return Status::invalid_sensor;
  }
  if (grid_.finalized()) {
    message_ = "sensor data added after plan(): call reset() before the next capture";
    return Status::invalid_sequence;
  }
  const Status s = check_pose(world_T_sensor);
  if (s != Status::ok) return s;
  if (registration_.outcome == RegistrationOutcome::sensor_disagreement && role == registration_.left_out) {
    message_ = "this sensor role was already added since reset() (and left out: sensor_disagreement)";
    return Status::invalid_sensor;
  }
  if (registration_mode_ != RegistrationMode::off && role == SensorRole::head &&
      sensors_.added[static_cast<uint32_t>(SensorRole::hand)])
    registration_.outcome = RegistrationOutcome::hand_added_first;
  sensors_.begin(r, world_T_sensor);
  make_ingest(in, world_T_sensor, cfg_, grid_, crop_lo_cells_, crop_hi_cells_, sensors_.sight_mm[r], ingest_lanes_,
              in_sensor_units ? units_.m[r] : 1.f);
  return Status::ok;
}

Status Planner::set_sensor_units(SensorRole role, float metres_per_unit) {
  const uint32_t r = static_cast<uint32_t>(role);
  if (r >= kMaxSensors) {
    message_ = "unknown sensor role";
    return Status::invalid_sensor;
  }
  if (!std::isfinite(metres_per_unit)) {
    message_ = "sensor units: metres per unit is not finite";
    return Status::non_finite;
  }
  if (!(metres_per_unit >= 1e-6f && metres_per_unit <= 1e3f)) {
    message_ = "sensor units: metres per unit outside 1e-6 .. 1e3";
    return Status::invalid_argument;
  }
  units_.m[r] = metres_per_unit;
  return Status::ok;
}

Status Planner::check_units(const ingest::State& in, SensorRole role, Status st) {
  if (st != Status::ok || in.kept != 0u || in.n_depth_sample == 0u) return st;
  const char* why = units_mistake(in.depth_sample, in.n_depth_sample, cfg_.range_min_m, cfg_.range_max_m,
                                  units_.m[static_cast<uint32_t>(role) % kMaxSensors]);
  if (why == nullptr) return st;
  message_ = why;
  return Status::invalid_argument;
}

uint32_t Planner::ingest_lanes() const { return ingest::lanes(ingest_lanes_); }

// The bookkeeping both kinds of input end with.
Status Planner::end_ingest(uint32_t offered, uint32_t finite, uint32_t kept, uint64_t t0, Status st) {
  counts_.input += offered;
  counts_.finite += finite;
  counts_.after_filter += kept;
  ingest_us_ += static_cast<uint32_t>(platform::monotonic_us() - t0);
  if (st == Status::capacity_exceeded) {
    overflow_ = true;
    message_ =
        "more occupied voxels than the build's FG_MAX_VOXELS with the crop box shrunk to crop_shrink_min (or a cloud "
        "that crowds the voxel hash); shrink the crop box or enlarge the voxel leaf";
  }
  return st;
}

void Planner::make_room(ingest::State& in, uint32_t n) {
  if (grid_.size() + n > kMaxVoxels) shrink_crop(in);
}

// The merged cloud needs more voxels than the grid holds (a noisy sensor smears the
// table over several layers of cells, most of them far from the target): rather than
// refuse the capture, the crop box's x and y halves shrink about the workspace centre,
// kCropShrink a step and not below crop_shrink_min, to whole cells, until the voxels
// left fill at most kCropRefill of the grid. The voxels outside are dropped and the
// ingest goes on in the smaller box, so the grid is the one the points inside it alone
// would have made (same voxels, order and sums). Bounded: each step shrinks both halves
// by a cell at least, or ends at the floor.
void Planner::shrink_crop(ingest::State& in) {
  constexpr float kCropShrink = 0.85f, kCropRefill = 0.75f;
  const float leaf = grid_.leaf();
  const float floor_cells = cfg_.crop_shrink_min_m / leaf;
  const Vec3 centre = (Vec3(cfg_.workspace_centre_x_m, cfg_.workspace_centre_y_m, 0.f) - grid_.origin()) / leaf;
  while (static_cast<float>(grid_.size()) > kCropRefill * static_cast<float>(kMaxVoxels)) {
    uint32_t lo[2], hi[2];
    bool moved = false;
    for (int j = 0; j < 2; ++j) {
      // The whole cells the box in use accepts entirely: [ceil(lo), floor(hi+)), where
      // hi+ is the next float up (a box of whole cells holds hi just below a boundary).
      const float first = std::ceil(crop_lo_cells_[j]);
      const float end = std::floor(std::nextafter(crop_hi_cells_[j], 3.0e38f));
      // Its half, shrunk by kCropShrink (a cell at least), not below the floor.
      const float half_now = 0.5f * (end - first);
      const float half = std::fmax(floor_cells, std::fmin(half_now - 1.f, kCropShrink * half_now));
      const float a = std::fmax(std::ceil(centre[j] - half), first);
      const float b = std::fmin(std::floor(centre[j] + half), end);
      if (!(a < b)) return;  // the workspace centre lies outside the box
      lo[j] = static_cast<uint32_t>(a);
      hi[j] = static_cast<uint32_t>(b);
      moved = moved || a > first || b < end;
    }
    if (!moved) break;  // at the floor
    crop_used_.points_dropped += grid_.keep_xy_range(lo[0], hi[0], lo[1], hi[1]);
    for (int j = 0; j < 2; ++j) {
      crop_lo_cells_[j] = static_cast<float>(lo[j]);
      // f <= hi keeps exactly the cells below hi[j]: the largest float under it.
      crop_hi_cells_[j] = std::nextafter(static_cast<float>(hi[j]), 0.f);
      in.lo[j] = crop_lo_cells_[j];
      in.hi[j] = crop_hi_cells_[j];
    }
    ++crop_used_.shrinks;
    crop_used_.min_x = grid_.origin().x() + static_cast<float>(lo[0]) * leaf;
    crop_used_.max_x = grid_.origin().x() + static_cast<float>(hi[0]) * leaf;
    crop_used_.min_y = grid_.origin().y() + static_cast<float>(lo[1]) * leaf;
    crop_used_.max_y = grid_.origin().y() + static_cast<float>(hi[1]) * leaf;
  }
}

// A.4b: the hand's cloud after the head's is read twice. The first pass (State::
// moments_only) gathers its depths per direction; this registers them to the head's
// voxels and makes `in` the second pass: the ingest with the corrected pose.
bool Planner::registers(SensorRole role) const {
  return registration_mode_ != RegistrationMode::off && role == SensorRole::hand &&
         sensors_.added[static_cast<uint32_t>(SensorRole::head)];
}

// The per-view memory, idle until plan(), holds the first pass's depth moments and the
// registration's samples.
namespace {
constexpr size_t kMomentFloats = size_t{3} * kMomentBins * kMomentBins;
}  // namespace

void Planner::begin_hand_pass(ingest::State& in) {
  static_assert(sizeof(DepthMoments) == 3 * sizeof(float), "moments are three floats");
  static_assert(
      (kMomentFloats + kRegistrationScratchFloats) * sizeof(float) <= sizeof(ViewWork) && kMomentFloats % 2 == 0,
      "the registration borrows the per-view memory, idle until plan(), without growing it");
  float* const mem = reinterpret_cast<float*>(view_words_);
  for (size_t i = 0; i < kMomentFloats; ++i) mem[i] = 0.f;
  in.moments = reinterpret_cast<DepthMoments*>(mem);
  in.moments_only = true;
}

bool Planner::register_hand(ingest::State& in, bool in_sensor_units) {
  const uint64_t t0 = platform::monotonic_us();
  constexpr uint32_t kHand = static_cast<uint32_t>(SensorRole::hand);
  RegistrationParams params;
  params.max_samples = kRegistrationSamples;
  params.min_pairs = kRegistrationSamples / 16u;  // the same share of the samples in every build (64 of 1,024)
  float* const mem = reinterpret_cast<float*>(view_words_);
  Pose& hand = sensors_.pose[kHand];
  if (in.moment_in_range > 0u) {
    registration_ =
        fg::register_hand(grid_, sensors_, reinterpret_cast<const DepthMoments*>(mem), params, mem + kMomentFloats);
  } else {  // no depth within the range: nothing to register, and the ingest's units check tells why
    registration_ = RegistrationResult{};
    registration_.outcome = RegistrationOutcome::too_little_overlap;
  }
  if (registration_.outcome == RegistrationOutcome::sensor_disagreement) {
    if (registration_.left_out == SensorRole::hand) {
      // A.4c: the hand's points stay out; the plan is the head's alone.
      sensors_.added[kHand] = false;
      registration_.us = static_cast<uint32_t>(platform::monotonic_us() - t0);
      return false;
    }
    // The head's table is off level and the hand's is not: the head's points leave the
    // grid, and the hand's, as given, make the plan alone.
    leave_out_head();
  }
  hand = registration_.hand_pose(hand);
  sensors_.origin[kHand] = hand.t;
  in = ingest::State{};
  make_ingest(in, hand, cfg_, grid_, crop_lo_cells_, crop_hi_cells_, sensors_.sight_mm[kHand], ingest_lanes_,
              in_sensor_units ? units_.m[kHand] : 1.f);
  registration_.us = static_cast<uint32_t>(platform::monotonic_us() - t0);
  return true;
}

Status Planner::add_points(SensorRole role, const float* xyz, uint32_t count, uint32_t stride_bytes,
                           const Pose& world_T_sensor) {
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

Status Planner::add_points_planar(SensorRole role, const float* x, const float* y, const float* z, uint32_t count,
                                  const Pose& world_T_sensor) {
  if ((x == nullptr || y == nullptr || z == nullptr) && count > 0) {
    message_ = "a coordinate array is null";
    return Status::invalid_argument;
  }
  const uint8_t* const base[3] = {reinterpret_cast<const uint8_t*>(x), reinterpret_cast<const uint8_t*>(y),
                                  reinterpret_cast<const uint8_t*>(z)};
  return add_coordinates(role, base, count, sizeof(float), world_T_sensor);
}

bool Planner::ingest_piece(ingest::State& in, const uint8_t* const base[3], uint32_t count, uint32_t stride_bytes) {
  if (in.moments_only) {  // the registration's first pass adds no voxel
    ingest::add_moments(in, base, count, stride_bytes);
    return true;
  }
  const uint8_t *bx = base[0], *by = base[1], *bz = base[2];
  // x, y and z arrays are read in place; other strides are gathered into a block.
  const bool planar = stride_bytes == sizeof(float);
  Block blk;
  for (uint32_t i = 0; i < count; i += ingest::State::kBatch) {
    const uint32_t n = count - i < ingest::State::kBatch ? count - i : ingest::State::kBatch;
    const float *x = blk.x, *y = blk.y, *z = blk.z;
    if (planar) {
      x = reinterpret_cast<const float*>(bx) + i;
      y = reinterpret_cast<const float*>(by) + i;
      z = reinterpret_cast<const float*>(bz) + i;
    } else {
      const size_t off = static_cast<size_t>(i) * stride_bytes;
      const uint8_t* const b[3] = {bx + off, by + off, bz + off};
      gather(blk, b, stride_bytes, n, i + n < count ? n : n - 1);
    }
    make_room(in, n);
    if (!ingest::add_block(in, grid_, x, y, z, n)) return false;
  }
  return true;
}

Status Planner::add_coordinates(SensorRole role, const uint8_t* const base[3], uint32_t count, uint32_t stride_bytes,
                                const Pose& world_T_sensor) {
  ingest::State in;
  const Status s = ingest_begin(role, world_T_sensor, in);
  if (s != Status::ok) return s;
  const uint64_t t0 = platform::monotonic_us();
  if (registers(role)) {
    begin_hand_pass(in);
    (void)ingest_piece(in, base, count, stride_bytes);  // adds no voxel: cannot fail
    if (!register_hand(in, true)) return end_ingest(count, 0, 0, t0, Status::ok);
  }
  const Status st = ingest_piece(in, base, count, stride_bytes) ? Status::ok : Status::capacity_exceeded;
  return end_ingest(count, in.offered - in.nonfinite, in.kept, t0, check_units(in, role, st));
}

// One pass over a point source; `offered` counts its points.
Status Planner::read_source(ingest::State& in, PointSource& source, uint32_t& offered) {
  // Points of one sensor, so its offered count stays within 32 bits as one call's would.
  offered = 0;
  // Bounded by the source's points: each piece adds at least one, and at most 2^32 - 1
  // are taken (a source that never ends is refused there).
  for (;;) {
    PointPiece piece;
    if (!source.next(piece)) {
      message_ = "the point source failed";
      return Status::invalid_argument;
    }
    if (piece.count == 0) return Status::ok;
    if (piece.x == nullptr || piece.y == nullptr || piece.z == nullptr || piece.stride < sizeof(float)) {
      message_ = "a piece of the point source has a null coordinate array or a stride under 4 bytes";
      return Status::invalid_argument;
    }
    if (piece.count > 0xFFFFFFFFu - offered) {
      message_ = "a point source offered more than 2^32 - 1 points";
      return Status::invalid_argument;
    }
    offered += piece.count;
    const uint8_t* const base[3] = {piece.x, piece.y, piece.z};
    if (!ingest_piece(in, base, piece.count, piece.stride)) return Status::capacity_exceeded;
  }
}

Status Planner::add_point_source(SensorRole role, PointSource& source, const Pose& world_T_sensor) {
  ingest::State in;
  const Status s = ingest_begin(role, world_T_sensor, in);
  if (s != Status::ok) return s;
  const uint64_t t0 = platform::monotonic_us();
  uint32_t offered = 0;
  if (registers(role) && source.can_rewind()) {
    begin_hand_pass(in);
    const Status first = read_source(in, source, offered);
    if (first != Status::ok) return end_ingest(offered, 0, 0, t0, first);
    if (!source.rewind()) {
      message_ = "the point source failed to rewind";
      return end_ingest(offered, 0, 0, t0, Status::invalid_argument);
    }
    if (!register_hand(in, true)) return end_ingest(offered, 0, 0, t0, Status::ok);
  }
  const Status st = read_source(in, source, offered);
  return end_ingest(offered, in.offered - in.nonfinite, in.kept, t0, st == Status::ok ? check_units(in, role, st) : st);
}

// One pass over a depth image's returns.
Status Planner::depth_pass(ingest::State& in, const uint16_t* depth_mm, uint16_t width, uint16_t height,
                           const PinholeIntrinsics& k) {
  const float ifx = 1.f / k.fx, ify = 1.f / k.fy;
  if (in.moments_only) {  // the registration's first pass: every fourth return
    ingest::add_moments_depth(in, depth_mm, width, height, k);
    return Status::ok;
  }
  Status st = Status::ok;
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
      if (++blk.n == ingest::State::kBatch) {
        blk.n = 0;
        make_room(in, ingest::State::kBatch);
        if (!ingest::add_block(in, grid_, blk.x, blk.y, blk.z, ingest::State::kBatch)) {
          st = Status::capacity_exceeded;
          break;
        }
      }
    }
  }
  if (st == Status::ok) {
    make_room(in, blk.n);
    if (!ingest::add_block(in, grid_, blk.x, blk.y, blk.z, blk.n)) st = Status::capacity_exceeded;
  }
  return st;
}

Status Planner::add_depth_image(SensorRole role, const uint16_t* depth_mm, uint16_t width, uint16_t height,
                                const PinholeIntrinsics& k, const Pose& world_T_sensor) {
  if (depth_mm == nullptr || width == 0 || height == 0) {
    message_ = "depth image is null or empty";
    return Status::invalid_argument;
  }
  if (!(std::isfinite(k.fx) && std::isfinite(k.fy) && std::isfinite(k.cx) && std::isfinite(k.cy))) {
    message_ = "depth intrinsics have a NaN or Inf value";
    return Status::non_finite;
  }
  if (!(k.fx > 1.f && k.fy > 1.f && k.fx < 1e5f && k.fy < 1e5f) || std::fabs(k.cx) > 1e5f || std::fabs(k.cy) > 1e5f) {
    message_ = "depth intrinsics are out of range (focal length must be 1..1e5 px)";
    return Status::invalid_argument;
  }
  ingest::State in;
  const Status s = ingest_begin(role, world_T_sensor, in, false);  // metres from its millimetres
  if (s != Status::ok) return s;
  const uint64_t t0 = platform::monotonic_us();
  if (registers(role)) {
    begin_hand_pass(in);
    (void)depth_pass(in, depth_mm, width, height, k);  // adds no voxel: cannot fail
    if (!register_hand(in, false)) return end_ingest(static_cast<uint32_t>(width) * height, 0, 0, t0, Status::ok);
  }
  const Status st = depth_pass(in, depth_mm, width, height, k);
  return end_ingest(static_cast<uint32_t>(width) * height, in.offered - in.nonfinite, in.kept, t0, st);
}

}  // namespace fg
