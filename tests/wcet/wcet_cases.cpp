// Worst-case timing harness: the input generators (docs/worst-case-timing.md explains
// each case). Every adversarial case is sized from the build's capacities
// (kMaxVoxels, kMaxObjectPoints, kMaxViewpoints, kMaxScanLines, kMaxCandidates,
// kRansacMaxIters, ...) and starts from the default PlannerConfig; the options a case
// changes are listed in CaseInput::overrides (all within their validated ranges).
#include "wcet_cases.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <unordered_set>

#include "fg/core/limits.hpp"
#include "io/config_options.hpp"
#include "io/pcd.hpp"
#include "io/ply.hpp"
#include "io/scene.hpp"
#include "sim/pinhole.hpp"
#include "sim/scene_gen.hpp"

#ifndef FG_SOURCE_DIR
#define FG_SOURCE_DIR "."
#endif

namespace fg::wcet {
namespace {

constexpr float kPi = 3.14159265358979f;

// A host-class build (sized for two 640x480 sensors) or a small one (cortex-m7 class).
bool small_build() { return kMaxVoxels < 32768u; }

// splitmix64: the generators' own deterministic random numbers.
struct Rng {
  uint64_t s;
  explicit Rng(uint64_t seed) : s(seed) {}
  uint64_t next() {
    uint64_t z = (s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  uint32_t below(uint32_t n) { return static_cast<uint32_t>(next() % n); }
  float unit() { return static_cast<float>(next() >> 40) / static_cast<float>(1ull << 24); }  // [0, 1)
  float sym() { return 2.f * unit() - 1.f; }                                                  // [-1, 1)
};

// A sensor looking straight down from `pos` (optical z = world -z): its range filter
// (sensor-frame depth z in [range_min, range_max]) then keeps the world heights
// pos.z - range_max .. pos.z - range_min wherever the point lies in x and y.
Pose top_down(float x, float y, float z) {
  Pose p;
  p.R << 1.f, 0.f, 0.f, 0.f, -1.f, 0.f, 0.f, 0.f, -1.f;
  p.t = Vec3(x, y, z);
  return p;
}

// The planner's voxel grid as planner_ingest.cpp sets it up in reset(): cell (0,0,0)
// has its corner 2.5 cells below the crop box's lower corner; cell i's centre is
// origin + (i + 0.5) * leaf. The crop box spans cells [2, 2 + n) per axis; the
// generators keep to [3, 2 + n - 1) so no point sits on the crop boundary.
struct Grid {
  Vec3 origin = Vec3::Zero();
  float leaf = 0.005f;
  int nx = 0, ny = 0, nz = 0;
  Vec3 centre(int i, int j, int k) const {
    return origin +
           leaf * Vec3(static_cast<float>(i) + 0.5f, static_cast<float>(j) + 0.5f, static_cast<float>(k) + 0.5f);
  }
  int cell_x(float x) const { return static_cast<int>(std::floor((x - origin.x()) / leaf)); }
  int cell_y(float y) const { return static_cast<int>(std::floor((y - origin.y()) / leaf)); }
  int cell_z(float z) const { return static_cast<int>(std::floor((z - origin.z()) / leaf)); }
  // The cells the cases fill: those of the crop box that its shrink keeps (the box of
  // crop_shrink_min about the workspace centre, Planner::shrink_crop), so a case of
  // kMaxVoxels cells pays for the shrink's compactions and keeps every cell.
  int xlo = 3, xhi = 0, ylo = 3, yhi = 0;
  int x_lo() const { return xlo; }
  int x_hi() const { return xhi; }  // exclusive
  int y_lo() const { return ylo; }
  int y_hi() const { return yhi; }
};

Grid grid_of(const PlannerConfig& c) {
  Grid g;
  g.leaf = c.voxel_leaf_m;
  const Vec3 lo(c.workspace_centre_x_m - c.crop_half_x_m, c.workspace_centre_y_m - c.crop_half_y_m, c.crop_min_z_m);
  g.origin = lo - Vec3::Constant(2.5f * c.voxel_leaf_m);
  g.nx = static_cast<int>(std::floor(2.f * c.crop_half_x_m / c.voxel_leaf_m + 1e-3f));
  g.ny = static_cast<int>(std::floor(2.f * c.crop_half_y_m / c.voxel_leaf_m + 1e-3f));
  g.nz = static_cast<int>(std::floor((c.crop_max_z_m - c.crop_min_z_m) / c.voxel_leaf_m + 1e-3f));
  g.xhi = 2 + g.nx - 1;
  g.yhi = 2 + g.ny - 1;
  // Planner::shrink_crop's floor box in cells: [ceil(centre - half), floor(centre + half)).
  const float half = c.crop_shrink_min_m / c.voxel_leaf_m;
  const float cx = (c.workspace_centre_x_m - g.origin.x()) / c.voxel_leaf_m;
  const float cy = (c.workspace_centre_y_m - g.origin.y()) / c.voxel_leaf_m;
  g.xlo = std::max(g.xlo, static_cast<int>(std::ceil(cx - half)));
  g.xhi = std::min(g.xhi, static_cast<int>(std::floor(cx + half)));
  g.ylo = std::max(g.ylo, static_cast<int>(std::ceil(cy - half)));
  g.yhi = std::min(g.yhi, static_cast<int>(std::floor(cy + half)));
  return g;
}

// The synthetic cases' rig: two sensors above the workspace centre looking straight
// down, 0.6 m to either side in y (hand +y, head -y), so an upright object at the
// centre is seen from opposite sides (the sensor arc about a vertical axis is 180 deg).
// Points are generated between world z = kZLo and the rig's highest accepted height.
constexpr float kSideOffset = 0.6f;
constexpr float kZLo = 0.0f;

// Builds the two clouds from sets of distinct cells.
class Builder {
 public:
  Builder(const PlannerConfig& cfg, float sensor_height) : cfg_(cfg), g_(grid_of(cfg)), height_(sensor_height) {
    z_hi_ = sensor_height - cfg.range_min_m - 0.02f;
    z_hi_ = std::min(z_hi_, cfg.crop_max_z_m - 0.02f);
  }
  const Grid& grid() const { return g_; }
  float z_hi() const { return z_hi_; }
  int k_lo() const { return std::max(g_.cell_z(kZLo), 3); }
  int k_hi() const { return g_.cell_z(z_hi_); }  // inclusive
  bool in_range(int i, int j, int k) const {
    return i >= g_.x_lo() && i < g_.x_hi() && j >= g_.y_lo() && j < g_.y_hi() && k >= k_lo() && k <= k_hi();
  }
  static uint64_t key(int i, int j, int k) {
    return static_cast<uint64_t>(i) | (static_cast<uint64_t>(j) << 21) | (static_cast<uint64_t>(k) << 42);
  }
  bool used(int i, int j, int k) const { return used_.count(key(i, j, k)) != 0; }
  //! True when no used cell lies in the 3x3x3 block around (i, j, k) (so a new cell
  //! there is a cluster of its own under 26-connectivity).
  bool isolated(int i, int j, int k, int r = 1) const {
    for (int dz = -r; dz <= r; ++dz)
      for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx)
          if (used(i + dx, j + dy, k + dz)) return false;
    return true;
  }
  //! Adds a cell (once) to the head's (sensor 0) or the hand's (1) list; `jitter` is the
  //! largest offset from the cell centre, per axis, in cells (0: exact centres).
  bool add(int sensor, int i, int j, int k, float jitter = 0.3f) {
    if (!in_range(i, j, k)) return false;
    if (!used_.insert(key(i, j, k)).second) return false;
    Vec3 p = g_.centre(i, j, k);
    if (jitter > 0.f) p += g_.leaf * jitter * Vec3(rng_.sym(), rng_.sym(), rng_.sym());
    cells_[sensor].push_back(p);
    return true;
  }
  bool add_world(int sensor, const Vec3& p, float jitter = 0.3f) {
    return add(sensor, g_.cell_x(p.x()), g_.cell_y(p.y()), g_.cell_z(p.z()), jitter);
  }
  //! Appends a point to a sensor's list without claiming a cell (the cell is shared).
  void append(int sensor, const Vec3& p) { cells_[sensor].push_back(p); }
  const std::vector<Vec3>& list(int sensor) const { return cells_[sensor]; }
  uint32_t distinct() const { return static_cast<uint32_t>(used_.size()); }
  uint32_t count(int sensor) const { return static_cast<uint32_t>(cells_[sensor].size()); }
  Rng& rng() { return rng_; }

  //! Each sensor's cloud: its cells cycled in order until `points` points (so every
  //! case offers the same input volume as the typical one; with more distinct cells
  //! than the ingest's cell cache, every point misses it).
  void finish(CaseInput& out, uint32_t points) const {
    const float cx = cfg_.workspace_centre_x_m, cy = cfg_.workspace_centre_y_m;
    const Pose poses[2] = {top_down(cx, cy - kSideOffset, height_), top_down(cx, cy + kSideOffset, height_)};
    const SensorRole roles[2] = {SensorRole::head, SensorRole::hand};
    for (int s = 0; s < 2; ++s) {
      const std::vector<Vec3>& c = cells_[s];
      if (c.empty()) continue;
      SensorInput in;
      in.role = roles[s];
      in.pose = poses[s];
      in.xyz.resize(static_cast<size_t>(points) * 3);
      for (uint32_t i = 0; i < points; ++i) {
        const Vec3 w = c[i % c.size()];
        // p_sensor = R^T (p_world - t) with R = diag(1, -1, -1).
        in.xyz[3 * i + 0] = w.x() - in.pose.t.x();
        in.xyz[3 * i + 1] = in.pose.t.y() - w.y();
        in.xyz[3 * i + 2] = in.pose.t.z() - w.z();
      }
      out.sensors.push_back(std::move(in));
    }
    out.distinct_cells = distinct();
  }

 private:
  PlannerConfig cfg_;
  Grid g_;
  float height_;
  float z_hi_;
  std::unordered_set<uint64_t> used_;
  std::vector<Vec3> cells_[2];
  Rng rng_{0x5eed1234ull};
};

char buf[512];
template <typename... A>
std::string fmt(const char* f, A... a) {
  std::snprintf(buf, sizeof buf, f, a...);
  return buf;
}

void set(CaseInput& c, const char* name, float v, float& field) {
  field = v;
  c.overrides.push_back(fmt("%s=%g", name, static_cast<double>(v)));
}
void set(CaseInput& c, const char* name, uint32_t v, uint32_t& field) {
  field = v;
  c.overrides.push_back(fmt("%s=%u", name, v));
}

// ---------------------------------------------------------------- shapes (cell sets)

// Cells of a sphere shell (|centre distance - r| <= leaf / 2).
template <typename F>
void sphere_shell(const Grid& g, const Vec3& c, float r, F&& take) {
  const int i0 = g.cell_x(c.x() - r) - 1, i1 = g.cell_x(c.x() + r) + 1;
  const int j0 = g.cell_y(c.y() - r) - 1, j1 = g.cell_y(c.y() + r) + 1;
  const int k0 = g.cell_z(c.z() - r) - 1, k1 = g.cell_z(c.z() + r) + 1;
  for (int k = k0; k <= k1; ++k)
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const float d = (g.centre(i, j, k) - c).norm();
        if (std::fabs(d - r) <= 0.5f * g.leaf) take(i, j, k);
      }
}

// Cells of a vertical tube (|xy distance - r| <= leaf / 2), z in [z0, z1].
template <typename F>
void tube(const Grid& g, float cx, float cy, float r, float z0, float z1, F&& take) {
  const int i0 = g.cell_x(cx - r) - 1, i1 = g.cell_x(cx + r) + 1;
  const int j0 = g.cell_y(cy - r) - 1, j1 = g.cell_y(cy + r) + 1;
  for (int k = g.cell_z(z0); k <= g.cell_z(z1); ++k)
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const Vec3 p = g.centre(i, j, k);
        const float d = std::hypot(p.x() - cx, p.y() - cy);
        if (std::fabs(d - r) <= 0.5f * g.leaf) take(i, j, k);
      }
}

// Cells on the surface of an axis-aligned box [lo, hi].
template <typename F>
void box_shell(const Grid& g, const Vec3& lo, const Vec3& hi, F&& take) {
  const int i0 = g.cell_x(lo.x()), i1 = g.cell_x(hi.x());
  const int j0 = g.cell_y(lo.y()), j1 = g.cell_y(hi.y());
  const int k0 = g.cell_z(lo.z()), k1 = g.cell_z(hi.z());
  for (int k = k0; k <= k1; ++k)
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i)
        if (i == i0 || i == i1 || j == j0 || j == j1 || k == k0 || k == k1) take(i, j, k);
}

