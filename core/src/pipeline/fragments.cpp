// Stage A.6, second step: fragments of one object joined (fragments.hpp).
#include "fg/core/pipeline/fragments.hpp"

#include <cmath>

namespace fg {
namespace {
// A group holds at most the listed objects: its root keeps the others' seeds.
static_assert(kMaxJoinedFragments + 1u >= kMaxObjects, "every other listed object fits a group's fragments");
// Segments tested between two objects at most: from evenly chosen points of one.
constexpr uint32_t kFragmentSegments = 16;

// The distance between two axis-aligned boxes (0 when they overlap).
float box_gap(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1) {
  float s = 0.f;
  for (int k = 0; k < 3; ++k) {
    const float g = std::fmax(0.f, std::fmax(a0[k] - b1[k], b0[k] - a1[k]));
    s += g * g;
  }
  return std::sqrt(s);
}

// Up to kFragmentSamples of the voxels v[0, n) whose centroids lie within `gap` of the
// box [lo, hi], evenly over them, into out; returns how many.
uint32_t near_box(const VoxelGrid& grid, const uint32_t* v, uint32_t n, const Vec3& lo, const Vec3& hi, float gap,
                  uint32_t* out) {
  uint32_t count = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const Vec3 c = grid.centroid(v[i]);
    count += box_gap(c, c, lo, hi) <= gap ? 1u : 0u;
  }
  if (count == 0u) return 0u;
  const uint32_t stride = (count + kFragmentSamples - 1u) / kFragmentSamples;
  uint32_t m = 0, seen = 0;
  for (uint32_t i = 0; i < n && m < kFragmentSamples; ++i) {
    const Vec3 c = grid.centroid(v[i]);
    if (!(box_gap(c, c, lo, hi) <= gap)) continue;
    if (seen++ % stride == 0u) out[m++] = v[i];
  }
  return m;
}

// Objects a and b (their voxels) meet through space no sensor saw free: segments from
// evenly chosen points of a near b to their nearest points of b within `gap`. The
// segments between one object's fragments run through its inside, hidden behind the
// surfaces each sensor saw; between two objects, through the space beside and above
// them, which some sensor saw past them.
bool meet_unseen(const VoxelGrid& grid, const SensorViews& views, const uint32_t* a, uint32_t na,
                 const ObjectSummary& oa, const uint32_t* b, uint32_t nb, const ObjectSummary& ob, float gap,
                 uint32_t* scratch) {
  uint32_t* const sa = scratch;
  uint32_t* const sb = scratch + kFragmentSamples;
  const uint32_t ma = near_box(grid, a, na, ob.box_min, ob.box_max, gap, sa);
  const uint32_t mb = near_box(grid, b, nb, oa.box_min, oa.box_max, gap, sb);
  const uint32_t every = ma > kFragmentSegments ? (ma + kFragmentSegments - 1u) / kFragmentSegments : 1u;
  const float step = 0.5f * grid.leaf();
  uint32_t segments = 0;
  for (uint32_t i = 0; i < ma; i += every) {
    const Vec3 pa = grid.centroid(sa[i]);
    float best = gap * gap;
    Vec3 pb = pa;
    bool found = false;
    for (uint32_t j = 0; j < mb; ++j) {
      const Vec3 q = grid.centroid(sb[j]);
      const float d2 = (q - pa).squaredNorm();
      if (d2 <= best) {
        best = d2;
        pb = q;
        found = true;
      }
    }
    if (!found) continue;
    ++segments;
    const uint32_t steps = static_cast<uint32_t>(std::ceil(std::sqrt(best) / step));
    for (uint32_t k = 1; k < steps; ++k) {
      const Vec3 q = pa + (pb - pa) * (static_cast<float>(k) / static_cast<float>(steps));
      if (views.visibility(q) == Sight::seen_free) return false;
    }
  }
  return segments > 0u;
}

float distance2_to_centre(const ObjectSummary& o, const ClusterParams& cp) {
  const float dx = o.centroid.x() - cp.centre_x, dy = o.centroid.y() - cp.centre_y;
  return dx * dx + dy * dy;
}
}  // namespace

float fragment_gap(const PlannerConfig& cfg) { return 0.5f * cfg.gripper.max_opening_m; }

