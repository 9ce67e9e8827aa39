#include "fg/core/cluster.hpp"

#include <cstring>

#include "fg/core/byte_order.hpp"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define FG_CLUSTER_AVX2 1
#include <immintrin.h>
#else
#define FG_CLUSTER_AVX2 0
#endif

namespace fg {

namespace detail {
uint32_t filter_mask_scalar(const VoxelGrid::LookupFilter& f, uint64_t kh, const uint64_t* oh, uint32_t n) {
  uint32_t out = 0;
  for (uint32_t o = 0; o < n; ++o)
    if (f.may_hold(kh + oh[o])) out |= 1u << o;
  return out;
}

#if FG_CLUSTER_AVX2
// may_hold()'s arithmetic, four hashes per step: the 64-bit multiply of filter_mix from
// 32-bit halves (AVX2 multiplies 32 x 32 -> 64 bits only; the same product mod 2^64),
// the two bits by variable shifts, the four words gathered. The hash array is read in
// whole steps of four (the caller pads it); bits at and past n are cleared.
__attribute__((target("avx2"))) uint32_t filter_mask_avx2(const VoxelGrid::LookupFilter& f, uint64_t kh,
                                                          const uint64_t* oh, uint32_t n) {
  const uint64_t mul = VoxelGrid::kFilterMixMul;
  const __m256i vkh = _mm256_set1_epi64x(static_cast<long long>(kh));
  const __m256i mul_lo = _mm256_set1_epi64x(static_cast<long long>(mul & 0xFFFFFFFFu));
  const __m256i mul_hi = _mm256_set1_epi64x(static_cast<long long>(mul >> 32));
  const __m256i six_bits = _mm256_set1_epi64x(63), one = _mm256_set1_epi64x(1);
  const __m128i shift = _mm_cvtsi32_si128(static_cast<int>(f.shift));
  const long long* const words = reinterpret_cast<const long long*>(f.words);
  uint32_t out = 0;
  for (uint32_t o = 0; o < n; o += 4) {
    const __m256i h = _mm256_add_epi64(vkh, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(oh + o)));
    const __m256i a = _mm256_xor_si256(h, _mm256_srli_epi64(h, 32));
    const __m256i cross =
        _mm256_add_epi64(_mm256_mul_epu32(_mm256_srli_epi64(a, 32), mul_lo), _mm256_mul_epu32(a, mul_hi));
    const __m256i g = _mm256_add_epi64(_mm256_mul_epu32(a, mul_lo), _mm256_slli_epi64(cross, 32));
    const __m256i m = _mm256_or_si256(_mm256_sllv_epi64(one, _mm256_and_si256(_mm256_srli_epi64(g, 32), six_bits)),
                                      _mm256_sllv_epi64(one, _mm256_and_si256(_mm256_srli_epi64(g, 26), six_bits)));
    const __m256i w = _mm256_i64gather_epi64(words, _mm256_srl_epi64(g, shift), 8);
    const __m256i hit = _mm256_cmpeq_epi64(_mm256_and_si256(w, m), m);
    out |= static_cast<uint32_t>(_mm256_movemask_pd(_mm256_castsi256_pd(hit))) << o;
  }
  return n >= 32u ? out : out & ((1u << n) - 1u);
}
#endif

bool filter_mask_vector_available() {
#if FG_CLUSTER_AVX2
  __builtin_cpu_init();  // idempotent
  return __builtin_cpu_supports("avx2") != 0;
#else
  return false;
#endif
}

uint32_t filter_mask_vector(const VoxelGrid::LookupFilter& f, uint64_t kh, const uint64_t* oh, uint32_t n) {
#if FG_CLUSTER_AVX2
  return filter_mask_avx2(f, kh, oh, n);
#else
  return filter_mask_scalar(f, kh, oh, n);
#endif
}
}  // namespace detail