// Isolated single cells (noise clusters of one voxel) at random places of the whole
// crop box and height range, at least `clear` cells from every used cell, until the
// builder holds `total` distinct cells. Alternates between the sensors from `sensor`.
bool scatter_singletons(Builder& b, uint32_t total, int sensor, int clear = 1) {
  const Grid& g = b.grid();
  uint64_t tries = 0;
  while (b.distinct() < total) {
    if (++tries > 100ull * total + 100000ull) return false;
    const int i = g.x_lo() + static_cast<int>(b.rng().below(static_cast<uint32_t>(g.x_hi() - g.x_lo())));
    const int j = g.y_lo() + static_cast<int>(b.rng().below(static_cast<uint32_t>(g.y_hi() - g.y_lo())));
    const int k = b.k_lo() + static_cast<int>(b.rng().below(static_cast<uint32_t>(b.k_hi() - b.k_lo() + 1)));
    if (!b.isolated(i, j, k, clear)) continue;
    b.add(sensor, i, j, k);
    sensor = 1 - sensor;
  }
  return true;
}

// ---------------------------------------------------------------- the typical cases

bool load_example(CaseInput& out, std::string& err) {
  const std::string path = std::string(FG_SOURCE_DIR) + "/examples/two-sensor-box/scene.json";
  host::Scene scene;
  if (auto r = host::read_scene(path, scene); !r.ok) {
    err = r.error;
    return false;
  }
  out.cfg.gripper.max_opening_m = static_cast<float>(scene.gripper.max_opening);
  out.cfg.gripper.finger_width_m = static_cast<float>(scene.gripper.finger_width);
  out.cfg.gripper.finger_depth_m = static_cast<float>(scene.gripper.finger_depth);
  for (const auto& s : scene.sensors) {
    if (!s.pose) {
      err = "the example scene needs sensor poses";
      return false;
    }
    host::PointCloud c;
    if (auto r = host::read_cloud(s.cloud_path, c); !r.ok) {
      err = r.error;
      return false;
    }
    SensorInput in;
    in.role = s.name == "head" ? SensorRole::head : SensorRole::hand;
    in.pose = host::to_pose(*s.pose);
    in.xyz.assign(c.xyz.begin(), c.xyz.end());
    out.sensors.push_back(std::move(in));
  }
  out.note = "examples/two-sensor-box (real two-sensor capture, 2 x 640x480 PCD)";
  return true;
}

