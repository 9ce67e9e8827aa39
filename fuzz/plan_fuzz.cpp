// Fuzz target: the core planner (fg::Planner configure / reset / set_target /
// set_sensor_units / add_points /
// add_point_source / add_depth_image / plan / analyze_view / plan_object / more_grasps)
// on inputs decoded from the bytes. It asserts nothing about the outcome: the findings
// are crashes, sanitizer reports, hangs, and any heap use inside the core (the no-heap
// guard is armed around every core call and abort()s on an allocation or a free).
//
// Input layout (little endian; bytes past the end read as 0, so every input decodes):
//   u8  config   bits 0-2: preset (see apply_preset), bits 3-5: number of overrides
//   overrides:   u8 field index, 4 bytes value (float or uint32 by field), each
//   u8  flags    bits 0-1: sensor blocks (0..3), bit 2: plan twice, bit 3: analyze_view,
//                bit 4: a target block follows, bit 5: object calls after the plan,
//                bit 6: plan_object(0) before the plan (out of sequence), bit 7: a units
//                block follows (after the target's)
//   u8  view     analyze_view index (modulo view_count() + 2: out of range included)
//   target (bit 4): u8 kind (modulo 4: 0 by rule, 1 nearest point, 2 inside box, 3 the
//                next byte as the raw kind, valid or not), then 9 floats: point, box_min,
//                box_max (raw: NaN, Inf, huge values and inverted boxes reach set_target)
//   units (bit 7): u8 role (raw & 3: 2 and 3 are invalid roles), float metres per unit
//                (raw: 0, negative, NaN, huge reach set_sensor_units)
//   sensor block, repeated:
//     u8 role    raw & 3 (0 head, 1 hand, 2 and 3 are invalid roles)
//     u8 kind    bit 0: 0 add_points, 1 add_depth_image; bits 1-2: pose encoding;
//                bit 3: pass a null data pointer; bit 4: points through
//                add_point_source in pieces of 1 + (bits 5-7) points
//     pose       encoding 0: R (9 floats, row major) + t (3 floats), raw
//                encoding 1: quaternion w x y z (4 floats, normalised here) + t (3 floats)
//                encoding 2: look-at: eye (3 floats), target (3 floats)
//                encoding 3: identity rotation, t (3 floats)
//     points:    u8 stride (bytes; < 12 is an invalid argument), u16 payload bytes,
//                payload: points of x y z floats `stride` bytes apart
//     depth:     u8 width % 65, u8 height % 65, fx fy cx cy (4 floats), u16 payload bytes,
//                payload: uint16 millimetres, row major (missing pixels are 0)
//   object calls (bit 5), after the plan: u8 n (1 + n % 4 calls), each u8 index (0xFF:
//                2^32 - 1, else modulo object_count() + 2: out of range included) and
//                u8 more (more_grasps after it: bits 0-4 max, modulo kMaxRankedGrasps + 2;
//                bit 7 a null output)
// The target, the units and every other setting start afresh on each input.
// Raw floats reach the core as they are: NaN, Inf, denormals, huge values.
// fuzz/make_seeds.py writes seeds in this layout.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>

#include "byte_reader.hpp"
#include "fg/core/planner.hpp"
#include "no_heap_guard.hpp"

