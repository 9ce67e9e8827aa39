// Fuzz target: sequences of firmware C API calls (firmware_api/include/forcegrasp/
// forcegrasp.h) on two workspaces: any order, null pointers, undersized, misaligned or
// bogus workspace memory, raw config fields, raw roles, poses, points and depth images.
// Findings: crashes, sanitizer reports, hangs, heap use inside the API (the no-heap
// guard is armed around every call), and breaches of the API's promises checked below
// (a failed fg_init writes nothing and sets *out to NULL; refusals of bad memory have
// their own statuses; every status has a name; messages are never NULL; an FG_OK grasp
// is finite, with unit vectors and a width inside the gripper's opening; the object
// list fits its array and marks at most one target; fg_plan_object plans only for an
// index of the list).
//
// Input: a sequence of operations until the bytes run out (at most 64), each a u8 op
// code (modulo 13) and its arguments; bytes past the end read as 0.
//   0 init        u8 slot, u8 memory (bits 0-3 misalignment, bits 4-5 size: whole
//                 buffer / exactly fg_workspace_size() / one byte less / u16 * 64;
//                 bit 6 null memory, bit 7 null out), u8 config (0 default, 1 raw
//                 struct_size, 2 raw abi_version, 3 null, 4-7: 1-4 raw field overrides:
//                 u8 field, u32 value)
//   1 reset       u8 slot
//   2 add_points  u8 slot, i8 role, u8 flags (bit 0 null xyz, bit 1 null pose, bits 2-3
//                 pose: identity / 12 raw floats / looking down from a raw height /
//                 raw translation), u8 stride, u16 payload bytes, payload
//   3 add_depth   u8 slot, i8 role, u8 flags (bit 0 null image, bit 1 null pose, bits
//                 2-3 pose as above, bit 4 null intrinsics), u8 width % 65, u8 height % 65,
//                 4 raw floats fx fy cx cy, u16 payload bytes, payload (uint16 mm)
//   4 plan        u8 slot, u8 (bit 0: null output)
//   5 message     u8 slot
//   6 strings     i32 status, i32 reason
//   7 bogus       u8 variant: a call on NULL, zeroed bytes, the inside of a workspace,
//                 a byte copy of a workspace's header
//   8 check       u8 count % 5 raw field overrides on the defaults
//   9 task        u8 slot, u8 flags (bit 0 use_head, bit 1 use_hand, bit 2 null callback,
//                 bit 3 raw struct_size, bit 4 sensors fail, bit 5 arm refuses, bit 6 arm
//                 faults, bit 7 gripper closes on nothing), u8 steps, u8 extra: a grasp
//                 task on callback hardware (sensors replay the last depth payload with
//                 the last pose; the arm reaches each target in two ticks), stepped
//                 `steps` times, aborted when bit 0 of extra is set
//  10 target      u8 slot, u8 variant (modulo 4: 0 clear, 1 point, 2 box, 3 null
//                 pointers: point, box_min or box_max by bits 2-3), 9 raw floats: point,
//                 box_min, box_max (NaN, Inf, huge values, inverted boxes)
//  11 objects     u8 slot, u8 flags (bit 0 null array, bit 1 null count, bit 2 null
//                 dropped), u8 capacity (modulo FG_MAX_OBJECTS + 2: 0 included)
//  12 plan_object u8 slot, u8 index (0xFF: 2^32 - 1, else modulo the listed count + 2),
//                 u8 flags (bit 0 null output, bit 1 ranked, bits 2-5 capacity of the
//                 ranked array, 0 included)
// Slot 2 and 3 name no workspace (NULL), so calls on them test that path too.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "byte_reader.hpp"
#include "forcegrasp/forcegrasp.h"
#include "no_heap_guard.hpp"