// A simulated box on a table seen by the head and hand cameras (hal/sim, Xtion-like
// noise), through add_depth_image. Host builds: 640x480 and the default config. Small
// builds: the same scene at 160x120 with the crop box narrowed to +-0.15 m about the
// object (the whole table at 5 mm does not fit 4,096 voxels).
bool sim_box(CaseInput& out, std::string& err) {
  constexpr uint64_t kSeed = 7;
  sim::SceneOptions opt;
  opt.second_object_rate = 0.0;
  if (small_build()) {
    opt.intrinsics.width = 160;
    opt.intrinsics.height = 120;
    opt.intrinsics.fx = opt.intrinsics.fy = 131.25;
    opt.intrinsics.cx = 79.5;
    opt.intrinsics.cy = 59.5;
  }
  const sim::GeneratedScene scene = sim::make_scene(sim::ObjectKind::box, kSeed, opt);
  const sim::SceneImages img = sim::render_scene(scene);
  if (small_build()) {
    set(out, "workspace_centre_x", static_cast<float>(scene.truth.target_centre.x()), out.cfg.workspace_centre_x_m);
    set(out, "workspace_centre_y", static_cast<float>(scene.truth.target_centre.y()), out.cfg.workspace_centre_y_m);
    set(out, "crop_half_x", 0.15f, out.cfg.crop_half_x_m);
    set(out, "crop_half_y", 0.15f, out.cfg.crop_half_y_m);
  }
  const sim::DepthImage* ims[2] = {&img.head, &img.hand};
  const sim::Camera* cams[2] = {&scene.head, &scene.hand};
  for (int s = 0; s < 2; ++s) {
    SensorInput in;
    in.role = s == 0 ? SensorRole::head : SensorRole::hand;
    in.pose = cams[s]->world_T_sensor.to_pose();
    in.depth = ims[s]->mm;
    in.width = static_cast<uint16_t>(ims[s]->width);
    in.height = static_cast<uint16_t>(ims[s]->height);
    in.k = fg::sim::to_pinhole(cams[s]->K);
    out.sensors.push_back(std::move(in));
  }
  out.note = fmt("hal/sim box seed %llu, 2 x %dx%d depth images", static_cast<unsigned long long>(kSeed),
                 opt.intrinsics.width, opt.intrinsics.height);
  (void)err;
  return true;
}

