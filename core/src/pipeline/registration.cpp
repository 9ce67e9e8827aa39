// Stage A.4b: the hand sensor registered to the head sensor (registration.hpp).
#include "fg/core/pipeline/registration.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fg {

const char* to_string(RegistrationOutcome o) {
  switch (o) {
    case RegistrationOutcome::not_run:
      return "not_run";
    case RegistrationOutcome::corrected:
      return "corrected";
    case RegistrationOutcome::calibration_kept:
      return "calibration_kept";
    case RegistrationOutcome::too_little_overlap:
      return "too_little_overlap";
    case RegistrationOutcome::implausible:
      return "implausible";
    case RegistrationOutcome::hand_added_first:
      return "hand_added_first";
    case RegistrationOutcome::sensor_disagreement:
      return "sensor_disagreement";
  }
  return "unknown";
}

Pose RegistrationResult::hand_pose(const Pose& given) const {
  if (outcome != RegistrationOutcome::corrected) return given;
  Pose p;
  p.R = correction.R * given.R;
  p.t = correction.R * given.t + correction.t;
  return p;
}

namespace {

// A bin's mean needs a few returns; a bin holds about 20 of a 640x480 sensor's pixels
// on the host's map.
constexpr float kMinReturns = 3.f;
constexpr float kEdgeShare = 0.05f;
// A bin's depths may spread 2x (in variance) beyond a plane's, plus 1.5 mm of noise.
constexpr float kSpreadSlack = 2.f, kNoiseFloor = 0.0015f;
// Pairs' worth of constraint a direction needs before the registration moves along it.
constexpr float kMinInformation = 16.f;
// Normals within 30 degrees: the same surface.
constexpr float kSameSurfaceCos = 0.866f;
// Surfaces seen within 80 degrees of their normal.
constexpr float kGrazingCos = 0.17f;

// Rodrigues: the rotation by the vector w (its length in radians).
Mat3 rotation_of(const Vec3& w) {
  const float a = w.norm();
  if (a < 1e-12f) return Mat3::Identity();
  const Vec3 k = w / a;
  Mat3 K;
  K << 0.f, -k.z(), k.y(), k.z(), 0.f, -k.x(), -k.y(), k.x(), 0.f;
  return Mat3::Identity() + std::sin(a) * K + (1.f - std::cos(a)) * (K * K);
}

float angle_of(const Mat3& R) {
  const float c = 0.5f * (R.trace() - 1.f);
  return std::acos(c > 1.f ? 1.f : (c < -1.f ? -1.f : c));
}

// A surface from the depths d of a direction bin (u, v) and its four neighbours (+u, -u,
// +v, -v) in a map of 2 half bins per axis over x/z, y/z in [-1, 1): the bin's point on
// its centre ray (s) and its normal (n), facing the sensor along `ray`. False when a
// neighbour lies more than 5% of the range away (across an edge: the slope that would
// need, over one of the host's moment bins, is beyond 73 degrees), the normal is
// undefined, or the surface is seen grazing, beyond 80 degrees (its depths run along it).
bool surface_of(const float d[5], int u, int v, float half, const Vec3& ray, Vec3& s, Vec3& n) {
  for (int k = 1; k < 5; ++k)
    if (std::fabs(d[k] - d[0]) > kEdgeShare * d[0]) return false;
  const auto bin_point = [&](int du, int dv, float depth) {
    return Vec3(((static_cast<float>(u + du) + 0.5f) / half - 1.f) * depth,
                ((static_cast<float>(v + dv) + 0.5f) / half - 1.f) * depth, depth);
  };
  n = (bin_point(1, 0, d[1]) - bin_point(-1, 0, d[2])).cross(bin_point(0, 1, d[3]) - bin_point(0, -1, d[4]));
  const float len = n.norm();
  if (!(len > 0.f)) return false;
  n /= len;
  s = bin_point(0, 0, d[0]);
  if (n.dot(ray) > 0.f) n = -n;
  return -n.dot(ray.normalized()) >= kGrazingCos;
}

// The hand's map bin (v * kMomentBins + u) where the world point h projects from the
// hand pose (Rs, ts), one bin inside the map's border; -1 outside.
int32_t hand_bin(const Mat3& Rs, const Vec3& ts, const Vec3& h) {
  constexpr float half = 0.5f * static_cast<float>(kMomentBins);
  const Vec3 p = Rs.transpose() * (h - ts);
  if (!(p.z() > 0.05f)) return -1;
  const float bu = (p.x() / p.z() + 1.f) * half, bv = (p.y() / p.z() + 1.f) * half;
  constexpr float lo = 1.f, hi = static_cast<float>(kMomentBins - 1);
  if (!(bu >= lo && bv >= lo && bu < hi && bv < hi)) return -1;
  return static_cast<int32_t>(bv) * static_cast<int32_t>(kMomentBins) + static_cast<int32_t>(bu);
}

// The hand's surface in its map's bin: the point s on the bin's centre ray at the bin's
// mean depth, and its normal n (the hand sensor's frame). False when the hand saw too
// little there, or the bin straddles an edge (its depths spread, or a neighbour's mean
// jumps).
bool bin_surface(const DepthMoments* map, int32_t bin, Vec3& s, Vec3& n) {
  constexpr float half = 0.5f * static_cast<float>(kMomentBins);
  const int32_t u = bin % static_cast<int32_t>(kMomentBins), v = bin / static_cast<int32_t>(kMomentBins);
  float d[5];  // the bin, then +u, -u, +v, -v
  const int32_t step[5] = {0, 1, -1, static_cast<int32_t>(kMomentBins), -static_cast<int32_t>(kMomentBins)};
  float var0 = 0.f;
  for (int k = 0; k < 5; ++k) {
    const DepthMoments& m = map[bin + step[k]];
    if (!(m.n >= kMinReturns)) return false;
    d[k] = m.sum / m.n;
    if (k == 0) var0 = m.sq / m.n - d[0] * d[0];
  }
  // One plane spreads a bin's depths by its slope across the bin (a uniform spread over
  // one bin of the neighbours' mean step: variance step^2 / 12 per axis) plus the
  // sensor's noise; a bin spread wider holds two surfaces (an edge), and its mean lies on
  // neither. (A neighbour across an edge: surface_of.)
  const float gu = 0.5f * (d[1] - d[2]), gv = 0.5f * (d[3] - d[4]);
  if (var0 > kSpreadSlack * (gu * gu + gv * gv) / 12.f + kNoiseFloor * kNoiseFloor) return false;
  // The bin's mean is its surface at the bin's centre ray, which the normal faces.
  const Vec3 centre(((static_cast<float>(u) + 0.5f) / half - 1.f) * d[0],
                    ((static_cast<float>(v) + 0.5f) / half - 1.f) * d[0], d[0]);
  return surface_of(d, u, v, half, centre, s, n);
}

// The world point h in the head's frame (p) and its bin (u, v) in the head's sight map,
// one bin inside the map's border; false outside it or behind the sensor.
bool head_sight_bin(const SensorViews& views, const Vec3& h, Vec3& p, int& u, int& v) {
  constexpr float half = 0.5f * static_cast<float>(kSightBins);
  const Pose& head = views.pose[static_cast<uint32_t>(SensorRole::head)];
  p = head.R.transpose() * (h - head.t);
  if (!(p.z() > 0.05f)) return false;
  const float bu = (p.x() / p.z() + 1.f) * half, bv = (p.y() / p.z() + 1.f) * half;
  if (!(bu >= 1.f && bv >= 1.f && bu < static_cast<float>(kSightBins - 1) && bv < static_cast<float>(kSightBins - 1)))
    return false;
  u = static_cast<int>(bu);
  v = static_cast<int>(bv);
  return true;
}

// The head's surface normal (world) at a sample that lies at p in the head's frame, in
// its sight bin (u, v) (head_sight_bin), from its map of nearest returns (the returns
// one bin to each side, 8 mm apart at 1 m on the host's map: the nearest return of a bin
// is biased toward the sensor, alike in neighbouring bins, so their slope is not). False
// on a depth edge or where the head saw nothing.
bool head_normal(const SensorViews& views, const Vec3& p, int u, int v, Vec3& nw) {
  constexpr uint32_t kHeadRole = static_cast<uint32_t>(SensorRole::head);
  constexpr float half = 0.5f * static_cast<float>(kSightBins);
  const int du[5] = {0, 1, -1, 0, 0}, dv[5] = {0, 0, 0, 1, -1};
  float d[5];
  for (int k = 0; k < 5; ++k) {
    const uint16_t mm = views.sight_mm[kHeadRole][(v + dv[k]) * static_cast<int>(kSightBins) + (u + du[k])];
    if (mm == 0xFFFFu) return false;
    d[k] = 0.001f * static_cast<float>(mm);
  }
  Vec3 s, n;
  if (!surface_of(d, u, v, half, p, s, n)) return false;
  nw = views.pose[kHeadRole].R * n;
  return true;
}

// Eigen-decomposition of a symmetric 6x6 matrix by cyclic Jacobi rotations (bounded
// sweeps): A = V diag(d) V^T.
void jacobi6(float A[6][6], float V[6][6], float d[6]) {
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) V[i][j] = i == j ? 1.f : 0.f;
  for (int sweep = 0; sweep < 12; ++sweep) {
    float off = 0.f;
    for (int p = 0; p < 6; ++p)
      for (int q = p + 1; q < 6; ++q) off += A[p][q] * A[p][q];
    if (off < 1e-24f) break;
    for (int p = 0; p < 6; ++p)
      for (int q = p + 1; q < 6; ++q) {
        if (std::fabs(A[p][q]) < 1e-30f) continue;
        const float theta = 0.5f * (A[q][q] - A[p][p]) / A[p][q];
        const float t = (theta >= 0.f ? 1.f : -1.f) / (std::fabs(theta) + std::sqrt(theta * theta + 1.f));
        const float c = 1.f / std::sqrt(t * t + 1.f), s = t * c;
        for (int k = 0; k < 6; ++k) {  // columns p, q
          const float akp = A[k][p], akq = A[k][q];
          A[k][p] = c * akp - s * akq;
          A[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < 6; ++k) {  // rows p, q
          const float apk = A[p][k], aqk = A[q][k];
          A[p][k] = c * apk - s * aqk;
          A[q][k] = s * apk + c * aqk;
        }
        for (int k = 0; k < 6; ++k) {
          const float vkp = V[k][p], vkq = V[k][q];
          V[k][p] = c * vkp - s * vkq;
          V[k][q] = s * vkp + c * vkq;
        }
      }
  }
  for (int i = 0; i < 6; ++i) d[i] = A[i][i];
}

// Samples are taken evenly over the directions of the head's normals where they lie, in
// six classes: the four sides (the dominant horizontal axis of the world normal, either
// sign), the table (facing up, at its height) and the raised surfaces facing up (the
// objects' tops). A table fills the view, and samples spread evenly over it would leave
// few on the objects, which alone fix the slide and the turn in the table's plane. A
// surface facing down is not seen by sensors looking down at a table.
constexpr uint32_t kNormalClasses = 6;
constexpr uint8_t kUp = 4, kRaised = 5;
constexpr uint8_t kNotInView = kNormalClasses;  // the hand saw no surface there, or the head none (or faces down)
constexpr uint8_t kEdge = kNormalClasses + 1;   // the hand saw a surface, the head an edge
// A surface facing up more than this above the table is an object's: a few times the
// sensors' noise and the voxel's size.
constexpr float kRaisedM = 0.01f;
// A class code with the tops told from the table: a surface facing up is raised (an
// object's top) above raised_z, the table's height and noise (raised_height).
uint8_t with_tops(uint8_t k, float z, float raised_z) { return k == kUp && z > raised_z ? kRaised : k; }
uint8_t normal_class(const Vec3& n) {
  const Vec3 a = n.cwiseAbs();
  if (a.z() >= a.x() && a.z() >= a.y()) return n.z() >= 0.f ? kUp : kNotInView;
  const uint8_t axis = a.x() >= a.y() ? 0u : 1u;
  return static_cast<uint8_t>(2u * axis + (n[axis] < 0.f ? 1u : 0u));
}

struct Sample {
  Vec3 p, n;  // the head's voxel centroid and its surface's normal
  // The hand's surface in the bin the sample last projected to (its frame): a bin's
  // surface depends on the bin alone, and the samples keep their bins once the
  // alignment settles, so most passes look up no map.
  Vec3 hs, hn;
  int32_t bin;  // -1: none yet
  int32_t has_surface;
};
static_assert(sizeof(Sample) == kRegistrationSampleFloats * sizeof(float), "the scratch's size per sample");

// The hand's surface at sample `smp` from the hand pose (Rs, ts), through its cache: a
// world point w on it and its outward normal nw. False when the hand saw too little
// there, or its bin straddles an edge.
bool hand_surface(const DepthMoments* map, const Mat3& Rs, const Vec3& ts, Sample& smp, Vec3& w, Vec3& nw) {
  const int32_t bin = hand_bin(Rs, ts, smp.p);
  if (bin < 0) return false;
  if (bin != smp.bin) {
    smp.bin = bin;
    smp.has_surface = bin_surface(map, bin, smp.hs, smp.hn) ? 1 : 0;
  }
  if (smp.has_surface == 0) return false;
  w = Rs * smp.hs + ts;
  nw = Rs * smp.hn;
  return true;
}

struct Sums {
  float H[6][6] = {};
  float g[6] = {};
  float cost = 0.f;  // Tukey's, saturated pairs and missing ones excluded
  float sq = 0.f;    // squared residuals of the pairs
  uint32_t pairs = 0;
};

// One pass over the samples with the hand moved by (R, t): the Tukey-weighted normal
// equations of the increment (rotation about `pivot` scaled by `lever`, translation).
Sums accumulate(const DepthMoments* map, const Pose& hand, Sample* samples, uint32_t n, const Mat3& R, const Vec3& t,
                const Vec3& pivot, float lever, float gate) {
  Sums s;
  const Mat3 Rs = R * hand.R;
  const Vec3 ts = R * hand.t + t;
  const float inv_gate2 = 1.f / (gate * gate);
  for (uint32_t i = 0; i < n; ++i) {
    Vec3 w, nw;
    if (!hand_surface(map, Rs, ts, samples[i], w, nw)) continue;
    // The two sensors' normals agree on a surface both saw; a sample beside an edge
    // lands on the other face of it.
    if (!(nw.dot(samples[i].n) >= kSameSurfaceCos)) continue;
    const float e = nw.dot(w - samples[i].p);
    const float r2 = e * e * inv_gate2;
    if (!(r2 < 1.f)) continue;
    const float wt = (1.f - r2) * (1.f - r2);
    // The hand's local plane turns with it: d e / d omega = (h - pivot) x n.
    const Vec3 a = (samples[i].p - pivot).cross(nw) / lever;
    const float J[6] = {a.x(), a.y(), a.z(), nw.x(), nw.y(), nw.z()};
    for (int p = 0; p < 6; ++p) {
      s.g[p] += wt * J[p] * e;
      for (int q = p; q < 6; ++q) s.H[p][q] += wt * J[p] * J[q];
    }
    s.cost += 1.f - (1.f - r2) * (1.f - r2) * (1.f - r2);
    s.sq += e * e;
    ++s.pairs;
  }
  for (int p = 0; p < 6; ++p)
    for (int q = 0; q < p; ++q) s.H[p][q] = s.H[q][p];
  return s;
}

// The head's samples: voxels that project where the hand saw a surface (as calibrated),
// so that none is wasted on what only the head saw, taken evenly over the classes of
// the head's normals there (normal_class): at most cap / 6 of each.
// - A first pass classifies every 16th voxel (count_step) and counts the classes; its
//   voxels facing up give the table's height and noise (raised_height), and those above
//   them are raised.
// - A class the first pass met at least quota times (a table fills most of the view
//   with one class) is abundant: it is taken from those voxels, every stride-th.
// - The others (an object's sides) are taken from every 4th voxel (every pre-th of
//   the grid), every stride-th of the class, but only where they can be: in the head's
//   view near a voxel of the first pass of such a class or on an edge the hand saw (a
//   cell of kSelectCellBins^2 head sight bins and its neighbours). Elsewhere a voxel costs
//   its projection only, not the two sensors' surfaces.
// - A scarce class (every pre-th voxel would not fill its quota either) is taken from
//   every voxel near where the first pass met it.
// Returns how many were taken into `samples`, and the height above which a surface is
// raised in `raised_z` (+infinity when the first pass met nothing facing up). A cell is
// kSelectCellBins head sight bins a side (31 mm at 1 m on the host).
static_assert(kNormalClasses + 2 <= 8, "a cell's classes in a byte's bits");
static_assert(kNormalClasses + 2 <= 16, "a first-pass class in 4 bits");
static_assert(size_t{kRegistrationSampleFloats} * kRegistrationSamples % 2 == 0, "the picking's work 8-byte aligned");
// The first pass visits at most 4 x cap + 1 voxels; three words each of its voxels facing
// up fit in the samples' room (one of them the voxel's index in the pass and its cell,
// 16 bits each).
constexpr uint32_t kFirstPassVoxels = 4u * kRegistrationSamples + 1u;
static_assert(size_t{3} * kFirstPassVoxels <= size_t{kRegistrationSampleFloats} * kRegistrationSamples,
              "the first pass's voxels facing up in the samples' room");
static_assert(kFirstPassVoxels <= 65536u && kSelectCells * kSelectCells <= 65536u, "16 bits each");

// The cells whose neighbourhood (the cell and the eight around it) met a class of
// `wanted_bits`, a bit each.
void mark_wanted_cells(const uint8_t* cell_classes, uint8_t wanted_bits, uint64_t* wanted_cells) {
  constexpr int kSide = static_cast<int>(kSelectCells);
  for (int cv = 0; cv < kSide; ++cv)
    for (int cu = 0; cu < kSide; ++cu) {
      if ((cell_classes[cv * kSide + cu] & wanted_bits) == 0u) continue;
      for (int y = cv - 1; y <= cv + 1; ++y)
        for (int x = cu - 1; x <= cu + 1; ++x)
          if (x >= 0 && y >= 0 && x < kSide && y < kSide) {
            const uint32_t b = static_cast<uint32_t>(y * kSide + x);
            wanted_cells[b / 64u] |= uint64_t{1} << (b % 64u);
          }
    }
}

// The table's height from the heights z[0, n) of surfaces facing up (reordered): the
// median of those within kTableBandM above their 10th percentile (the table is the
// lowest surface facing up, and the largest; the band keeps the objects' tops out).
// Returns the height above which a surface is raised: kRaisedM above the table, or
// four times the spread of the table's own heights (a far sensor's noise) if more;
// +infinity without heights.
constexpr float kTableBandM = 0.02f;
float raised_height(float* z, uint32_t n) {
  if (n == 0u) return std::numeric_limits<float>::infinity();
  float* const tenth = z + n / 10u;
  std::nth_element(z, tenth, z + n);
  const float lowest = *tenth;
  float* const band_end = std::partition(tenth, z + n, [lowest](float h) { return h <= lowest + kTableBandM; });
  const uint32_t band = static_cast<uint32_t>(band_end - tenth);  // at least the 10th percentile itself
  float* const median = tenth + band / 2u;
  std::nth_element(tenth, median, band_end);
  const float table_z = *median;
  float* const upper = tenth + (3u * band) / 4u;  // the 75th percentile: 0.67 spreads above the median
  std::nth_element(median, upper, band_end);
  const float spread = (*upper - table_z) / 0.6745f;
  return table_z + std::fmax(kRaisedM, 4.f * spread);
}

// What the picking reads: the grid, the sensors' views and the hand's moments; and
// how it classifies a voxel (the class codes above).
struct Picking {
  const VoxelGrid& grid;
  const SensorViews& views;
  const DepthMoments* moments;
  const Pose& hand;