namespace {

constexpr size_t kMemBytes = FG_WORKSPACE_SIZE + 64;
constexpr uint32_t kMaxDepthSide = 64;
constexpr size_t kMaxPayload = 65535;

alignas(64) unsigned char g_mem[2][kMemBytes];
fg_workspace* g_ws[4];  // slots 2, 3 stay NULL
alignas(16) unsigned char g_payload[kMaxPayload + 16];
uint16_t g_depth[kMaxDepthSide * kMaxDepthSide];
alignas(16) unsigned char g_junk[256];
const bool g_verbose = std::getenv("FG_FUZZ_API_VERBOSE") != nullptr;

using Reader = fg_fuzz::ByteReader;

[[noreturn]] void breach(const char* what, int status) {
  fg_fuzz::disarm();
  std::fprintf(stderr, "\n==fg-api== FINDING: %s (status %d)\n", what, status);
  std::abort();
}

// Every status an API call returns must be a named one.
fg_status named(fg_status s) {
  if (std::strcmp(fg_status_str(s), "FG_UNKNOWN_STATUS") == 0) breach("a call returned an unnamed status", s);
  return s;
}

// A raw write into any field of fg_config (floats and uint32 alike: 4 bytes each).
void override_field(fg_config& c, uint8_t index, uint32_t value) {
  static_assert(sizeof(fg_config) % 4 == 0, "fg_config is a sequence of 4-byte fields");
  const size_t fields = sizeof(fg_config) / 4;
  // Field 0 and 1 are struct_size and abi_version: the header ops reach those.
  const size_t k = 2 + index % (fields - 2);
  std::memcpy(reinterpret_cast<unsigned char*>(&c) + 4 * k, &value, 4);
}

fg_pose read_pose(uint32_t encoding, Reader& r) {
  fg_pose p = {{1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 0, 0}};
  switch (encoding) {
    case 0:
      p.t[0] = 0.5f;
      p.t[2] = 0.9f;
      break;  // identity rotation: looking up
    case 1:
      for (float& v : p.r) v = r.f32();
      for (float& v : p.t) v = r.f32();
      break;
    case 2: {  // looking straight down from a raw height above the workspace centre
      const float rd[9] = {1, 0, 0, 0, -1, 0, 0, 0, -1};
      std::memcpy(p.r, rd, sizeof rd);
      p.t[0] = 0.5f;
      p.t[2] = r.f32();
      break;
    }
    default:
      for (float& v : p.t) v = r.f32();
      break;
  }
  return p;
}

fg_workspace* slot_ws(uint8_t s) { return g_ws[s & 3u]; }

// A byte read as a signed one (two's complement): roles from -128 to 127.
int32_t i8(uint8_t b) { return b < 128u ? static_cast<int32_t>(b) : static_cast<int32_t>(b) - 256; }

// The last depth image decoded by op_add_depth: what the task's sensors replay.
struct LastImage {
  uint16_t width = 0, height = 0;
  fg_intrinsics k{};
  fg_pose pose = {{1, 0, 0, 0, 1, 0, 0, 0, 1}, {0.5f, 0.f, 0.9f}};
} g_last;

// Callback hardware for the task op: bounded, deterministic, no allocation.
struct FakeHw {
  uint8_t flags = 0;
  uint64_t t_us = 0;
  double q[6] = {}, target[6] = {};
  int arm_left = 0, grip_left = 0;
  bool contact = false;
  float width = 0.f;
} g_hw;

uint64_t hw_now(void* c) { return static_cast<FakeHw*>(c)->t_us; }
int32_t hw_request(void* c, int32_t) { return (static_cast<FakeHw*>(c)->flags & 16u) != 0 ? 1 : 0; }
int32_t hw_poll(void*, int32_t, fg_depth_frame* out) {
  out->depth_mm = g_depth;
  out->width = g_last.width;
  out->height = g_last.height;
  out->k = g_last.k;
  return FG_CAPTURE_READY;
}
int32_t hw_move(void* c, const double q[6], double) {
  FakeHw* h = static_cast<FakeHw*>(c);
  if ((h->flags & 32u) != 0) return 1;
  for (int i = 0; i < 6; ++i) h->target[i] = q[i];
  h->arm_left = 2;
  return 0;
}
int32_t hw_arm_read(void* c, fg_arm_state* out) {
  FakeHw* h = static_cast<FakeHw*>(c);
  if (h->arm_left > 0 && --h->arm_left == 0)
    for (int i = 0; i < 6; ++i) h->q[i] = h->target[i];
  for (int i = 0; i < 6; ++i) out->q[i] = h->q[i];
  out->moving = h->arm_left > 0 ? 1u : 0u;
  out->fault = (h->flags & 64u) != 0 && h->arm_left > 0 ? 1u : 0u;
  return 0;
}
void hw_stop(void* c) { static_cast<FakeHw*>(c)->arm_left = 0; }
int32_t hw_open(void* c, float w) {
  FakeHw* h = static_cast<FakeHw*>(c);
  h->width = w;
  h->grip_left = 1;
  h->contact = false;
  return 0;
}
int32_t hw_close(void* c, float) {
  FakeHw* h = static_cast<FakeHw*>(c);
  h->contact = (h->flags & 128u) == 0;
  h->width = h->contact ? 0.04f : 0.f;
  h->grip_left = 1;
  return 0;
}
int32_t hw_grip_read(void* c, fg_gripper_state* out) {
  FakeHw* h = static_cast<FakeHw*>(c);
  if (h->grip_left > 0) --h->grip_left;
  out->width_m = h->width;
  out->moving = h->grip_left > 0 ? 1u : 0u;
  out->contact = h->contact && h->grip_left == 0 ? 1u : 0u;
  out->fault = 0;
  return 0;
}

void op_task(Reader& r) {
  fg_workspace* ws = slot_ws(r.u8());
  const uint8_t flags = r.u8(), steps = r.u8(), extra = r.u8();
  g_hw = FakeHw{};
  g_hw.flags = flags;
  fg_hal_ops ops = {&g_hw, hw_now, hw_request, hw_poll, hw_move, hw_arm_read, hw_stop, hw_open, hw_close, hw_grip_read};
  if ((flags & 4u) != 0) ops.gripper_read = nullptr;
  fg_task_config tc;
  if (fg_task_config_default(&tc) != FG_OK) std::abort();  // the defaults are always valid
  tc.world_T_head = g_last.pose;
  tc.tool0_T_hand = g_last.pose;
  tc.use_head = flags & 1u;
  tc.use_hand = (flags >> 1) & 1u;
  if ((flags & 8u) != 0) tc.struct_size = extra;
  fg_fuzz::arm();
  const fg_status s = named(fg_task_start(ws, &tc, &ops));
  fg_fuzz::disarm();
  for (uint32_t i = 0; i < steps; ++i) {
    fg_task_status st;
    fg_fuzz::arm();
    const fg_status k = named(fg_task_step(ws, &st));
    fg_fuzz::disarm();
    if ((k == FG_OK) != (s == FG_OK)) breach("fg_task_step disagrees with fg_task_start", k);
    if (k != FG_OK) break;
    if (st.state < FG_TASK_IDLE || st.state > FG_TASK_FAILED) breach("task state out of range", st.state);
    if (st.state == FG_TASK_SUCCEEDED)
      for (int j = 0; j < 6; ++j)
        if (!std::isfinite(st.q_grasp[j]) || !std::isfinite(st.q_lift[j])) breach("non-finite joint target", 0);
    if (g_verbose && (st.state == FG_TASK_SUCCEEDED || st.state == FG_TASK_FAILED))
      std::fprintf(stderr, "api_fuzz: task %s, failure %d after %u ticks\n",
                   st.state == FG_TASK_SUCCEEDED ? "succeeded" : "failed", st.failure, st.ticks);
    if (st.state == FG_TASK_SUCCEEDED || st.state == FG_TASK_FAILED) break;
    g_hw.t_us += 8000;
    if ((extra & 1u) != 0 && i == steps / 2u) {
      fg_fuzz::arm();
      named(fg_task_abort(ws));
      fg_fuzz::disarm();
    }
  }
}

void op_init(Reader& r) {
  const uint8_t slot = r.u8() & 1u, mem = r.u8(), cfgv = r.u8();
  const size_t offset = mem & 15u;
  size_t size = kMemBytes - offset;
  switch ((mem >> 4) & 3u) {
    case 1:
      size = fg_workspace_size();
      break;
    case 2:
      size = fg_workspace_size() - 1;
      break;
    case 3:
      size = static_cast<size_t>(r.u16()) * 64u;
      break;
    default:
      break;
  }
  if (size > kMemBytes - offset) size = kMemBytes - offset;
  unsigned char* memory = (mem & 64u) != 0 ? nullptr : g_mem[slot] + offset;
  fg_config cfg;
  if (fg_config_default(&cfg) != FG_OK) std::abort();  // the defaults are always valid
  const fg_config* cfgp = &cfg;
  const uint32_t v = cfgv & 7u;
  if (v == 1) cfg.struct_size = r.u32();
  if (v == 2) cfg.abi_version = r.u32();
  if (v == 3) cfgp = nullptr;
  for (uint32_t i = 0; v >= 4 && i < v - 3; ++i) {
    const uint8_t f = r.u8();
    override_field(cfg, f, r.u32());
  }
  unsigned char before[64];
  if (memory != nullptr) std::memcpy(before, memory, sizeof before);
  fg_workspace* out = reinterpret_cast<fg_workspace*>(g_junk);  // must become NULL on failure
  fg_workspace** outp = (mem & 128u) != 0 ? nullptr : &out;
  g_ws[slot] = nullptr;
  fg_fuzz::arm();
  const fg_status s = named(fg_init(memory, size, cfgp, outp));
  fg_fuzz::disarm();
  if (s == FG_OK) {
    if (memory == nullptr || outp == nullptr || (offset % FG_WORKSPACE_ALIGN) != 0 || size < fg_workspace_size())
      breach("fg_init accepted bad memory", s);
    if (static_cast<void*>(out) != static_cast<void*>(memory))
      breach("fg_init's workspace is not at the memory given", s);
    g_ws[slot] = out;
    return;
  }
  if (outp != nullptr && out != nullptr) breach("a failed fg_init left *out non-NULL", s);
  if (memory != nullptr && std::memcmp(before, memory, sizeof before) != 0)
    breach("a failed fg_init wrote into the memory", s);
  if (memory != nullptr && outp != nullptr && cfgp != nullptr) {
    if ((offset % FG_WORKSPACE_ALIGN) != 0 && s != FG_ERR_WORKSPACE_MISALIGNED)
      breach("misaligned memory not reported as FG_ERR_WORKSPACE_MISALIGNED", s);
    if ((offset % FG_WORKSPACE_ALIGN) == 0 && size < fg_workspace_size() && s != FG_ERR_WORKSPACE_TOO_SMALL)
      breach("undersized memory not reported as FG_ERR_WORKSPACE_TOO_SMALL", s);
  }
}

void op_add_points(Reader& r) {
  fg_workspace* ws = slot_ws(r.u8());
  const int32_t role = i8(r.u8());
  const uint8_t flags = r.u8();
  const fg_pose pose = read_pose((flags >> 2) & 3u, r);
  const size_t stride = r.u8();
  const uint8_t* src = nullptr;
  const size_t n = r.take(r.u16(), src);
  std::memcpy(g_payload, src, n);
  // An honest count: every point lies inside the bytes given.
  const size_t step = stride < 12 ? 12 : stride;
  const size_t count = n >= 12 ? (n - 12) / step + 1 : 0;
  const float* xyz = (flags & 1u) != 0 ? nullptr : reinterpret_cast<const float*>(g_payload);
  fg_fuzz::arm();
  named(fg_add_points(ws, role, xyz, count, stride, (flags & 2u) != 0 ? nullptr : &pose));
  fg_fuzz::disarm();
}

void op_add_depth(Reader& r) {
  fg_workspace* ws = slot_ws(r.u8());
  const int32_t role = i8(r.u8());
  const uint8_t flags = r.u8();
  const fg_pose pose = read_pose((flags >> 2) & 3u, r);
  const uint16_t w = static_cast<uint16_t>(r.u8() % (kMaxDepthSide + 1));
  const uint16_t h = static_cast<uint16_t>(r.u8() % (kMaxDepthSide + 1));
  fg_intrinsics k;
  k.fx = r.f32();
  k.fy = r.f32();
  k.cx = r.f32();
  k.cy = r.f32();
  const uint8_t* src = nullptr;
  const size_t n = r.take(r.u16(), src);
  for (size_t i = 0; i < static_cast<size_t>(w) * h; ++i)
    g_depth[i] = 2 * i + 1 < n ? static_cast<uint16_t>(src[2 * i] | (src[2 * i + 1] << 8)) : 0;
  g_last.width = w;
  g_last.height = h;
  g_last.k = k;
  g_last.pose = pose;
  fg_fuzz::arm();
  named(fg_add_depth_image(ws, role, (flags & 1u) != 0 ? nullptr : g_depth, w, h, (flags & 16u) != 0 ? nullptr : &k,
                           (flags & 2u) != 0 ? nullptr : &pose));
  fg_fuzz::disarm();
}

bool unit(const float v[3]) {
  const float n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return std::fabs(n - 1.f) < 1e-3f;
}

// An FG_OK grasp: finite, with unit vectors and a width inside any opening.
void check_grasp(const fg_grasp& g, fg_status s) {
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(g.position[i]) || !std::isfinite(g.pregrasp[i])) breach("non-finite grasp position", s);
  if (!unit(g.approach) || !unit(g.closing)) breach("grasp directions are not unit vectors", s);
  if (!(g.width_m >= 0.f && g.width_m <= 0.5f)) breach("grasp width outside any opening", s);
}