namespace {
struct Offset {
  uint32_t delta;     // pack(dx, dy, dz) in two's complement per field, summed
  int8_t dx, dy, dz;  // the offset itself (the bitmap's step, flood_bits)
  uint64_t hash;      // VoxelGrid::filter_hash_of_offset of the signed sum
};
// Offsets within 2 cells: 32 (26 within 1).
constexpr uint32_t kMaxOffsets = 32;
// The offsets' filter hashes on their own, zero-padded to a whole vector step.
struct OffsetHashes {
  alignas(32) uint64_t h[kMaxOffsets] = {};
};
static_assert(kMaxOffsets % 4 == 0 && kMaxOffsets <= 32, "whole steps of four; one mask bit per offset");

// Neighbour offsets within `cells` (Euclidean in cell units, so 1 -> 26, 2 -> 32).
uint32_t make_offsets(uint32_t cells, Offset* out, OffsetHashes& hashes) {
  const int32_t r = static_cast<int32_t>(cells);
  uint32_t n = 0;
  for (int32_t dz = -r; dz <= r; ++dz)
    for (int32_t dy = -r; dy <= r; ++dy)
      for (int32_t dx = -r; dx <= r; ++dx) {
        const int32_t d2 = dx * dx + dy * dy + dz * dz;
        if (d2 == 0) continue;
        if (r > 1 && d2 > r * r) continue;
        out[n++] =
            Offset{static_cast<uint32_t>(dx) + (static_cast<uint32_t>(dy) << 11) + (static_cast<uint32_t>(dz) << 22),
                   static_cast<int8_t>(dx), static_cast<int8_t>(dy), static_cast<int8_t>(dz),
                   VoxelGrid::filter_hash_of_offset(dx + dy * (int64_t{1} << 11) + dz * (int64_t{1} << 22))};
        hashes.h[n - 1] = out[n - 1].hash;
      }
  return n;
}

// What a walk gathers: the sums of its voxels' centroids, the box of its cells (key
// indices), and, with a probe (a target point or box), the least squared distance of a
// centroid to the point or the count of centroids inside the box.
struct Walk {
  const TargetSpec* probe = nullptr;  // kept by start()
  float sum_x = 0.f, sum_y = 0.f, sum_z = 0.f;
  uint32_t x0 = 0xFFFFFFFFu, x1 = 0, y0 = 0xFFFFFFFFu, y1 = 0, z0 = 0xFFFFFFFFu, z1 = 0;
  float near_d2 = 0.f;
  uint32_t inside = 0;
  void start() {
    const TargetSpec* p = probe;
    *this = Walk{};
    probe = p;
    near_d2 = 3.0e38f;
  }
  // Takes voxel i into the sums, the box and the probe; returns its key.
  uint32_t add(const VoxelGrid& grid, uint32_t i) {
    const Vec3 c = grid.centroid(i);
    sum_x += c.x();
    sum_y += c.y();
    sum_z += c.z();
    if (probe != nullptr) {
      if (probe->kind == TargetKind::nearest_point) {
        const float d2 = (c - probe->point).squaredNorm();
        near_d2 = d2 < near_d2 ? d2 : near_d2;
      } else {
        const bool in = (c.array() >= probe->box_min.array()).all() && (c.array() <= probe->box_max.array()).all();
        inside += in ? 1u : 0u;
      }
    }
    const uint32_t k = grid.key(i);
    const uint32_t kx = VoxelGrid::key_x(k), ky = VoxelGrid::key_y(k), kz = VoxelGrid::key_z(k);
    x0 = kx < x0 ? kx : x0;
    x1 = kx > x1 ? kx : x1;
    y0 = ky < y0 ? ky : y0;
    y1 = ky > y1 ? ky : y1;
    z0 = kz < z0 ? kz : z0;
    z1 = kz > z1 ? kz : z1;
    return k;
  }
};

// Breadth-first walk of the component of `seed` through the voxels in state `from`;
// marks it `mark` (!= from); returns its size and leaves its voxels in queue[0, size).
uint32_t flood(const VoxelGrid& grid, uint8_t* state, uint32_t* queue, uint32_t seed, const Offset* off,
               const OffsetHashes& hashes, uint32_t n_off, uint8_t from, uint8_t mark, Walk& w) {
  uint32_t head = 0, tail = 0;
  queue[tail++] = seed;
  state[seed] = mark;
  w.start();
  const VoxelGrid::LookupFilter filter = grid.lookup_filter();
  // The filter's verdicts on all the neighbours at once where the CPU has AVX2 (about
  // 9 instructions a test, the call included, instead of 23: the worst case, isolated
  // voxels up to kMaxVoxels whose cells the bitmap cannot hold, is 32 tests a voxel);
  // the same neighbours in the same order either way.
  const bool vector = filter.words != nullptr && detail::filter_mask_vector_available();
  while (head < tail) {  // bounded: each voxel enters the queue at most once
    // A neighbour's key is the packed sum: inserted cells keep a 2-cell margin inside
    // each field's range, so no field under- or overflows into the next.
    // The filter's hash of a neighbour is a sum too (voxel_grid.hpp).
    const uint32_t k = w.add(grid, queue[head++]);
    const uint64_t kh = VoxelGrid::filter_hash(k);
    const auto visit = [&](uint32_t o) {
      const uint32_t j = grid.find_in_table(k + off[o].delta);
      if (j == VoxelGrid::kNone || state[j] != from) return;
      state[j] = mark;
      queue[tail++] = j;
    };
    if (vector) {
      for (uint32_t maybe = detail::filter_mask_vector(filter, kh, hashes.h, n_off); maybe != 0u; maybe &= maybe - 1u)
        visit(static_cast<uint32_t>(__builtin_ctz(maybe)));
      continue;
    }
    for (uint32_t o = 0; o < n_off; ++o) {
      if (filter.words != nullptr && !filter.may_hold(kh + hashes.h[o])) continue;  // most absent cells
      visit(o);
    }
  }
  return tail;
}

// flood() over a bitmap of the cells in state `from` (build_cell_bitmap): a neighbour
// is entered when its bit is set, and its bit is cleared as its state becomes `mark`,
// so the bits are the voxels flood() would enter and the walk visits them in the same
// order. `lin`: each offset as a step in the bitmap.
uint32_t flood_bits(const VoxelGrid& grid, uint8_t* state, uint32_t* queue, uint32_t seed, const Offset* off,
                    const int32_t* lin, uint32_t n_off, CellBitmap& bits, uint8_t mark, Walk& w) {
  uint32_t head = 0, tail = 0;
  queue[tail++] = seed;
  state[seed] = mark;
  uint64_t* const words = bits.words;
  {
    const uint32_t c = bits.cell(grid.key(seed));
    words[c >> 6] &= ~(uint64_t{1} << (c & 63u));
  }
  w.start();
  while (head < tail) {  // bounded: each voxel enters the queue at most once
    const uint32_t k = w.add(grid, queue[head++]);
    const int32_t base = static_cast<int32_t>(bits.cell(k));
    for (uint32_t o = 0; o < n_off; ++o) {
      const uint32_t cell = static_cast<uint32_t>(base + lin[o]);
      const uint64_t bit = uint64_t{1} << (cell & 63u);
      if ((words[cell >> 6] & bit) == 0u) continue;  // empty, or walked already
      words[cell >> 6] &= ~bit;
      const uint32_t j = grid.find_in_table(k + off[o].delta);
      if (j == VoxelGrid::kNone) continue;  // a voxel of this state the index does not hold
      state[j] = mark;
      queue[tail++] = j;
    }
  }
  return tail;
}

// The first voxel at or after i whose state is s, or n: eight states per step (the
// plan's few object voxels lie scattered among the table's). A byte of w ^ (s in every
// byte) is zero where the state is s; the lowest byte the zero-byte test flags is
// always one (bytes above a zero byte may be flagged falsely, never the lowest).
uint32_t next_in_state(const uint8_t* state, uint32_t n, uint32_t i, uint8_t s) {
  constexpr uint64_t kOnes = 0x0101010101010101ull;
  for (; i < n && (i & 7u) != 0u; ++i)
    if (state[i] == s) return i;
  for (; i + 8u <= n; i += 8u) {
    uint64_t w;
    std::memcpy(&w, state + i, sizeof w);
    // Byte b of the word is state[i + b] on every target: the false flags lie above
    // (after) the first true one, so the lowest stays the answer.
    const uint64_t t = le_order64(w) ^ (kOnes * s);
    const uint64_t z = (t - kOnes) & ~t & (kOnes << 7);
    if (z != 0u) return i + (static_cast<uint32_t>(__builtin_ctzll(z)) >> 3);
  }
  for (; i < n; ++i)
    if (state[i] == s) return i;
  return n;
}

// Keeps `c` in the list of the largest clusters (size descending, ties in the order
// found); the size of whatever falls off the end goes to largest_dropped.
void keep_largest(ClusterResult& res, const ClusterSummary& c) {
  uint32_t pos = res.n_largest;
  while (pos > 0 && c.size > res.largest[pos - 1].size) --pos;
  const uint32_t cap = ClusterResult::kLargestKept;
  if (pos >= cap) {
    res.largest_dropped = c.size > res.largest_dropped ? c.size : res.largest_dropped;
    return;
  }
  if (res.n_largest == cap) {
    const uint32_t evicted = res.largest[cap - 1].size;
    res.largest_dropped = evicted > res.largest_dropped ? evicted : res.largest_dropped;
  }
  const uint32_t last = res.n_largest < cap ? res.n_largest : cap - 1;
  for (uint32_t i = last; i > pos; --i) res.largest[i] = res.largest[i - 1];
  res.largest[pos] = c;
  if (res.n_largest < cap) ++res.n_largest;
}

// Keeps `o` in the list of the objects nearest the workspace centre (x-y distance of
// the centroids, ascending, ties in the order found); one falling off the end counts
// in objects_dropped.
void keep_nearest(ClusterResult& res, const ObjectSummary& o, float cx, float cy) {
  const auto d2 = [cx, cy](const ObjectSummary& a) {
    const float dx = a.centroid.x() - cx, dy = a.centroid.y() - cy;
    return dx * dx + dy * dy;
  };
  const float d = d2(o);
  uint32_t pos = res.n_objects;
  while (pos > 0 && d < d2(res.objects[pos - 1])) --pos;
  if (pos >= kMaxObjects) {
    ++res.objects_dropped;
    return;
  }
  if (res.n_objects == kMaxObjects) ++res.objects_dropped;
  const uint32_t last = res.n_objects < kMaxObjects ? res.n_objects : kMaxObjects - 1;
  for (uint32_t i = last; i > pos; --i) res.objects[i] = res.objects[i - 1];
  res.objects[pos] = o;
  if (res.n_objects < kMaxObjects) ++res.n_objects;
}

// A walked cluster as the object list holds it: the mean of its centroids and the
// world box of its cells.
ObjectSummary summarize(const VoxelGrid& grid, uint32_t seed, uint32_t size, const Walk& w) {
  const float leaf = grid.leaf();
  const Vec3& origin = grid.origin();
  ObjectSummary o;
  o.seed = seed;
  o.voxels = size;
  o.centroid = Vec3(w.sum_x, w.sum_y, w.sum_z) / static_cast<float>(size);
  o.box_min = origin + leaf * Vec3(static_cast<float>(w.x0), static_cast<float>(w.y0), static_cast<float>(w.z0));
  o.box_max =
      origin + leaf * Vec3(static_cast<float>(w.x1 + 1u), static_cast<float>(w.y1 + 1u), static_cast<float>(w.z1 + 1u));
  return o;
}

// The cluster's x-y footprint (its cells' x-y box: the cell centres grown by half a
// voxel) contains (cx, cy).
bool footprint_covers(const VoxelGrid& grid, const ClusterSummary& c, float cx, float cy) {
  const float leaf = grid.leaf();
  const Vec3& origin = grid.origin();
  const float x0 = origin.x() + leaf * static_cast<float>(c.x0);
  const float x1 = origin.x() + leaf * static_cast<float>(c.x1 + 1u);
  const float y0 = origin.y() + leaf * static_cast<float>(c.y0);
  const float y1 = origin.y() + leaf * static_cast<float>(c.y1 + 1u);
  return cx >= x0 && cx <= x1 && cy >= y0 && cy <= y1;
}
}  // namespace