namespace {

constexpr uint32_t kMaxDepthSide = 64;
constexpr size_t kMaxPointBytes = 65535;  // a u16 payload length

// Everything the core touches lives in static storage: nothing here allocates.
fg::Planner g_planner;  // ~4 MB, constructed once
fg::PlanResult g_result;
fg::ViewDetail g_detail;
fg::RankedGrasp g_more[fg::kMaxRankedGrasps + 2];
alignas(16) unsigned char g_points[kMaxPointBytes + 16];
uint16_t g_depth[kMaxDepthSide * kMaxDepthSide];
const bool g_verbose = std::getenv("FG_FUZZ_PLAN_VERBOSE") != nullptr;

using Reader = fg_fuzz::ByteReader;

void apply_preset(fg::PlannerConfig& c, uint32_t preset) {
  switch (preset) {
    case 1:
      c.extend_search = false;
      break;
    case 2:
      c.paper_depth = true;
      c.centre_weight = 1e-6f;
      break;
    case 3:
      c.executability_checks = false;
      break;
    case 4:
      c.voxel_leaf_m = 0.01f;
      c.min_object_points = 10;
      break;
    case 5:
      c.target_rule = fg::TargetRule::largest;
      c.cluster_cells = 2;
      break;
    case 6:
      c.friction_mu = 0.f;
      c.ransac_iterations = 20;
      break;
    case 7:
      c.min_object_points = 3;
      c.dtheta_rad = 0.0087f;
      break;
    default:
      break;  // 0: the documented defaults
  }
}

void apply_override(fg::PlannerConfig& c, uint8_t index, Reader& r) {
  float* floats[] = {&c.gripper.max_opening_m,
                     &c.gripper.min_opening_m,
                     &c.gripper.finger_width_m,
                     &c.gripper.finger_depth_m,
                     &c.gripper.finger_thickness_m,
                     &c.gripper.palm_depth_m,
                     &c.gripper.palm_width_m,
                     &c.range_min_m,
                     &c.range_max_m,
                     &c.crop_half_x_m,
                     &c.crop_half_y_m,
                     &c.crop_min_z_m,
                     &c.crop_max_z_m,
                     &c.voxel_leaf_m,
                     &c.plane_distance_m,
                     &c.plane_max_tilt_rad,
                     &c.object_min_height_m,
                     &c.workspace_centre_x_m,
                     &c.workspace_centre_y_m,
                     &c.dtheta_rad,
                     &c.single_sensor_arc_rad,
                     &c.vertical_snap_rad,
                     &c.vertical_snap_round_rad,
                     &c.axis_ratio_min,
                     &c.extension_dtheta_rad,
                     &c.approach_view_max_rad,
                     &c.scan_delta_m,
                     &c.dx_threshold_m,
                     &c.width_margin_m,
                     &c.hull_cell_m,
                     &c.centre_weight,
                     &c.beta_max_rad,
                     &c.contact_band_m,
                     &c.reach_width_ratio,
                     &c.friction_mu,
                     &c.table_clearance_m,
                     &c.collision_tolerance_m,
                     &c.pregrasp_clearance_m,
                     &c.palm_clearance_m};
  uint32_t* ints[] = {&c.ransac_iterations, &c.ransac_seed,        &c.cluster_cells,
                      &c.min_object_points, &c.hull_closing_cells, &c.candidates_per_view};
  bool* flags[] = {&c.extend_search, &c.paper_depth, &c.executability_checks};
  constexpr size_t nf = sizeof floats / sizeof floats[0];
  constexpr size_t ni = sizeof ints / sizeof ints[0];
  constexpr size_t nb = sizeof flags / sizeof flags[0];
  const size_t k = index % (nf + ni + nb + 1);
  if (k < nf) {
    *floats[k] = r.f32();
  } else if (k < nf + ni) {
    *ints[k - nf] = r.u32();
  } else if (k < nf + ni + nb) {
    *flags[k - nf - ni] = (r.u32() & 1u) != 0;
  } else {
    c.target_rule = static_cast<fg::TargetRule>(r.u32() & 0xFFu);  // any byte, valid or not
  }
}

fg::Pose read_pose(uint32_t encoding, Reader& r) {
  fg::Pose p;
  switch (encoding) {
    case 0:
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) p.R(i, j) = r.f32();
      for (int i = 0; i < 3; ++i) p.t(i) = r.f32();
      break;
    case 1: {
      float q[4];
      for (float& v : q) v = r.f32();
      const float n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
      // A zero quaternion becomes NaN (no division by zero here); NaN and Inf stay so.
      const float inv = n > 0.f ? 1.f / n : std::numeric_limits<float>::quiet_NaN();
      const Eigen::Quaternionf qq(q[0] * inv, q[1] * inv, q[2] * inv, q[3] * inv);
      p.R = qq.toRotationMatrix();
      for (int i = 0; i < 3; ++i) p.t(i) = r.f32();
      break;
    }
    case 2: {
      fg::Vec3 eye, target;
      for (int i = 0; i < 3; ++i) eye(i) = r.f32();
      for (int i = 0; i < 3; ++i) target(i) = r.f32();
      const fg::Vec3 z = (target - eye).normalized();
      fg::Vec3 x = z.cross(fg::Vec3::UnitZ());
      if (x.norm() < 1e-6f) x = fg::Vec3::UnitX();
      x.normalize();
      p.R.col(0) = x;
      p.R.col(1) = z.cross(x);
      p.R.col(2) = z;
      p.t = eye;
      break;
    }
    default:
      for (int i = 0; i < 3; ++i) p.t(i) = r.f32();
      break;
  }
  return p;
}

struct Call {
  fg::SensorRole role;
  bool depth;
  bool null_data;
  fg::Pose pose;
  // points
  const float* xyz = nullptr;
  uint32_t count = 0, stride = 0;
  bool pieces = false;
  uint32_t piece_points = 1;
  // depth image
  uint16_t width = 0, height = 0;
  fg::PinholeIntrinsics k;
};