  // The class code of the voxel at c.p, which lies at ph in the head's frame, in its
  // sight bin (u, v).
  uint8_t classify_in_view(Sample& c, const Vec3& ph, int u, int v) const {
    c.bin = -1;
    Vec3 w, nw;
    if (!hand_surface(moments, hand.R, hand.t, c, w, nw)) return kNotInView;
    if (!head_normal(views, ph, u, v, c.n)) return kEdge;
    // A surface that faces away from the hand (or is grazing to it): the hand did not
    // see it, whatever it saw in that direction.
    if (!(c.n.dot((hand.t - c.p).normalized()) >= kGrazingCos)) return kNotInView;
    return normal_class(c.n);
  }
  // Voxel i's class code, and its head sight bin (u, v) when it has one.
  uint8_t classify(uint32_t i, Sample& c, int& u, int& v) const {
    c.p = grid.centroid(i);
    c.bin = -1;
    Vec3 ph;
    if (!head_sight_bin(views, c.p, ph, u, v)) return kNotInView;
    return classify_in_view(c, ph, u, v);
  }
  static uint32_t cell_of(int u, int v) {
    return static_cast<uint32_t>((v / static_cast<int>(kSelectCellBins)) * static_cast<int>(kSelectCells) +
                                 u / static_cast<int>(kSelectCellBins));
  }
  static bool in_cells(const uint64_t* bits, int u, int v) {
    const uint32_t b = cell_of(u, v);
    return (bits[b / 64u] >> (b % 64u) & 1u) != 0u;
  }