// ---------------------------------------------------------------- adversarial cases

// Every point in its own voxel: a lattice of kMaxVoxels cells two cells apart (no two
// cells touch, so each is a cluster of one), each cell used once per cycle of the
// input, so (with more cells than the ingest's cache) every point misses the cache.
// Lattice layers hold less than 10% of the cells: no plane is accepted.
bool own_voxel(CaseInput& out, uint32_t points, uint32_t cells, std::string& err) {
  Builder b(out.cfg, 0.8f);
  const int layers_max = (b.k_hi() - b.k_lo()) / 2 + 1;
  int C = static_cast<int>(std::lround(std::cbrt(static_cast<double>(kMaxVoxels)) / 2.0));
  C = std::min(std::max(C, 11), layers_max);
  const int A = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(cells) / C)));
  const Grid& g = b.grid();
  if (2 * A > g.x_hi() - g.x_lo() || 2 * A > g.y_hi() - g.y_lo()) {
    err = "lattice does not fit the crop box";
    return false;
  }
  const int i0 = (g.x_lo() + g.x_hi()) / 2 - A, j0 = (g.y_lo() + g.y_hi()) / 2 - A;
  uint32_t n = 0;
  for (int c = 0; c < C && n < cells; ++c)
    for (int a = 0; a < A && n < cells; ++a)
      for (int bb = 0; bb < A && n < cells; ++bb) {
        // First half of the cells to the head, the rest to the hand.
        if (b.add(n < cells / 2 ? 0 : 1, i0 + 2 * a, j0 + 2 * bb, b.k_lo() + 2 * c)) ++n;
      }
  if (n != cells) {
    err = "lattice generation failed";
    return false;
  }
  b.finish(out, points);
  out.note = fmt("%u cells, lattice %dx%dx%d at 2-cell spacing, %u points per sensor", cells, A, A, C, points);
  return true;
}

bool one_voxel(CaseInput& out, uint32_t points) {
  Builder b(out.cfg, 0.8f);
  const Grid& g = b.grid();
  const Vec3 c(out.cfg.workspace_centre_x_m, out.cfg.workspace_centre_y_m, 0.2f);
  b.add(0, g.cell_x(c.x()), g.cell_y(c.y()), g.cell_z(c.z()));
  b.append(1, b.list(0)[0]);  // the hand sees the same cell
  b.finish(out, points);
  out.note = fmt("%u points per sensor, all in one 5 mm cell", points);
  return true;
}

// No plane: an upright box-shaped object at the centre and kMaxVoxels minus its size
// isolated single voxels scattered through the whole crop box (no support plane, every
// voxel free, the cluster stage floods all of them).
bool no_plane(CaseInput& out, uint32_t points, std::string& err) {
  Builder b(out.cfg, 0.8f);
  const Grid& g = b.grid();
  const float cx = out.cfg.workspace_centre_x_m, cy = out.cfg.workspace_centre_y_m;
  const Vec3 half = small_build() ? Vec3(0.02f, 0.015f, 0.05f) : Vec3(0.03f, 0.02f, 0.10f);
  box_shell(g, Vec3(cx, cy, 0.05f) - Vec3(half.x(), half.y(), 0.f),
            Vec3(cx, cy, 0.05f) + Vec3(half.x(), half.y(), 2.f * half.z()),
            [&](int i, int j, int k) { b.add(0, i, j, k); });
  const uint32_t object = b.distinct();
  if (object > kMaxObjectPoints) {
    err = "object larger than kMaxObjectPoints";
    return false;
  }
  if (!scatter_singletons(b, kMaxVoxels, 0, 2)) {
    err = "scatter failed";
    return false;
  }
  b.finish(out, points);
  out.note = fmt("box object of %u voxels + %u isolated voxels (%u in all)", object, kMaxVoxels - object, kMaxVoxels);
  return true;
}

// All plane: kMaxVoxels voxels (or as many as three layers of the area the crop box's
// shrink keeps hold) in a horizontal slab two or three cells thick: the outer layers'
// points lie within 5.5 mm of the middle one, under object_min_height, so all are table.
bool all_plane(CaseInput& out, uint32_t points, std::string& err) {
  Builder b(out.cfg, 0.8f);
  const Grid& g = b.grid();
  const int avail = std::min(g.x_hi() - g.x_lo(), g.y_hi() - g.y_lo());
  const int layers = static_cast<uint64_t>(2) * avail * avail >= kMaxVoxels ? 2 : 3;
  const uint32_t cells =
      static_cast<uint32_t>(std::min<uint64_t>(kMaxVoxels, static_cast<uint64_t>(layers) * avail * avail));
  const int per_layer = static_cast<int>((cells + layers - 1) / layers);
  const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(per_layer))));
  if (side > avail) {
    err = "slab does not fit the crop box";
    return false;
  }
  const int i0 = (g.x_lo() + g.x_hi() - side) / 2, j0 = (g.y_lo() + g.y_hi() - side) / 2;
  const int k0 = g.cell_z(0.05f);
  uint32_t n = 0;
  for (int layer = 0; layer < layers; ++layer)
    for (int a = 0; a < side && n < cells; ++a)
      for (int c = 0; c < side && n < cells && n < static_cast<uint32_t>((layer + 1) * per_layer); ++c)
        if (b.add(layer & 1, i0 + a, j0 + c, k0 + layer, 0.1f)) ++n;
  b.finish(out, points);
  out.note = fmt("%u voxels, slab %dx%dx%d cells", n, side, side, layers);
  return true;
}