void op_plan(Reader& r) {
  fg_workspace* ws = slot_ws(r.u8());
  const bool null_out = (r.u8() & 1u) != 0;
  fg_grasp g;
  fg_fuzz::arm();
  const fg_status s = named(fg_plan(ws, null_out ? nullptr : &g));
  fg_fuzz::disarm();
  if (g_verbose) std::fprintf(stderr, "api_fuzz: plan %s\n", fg_status_str(s));
  // The advice after it: finite when given, zero throughout when not; after a plan that
  // ran (ok or no_grasp), given only for a refusal as occluded.
  fg_look_advice_result look;
  fg_fuzz::arm();
  const fg_status ls = named(fg_look_advice(ws, null_out ? nullptr : &look));  // no byte more read
  fg_fuzz::disarm();
  if (null_out && ls == FG_OK) breach("a null look advice output was accepted", ls);
  if (ls == FG_OK) {
    const bool planned = (s == FG_OK || s == FG_NO_GRASP) && !null_out;
    if (look.valid != 0 && look.valid != 1) breach("look advice neither valid nor not", s);
    if (planned && look.valid != 0 && !(s == FG_NO_GRASP && g.reason == FG_REASON_OCCLUDED))
      breach("look advice outside a refusal as occluded", s);
    for (int i = 0; i < 3; ++i) {
      if (look.valid != 0 && !(std::isfinite(look.at[i]) && std::isfinite(look.from[i])))
        breach("non-finite look advice", s);
      if (look.valid == 0 && (look.at[i] != 0.f || look.from[i] != 0.f)) breach("look advice without valid", s);
    }
  }
  if (s != FG_OK) return;
  if (null_out) breach("fg_plan returned FG_OK without an output", s);
  check_grasp(g, s);
}