bool build_cell_bitmap(const VoxelGrid& grid, const uint8_t* state, uint8_t from, uint32_t* list, uint64_t* words,
                       uint32_t n_words, CellBitmap& out) {
  out = CellBitmap{};
  if (words == nullptr || list == nullptr) return false;
  // The set's voxels first, listed without a branch on the state: the plan's few
  // object voxels lie scattered among the table's, so such a branch would mostly guess
  // wrong, and only their keys are read.
  const uint32_t n = grid.size();
  uint32_t m = 0;
  for (uint32_t i = 0; i < n; ++i) {
    list[m] = i;
    m += state[i] == from ? 1u : 0u;
  }
  if (m == 0) return false;
  uint32_t lo[3] = {0xFFFFFFFFu, 0xFFFFFFFFu, 0xFFFFFFFFu}, hi[3] = {0, 0, 0};
  for (uint32_t j = 0; j < m; ++j) {
    const uint32_t k = grid.key(list[j]);
    const uint32_t c[3] = {VoxelGrid::key_x(k), VoxelGrid::key_y(k), VoxelGrid::key_z(k)};
    for (int a = 0; a < 3; ++a) {
      lo[a] = c[a] < lo[a] ? c[a] : lo[a];
      hi[a] = c[a] > hi[a] ? c[a] : hi[a];
    }
  }
  // Keys keep 2 cells inside each field's range (voxel_grid.hpp), so lo - 2 >= 0.
  const uint64_t nx = hi[0] - lo[0] + 5u, ny = hi[1] - lo[1] + 5u, nz = hi[2] - lo[2] + 5u;
  const uint64_t need = (nx * ny * nz + 63u) / 64u;
  if (need > n_words) return false;
  for (uint64_t w = 0; w < need; ++w) words[w] = 0u;
  out.words = words;
  out.x0 = lo[0] - 2u;
  out.y0 = lo[1] - 2u;
  out.z0 = lo[2] - 2u;
  out.nx = static_cast<uint32_t>(nx);
  out.ny = static_cast<uint32_t>(ny);
  for (uint32_t j = 0; j < m; ++j) {
    const uint32_t c = out.cell(grid.key(list[j]));
    words[c >> 6] |= uint64_t{1} << (c & 63u);
  }
  return true;
}