// Decodes one sensor block; payloads are copied into the static buffers (one block's
// payload at a time: the calls below run before the next block is decoded).
Call read_call(Reader& r) {
  Call c;
  c.role = static_cast<fg::SensorRole>(r.u8() & 3u);
  const uint8_t kind = r.u8();
  c.depth = (kind & 1u) != 0;
  c.null_data = (kind & 8u) != 0;
  c.pieces = (kind & 16u) != 0;
  c.piece_points = 1u + (kind >> 5);
  c.pose = read_pose((kind >> 1) & 3u, r);
  if (!c.depth) {
    c.stride = r.u8();
    const uint8_t* src = nullptr;
    const size_t n = r.take(r.u16(), src);
    std::memcpy(g_points, src, n);
    // Honest count: every point lies inside the bytes given (stride >= 12 assumed for
    // the bound, so a core that read below 12 would still stay inside the buffer).
    const uint32_t step = c.stride < 12 ? 12 : c.stride;
    c.count = n >= 12 ? static_cast<uint32_t>((n - 12) / step + 1) : 0;
    c.xyz = c.null_data ? nullptr : reinterpret_cast<const float*>(g_points);
  } else {
    c.width = static_cast<uint16_t>(r.u8() % (kMaxDepthSide + 1));
    c.height = static_cast<uint16_t>(r.u8() % (kMaxDepthSide + 1));
    c.k.fx = r.f32();
    c.k.fy = r.f32();
    c.k.cx = r.f32();
    c.k.cy = r.f32();
    const uint8_t* src = nullptr;
    const size_t n = r.take(r.u16(), src);
    const size_t pixels = static_cast<size_t>(c.width) * c.height;
    for (size_t i = 0; i < pixels; ++i) {
      g_depth[i] = 2 * i + 1 < n ? static_cast<uint16_t>(src[2 * i] | (src[2 * i + 1] << 8)) : 0;
    }
  }
  return c;
}

// A target as the bytes give it: any kind byte, any floats.
fg::TargetSpec read_target(Reader& r) {
  fg::TargetSpec t;
  switch (r.u8() % 4u) {
    case 1:
      t.kind = fg::TargetKind::nearest_point;
      break;
    case 2:
      t.kind = fg::TargetKind::inside_box;
      break;
    case 3:
      t.kind = static_cast<fg::TargetKind>(r.u8());  // any byte, valid or not
      break;
    default:
      break;  // 0: by rule
  }
  for (int i = 0; i < 3; ++i) t.point(i) = r.f32();
  for (int i = 0; i < 3; ++i) t.box_min(i) = r.f32();
  for (int i = 0; i < 3; ++i) t.box_max(i) = r.f32();
  return t;
}

// After the plan: plan_object for a few indices of its list (out of range included),
// each followed by more_grasps on that object; their statuses go to st[ns..].
void object_calls(Reader& r, fg::Status* st, uint32_t& ns) {
  const uint32_t n = 1u + r.u8() % 4u;
  for (uint32_t i = 0; i < n; ++i) {
    const uint8_t index_byte = r.u8(), more_byte = r.u8();
    fg_fuzz::arm();
    const uint32_t k = index_byte == 0xFFu ? UINT32_MAX : index_byte % (g_planner.object_count() + 2u);
    st[ns++] = g_planner.plan_object(k, g_result);
    const uint32_t max = (more_byte & 31u) % (fg::kMaxRankedGrasps + 2u);
    (void)g_planner.more_grasps((more_byte & 128u) != 0 ? nullptr : g_more, max);
    fg_fuzz::disarm();
  }
}

// A call's points handed over in pieces of a few points each (the last may be shorter),
// each piece's coordinates in place in the payload; a null payload is a null piece. A
// source of an even number of points per piece can rewind (the hand's registration reads
// it twice), one of an odd number cannot.
class Pieces final : public fg::PointSource {
 public:
  explicit Pieces(const Call& c) : c_(c) {}
  bool can_rewind() const override { return c_.piece_points % 2u == 0u; }
  bool rewind() override {
    at_ = 0;
    return true;
  }
  bool next(fg::PointPiece& piece) override {
    piece = fg::PointPiece{};
    if (at_ >= c_.count) return true;
    const uint8_t* p = reinterpret_cast<const uint8_t*>(c_.xyz);
    const size_t off = static_cast<size_t>(at_) * c_.stride;
    piece.x = p == nullptr ? nullptr : p + off;
    piece.y = p == nullptr ? nullptr : p + off + 4;
    piece.z = p == nullptr ? nullptr : p + off + 8;
    piece.stride = c_.stride;
    piece.count = c_.count - at_ < c_.piece_points ? c_.count - at_ : c_.piece_points;
    at_ += piece.count;
    return true;
  }