  // The first pass, over every count_step-th voxel: each one's class code in 4 bits
  // (first_class), the codes met per cell (a bit each, cell_classes) and per class
  // (seen). Its voxels facing up wait in `room` (the samples', not yet taken) until the
  // table's height is known: those raised become kRaised. Returns the height above
  // which a surface is raised.
  float first_pass(uint32_t count_step, uint8_t* first_class, uint8_t* cell_classes, uint32_t* seen, void* room) const {
    uint32_t* const up_voxel = static_cast<uint32_t*>(room);  // index in the pass | cell << 16
    float* const up_z = reinterpret_cast<float*>(up_voxel + kFirstPassVoxels);
    float* const up_z_sorted = up_z + kFirstPassVoxels;
    uint32_t ups = 0;
    Sample c;
    for (uint32_t i = 0, j = 0; i < grid.size(); i += count_step, ++j) {
      int u = 0, v = 0;
      const uint8_t k = classify(i, c, u, v);
      first_class[j / 2u] = (j & 1u) == 0u ? k : static_cast<uint8_t>(first_class[j / 2u] | k << 4u);
      if (k < kNormalClasses) ++seen[k];
      if (k != kNotInView) cell_classes[cell_of(u, v)] |= static_cast<uint8_t>(1u << k);
      if (k == kUp) {
        up_voxel[ups] = j | cell_of(u, v) << 16u;
        up_z[ups] = up_z_sorted[ups] = c.p.z();
        ++ups;
      }
    }
    const float raised_z = raised_height(up_z_sorted, ups);
    for (uint32_t a = 0; a < ups; ++a) {
      if (!(up_z[a] > raised_z)) continue;
      const uint32_t j = up_voxel[a] & 0xFFFFu;
      const uint32_t kept = (j & 1u) != 0u ? 0x0Fu : 0xF0u;  // the other voxel's nibble
      first_class[j / 2u] = static_cast<uint8_t>((first_class[j / 2u] & kept) | uint32_t{kRaised} << (4u * (j & 1u)));
      cell_classes[up_voxel[a] >> 16u] |= static_cast<uint8_t>(1u << kRaised);
      --seen[kUp];
      ++seen[kRaised];
    }
    return raised_z;
  }
};

uint32_t select_samples(const VoxelGrid& grid, const SensorViews& views, const DepthMoments* moments, uint32_t cap,
                        Sample* samples, uint64_t* work, float& raised_z) {
  cap = cap < kRegistrationSamples ? cap : kRegistrationSamples;
  if (cap == 0u) return 0u;
  const uint32_t size = grid.size();
  const uint32_t pre = (size + 16u * cap - 1u) / (16u * cap);
  const uint32_t count_step = 4u * pre;  // at most 4 x cap voxels
  const uint32_t quota = cap / kNormalClasses > 0u ? cap / kNormalClasses : 1u;
  const Picking picking{grid, views, moments, views.pose[static_cast<uint32_t>(SensorRole::hand)]};
  uint8_t* const first_class = reinterpret_cast<uint8_t*>(work);
  uint8_t* const cell_classes = first_class + size_t{2} * kRegistrationSamples;
  uint64_t* const wanted_cells = work + (kSelectionClassBytes + 7u) / 8u;
  uint64_t* const dense_cells = wanted_cells + kSelectCellWords;
  for (uint32_t b = 0; b < kSelectCells * kSelectCells; ++b) cell_classes[b] = 0;
  for (uint32_t w = 0; w < 2u * kSelectCellWords; ++w) wanted_cells[w] = 0;
  uint32_t seen[kNormalClasses] = {};
  raised_z = picking.first_pass(count_step, first_class, cell_classes, seen, samples);
  // Abundant: the first pass alone met the quota; it is taken from those voxels. Scarce:
  // every pre-th voxel would not meet it either (a small object's sides and top); it is
  // taken from every voxel near where the first pass met it.
  uint32_t stride[kNormalClasses], taken[kNormalClasses] = {}, met[kNormalClasses] = {};
  bool abundant[kNormalClasses], scarce[kNormalClasses];
  uint8_t wanted_bits = static_cast<uint8_t>(1u << kEdge), scarce_bits = 0;
  for (uint32_t k = 0; k < kNormalClasses; ++k) {
    abundant[k] = seen[k] >= quota;
    scarce[k] = 4u * seen[k] < quota;
    const uint32_t met_expected = abundant[k] ? seen[k] : (scarce[k] ? 16u : 4u) * seen[k];
    stride[k] = met_expected > quota ? (met_expected + quota - 1u) / quota : 1u;
    if (!abundant[k]) wanted_bits |= static_cast<uint8_t>(1u << k);
    if (scarce[k]) scarce_bits |= static_cast<uint8_t>(1u << k);
  }
  mark_wanted_cells(cell_classes, wanted_bits, wanted_cells);
  mark_wanted_cells(cell_classes, scarce_bits, dense_cells);
  uint32_t n = 0;
  Sample c;
  // Voxel i, of the first pass (its class known) or not (`u`, `v` its head sight bin),
  // taken when its class still wants samples.
  const auto offer = [&](uint32_t i, bool first, uint8_t k, int u, int v) {
    if (k >= kNormalClasses || taken[k] == quota || n == cap) return;
    if ((abundant[k] && !first) || met[k]++ % stride[k] != 0u) return;
    if (first) (void)picking.classify(i, c, u, v);  // the sample's normal and hand surface
    ++taken[k];
    samples[n++] = c;
  };
  // Voxel i's class when its head sight bin lies in a wanted cell, else kNotInView.
  const auto rare_class = [&](uint32_t i, int& u, int& v) -> uint8_t {
    Vec3 ph;
    c.p = grid.centroid(i);
    if (!head_sight_bin(views, c.p, ph, u, v) || !Picking::in_cells(wanted_cells, u, v)) return kNotInView;
    return with_tops(picking.classify_in_view(c, ph, u, v), c.p.z(), raised_z);
  };
  for (uint32_t i = 0; i < size && n < cap; i += pre) {
    int u = 0, v = 0;
    if (i % count_step == 0u) {
      const uint32_t j = i / count_step;
      const uint8_t k = static_cast<uint8_t>(first_class[j / 2u] >> (4u * (j & 1u)) & 15u);
      offer(i, true, k, u, v);
      Vec3 ph;
      if (scarce_bits == 0u || k == kNotInView || !head_sight_bin(views, grid.centroid(i), ph, u, v)) continue;
    } else {
      const uint8_t k = rare_class(i, u, v);
      if (k == kNotInView) continue;
      offer(i, false, k, u, v);
    }
    if (!Picking::in_cells(dense_cells, u, v)) continue;
    // The voxels up to the next probe lie mostly where it does (the grid keeps the
    // order the sensor's rows came in): near a scarce class, each is looked at for it.
    // (None of them is of the first pass: its voxels are every count_step-th, a multiple
    // of pre.)
    for (uint32_t e = i + 1; e < i + pre && e < size && n < cap; ++e) {
      const uint8_t k = rare_class(e, u, v);
      if (k < kNormalClasses && scarce[k]) offer(e, false, k, u, v);
    }
  }
  return n;
}

// One Gauss-Newton step from the normal equations `s`: the increment (a turn about the
// pivot, scaled by the lever, then a move) folded into (R, t); its size at the samples.
float step_once(Sums& s, bool coarse, float lever, const Vec3& pivot, Mat3& R, Vec3& t) {
  // H x = -g over the directions the pairs constrain, none along the others. A pair
  // adds at most 1 to H along its own direction (unit normal; the turn scaled by the
  // lever), so an eigenvalue counts the pairs behind that direction: fewer than
  // kMinInformation, and a few stray pairs would decide it.
  // While the gate is wide (coarse: the first steps), only the translation moves: the
  // pairs then still include mismatches, which a turn, weakly held by a few centimetres
  // of object sides, would follow far; a turn's own error is mostly a shift locally.
  if (coarse)
    for (int p = 0; p < 3; ++p) {
      s.g[p] = 0.f;
      for (int q = 0; q < 6; ++q) s.H[p][q] = s.H[q][p] = p == q ? 1.f : 0.f;
    }
  float V[6][6], d[6];
  jacobi6(s.H, V, d);
  float dmax = 0.f;
  for (float di : d) dmax = std::fmax(dmax, di);
  float x[6] = {};
  for (int k = 0; k < 6; ++k) {
    if (!(d[k] >= kMinInformation) || !(d[k] > 1e-3f * dmax)) continue;
    float proj = 0.f;
    for (int p = 0; p < 6; ++p) proj += V[p][k] * s.g[p];
    for (int p = 0; p < 6; ++p) x[p] -= V[p][k] * proj / d[k];
  }
  const Vec3 w = Vec3(x[0], x[1], x[2]) / lever, tau(x[3], x[4], x[5]);
  const Mat3 dR = rotation_of(w);
  // The increment turns the hand's points about the pivot, then moves them by tau.
  const Vec3 dt = pivot - dR * pivot + tau;
  R = dR * R;
  t = dR * t + dt;
  return tau.norm() + w.norm() * lever;
}

// Whether the head saw past the world point w along its ray by more than `margin`: its
// nearest returns in w's direction bin and the eight around it all lie beyond w (its
// sight map). The neighbours keep a silhouette, where a bin's nearest return may come
// from the background beside w, and a single bin without returns (a dropout) out of it.
bool head_saw_past(const SensorViews& views, const Vec3& w, float margin) {
  constexpr uint32_t kHeadRole = static_cast<uint32_t>(SensorRole::head);
  Vec3 p;
  int u = 0, v = 0;
  if (!head_sight_bin(views, w, p, u, v)) return false;
  for (int dv = -1; dv <= 1; ++dv)
    for (int du = -1; du <= 1; ++du) {
      const uint16_t mm = views.sight_mm[kHeadRole][(v + dv) * static_cast<int>(kSightBins) + (u + du)];
      if (mm == 0xFFFFu || !(0.001f * static_cast<float>(mm) > p.z() + margin)) return false;
    }
  return true;
}

// The two clouds against each other with the hand at `hand` (the pose the fusion will
// use): of the head's samples where the hand saw a surface (`compared`), the share where
// one sensor saw through the other's surface by more than `margin`. A surface is
// solid: a ray cannot pass it and return from behind it. So the hand cannot see a
// surface behind a head sample (the sample lies in front of it, toward the hand), nor
// the head past the hand's surface. Either way the two clouds place the same surface
// in different places; checked both ways, since an error that moves the hand's
// surfaces toward the hand hides them from the first test.
float see_through_share(const SensorViews& views, const DepthMoments* moments, const Pose& hand, Sample* samples,
                        uint32_t n, float margin, uint32_t& compared) {
  uint32_t through = 0;
  compared = 0;
  for (uint32_t i = 0; i < n; ++i) {
    Vec3 w, nw;
    if (!hand_surface(moments, hand.R, hand.t, samples[i], w, nw)) continue;
    ++compared;
    // nw faces the hand: a sample at w + a nw (a > 0) lies a in front of the surface.
    if (nw.dot(w - samples[i].p) < -margin || head_saw_past(views, w, margin)) ++through;
  }
  return compared > 0 ? static_cast<float>(through) / static_cast<float>(compared) : 0.f;
}

// Each sensor's table as its own surfaces place it, the hand at `hand`: the mean normal
// of its samples' surfaces that face within 30 degrees of world up (kFacingUpCos: the
// table and the objects' tops; a side is steeper), then again of those within 10
// degrees of that mean (kTableSpreadCos: the table's own normals scatter by a few
// degrees, a dome's or a sloped top's do not stay with them); its angle off up, in
// degrees. NaN with fewer than min_level_samples in either mean.
constexpr float kFacingUpCos = 0.866f;     // 30 deg
constexpr float kTableSpreadCos = 0.985f;  // 10 deg
template <class NormalOf>
float table_tilt_deg(uint32_t n, uint32_t min_count, NormalOf normal_of) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  Vec3 mean = Vec3::UnitZ();
  float cos_min = kFacingUpCos;
  for (int round = 0; round < 2; ++round) {
    Vec3 sum = Vec3::Zero();
    uint32_t count = 0;
    for (uint32_t i = 0; i < n; ++i) {
      Vec3 nw;
      if (normal_of(i, nw) && nw.dot(mean) >= cos_min) {
        sum += nw;
        ++count;
      }
    }
    if (count < min_count || !(sum.norm() > 0.f)) return nan;
    mean = sum / sum.norm();
    cos_min = kTableSpreadCos;
  }
  return std::acos(mean.z() > 1.f ? 1.f : mean.z()) * 57.2957795f;
}
void table_tilts(const DepthMoments* moments, const Pose& hand, Sample* samples, uint32_t n,
                 const RegistrationParams& params, RegistrationResult& out) {
  out.head_tilt_deg = table_tilt_deg(n, params.min_level_samples, [&](uint32_t i, Vec3& nw) {
    nw = samples[i].n;
    return true;
  });
  out.hand_tilt_deg = table_tilt_deg(n, params.min_level_samples, [&](uint32_t i, Vec3& nw) {
    Vec3 w;
    return hand_surface(moments, hand.R, hand.t, samples[i], w, nw);
  });
}