void cluster_and_pick(const VoxelGrid& grid, uint8_t* state, uint32_t* queue, const ClusterParams& prm,
                      uint32_t* target, uint32_t target_capacity, ClusterResult& res, CellBitmap* free_cells) {
  Offset off[kMaxOffsets];
  OffsetHashes hashes;
  const uint32_t n_off = make_offsets(prm.cells > 2 ? 2u : prm.cells, off, hashes);
  int32_t lin[kMaxOffsets];
  if (free_cells != nullptr)
    for (uint32_t o = 0; o < n_off; ++o)
      lin[o] = off[o].dx +
               static_cast<int32_t>(free_cells->nx) * (off[o].dy + static_cast<int32_t>(free_cells->ny) * off[o].dz);
  res.clear();
  const uint32_t n = grid.size();
  uint32_t best_seed = VoxelGrid::kNone, best_size = 0;
  float best_score = 0.f;
  uint32_t free_total = 0;
  const TargetSpec* const probe = prm.target.kind == TargetKind::by_rule ? nullptr : &prm.target;
  // Each cluster of min_points or more stays in the queue after the ones before it
  // (ObjectSummary::first); a smaller one is overwritten by the next.
  uint32_t kept = 0;
  for (uint32_t i = next_in_state(state, n, 0, kVoxelFree); i < n; i = next_in_state(state, n, i + 1u, kVoxelFree)) {
    Walk w;
    w.probe = probe;
    uint32_t* const walk = queue + kept;
    const uint32_t size = free_cells != nullptr
                              ? flood_bits(grid, state, walk, i, off, lin, n_off, *free_cells, kVoxelVisited, w)
                              : flood(grid, state, walk, i, off, hashes, n_off, kVoxelFree, kVoxelVisited, w);
    free_total += size;
    if (size < prm.min_points) continue;
    kept += size;
    ++res.clusters;
    keep_largest(res, ClusterSummary{i, size, w.x0, w.x1, w.y0, w.y1});
    ObjectSummary o = summarize(grid, i, size, w);
    o.first = kept - size;
    keep_nearest(res, o, prm.centre_x, prm.centre_y);
    float score;
    if (prm.target.kind == TargetKind::nearest_point) {
      score = w.near_d2;
    } else if (prm.target.kind == TargetKind::inside_box) {
      if (w.inside == 0u) continue;  // not a candidate: nothing of it in the box
      score = -static_cast<float>(w.inside);
    } else if (prm.rule == TargetRule::largest) {
      score = -static_cast<float>(size);
    } else {
      const float cx = w.sum_x / static_cast<float>(size) - prm.centre_x;
      const float cy = w.sum_y / static_cast<float>(size) - prm.centre_y;
      score = cx * cx + cy * cy;
    }
    if (best_seed == VoxelGrid::kNone || score < best_score) {
      best_seed = i;
      best_size = size;
      best_score = score;
      // Keep the leader's voxels (its walk is in the queue until the next flood), so
      // the winner need not be walked again. Each component is copied at most once.
      if (size <= target_capacity)
        for (uint32_t k = 0; k < size; ++k) target[k] = walk[k];
    }
  }
  if (best_seed == VoxelGrid::kNone) {
    res.other_points = free_total;
    return;
  }
  res.target_size = best_size;
  res.other_points = free_total - best_size;
  if (best_size <= target_capacity) {
    for (uint32_t k = 0; k < best_size; ++k) state[target[k]] = kVoxelTarget;
    return;
  }
  // Larger than the caller's list (the caller reports capacity_exceeded): walk the
  // winner again to mark it, turning it from visited into target.
  for (uint32_t i = 0; i < n; ++i)
    if (state[i] == kVoxelVisited) state[i] = kVoxelFree;
  Walk w;
  (void)flood(grid, state, queue, best_seed, off, hashes, n_off, kVoxelFree, kVoxelTarget, w);
  for (uint32_t i = 0; i < n; ++i)
    if (state[i] == kVoxelFree) state[i] = kVoxelVisited;
  for (uint32_t i = 0; i < target_capacity; ++i) target[i] = queue[i];
}