 private:
  const Call& c_;
  uint32_t at_ = 0;
};

fg::Status run_call(const Call& c) {
  if (!c.depth && c.pieces) {
    Pieces src(c);
    return g_planner.add_point_source(c.role, src, c.pose);
  }
  if (!c.depth) return g_planner.add_points(c.role, c.xyz, c.count, c.stride, c.pose);
  return g_planner.add_depth_image(c.role, c.null_data ? nullptr : g_depth, c.width, c.height, c.k, c.pose);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const bool live = (fg_fuzz::guard_self_test(), true);
  (void)live;

  Reader r(data, size);
  fg::PlannerConfig cfg;
  const uint8_t cfg_byte = r.u8();
  apply_preset(cfg, cfg_byte & 7u);
  for (uint32_t i = 0; i < ((cfg_byte >> 3) & 7u); ++i) apply_override(cfg, r.u8(), r);
  const uint8_t flags = r.u8();
  const uint8_t view_byte = r.u8();
  const uint32_t blocks = flags & 3u;

  fg::Status st[16] = {};
  uint32_t ns = 0;
  fg_fuzz::arm();
  const char* field = nullptr;
  st[ns++] = g_planner.configure(cfg, &field);
  if (st[0] != fg::Status::ok) {
    // Never keep the previous input's configuration: each input runs on a fresh state.
    if (g_planner.configure(fg::PlannerConfig{}) != fg::Status::ok) std::abort();  // the defaults are always valid
  }
  g_planner.reset();
  // Nor the previous input's target: the default (always valid), then this input's.
  if (g_planner.set_target(fg::TargetSpec{}) != fg::Status::ok) std::abort();
  for (const fg::SensorRole role : {fg::SensorRole::head, fg::SensorRole::hand})  // nor its units
    if (g_planner.set_sensor_units(role, 1.f) != fg::Status::ok) std::abort();
  // The hand after the head is registered to it (A.4b), its cloud read twice, and the
  // clouds checked against each other (A.4c): the view byte's top bits choose the mode
  // (on twice as often as strict and off).
  const uint32_t mode = view_byte >> 6;
  g_planner.set_registration(mode == 3u   ? fg::RegistrationMode::off
                             : mode == 2u ? fg::RegistrationMode::strict
                                          : fg::RegistrationMode::on);
  fg_fuzz::disarm();
  if ((flags & 16u) != 0) {
    const fg::TargetSpec target = read_target(r);
    fg_fuzz::arm();
    st[ns++] = g_planner.set_target(target);
    fg_fuzz::disarm();
  }
  if ((flags & 128u) != 0) {
    const auto role = static_cast<fg::SensorRole>(r.u8() & 3u);
    const float metres_per_unit = r.f32();
    fg_fuzz::arm();
    st[ns++] = g_planner.set_sensor_units(role, metres_per_unit);
    fg_fuzz::disarm();
  }

  for (uint32_t b = 0; b < blocks; ++b) {
    const Call c = read_call(r);  // decoding (outside the core) is not guarded
    fg_fuzz::arm();
    st[ns++] = run_call(c);
    fg_fuzz::disarm();
  }

  fg_fuzz::arm();
  if ((flags & 64u) != 0) st[ns++] = g_planner.plan_object(0, g_result);  // invalid_sequence
  st[ns++] = g_planner.plan(g_result);
  if ((flags & 4u) != 0) st[ns++] = g_planner.plan(g_result);
  if ((flags & 8u) != 0) {
    const uint32_t views = g_planner.view_count();
    st[ns++] = g_planner.analyze_view((view_byte & 63u) % (views + 2), g_detail);
  }
  fg_fuzz::disarm();
  if ((flags & 32u) != 0) object_calls(r, st, ns);

  if (g_verbose) {
    std::fprintf(stderr, "plan_fuzz: config %s%s, statuses:", fg::to_string(st[0]), field != nullptr ? field : "");
    for (uint32_t i = 1; i < ns; ++i) std::fprintf(stderr, " %s", fg::to_string(st[i]));
    std::fprintf(stderr,
                 "; reason %s, %u input, %u kept, %u voxels, %u object, %u views, %u candidates; "
                 "%u objects (%u dropped), target %d\n",
                 fg::to_string(g_result.reason), g_result.points.input, g_result.points.after_filter,
                 g_result.points.voxels, g_result.points.object, g_result.viewpoints, g_result.candidates,
                 g_planner.object_count(), g_planner.objects_dropped(), g_planner.target_object());
  }
  return 0;
}