void op_target(Reader& r) {
  fg_workspace* ws = slot_ws(r.u8());
  const uint8_t variant = r.u8();
  float v[9];
  for (float& f : v) f = r.f32();
  const float* point = v;
  const float* box_min = v + 3;
  const float* box_max = v + 6;
  if (variant % 4u == 3u) {  // a null pointer in place of one of them
    const uint32_t which = (variant >> 2) % 3u;
    if (which == 0) point = nullptr;
    if (which == 1) box_min = nullptr;
    if (which == 2) box_max = nullptr;
  }
  fg_fuzz::arm();
  fg_status s = FG_OK;
  if (variant % 4u == 0u) {
    s = named(fg_clear_target(ws));
  } else if (variant % 4u == 1u || (variant % 4u == 3u && point == nullptr)) {
    s = named(fg_set_target_point(ws, point));
  } else {
    s = named(fg_set_target_box(ws, box_min, box_max));
  }
  fg_fuzz::disarm();
  if (ws != nullptr && variant % 4u == 3u && s != FG_ERR_INVALID_ARGUMENT)
    breach("a null target pointer was not refused", s);
}

// The list of objects as fg_objects gives it to an array of `capacity`; FG_OK or a refusal.
fg_status list_objects(fg_workspace* ws, fg_object* out, uint32_t capacity, uint32_t* count, uint32_t* dropped) {
  fg_fuzz::arm();
  const fg_status s = named(fg_objects(ws, out, capacity, count, dropped));
  fg_fuzz::disarm();
  if (s != FG_OK) return s;
  if (*count > capacity || *count > FG_MAX_OBJECTS) breach("fg_objects wrote more than its array holds", s);
  uint32_t targets = 0;
  for (uint32_t k = 0; k < *count; ++k) {
    const fg_object& o = out[k];
    if (o.is_target > 1u) breach("is_target is neither 0 nor 1", s);
    targets += o.is_target;
    if (o.voxels == 0) breach("a listed object has no voxel", s);
    for (int i = 0; i < 3; ++i)
      if (!std::isfinite(o.centroid[i]) || !(o.box_min[i] <= o.box_max[i])) breach("an object's box is malformed", s);
  }
  if (targets > 1u) breach("more than one object marked as the target", s);
  return s;
}