// The most RANSAC work: 11 horizontal layers 1.5 cm apart (farther than the 1 cm
// inlier distance, so a plane holds one layer: 9.1% of the points, below the 10%
// acceptance and too few for the 99% early stop), each with kMaxVoxels / 11 cells at
// random over the whole crop area (wide and flat: almost every 3-point sample is a
// near-horizontal hypothesis that gets scored on 4,096 points).
bool ransac_layers(CaseInput& out, uint32_t points, bool max_iters, std::string& err) {
  if (max_iters) set(out, "ransac_iterations", kRansacMaxIters, out.cfg.ransac_iterations);
  Builder b(out.cfg, 0.8f);
  const Grid& g = b.grid();
  constexpr int kLayers = 11, kSpacing = 3;
  const int k0 = g.cell_z(0.03f);
  if (k0 + kSpacing * (kLayers - 1) > b.k_hi()) {
    err = "layers do not fit the height range";
    return false;
  }
  for (int l = 0; l < kLayers; ++l) {
    const uint32_t want = kMaxVoxels / kLayers + (static_cast<uint32_t>(l) < kMaxVoxels % kLayers ? 1u : 0u);
    uint32_t n = 0;
    while (n < want) {
      const int i = g.x_lo() + static_cast<int>(b.rng().below(static_cast<uint32_t>(g.x_hi() - g.x_lo())));
      const int j = g.y_lo() + static_cast<int>(b.rng().below(static_cast<uint32_t>(g.y_hi() - g.y_lo())));
      if (b.add(static_cast<int>(n & 1u), i, j, k0 + kSpacing * l, 0.f)) ++n;
    }
  }
  b.finish(out, points);
  out.note = fmt("%d layers x ~%u voxels, %.1f cm apart, ransac_iterations %u", kLayers, kMaxVoxels / kLayers,
                 kSpacing * out.cfg.voxel_leaf_m * 100.0, out.cfg.ransac_iterations);
  return true;
}

// Collinear and duplicate points for the hulls: a square plate one voxel thick
// standing upright in the x-z plane (exact cell centres, no jitter), kMaxObjectPoints
// voxels, no support plane. Its axis is ill-defined (square), so the viewpoints turn
// about world z; the sensor arc (180 deg) passes the edge-on view, where every point
// projects onto one vertical line and each row of the plate onto one point.
bool hull_degenerate(CaseInput& out, uint32_t points, std::string& err) {
  set(out, "approach_view_max", 3.1416f, out.cfg.approach_view_max_rad);
  int side = static_cast<int>(std::floor(std::sqrt(static_cast<double>(kMaxObjectPoints))));
  Builder b(out.cfg, 1.2f);  // higher sensors: room for a tall plate
  const Grid& g = b.grid();
  side = std::min(side, b.k_hi() - b.k_lo() - 2);
  const int i0 = g.cell_x(out.cfg.workspace_centre_x_m) - side / 2;
  const int j = g.cell_y(out.cfg.workspace_centre_y_m);
  const int k0 = b.k_lo() + 2;
  for (int k = 0; k < side; ++k)
    for (int i = 0; i < side; ++i) b.add(k < side / 2 ? 0 : 1, i0 + i, j, k0 + k, 0.f);
  if (b.distinct() != static_cast<uint32_t>(side * side)) {
    err = "plate generation failed";
    return false;
  }
  b.finish(out, points);
  out.note = fmt("plate %dx%d voxels (one thick), exact cell centres", side, side);
  return true;
}

// The most viewpoints and scan lines: the smallest allowed viewpoint steps, every
// approach allowed, the smallest scan-line spacing and hull cell, the most candidates
// per viewpoint; the object a sphere shell of (at most) kMaxObjectPoints voxels, wider
// than the gripper from every side (every viewpoint analysed in full, none yields a
// grasp, so the search runs until kMaxViewpoints).
// The largest sphere-shell radius (centre 2 cm above the floor of the height range
// plus the radius) with at most `cells` voxels, or (over = true) the smallest one
// with more.
float shell_radius(const Grid& g, const Vec3& c0, uint32_t cells, bool over) {
  auto count = [&](float r) {
    uint32_t n = 0;
    sphere_shell(g, Vec3(c0.x(), c0.y(), c0.z() + r), r, [&](int, int, int) { ++n; });
    return n;
  };
  float r = 0.01f;
  const float step = 0.1f * g.leaf;
  while (count(r + step) <= cells && r < 0.5f) r += step;
  if (!over) return r;
  while (count(r) <= cells && r < 0.5f) r += step;
  return r;
}

// The most viewpoints and scan lines: the smallest allowed viewpoint steps, every
// approach allowed, the smallest scan-line spacing and hull cell, the most candidates
// per viewpoint; the object a sphere shell of (at most) kMaxObjectPoints voxels, wider
// than the gripper from every side (every viewpoint analysed in full, none yields a
// grasp, so the search runs until kMaxViewpoints). With over = true: the smallest
// shell with more than kMaxObjectPoints voxels (the object capacity is exceeded).
// A one-layer table slab of `cells` voxels (square, centred under the workspace
// centre) at height z, to the head's list.
void table_slab(Builder& b, uint32_t cells, float z) {
  const Grid& g = b.grid();
  const int side = std::min(static_cast<int>(std::ceil(std::sqrt(static_cast<double>(cells)))),
                            std::min(g.x_hi() - g.x_lo(), g.y_hi() - g.y_lo()));
  const int i0 = (g.x_lo() + g.x_hi() - side) / 2, j0 = (g.y_lo() + g.y_hi() - side) / 2;
  uint32_t n = 0;
  for (int a = 0; a < side && n < cells; ++a)
    for (int c = 0; c < side && n < cells; ++c)
      if (b.add(0, i0 + a, j0 + c, g.cell_z(z), 0.2f)) ++n;
}