// Stage A.4b's second step: the slide along the table. Point-to-plane pairs fix the
// height and the tilt from the table and the objects' tops, but the slide only from the
// sides both sensors saw and the tops' slopes, and sensors that look from opposite sides
// see few of either: too few pairs for the alignment to move along the table
// (kMinInformation). Where a surface both saw curves or ends, though, a wrong slide puts
// the hand's depth along its ray off the head's samples there. The slide is searched on
// a grid, coarse to fine, for the least projective misfit of the head's samples off the
// table: a global search, where the alignment's steps would follow the few pairs into a
// wrong minimum.

// At most this many samples off the table take part (every k-th of them), in the hand's
// frame: the selection's work memory, idle by then, holds them.
constexpr uint32_t kSlideSamples =
    static_cast<uint32_t>(2u * kSelectionWords / 3u) < 256u ? static_cast<uint32_t>(2u * kSelectionWords / 3u) : 256u;

// The hand's mean depth along the ray to the point q (the hand's frame), bilinear
// between the centres of its map's bins, minus q's depth: false outside the map or where
// the hand saw too little around it.
bool projective_residual(const DepthMoments* map, const Vec3& q, float& r) {
  constexpr float half = 0.5f * static_cast<float>(kMomentBins);
  if (!(q.z() > 0.05f)) return false;
  const float inv = 1.f / q.z();
  const float bu = (q.x() * inv + 1.f) * half - 0.5f, bv = (q.y() * inv + 1.f) * half - 0.5f;
  constexpr float hi = static_cast<float>(kMomentBins - 1);
  if (!(bu >= 0.f && bv >= 0.f && bu < hi && bv < hi)) return false;
  const int u = static_cast<int>(bu), v = static_cast<int>(bv);
  const float fu = bu - static_cast<float>(u), fv = bv - static_cast<float>(v);
  const float w[4] = {(1.f - fu) * (1.f - fv), fu * (1.f - fv), (1.f - fu) * fv, fu * fv};
  const DepthMoments* m = map + static_cast<size_t>(v) * kMomentBins + static_cast<size_t>(u);
  const DepthMoments* corner[4] = {m, m + 1, m + kMomentBins, m + kMomentBins + 1};
  float depth = 0.f, wsum = 0.f;
  for (int k = 0; k < 4; ++k)
    if (corner[k]->n >= kMinReturns) {
      depth += w[k] * corner[k]->sum / corner[k]->n;
      wsum += w[k];
    }
  // Most of the weight on bins with returns: else the hand saw too little there.
  if (!(wsum > 0.5f)) return false;
  r = depth / wsum - q.z();
  return true;
}