uint32_t retarget_to_cover(const VoxelGrid& grid, uint8_t* state, uint32_t* queue, const ClusterParams& prm,
                           const uint32_t* old_target, uint32_t old_size, float cx, float cy, uint32_t* target,
                           uint32_t target_capacity, const ClusterResult* labelled) {
  Offset off[kMaxOffsets];
  OffsetHashes hashes;
  const uint32_t n_off = make_offsets(prm.cells > 2 ? 2u : prm.cells, off, hashes);
  const uint32_t n = grid.size();
  // The largest that covers (cx, cy) wins, the first found on ties.
  uint32_t best_seed = VoxelGrid::kNone, best_size = 0;
  const auto consider = [&](const ClusterSummary& c) {
    if (c.size < prm.min_points || c.size <= old_size || c.size > target_capacity || c.size <= best_size) return;
    if (!footprint_covers(grid, c, cx, cy)) return;
    best_seed = c.seed;
    best_size = c.size;
  };
  // Every cluster larger than the old target in the labelling's list, in the order a
  // walk would find them among equals: no walk. Otherwise every component of the
  // clusters not picked, walked once (visited -> free).
  const bool from_list = labelled != nullptr && labelled->largest_dropped <= old_size;
  if (from_list) {
    for (uint32_t k = 0; k < labelled->n_largest; ++k) consider(labelled->largest[k]);
  } else {
    for (uint32_t i = 0; i < n; ++i) {
      if (state[i] != kVoxelVisited) continue;
      Walk w;
      const uint32_t size = flood(grid, state, queue, i, off, hashes, n_off, kVoxelVisited, kVoxelFree, w);
      consider(ClusterSummary{i, size, w.x0, w.x1, w.y0, w.y1});
    }
  }
  if (best_seed != VoxelGrid::kNone) {
    // The old target joins the other objects before `target` (which may be the same
    // array) is overwritten; it is a component of its own, so the walk below never
    // reaches it.
    for (uint32_t k = 0; k < old_size; ++k) state[old_target[k]] = kVoxelVisited;
    Walk w;
    (void)flood(grid, state, queue, best_seed, off, hashes, n_off, from_list ? kVoxelVisited : kVoxelFree, kVoxelTarget,
                w);
    for (uint32_t k = 0; k < best_size; ++k) target[k] = queue[k];
  }
  if (!from_list)
    for (uint32_t i = 0; i < n; ++i)
      if (state[i] == kVoxelFree) state[i] = kVoxelVisited;
  return best_size;
}