// views_max's options: the smallest viewpoint steps, every approach, the smallest
// scan-line spacing and hull cell, the most candidates per viewpoint.
void set_views_max_options(CaseInput& out) {
  set(out, "dtheta", 0.0087f, out.cfg.dtheta_rad);
  set(out, "extension_dtheta", 0.0087f, out.cfg.extension_dtheta_rad);
  set(out, "approach_view_max", 3.1416f, out.cfg.approach_view_max_rad);
  set(out, "scan_delta", 0.0005f, out.cfg.scan_delta_m);
  set(out, "hull_cell", 0.0005f, out.cfg.hull_cell_m);
  set(out, "candidates_per_view", 16u, out.cfg.candidates_per_view);
}

bool sphere_case(CaseInput& out, uint32_t points, bool over, std::string& err) {
  if (!over) set_views_max_options(out);
  Builder b(out.cfg, 0.8f);
  const Grid& g = b.grid();
  // object_overflow: the sphere floats 2 cm above a table (the table is the plane RANSAC
  // must find; without one, small spheres lose their lower half to an "equator plane").
  const float floor_z = over ? 0.04f : 0.02f;
  const Vec3 base(out.cfg.workspace_centre_x_m, out.cfg.workspace_centre_y_m, floor_z);
  const float r = shell_radius(g, base, kMaxObjectPoints, over);
  const Vec3 c = base + Vec3(0.f, 0.f, r);
  if (c.z() + r > b.z_hi()) {
    err = "sphere does not fit the height range";
    return false;
  }
  sphere_shell(g, c, r, [&](int i, int j, int k) { b.add(g.centre(i, j, k).y() < c.y() ? 0 : 1, i, j, k); });
  const uint32_t sphere = b.distinct();
  if (over ? sphere <= kMaxObjectPoints : sphere > kMaxObjectPoints) {
    err = "sphere size search failed";
    return false;
  }
  uint32_t table = 0;
  if (over) {
    table = kMaxVoxels > sphere + kMaxObjectPoints ? kMaxVoxels - sphere - kMaxObjectPoints : 0u;
    table_slab(b, table, 0.02f);
    table = b.distinct() - sphere;
  }
  b.finish(out, points);
  out.note = over ? fmt("sphere shell r = %.1f mm, %u voxels, 2 cm above a table of %u voxels",
                        static_cast<double>(r * 1000.f), sphere, table)
                  : fmt("sphere shell r = %.1f mm, %u voxels", static_cast<double>(r * 1000.f), sphere);
  return true;
}

// The target-fragment fall-back at its most (docs/method.md A.6): views_max's options
// and sphere shell, moved 2 cells off the workspace centre, with a fragment nearer the
// centre: a flat square plate of 21 x 21 cells (wider than the opening both ways)
// inside the shell at its centre height, added first. The plate is the target and
// yields no grasp (its edge grasps hit the shell); it lies over the sphere's footprint,
// so the plan walks the other clusters again and searches the sphere in full too.
bool fallback_views_max(CaseInput& out, uint32_t points, std::string& err) {
  set_views_max_options(out);
  Builder b(out.cfg, 0.8f);
  const Grid& g = b.grid();
  const float cx = out.cfg.workspace_centre_x_m, cy = out.cfg.workspace_centre_y_m;
  const Vec3 base(cx + 2.f * g.leaf, cy, 0.02f);
  const float r = shell_radius(g, base, kMaxObjectPoints, false);
  const Vec3 c = base + Vec3(0.f, 0.f, r);
  if (c.z() + r > b.z_hi() || r < 0.09f) {
    err = "sphere does not fit the height range, or the plate does not fit inside it";
    return false;
  }
  const int half = std::min(10, static_cast<int>(r / g.leaf) - 6);
  const int ic = g.cell_x(cx), jc = g.cell_y(cy), kc = g.cell_z(c.z());
  for (int a = -half; a <= half; ++a)
    for (int d = -half; d <= half; ++d) b.add(a < 0 ? 0 : 1, ic + a, jc + d, kc, 0.f);
  const uint32_t plate = b.distinct();
  sphere_shell(g, c, r, [&](int i, int j, int k) { b.add(g.centre(i, j, k).y() < c.y() ? 0 : 1, i, j, k); });
  const uint32_t sphere = b.distinct() - plate;
  if (sphere > kMaxObjectPoints) {
    err = "sphere size search failed";
    return false;
  }
  b.finish(out, points);
  out.note = fmt("plate of %u voxels inside a sphere shell r = %.1f mm of %u voxels", plate,
                 static_cast<double>(r * 1000.f), sphere);
  return true;
}