// The misfit of the samples q[0, n) (the hand's frame) with the hand moved by `shift`
// (its frame: the samples move by -shift): per sample, the squared residual within
// `gate`, else gate^2 (seen through, hidden, or not seen).
float projective_misfit(const DepthMoments* map, const Vec3* q, uint32_t n, const Vec3& shift, float gate) {
  float cost = 0.f;
  for (uint32_t i = 0; i < n; ++i) {
    float r = 0.f;
    const bool seen = projective_residual(map, q[i] - shift, r);
    cost += seen && std::fabs(r) < gate ? r * r : gate * gate;
  }
  return cost;
}

// The slide (world, along the table) that best fits the m samples off the table to the
// hand's surfaces at `hand`: a grid of (2 * kSlideSteps + 1)^2 slides slide_step apart,
// then kSlideRefinements grids of 3 x 3, each half as fine, around the best. `q` holds
// kSlideSamples points. Zero unless it lowers the misfit by min_slide_gain_samples
// samples' worth (gate^2 each) and by the share min_slide_gain: noise alone, fitted,
// gains a few samples' worth, and a misfit that stays flat says the slide is not seen.
constexpr int kSlideSteps = 3;
constexpr int kSlideRefinements = 3;
Vec3 search_slide(const DepthMoments* map, const Pose& hand, const Sample* samples, uint32_t m,
                  const RegistrationParams& params, Vec3* q) {
  if (m < params.min_slide_samples) return Vec3::Zero();
  const uint32_t every = (m + kSlideSamples - 1u) / kSlideSamples;
  uint32_t nq = 0;
  for (uint32_t i = 0; i < m; i += every) q[nq++] = hand.R.transpose() * (samples[i].p - hand.t);
  const float gate = params.gate_end_m;
  // A world slide s moves the hand's frame by R^T s.
  const Vec3 ex = hand.R.transpose() * Vec3::UnitX(), ey = hand.R.transpose() * Vec3::UnitY();
  const float at_zero = projective_misfit(map, q, nq, Vec3::Zero(), gate);
  float bx = 0.f, by = 0.f, best_cost = at_zero;
  float step = params.slide_step_m;
  int reach = kSlideSteps;
  for (int level = 0; level <= kSlideRefinements; ++level) {
    const float cx = bx, cy = by;
    for (int iy = -reach; iy <= reach; ++iy)
      for (int ix = -reach; ix <= reach; ++ix) {
        if (ix == 0 && iy == 0) continue;  // the centre's cost is known
        const float x = cx + static_cast<float>(ix) * step, y = cy + static_cast<float>(iy) * step;
        const float cost = projective_misfit(map, q, nq, x * ex + y * ey, gate);
        if (cost < best_cost) {
          best_cost = cost;
          bx = x;
          by = y;
        }
      }
    step *= 0.5f;
    reach = 1;
  }
  const float gain = at_zero - best_cost;
  const bool found = gain >= params.min_slide_gain_samples * gate * gate && gain >= params.min_slide_gain * at_zero;
  return found ? Vec3(bx, by, 0.f) : Vec3::Zero();
}