uint32_t mark_cluster(const VoxelGrid& grid, uint8_t* state, uint32_t* queue, const ClusterParams& prm, uint32_t seed,
                      uint32_t* target, uint32_t target_capacity) {
  const uint32_t n = grid.size();
  if (seed >= n || (state[seed] != kVoxelVisited && state[seed] != kVoxelTarget)) return 0;
  for (uint32_t i = 0; i < n; ++i)
    if (state[i] == kVoxelTarget) state[i] = kVoxelVisited;
  Offset off[kMaxOffsets];
  OffsetHashes hashes;
  const uint32_t n_off = make_offsets(prm.cells > 2 ? 2u : prm.cells, off, hashes);
  Walk w;
  const uint32_t size = flood(grid, state, queue, seed, off, hashes, n_off, kVoxelVisited, kVoxelTarget, w);
  const uint32_t kept = size < target_capacity ? size : target_capacity;
  for (uint32_t k = 0; k < kept; ++k) target[k] = queue[k];
  return size;
}

uint32_t walk_cluster(const VoxelGrid& grid, uint8_t* state, uint32_t* queue, const ClusterParams& prm, uint32_t seed,
                      uint8_t from, uint8_t mark) {
  if (seed >= grid.size() || state[seed] != from || from == mark) return 0;
  Offset off[kMaxOffsets];
  OffsetHashes hashes;
  const uint32_t n_off = make_offsets(prm.cells > 2 ? 2u : prm.cells, off, hashes);
  Walk w;
  return flood(grid, state, queue, seed, off, hashes, n_off, from, mark, w);
}

Status validate(const TargetSpec& t, const char** message) {
  const char* why = "";
  Status s = Status::ok;
  if (t.kind != TargetKind::by_rule && t.kind != TargetKind::nearest_point && t.kind != TargetKind::inside_box) {
    s = Status::invalid_argument;
    why = "target: unknown kind";
  } else if (t.kind == TargetKind::nearest_point && !t.point.allFinite()) {
    s = Status::non_finite;
    why = "target point: a coordinate is not finite";
  } else if (t.kind == TargetKind::inside_box && !(t.box_min.allFinite() && t.box_max.allFinite())) {
    s = Status::non_finite;
    why = "target box: a coordinate is not finite";
  } else if (t.kind == TargetKind::inside_box && !(t.box_min.array() <= t.box_max.array()).all()) {
    s = Status::invalid_argument;
    why = "target box: a minimum is above its maximum";
  }
  if (message != nullptr) *message = why;
  return s;
}

}  // namespace fg