// The most candidates and checks: an upright tube (every viewpoint sees a tall
// narrow rectangle: all scan lines kept, many windows, each a candidate, so
// kMaxCandidates fill up), a ring around it at finger distance that every candidate's
// open fingers hit (so the collision check of every candidate runs until it reaches
// the ring), the ring's voxels added last, and isolated voxels up to kMaxVoxels before
// it (the collision check scans every voxel that is not table, in insertion order).
bool candidates_max(CaseInput& out, uint32_t points, std::string& err) {
  set(out, "dtheta", 0.0087f, out.cfg.dtheta_rad);
  set(out, "approach_view_max", 3.1416f, out.cfg.approach_view_max_rad);
  set(out, "scan_delta", 0.0005f, out.cfg.scan_delta_m);
  set(out, "candidates_per_view", 16u, out.cfg.candidates_per_view);
  Builder b(out.cfg, 0.8f);
  const Grid& g = b.grid();
  const float cx = out.cfg.workspace_centre_x_m, cy = out.cfg.workspace_centre_y_m;
  const float r = small_build() ? 0.015f : 0.02f;
  const float z0 = 0.06f, z1 = small_build() ? 0.26f : 0.42f;
  tube(g, cx, cy, r, z0, z1, [&](int i, int j, int k) { b.add(0, i, j, k); });
  const uint32_t tube_cells = b.distinct();
  // Small builds: a table slab (3 cm below the tube) so RANSAC's best plane is the
  // table; without it, a +-1 cm band through the ring holds over 10% of 4,096 voxels
  // and is taken for the support plane, cutting the tube in half.
  uint32_t table = 0;
  if (small_build()) {
    table_slab(b, kMaxVoxels / 6, 0.03f);
    table = b.distinct() - tube_cells;
  }
  if (tube_cells > kMaxObjectPoints) {
    err = "tube larger than kMaxObjectPoints";
    return false;
  }
  // The ring: centred 5 mm off the tube's axis (so the tube, not the ring, is nearest
  // the workspace centre), radius 60 mm, 8 cm tall about the tube's mid-height.
  const float zm = 0.5f * (z0 + z1);
  uint32_t ring_cells = 0;
  tube(g, cx + 0.005f, cy, 0.06f, zm - 0.04f, zm + 0.04f, [&](int, int, int) { ++ring_cells; });
  if (tube_cells + table + ring_cells >= kMaxVoxels) {
    err = "tube and ring exceed kMaxVoxels";
    return false;
  }
  // Isolated voxels away from both (at least 3 cells from any used cell and outside a
  // 0.15 m radius about the tube), then the ring last.
  {
    uint64_t tries = 0;
    int sensor = 0;
    while (b.distinct() < kMaxVoxels - ring_cells) {
      if (++tries > 200ull * kMaxVoxels) {
        err = "scatter failed";
        return false;
      }
      const int i = g.x_lo() + static_cast<int>(b.rng().below(static_cast<uint32_t>(g.x_hi() - g.x_lo())));
      const int j = g.y_lo() + static_cast<int>(b.rng().below(static_cast<uint32_t>(g.y_hi() - g.y_lo())));
      const int k = b.k_lo() + static_cast<int>(b.rng().below(static_cast<uint32_t>(b.k_hi() - b.k_lo() + 1)));
      const Vec3 p = g.centre(i, j, k);
      if (std::hypot(p.x() - cx, p.y() - cy) < 0.15f || !b.isolated(i, j, k, 2)) continue;
      b.add(sensor, i, j, k);
      sensor = 1 - sensor;
    }
  }
  tube(g, cx + 0.005f, cy, 0.06f, zm - 0.04f, zm + 0.04f, [&](int i, int j, int k) { b.add(1, i, j, k); });
  b.finish(out, points);
  out.note = fmt("tube r %.0f mm of %u voxels, ring of %u voxels added last, %u isolated voxels%s",
                 static_cast<double>(r * 1000.f), tube_cells, ring_cells, kMaxVoxels - tube_cells - ring_cells - table,
                 table ? fmt(", table of %u voxels", table).c_str() : "");
  return true;
}

// Pathological hashing: kMaxVoxels cells chosen so their home slots in the voxel hash
// (VoxelGrid::mix) fall in one narrow window. Without a
// bound, linear probing would walk one run growing to kMaxVoxels slots (O(n^2)
// probes); the grid refuses a cell past VoxelGrid::kMaxProbe, so this case measures
// that cap (the planner ends in capacity_exceeded). Cells are isolated from each
// other. Not a scene a sensor produces by chance.
bool hash_collide(CaseInput& out, uint32_t points, uint32_t cells, std::string& err) {
  Builder b(out.cfg, 0.8f);
  const Grid& g = b.grid();
  constexpr uint32_t kSlotBits = [] {
    uint32_t bits = 0;
    while ((1u << bits) < kVoxelHashSlots) ++bits;
    return bits;
  }();
  auto slot_of = [](uint32_t key) { return VoxelGrid::mix(key) >> (32 - kSlotBits); };
  // Candidate cells with their home slot in [0, W): grow W until enough isolated ones.
  uint32_t window = 64;
  for (;;) {
    Builder t(out.cfg, 0.8f);
    uint32_t n = 0;
    for (int k = b.k_lo(); k <= b.k_hi() && n < cells; ++k)
      for (int j = g.y_lo(); j < g.y_hi() && n < cells; ++j)
        for (int i = g.x_lo(); i < g.x_hi() && n < cells; ++i) {
          const uint32_t key =
              VoxelGrid::pack(static_cast<uint32_t>(i), static_cast<uint32_t>(j), static_cast<uint32_t>(k));
          if (slot_of(key) >= window || !t.isolated(i, j, k)) continue;
          if (t.add(static_cast<int>(n & 1u), i, j, k)) ++n;
        }
    if (n == cells) {
      b = std::move(t);
      break;
    }
    window *= 2;
    if (window > kVoxelHashSlots) {
      err = "not enough colliding cells";
      return false;
    }
  }
  // Each cell once per sensor pass: cycling all the input through an O(n) probe run
  // would take minutes; the point is the run, not the input volume.
  b.finish(out, std::min(points, (cells + 1) / 2));
  out.note = fmt("%u cells whose home slots lie in %u of %u hash slots", cells, window, kVoxelHashSlots);
  return true;
}

}  // namespace