// The RMS residual of the pairs of `s` (mm); 0 without pairs.
float rms_mm(const Sums& s) { return s.pairs > 0 ? 1000.f * std::sqrt(s.sq / static_cast<float>(s.pairs)) : 0.f; }

// `out` corrected by `c`, which moves the hand's origin by moved_origin (m).
void set_corrected(const Pose& c, float moved_origin, RegistrationResult& out) {
  out.outcome = RegistrationOutcome::corrected;
  out.correction = c;
  out.translation_mm = 1000.f * moved_origin;
  out.rotation_deg = angle_of(c.R) * 57.2957795f;
}

// The slide (search_slide) after the alignment `out` of the hand at `given`, folded into
// its correction when it is more than noise and the whole stays within the capture range.
void slide(const DepthMoments* moments, const Pose& given, Sample* samples, uint32_t n, uint32_t m,
           const RegistrationParams& params, Vec3* work, RegistrationResult& out) {
  const Vec3 shift = search_slide(moments, out.hand_pose(given), samples, m, params, work);
  if (!(shift.norm() >= params.min_correction_m)) return;
  Pose c = out.outcome == RegistrationOutcome::corrected ? out.correction : Pose{};
  c.t += shift;
  const float moved_origin = (c.R * given.t + c.t - given.t).norm();
  if (moved_origin > params.max_translation_m) return;
  const Sums after = accumulate(moments, given, samples, n, c.R, c.t, Vec3::Zero(), 1.f, params.gate_end_m);
  set_corrected(c, moved_origin, out);
  if (after.pairs > 0) out.residual_mm = rms_mm(after);
}

