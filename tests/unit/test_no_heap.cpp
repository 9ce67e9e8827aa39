// No heap on the planning path: every global operator new / delete (plain, array,
// nothrow, aligned, sized) is replaced here, and malloc / calloc / realloc / free /
// memalign / aligned_alloc / posix_memalign are defined here forwarding to glibc's
// __libc_* entry points, all counting while `armed` is set. A positive control
// proves the counters are live; then the counter is armed after the Planner is
// constructed and configured, and reset(), add_points() (and add_points_planar()) of a
// 640 x 480 organized cloud
// (table + box), add_depth_image() and plan() must not allocate. Nothing that may
// allocate (gtest assertions, std::string) runs while armed: counts go to plain
// variables and are checked after disarming.
//
// Under AddressSanitizer the allocator belongs to ASan: the replacements are compiled
// out and the tests skip.
#include <gtest/gtest.h>
#include <string.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <new>
#include <vector>

#include "fg/core/planner.hpp"
#include "synthetic_scene.hpp"

#if defined(__SANITIZE_ADDRESS__)
#define FG_TEST_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define FG_TEST_UNDER_ASAN 1
#endif
#endif
#ifndef FG_TEST_UNDER_ASAN
#define FG_TEST_UNDER_ASAN 0
#endif

namespace {

using fg::test::look_at;

// Single-threaded test: plain volatile counters are enough (and allocate nothing).
volatile bool g_armed = false;
volatile uint64_t g_new = 0;     // operator new / new[] (all variants)
volatile uint64_t g_delete = 0;  // operator delete / delete[] of a non-null pointer
volatile uint64_t g_malloc = 0;  // malloc, calloc, realloc, memalign family
volatile uint64_t g_free = 0;    // free of a non-null pointer

void* volatile g_sink = nullptr;  // keeps the positive control's allocations observable

}  // namespace

#if !FG_TEST_UNDER_ASAN

extern "C" {
void* __libc_malloc(size_t);
void* __libc_calloc(size_t, size_t);
void* __libc_realloc(void*, size_t);
void __libc_free(void*);
void* __libc_memalign(size_t, size_t);

void* malloc(size_t n) {
  if (g_armed) g_malloc = g_malloc + 1;
  return __libc_malloc(n);
}
void* calloc(size_t n, size_t s) {
  if (g_armed) g_malloc = g_malloc + 1;
  return __libc_calloc(n, s);
}
void* realloc(void* p, size_t n) {
  if (g_armed) g_malloc = g_malloc + 1;
  return __libc_realloc(p, n);
}
void free(void* p) {
  if (g_armed && p != nullptr) g_free = g_free + 1;
  __libc_free(p);
}
void* memalign(size_t a, size_t n) {
  if (g_armed) g_malloc = g_malloc + 1;
  return __libc_memalign(a, n);
}
void* aligned_alloc(size_t a, size_t n) {
  if (g_armed) g_malloc = g_malloc + 1;
  return __libc_memalign(a, n);
}
int posix_memalign(void** out, size_t a, size_t n) {
  if (g_armed) g_malloc = g_malloc + 1;
  if (a < sizeof(void*) || (a & (a - 1)) != 0) return 22;  // EINVAL
  void* p = __libc_memalign(a, n);
  if (p == nullptr && n != 0) return 12;  // ENOMEM
  *out = p;
  return 0;
}
}  // extern "C"

namespace {
void* counted_new(size_t n) {
  if (g_armed) g_new = g_new + 1;
  void* p = __libc_malloc(n == 0 ? 1 : n);
  return p;
}
void* counted_new_aligned(size_t n, std::align_val_t a) {
  if (g_armed) g_new = g_new + 1;
  size_t al = static_cast<size_t>(a);
  if (al < sizeof(void*)) al = sizeof(void*);
  return __libc_memalign(al, n == 0 ? 1 : n);
}
void counted_delete(void* p) {
  if (p == nullptr) return;
  if (g_armed) g_delete = g_delete + 1;
  __libc_free(p);
}
}  // namespace

void* operator new(size_t n) {
  void* p = counted_new(n);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}
void* operator new[](size_t n) {
  void* p = counted_new(n);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}
void* operator new(size_t n, const std::nothrow_t&) noexcept { return counted_new(n); }
void* operator new[](size_t n, const std::nothrow_t&) noexcept { return counted_new(n); }
void* operator new(size_t n, std::align_val_t a) {
  void* p = counted_new_aligned(n, a);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}
void* operator new[](size_t n, std::align_val_t a) {
  void* p = counted_new_aligned(n, a);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}