fg_object g_objects[FG_MAX_OBJECTS + 2];
fg_grasp g_ranked[16];

void op_objects(Reader& r) {
  fg_workspace* ws = slot_ws(r.u8());
  const uint8_t flags = r.u8();
  const uint32_t capacity = r.u8() % (FG_MAX_OBJECTS + 2u);
  uint32_t count = 0, dropped = 0;
  const fg_status s = list_objects(ws, (flags & 1u) != 0 ? nullptr : g_objects, capacity,
                                   (flags & 2u) != 0 ? nullptr : &count, (flags & 4u) != 0 ? nullptr : &dropped);
  const bool bad = (flags & 3u) != 0 || capacity == 0;
  if (ws != nullptr && bad != (s == FG_ERR_INVALID_ARGUMENT))
    breach("fg_objects' refusal disagrees with its arguments", s);
}

void op_plan_object(Reader& r) {
  fg_workspace* ws = slot_ws(r.u8());
  const uint8_t index_byte = r.u8(), flags = r.u8();
  uint32_t listed = 0;
  if (list_objects(ws, g_objects, FG_MAX_OBJECTS, &listed, nullptr) != FG_OK) listed = 0;
  const uint32_t index = index_byte == 0xFFu ? UINT32_MAX : index_byte % (listed + 2u);
  const bool null_out = (flags & 1u) != 0;
  const uint32_t capacity = (flags >> 2) & 15u;
  uint32_t count = 99;
  fg_fuzz::arm();
  const fg_status s = (flags & 2u) != 0
                          ? named(fg_plan_object_ranked(ws, index, null_out ? nullptr : g_ranked, capacity, &count))
                          : named(fg_plan_object(ws, index, null_out ? nullptr : g_ranked));
  fg_fuzz::disarm();
  if (g_verbose) std::fprintf(stderr, "api_fuzz: plan_object %u of %u: %s\n", index, listed, fg_status_str(s));
  if (ws != nullptr && (flags & 2u) != 0 && s != FG_OK && count != 0) breach("a refused ranked plan left a count", s);
  if (s != FG_OK) return;
  if (null_out) breach("fg_plan_object returned FG_OK without an output", s);
  if (index >= listed) breach("fg_plan_object planned for an index beyond the list", s);
  const uint32_t n = (flags & 2u) != 0 ? count : 1u;
  if (n == 0 || n > FG_MAX_RANKED_GRASPS || ((flags & 2u) != 0 && n > capacity))
    breach("the ranked count is out of its bounds", s);
  for (uint32_t i = 0; i < n; ++i) check_grasp(g_ranked[i], s);
}