const std::vector<CaseInfo>& case_list() {
  static const std::vector<CaseInfo> list = {
      {"typical_example", "all", "the shipped two-sensor example (real capture)", true, false},
      {"typical_box", "all", "hal/sim box on a table, two rendered depth images", true, true},
      {"own_voxel", "ingest, plane, cluster", "every point in its own voxel: kMaxVoxels cells, cache-missing order",
       false, true},
      {"voxel_overflow", "ingest", "kMaxVoxels + 1 distinct cells: the capacity is exceeded", false, true},
      {"one_voxel", "ingest", "every point in one voxel", false, true},
      {"no_plane", "plane, cluster", "no support plane: an object and isolated voxels up to kMaxVoxels", false, true},
      {"all_plane", "plane", "kMaxVoxels voxels, all on the support plane", false, true},
      {"ransac_max", "plane", "11 near-horizontal layers, no plane accepted, ransac_iterations = kRansacMaxIters",
       false, true},
      {"ransac_default", "plane", "the same layers with the default ransac_iterations", false, true},
      {"hull_degenerate", "xoy", "collinear and duplicate projections: an upright plate one voxel thick", false, true},
      {"object_overflow", "cluster", "a target of kMaxObjectPoints + 1 voxels: the capacity is exceeded", false, true},
      {"views_max", "frame, xoy", "the most viewpoints and scan lines (smallest steps, sphere too wide)", false, false},
      {"candidates_max", "xoz, select", "kMaxCandidates candidates, each rejected late by the collision scan", false,
       false},
      {"fallback_views_max", "cluster, frame, xoy",
       "views_max's sphere under a fragment target: the fall-back searches both", false, false},
      {"hash_collide", "ingest, reset", "kMaxVoxels cells colliding in the voxel hash (pathological)", false, false},
      {"registration_max", "ingest (registration)",
       "the reference typical input, the hand's pose 20 mm and 2 deg off: the registration corrects it", false, true},
      // The reference typical input planned with the options an adversarial case
      // changes: the ratio of that case at the same configuration.
      {"typical_at_ransac_max", "(reference)", "the reference typical input with ransac_max's options", true, false},
      {"typical_at_hull_degenerate", "(reference)", "the reference typical input with hull_degenerate's options", true,
       false},
      {"typical_at_views_max", "(reference)", "the reference typical input with views_max's options", true, false},
      {"typical_at_candidates_max", "(reference)", "the reference typical input with candidates_max's options", true,
       false},
      {"typical_at_fallback_views_max", "(reference)", "the reference typical input with fallback_views_max's options",
       true, false},
  };
  return list;
}

uint32_t default_points_per_sensor() { return small_build() ? 160u * 120u : 640u * 480u; }

const char* reference_typical_case() { return small_build() ? "typical_box" : "typical_example"; }

bool make_case(const std::string& name, uint32_t points, CaseInput& out, std::string& error, uint32_t hash_cells) {
  const std::string at = "typical_at_";
  if (name.compare(0, at.size(), at) == 0) {
    // The adversarial case is built only for its option list (a second or two).
    CaseInput adversarial;
    if (!make_case(name.substr(at.size()), points, adversarial, error, hash_cells)) return false;
    if (!make_case(reference_typical_case(), points, out, error, hash_cells)) return false;
    out.name = name;
    for (const std::string& o : adversarial.overrides) {
      const size_t eq = o.find('=');
      if (eq == std::string::npos || !fg::host::set_config_option(out.cfg, o.substr(0, eq), o.substr(eq + 1), error))
        return false;
      out.overrides.push_back(o);
    }
    out.note += (out.note.empty() ? "" : "; ") + std::string("options of ") + name.substr(at.size());
    return true;
  }
  out = CaseInput{};
  out.name = name;
  if (name == "registration_max") {
    // The hand's points as captured, its pose off in its own frame: the registration
    // (A.4b) samples, iterates and corrects, where an exact pose ends after a few steps.
    if (!make_case(reference_typical_case(), points, out, error, hash_cells)) return false;
    out.name = name;
    for (SensorInput& s : out.sensors) {
      if (s.role != SensorRole::hand) continue;
      const Mat3 turn = Eigen::AngleAxisf(0.0349066f, Vec3(0.3f, -0.5f, 0.8f).normalized()).toRotationMatrix();
      s.pose.t += s.pose.R * Vec3(0.012f, -0.010f, 0.012f);  // 20 mm
      s.pose.R = s.pose.R * turn;
    }
    out.note += "; the hand's pose 20 mm and 2 deg off";
    return true;
  }
  if (name == "typical_example") return load_example(out, error);
  if (name == "typical_box") return sim_box(out, error);
  if (name == "own_voxel") return own_voxel(out, points, kMaxVoxels, error);
  if (name == "voxel_overflow") return own_voxel(out, points, kMaxVoxels + 1, error);
  if (name == "one_voxel") return one_voxel(out, points);
  if (name == "no_plane") return no_plane(out, points, error);
  if (name == "all_plane") return all_plane(out, points, error);
  if (name == "ransac_max") return ransac_layers(out, points, true, error);
  if (name == "ransac_default") return ransac_layers(out, points, false, error);
  if (name == "hull_degenerate") return hull_degenerate(out, points, error);
  if (name == "views_max") return sphere_case(out, points, false, error);
  if (name == "object_overflow") return sphere_case(out, points, true, error);
  if (name == "candidates_max") return candidates_max(out, points, error);
  if (name == "fallback_views_max") return fallback_views_max(out, points, error);
  if (name == "hash_collide")
    return hash_collide(out, points, hash_cells == 0 ? kMaxVoxels : std::min(hash_cells, kMaxVoxels), error);
  error = "unknown case " + name;
  return false;
}

}  // namespace fg::wcet