void* operator new(size_t n, std::align_val_t a, const std::nothrow_t&) noexcept { return counted_new_aligned(n, a); }
void* operator new[](size_t n, std::align_val_t a, const std::nothrow_t&) noexcept { return counted_new_aligned(n, a); }

void operator delete(void* p) noexcept { counted_delete(p); }
void operator delete[](void* p) noexcept { counted_delete(p); }
void operator delete(void* p, size_t) noexcept { counted_delete(p); }
void operator delete[](void* p, size_t) noexcept { counted_delete(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { counted_delete(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { counted_delete(p); }
void operator delete(void* p, std::align_val_t) noexcept { counted_delete(p); }
void operator delete[](void* p, std::align_val_t) noexcept { counted_delete(p); }
void operator delete(void* p, size_t, std::align_val_t) noexcept { counted_delete(p); }
void operator delete[](void* p, size_t, std::align_val_t) noexcept { counted_delete(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { counted_delete(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { counted_delete(p); }

#endif  // !FG_TEST_UNDER_ASAN

namespace {

using fg::PlannerConfig;
using fg::PlanResult;
using fg::Pose;
using fg::SensorRole;
using fg::Status;
using fg::Vec3;

struct Counts {
  uint64_t news = 0, deletes = 0, mallocs = 0, frees = 0;
  uint64_t total() const { return news + deletes + mallocs + frees; }
};

void arm() {
  g_new = 0;
  g_delete = 0;
  g_malloc = 0;
  g_free = 0;
  std::atomic_signal_fence(std::memory_order_seq_cst);
  g_armed = true;
  std::atomic_signal_fence(std::memory_order_seq_cst);
}

Counts disarm() {
  std::atomic_signal_fence(std::memory_order_seq_cst);
  g_armed = false;
  std::atomic_signal_fence(std::memory_order_seq_cst);
  Counts c;
  c.news = g_new;
  c.deletes = g_delete;
  c.mallocs = g_malloc;
  c.frees = g_free;
  return c;
}

#define SKIP_UNDER_ASAN()                                                                     \
  do {                                                                                        \
    if (FG_TEST_UNDER_ASAN) GTEST_SKIP() << "the allocator belongs to AddressSanitizer here"; \
  } while (0)

TEST(NoHeap, CountersAreLive) {
  SKIP_UNDER_ASAN();
  arm();
  int* p = new int(5);
  g_sink = p;
  void* m = std::malloc(16);
  g_sink = m;
  const Counts during = disarm();
  std::free(m);
  delete p;
  EXPECT_EQ(during.news, 1u);
  EXPECT_EQ(during.mallocs, 1u);
  EXPECT_EQ(during.deletes, 0u);
  EXPECT_EQ(during.frees, 0u);

  // Frees, arrays, aligned and nothrow forms are seen as well.
  int* q = new int[7];
  g_sink = q;
  void* m2 = std::malloc(32);
  g_sink = m2;
  struct alignas(64) Wide {
    float v[16];
  };
  arm();
  delete[] q;
  std::free(m2);
  Wide* w = new Wide;
  g_sink = w;
  int* nt = new (std::nothrow) int(1);
  g_sink = nt;
  void* c = std::calloc(4, 4);
  g_sink = c;
  void* r = std::realloc(nullptr, 8);
  g_sink = r;
  char* dup = strdup("abc");  // allocated inside libc: interposition covers libc's own calls
  g_sink = dup;
  const Counts second = disarm();
  delete w;
  delete nt;
  std::free(c);
  std::free(r);
  std::free(dup);
  EXPECT_EQ(second.deletes, 1u);
  EXPECT_EQ(second.frees, 1u);
  EXPECT_EQ(second.news, 2u);
  EXPECT_EQ(second.mallocs, 3u);
  // Disarmed: nothing counted.
  const uint64_t before = g_new + g_malloc;
  std::vector<int> v(100, 1);
  g_sink = v.data();
  EXPECT_EQ(g_new + g_malloc, before);
}

// ---------------------------------------------------------------------------------
// A table and a box rendered here by ray casting.

struct Camera {
  Pose pose;  // world_T_sensor
  fg::PinholeIntrinsics k;
  uint32_t w = 640, h = 480;
};

// Sensor-frame depth (z) of pixel (u, v), or a negative value for a miss. Table top:
// z = 0 over [0.1, 0.9] x [-0.4, 0.4]; box: [0.465, 0.535] x [-0.025, 0.025] x [0, 0.12].
double cast(const Camera& cam, uint32_t u, uint32_t v) {
  const Eigen::Vector3d ray_s((u - cam.k.cx) / cam.k.fx, (v - cam.k.cy) / cam.k.fy, 1.0);
  const Eigen::Vector3d d = cam.pose.R.cast<double>() * ray_s;
  const Eigen::Vector3d o = cam.pose.t.cast<double>();
  const Eigen::Vector3d lo(0.465, -0.025, 0.0), hi(0.535, 0.025, 0.12);
  double best = -1;
  double t0 = 0, t1 = 1e9;
  bool hit = true;
  for (int a = 0; a < 3 && hit; ++a) {
    if (std::fabs(d[a]) < 1e-12) {
      hit = o[a] >= lo[a] && o[a] <= hi[a];
      continue;
    }
    double ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    hit = t0 <= t1;
  }
  if (hit) best = t0;
  if (d.z() < 0) {
    const double tp = -o.z() / d.z();
    const Eigen::Vector3d p = o + d * tp;
    if ((best < 0 || tp < best) && p.x() > 0.1 && p.x() < 0.9 && std::fabs(p.y()) < 0.4) best = tp;
  }
  return best;
}

std::vector<float> organized_cloud(const Camera& cam) {
  std::vector<float> xyz(static_cast<size_t>(cam.w) * cam.h * 3, std::numeric_limits<float>::quiet_NaN());
  for (uint32_t v = 0; v < cam.h; ++v)
    for (uint32_t u = 0; u < cam.w; ++u) {
      const double z = cast(cam, u, v);
      if (z <= 0) continue;
      float* p = &xyz[(static_cast<size_t>(v) * cam.w + u) * 3];
      p[0] = static_cast<float>((u - cam.k.cx) / cam.k.fx * z);
      p[1] = static_cast<float>((v - cam.k.cy) / cam.k.fy * z);
      p[2] = static_cast<float>(z);
    }
  return xyz;
}

std::vector<uint16_t> depth_image(const Camera& cam) {
  std::vector<uint16_t> d(static_cast<size_t>(cam.w) * cam.h, 0);
  for (uint32_t v = 0; v < cam.h; ++v)
    for (uint32_t u = 0; u < cam.w; ++u) {
      const double z = cast(cam, u, v);
      if (z > 0) d[static_cast<size_t>(v) * cam.w + u] = static_cast<uint16_t>(std::lround(z * 1000.0));
    }
  return d;
}

struct CycleResult {
  Status reset_status = Status::ok, points = Status::internal_error, depth = Status::internal_error,
         plan = Status::internal_error;
  Counts counts;
};

// One armed cycle: reset, both sensors, plan. Nothing here allocates by itself.
CycleResult armed_cycle(fg::Planner& pl, const Camera& head, const std::vector<float>& cloud, const Camera& hand,
                        const std::vector<uint16_t>& depth, PlanResult& out) {
  CycleResult r;
  arm();
  pl.reset();
  r.points = pl.add_points(SensorRole::head, cloud.data(), head.w * head.h, 12, head.pose);
  r.depth = pl.add_depth_image(SensorRole::hand, depth.data(), static_cast<uint16_t>(hand.w),
                               static_cast<uint16_t>(hand.h), hand.k, hand.pose);
  r.plan = pl.plan(out);
  r.counts = disarm();
  return r;
}

TEST(NoHeap, PlanningAllocatesNothing) {
  SKIP_UNDER_ASAN();
  Camera head, hand;
  head.pose = look_at(Vec3(0.f, 0.f, 0.6f), Vec3(0.5f, 0.f, 0.05f));
  hand.pose = look_at(Vec3(0.5f, -0.45f, 0.45f), Vec3(0.5f, 0.f, 0.05f));
  const std::vector<float> cloud = organized_cloud(head);
  const std::vector<uint16_t> depth = depth_image(hand);

  auto pl = std::make_unique<fg::Planner>();
  ASSERT_EQ(pl->configure(PlannerConfig{}), Status::ok);
  PlanResult out;
  const CycleResult first = armed_cycle(*pl, head, cloud, hand, depth, out);
  EXPECT_EQ(first.points, Status::ok);
  EXPECT_EQ(first.depth, Status::ok);
  EXPECT_EQ(first.plan, Status::ok) << out.message;
  EXPECT_EQ(first.counts.news, 0u);
  EXPECT_EQ(first.counts.deletes, 0u);
  EXPECT_EQ(first.counts.mallocs, 0u);
  EXPECT_EQ(first.counts.frees, 0u);
  // The scene was seen: points, an object, viewpoints.
  EXPECT_GT(out.points.after_filter, 100000u);
  EXPECT_GT(out.points.object, 100u);
  EXPECT_GT(out.viewpoints, 0u);

  // A second cycle on the same planner, and failure paths (no input, bad arguments,
  // no grasp) allocate nothing either.
  const CycleResult second = armed_cycle(*pl, head, cloud, hand, depth, out);
  EXPECT_EQ(second.plan, first.plan);
  EXPECT_EQ(second.counts.total(), 0u);

  // The head's cloud as x, y and z arrays (add_points_planar) instead of triples.
  std::vector<float> planar(cloud.size());
  const size_t n = cloud.size() / 3;
  for (size_t i = 0; i < n; ++i)
    for (size_t k = 0; k < 3; ++k) planar[k * n + i] = cloud[i * 3 + k];
  arm();
  pl->reset();
  const Status planar_points = pl->add_points_planar(SensorRole::head, planar.data(), planar.data() + n,
                                                     planar.data() + 2 * n, static_cast<uint32_t>(n), head.pose);
  const Status planar_plan = pl->plan(out);
  EXPECT_EQ(disarm().total(), 0u);
  EXPECT_EQ(planar_points, Status::ok);
  EXPECT_EQ(planar_plan, Status::ok) << out.message;

  arm();
  pl->reset();
  const Status no_input = pl->plan(out);
  const Status bad = pl->add_points(SensorRole::head, nullptr, 5, 12, Pose{});
  Pose reflect;
  reflect.R = -fg::Mat3::Identity();
  const Status bad_pose = pl->add_points(SensorRole::head, cloud.data(), 10, 12, reflect);
  const float nan_xyz[6] = {std::numeric_limits<float>::quiet_NaN(), 0.f, 1.f, 0.5f, 0.f, 1.f};
  const Status few = pl->add_points(SensorRole::head, nan_xyz, 2, 12, Pose{});
  const Status one_point = pl->plan(out);
  const Counts failure_paths = disarm();
  EXPECT_EQ(no_input, Status::no_input);
  EXPECT_EQ(bad, Status::invalid_argument);
  EXPECT_EQ(bad_pose, Status::invalid_pose);
  EXPECT_EQ(few, Status::ok);
  EXPECT_EQ(one_point, Status::no_grasp);
  EXPECT_EQ(failure_paths.total(), 0u);

  // The hand's pose 12 cm off: the registration finds the clouds disagree (A.4c), leaves
  // the hand out, and in strict mode the plan fails; neither allocates.
  Camera far = hand;
  far.pose.t += Vec3(0.12f, 0.05f, 0.f);
  for (const fg::RegistrationMode mode : {fg::RegistrationMode::on, fg::RegistrationMode::strict}) {
    pl->set_registration(mode);
    const CycleResult off = armed_cycle(*pl, head, cloud, far, depth, out);
    EXPECT_EQ(out.registration.outcome, fg::RegistrationOutcome::sensor_disagreement);
    EXPECT_EQ(off.plan, mode == fg::RegistrationMode::strict ? Status::sensor_disagreement : Status::ok) << out.message;
    EXPECT_EQ(off.counts.total(), 0u);
  }
  pl->set_registration(fg::RegistrationMode::on);
  // The head's pose turned 7 degrees about its horizontal image axis: its table leans, the
  // hand's does not, and the head's points leave the grid (A.4c); no allocation either.
  Camera tilted = head;
  tilted.pose.R = head.pose.R * Eigen::AngleAxisf(7.f * 3.14159265f / 180.f, Vec3::UnitX()).toRotationMatrix();
  const CycleResult head_out = armed_cycle(*pl, tilted, cloud, hand, depth, out);
  EXPECT_EQ(out.registration.outcome, fg::RegistrationOutcome::sensor_disagreement);
  EXPECT_EQ(out.registration.left_out, SensorRole::head) << out.registration.head_tilt_deg;
  EXPECT_EQ(head_out.counts.total(), 0u);
}

TEST(NoHeap, ConfigureAndConstructionDoNotAllocateEither) {
  SKIP_UNDER_ASAN();
  // Construction in caller memory (placement) and configure() with a new config.
  std::unique_ptr<unsigned char[]> mem(new unsigned char[sizeof(fg::Planner) + alignof(fg::Planner)]);
  void* raw = mem.get();
  size_t space = sizeof(fg::Planner) + alignof(fg::Planner);
  void* at = std::align(alignof(fg::Planner), sizeof(fg::Planner), raw, space);
  ASSERT_NE(at, nullptr);
  PlannerConfig cfg;
  cfg.voxel_leaf_m = 0.004f;
  arm();
  fg::Planner* pl = ::new (at) fg::Planner();
  const Status s = pl->configure(cfg);
  const Counts c = disarm();
  EXPECT_EQ(s, Status::ok);
  EXPECT_EQ(c.total(), 0u);
  pl->~Planner();
}

}  // namespace