void op_bogus(Reader& r) {
  const uint8_t v = r.u8() % 4u;
  fg_workspace* ws = nullptr;
  if (v == 1) {
    std::memset(g_junk, 0, sizeof g_junk);
    ws = reinterpret_cast<fg_workspace*>(g_junk);
  } else if (v == 2) {
    ws = reinterpret_cast<fg_workspace*>(g_mem[0] + 16);
  } else if (v == 3) {
    std::memcpy(g_junk, g_mem[0], sizeof g_junk);  // a copy names a magic but not itself
    ws = reinterpret_cast<fg_workspace*>(g_junk);
  }
  fg_grasp g;
  const fg_pose pose = {{1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 0, 0}};
  const float xyz[3] = {0.5f, 0.f, 0.5f};
  fg_fuzz::arm();
  const fg_status a = fg_plan(ws, &g), b = fg_reset(ws);
  const fg_status c = fg_add_points(ws, FG_SENSOR_HEAD, xyz, 1, 12, &pose);
  const char* m = fg_last_message(ws);
  // The target and object calls likewise.
  fg_object objects[2];
  uint32_t n = 0;
  const fg_status d[] = {fg_set_target_point(ws, xyz), fg_set_target_box(ws, xyz, xyz),
                         fg_clear_target(ws),          fg_objects(ws, objects, 2, &n, nullptr),
                         fg_plan_object(ws, 0, &g),    fg_plan_object_ranked(ws, 0, &g, 1, &n)};
  fg_fuzz::disarm();
  if (a != FG_ERR_NOT_A_WORKSPACE || b != FG_ERR_NOT_A_WORKSPACE || c != FG_ERR_NOT_A_WORKSPACE)
    breach("a call on memory that is no workspace was not refused", a);
  for (const fg_status e : d)
    if (e != FG_ERR_NOT_A_WORKSPACE)
      breach("a target or object call on memory that is no workspace was not refused", e);
  if (m == nullptr) breach("fg_last_message returned NULL", 0);
}