// The alignment of the samples (A.4b) and its verdict.
RegistrationResult align(const DepthMoments* moments, const Pose& hand, Sample* samples, uint32_t n,
                         const RegistrationParams& params) {
  RegistrationResult out;
  out.samples = n;
  Vec3 pivot = Vec3::Zero();
  for (uint32_t i = 0; i < n; ++i) pivot += samples[i].p;
  pivot /= static_cast<float>(n);
  float spread = 0.f;
  for (uint32_t i = 0; i < n; ++i) spread += (samples[i].p - pivot).squaredNorm();
  // The lever turns rotations into millimetres at the samples: their RMS distance from
  // the pivot (at least 5 cm, the size of a small object).
  const float lever = std::fmax(std::sqrt(spread / static_cast<float>(n)), 0.05f);

  Mat3 R = Mat3::Identity();
  Vec3 t = Vec3::Zero();
  float gate = params.gate_start_m;
  uint32_t it = 0;
  for (; it < params.max_iterations; ++it) {
    Sums s = accumulate(moments, hand, samples, n, R, t, pivot, lever, gate);
    if (s.pairs < 6u) break;
    const float step = step_once(s, gate > 2.f * params.gate_end_m, lever, pivot, R, t);
    // The gate shrinks to the final one as the alignment settles: wide first, to
    // capture surfaces centimetres apart, narrow last, to keep edges out.
    gate = std::fmax(params.gate_end_m, std::fmin(gate, 0.5f * gate + 2.f * step));
    if (step < 1e-4f && gate <= params.gate_end_m) {
      ++it;
      break;
    }
  }
  out.iterations = it;

  // The verdict, on the final gate: as calibrated and as corrected.
  const Sums before =
      accumulate(moments, hand, samples, n, Mat3::Identity(), Vec3::Zero(), pivot, lever, params.gate_end_m);
  const Sums after = accumulate(moments, hand, samples, n, R, t, pivot, lever, params.gate_end_m);
  out.residual_before_mm = rms_mm(before);
  const float moved_origin = (R * hand.t + t - hand.t).norm();
  const float angle = angle_of(R);
  // The largest move over the samples' extent: the pivot's plus the turn at the lever.
  const float move = (R * pivot + t - pivot).norm() + angle * lever;
  const bool enough =
      after.pairs >= params.min_pairs && static_cast<float>(after.pairs) >= params.min_overlap * static_cast<float>(n);
  out.pairs = enough ? after.pairs : before.pairs;
  out.overlap = static_cast<float>(out.pairs) / static_cast<float>(n);
  out.residual_mm = out.residual_before_mm;
  if (!enough && before.pairs < params.min_pairs) {
    out.outcome = RegistrationOutcome::too_little_overlap;
    return out;
  }
  if (moved_origin > params.max_translation_m || angle > params.max_rotation_rad) {
    out.outcome = RegistrationOutcome::implausible;
    return out;
  }
  // Kept unless the correction moves the hand's surfaces by more than the noise and
  // explains a share of their disagreement: the cost (the missing pairs counted at the
  // kernel's saturated value) falls by min_cost_drop at least. Noise alone, fitted,
  // lowers it by a few percent.
  const float cost_before = before.cost + static_cast<float>(n - before.pairs);
  const float cost_after = after.cost + static_cast<float>(n - after.pairs);
  if (!enough || move < params.min_correction_m || !(cost_after < (1.f - params.min_cost_drop) * cost_before)) {
    out.outcome = RegistrationOutcome::calibration_kept;
    return out;
  }
  Pose c;
  c.R = R;
  c.t = t;
  set_corrected(c, moved_origin, out);
  out.residual_mm = rms_mm(after);
  return out;
}

}  // namespace