void join_fragments(const VoxelGrid& grid, uint8_t* state, const uint32_t* queue, const ClusterParams& cp,
                    const SensorViews& views, float max_gap, LentWords lent, uint32_t* target_voxels, uint32_t capacity,
                    ClusterResult& res) {
  const uint32_t n = res.n_objects;
  // One sensor sees a convex body as one patch: the band it loses lies at the patch's
  // rim, and the space behind what it saw is hidden whatever lies there. Fragments need
  // two views.
  if (n < 2u || !views.both() || res.target_size == 0u || res.target_size > capacity ||
      size_t{lent.count} * 2u < size_t{2} * kFragmentSamples)
    return;
  uint32_t* const scratch = reinterpret_cast<uint32_t*>(lent.words);
  // By listed index (the entries are reordered below): where each object's voxels lie
  // in the labelling's queue, how many, its seed. Groups: each object's root is the
  // nearest member (the lowest index).
  uint32_t first[kMaxObjects], count[kMaxObjects], seed[kMaxObjects];
  uint32_t root[kMaxObjects], members[kMaxObjects], voxels[kMaxObjects];
  uint32_t old_target = n;  // the listed object the labelling picked (none: not listed)
  for (uint32_t k = 0; k < n; ++k) {
    first[k] = res.objects[k].first;
    count[k] = voxels[k] = res.objects[k].voxels;
    seed[k] = res.objects[k].seed;
    root[k] = k;
    members[k] = 1;
    if (state[seed[k]] == kVoxelTarget) old_target = k;
  }
  const auto find = [&root](uint32_t k) {
    while (root[k] != k) k = root[k];
    return k;
  };
  uint32_t tests = 0, joins = 0;
  for (uint32_t i = 0; i < n && tests < kMaxFragmentTests; ++i)
    for (uint32_t j = i + 1; j < n && tests < kMaxFragmentTests; ++j) {
      const uint32_t ri = find(i), rj = find(j);
      if (ri == rj || voxels[ri] + voxels[rj] > capacity) continue;
      const ObjectSummary &oi = res.objects[i], &oj = res.objects[j];
      if (box_gap(oi.box_min, oi.box_max, oj.box_min, oj.box_max) > max_gap) continue;
      ++tests;
      if (!meet_unseen(grid, views, queue + first[i], count[i], oi, queue + first[j], count[j], oj, max_gap, scratch))
        continue;
      const uint32_t lo = ri < rj ? ri : rj, hi = ri < rj ? rj : ri;
      root[hi] = lo;
      members[lo] += members[hi];
      voxels[lo] += voxels[hi];
      ++joins;
    }
  if (joins == 0u) return;
  // Each group in its root's entry: sizes, centroids and boxes combined, the other
  // members' seeds as its fragments.
  for (uint32_t k = 0; k < n; ++k) {
    const uint32_t r = find(k);
    if (r == k) continue;
    ObjectSummary& o = res.objects[r];
    const ObjectSummary& f = res.objects[k];
    const float w = static_cast<float>(o.voxels), wf = static_cast<float>(f.voxels);
    o.centroid = (o.centroid * w + f.centroid * wf) / (w + wf);
    o.voxels += f.voxels;
    o.box_min = o.box_min.cwiseMin(f.box_min);
    o.box_max = o.box_max.cwiseMax(f.box_max);
    o.fragment_seed[o.fragments++] = f.seed;
  }
  // The list: the roots, nearest the centre first (insertion, stable: ties keep their
  // order), the fragments' entries gone, sorted in place. `listed` keeps which listed
  // object each entry is.
  uint32_t listed[kMaxObjects], kept = 0;
  for (uint32_t k = 0; k < n; ++k) {
    if (find(k) != k) continue;
    res.objects[kept] = res.objects[k];  // kept <= k: an entry not yet read, or itself
    listed[kept++] = k;
  }
  for (uint32_t k = 1; k < kept; ++k) {
    const ObjectSummary o = res.objects[k];
    const uint32_t l = listed[k];
    const float d = distance2_to_centre(o, cp);
    uint32_t pos = k;
    for (; pos > 0 && d < distance2_to_centre(res.objects[pos - 1], cp); --pos) {
      res.objects[pos] = res.objects[pos - 1];
      listed[pos] = listed[pos - 1];
    }
    res.objects[pos] = o;
    listed[pos] = l;
  }
  res.n_objects = kept;
  res.clusters -= joins;
  // The target: the nearest object by the default rule, else the group of the one the
  // labelling picked; a target not listed, or alone and unchanged, stays as it was.
  const bool nearest = cp.target.kind == TargetKind::by_rule && cp.rule == TargetRule::nearest_to_centre;
  const uint32_t target_root = nearest ? listed[0] : (old_target < n ? find(old_target) : n);
  if (target_root == n || (members[target_root] == 1u && target_root == old_target)) return;
  for (uint32_t v = 0; v < res.target_size; ++v) state[target_voxels[v]] = kVoxelVisited;
  uint32_t size = 0;
  for (uint32_t k = 0; k < n; ++k) {
    if (find(k) != target_root) continue;
    for (uint32_t v = 0; v < count[k]; ++v, ++size) {
      state[queue[first[k] + v]] = kVoxelTarget;
      if (size < capacity) target_voxels[size] = queue[first[k] + v];
    }
  }
  res.other_points = res.other_points + res.target_size - size;
  res.target_size = size;
}

uint32_t mark_object(const VoxelGrid& grid, uint8_t* state, uint32_t* queue, const ClusterParams& cp,
                     const ObjectSummary& o, uint32_t* target, uint32_t capacity) {
  uint32_t size = mark_cluster(grid, state, queue, cp, o.seed, target, capacity);
  if (size == 0u) return 0u;
  for (uint32_t f = 0; f < o.fragments && f < kMaxJoinedFragments; ++f) {
    const uint32_t m = walk_cluster(grid, state, queue, cp, o.fragment_seed[f], kVoxelVisited, kVoxelTarget);
    for (uint32_t j = 0; j < m; ++j)
      if (size + j < capacity) target[size + j] = queue[j];
    size += m;
  }
  return size;
}

}  // namespace fg