void op_check(Reader& r) {
  fg_config cfg;
  if (fg_config_default(&cfg) != FG_OK) std::abort();  // the defaults are always valid
  const uint32_t n = r.u8() % 5u;
  for (uint32_t i = 0; i < n; ++i) {
    const uint8_t f = r.u8();
    override_field(cfg, f, r.u32());
  }
  const char* field = nullptr;
  fg_fuzz::arm();
  const fg_status s = named(fg_config_check(&cfg, &field));
  fg_fuzz::disarm();
  if (field == nullptr) breach("fg_config_check left the field name NULL", s);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const bool live = (fg_fuzz::guard_self_test(), true);
  (void)live;
  // Each input starts without workspaces, and no stale one in the buffers either.
  for (auto& ws : g_ws) ws = nullptr;
  g_last = LastImage{};
  for (auto& m : g_mem) std::memset(m, 0, 256);

  Reader r(data, size);
  for (int op = 0; op < 64 && !r.done(); ++op) {
    switch (r.u8() % 13u) {
      case 0:
        op_init(r);
        break;
      case 1: {
        fg_workspace* ws = slot_ws(r.u8());
        fg_fuzz::arm();
        named(fg_reset(ws));
        fg_fuzz::disarm();
        break;
      }
      case 2:
        op_add_points(r);
        break;
      case 3:
        op_add_depth(r);
        break;
      case 4:
        op_plan(r);
        break;
      case 5: {
        fg_workspace* ws = slot_ws(r.u8());
        fg_fuzz::arm();
        const char* m = fg_last_message(ws);
        fg_fuzz::disarm();
        if (m == nullptr) breach("fg_last_message returned NULL", 0);
        break;
      }
      case 6: {
        const int32_t s = static_cast<int32_t>(r.u32()), reason = static_cast<int32_t>(r.u32());
        if (fg_status_str(s) == nullptr || fg_reason_str(reason) == nullptr)
          breach("a string function returned NULL", s);
        break;
      }
      case 7:
        op_bogus(r);
        break;
      case 8:
        op_check(r);
        break;
      case 9:
        op_task(r);
        break;
      case 10:
        op_target(r);
        break;
      case 11:
        op_objects(r);
        break;
      default:
        op_plan_object(r);
        break;
    }
  }
  return 0;
}