RegistrationResult register_hand(const VoxelGrid& grid, const SensorViews& views, const DepthMoments* moments,
                                 const RegistrationParams& params, float* scratch) {
  RegistrationResult out;
  if (grid.finalized()) return out;
  Sample* samples = reinterpret_cast<Sample*>(scratch);
  uint64_t* const work =
      reinterpret_cast<uint64_t*>(scratch + size_t{kRegistrationSampleFloats} * kRegistrationSamples);
  float raised_z = 0.f;
  const uint32_t n = select_samples(grid, views, moments, params.max_samples, samples, work, raised_z);
  if (n == 0) {
    out.outcome = RegistrationOutcome::too_little_overlap;
    return out;
  }
  const Pose& given = views.pose[static_cast<uint32_t>(SensorRole::hand)];
  out = align(moments, given, samples, n, params);
  if (out.outcome == RegistrationOutcome::corrected || out.outcome == RegistrationOutcome::calibration_kept) {
    // The samples off the table first: the slide is searched on them.
    Sample* const off_table = std::partition(samples, samples + n, [raised_z](const Sample& smp) {
      return with_tops(normal_class(smp.n), smp.p.z(), raised_z) != kUp;
    });
    const uint32_t m = static_cast<uint32_t>(off_table - samples);
    slide(moments, given, samples, n, m, params, reinterpret_cast<Vec3*>(work), out);
  }
  // A.4c: whatever the alignment's verdict, do the clouds agree as they will be fused?
  const Pose used = out.hand_pose(given);
  out.see_through = see_through_share(views, moments, used, samples, n, params.see_through_m, out.compared);
  if (out.compared >= params.min_pairs && out.see_through > params.max_see_through) {
    out.outcome = RegistrationOutcome::sensor_disagreement;
    out.correction = Pose{};
    out.translation_mm = out.rotation_deg = 0.f;
    out.residual_mm = out.residual_before_mm;
    // Which one to believe: the sensor whose table is level, as the world's is. The
    // head (fixed, calibrated once) unless its table is off level and the hand's is not.
    table_tilts(moments, given, samples, n, params, out);
    const float level_deg = params.level_tilt_rad * 57.2957795f;
    out.left_out =
        out.head_tilt_deg > level_deg && out.hand_tilt_deg <= level_deg ? SensorRole::head : SensorRole::hand;
  }
  return out;
}

}  // namespace fg
